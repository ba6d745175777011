//! rollphase-core: the physics of rollphase, after Qian, Jung & Mahadevan, *Phase transitions in
//! rolling of irregular cylinders and spheres*, with no GPU, window, UI or command-line crate in
//! its dependency tree (the compiler keeps them apart: this crate cannot name them).
//!
//! | module | owns |
//! |---|---|
//! | [`numeric`] | quadrature, golden-section search, root finding, marching squares, eigenvalues (nalgebra) |
//! | [`geometry`] | bodies r(θ), r(u): exact derivatives, curvature, support points, shape files, generators (ours, and the paper authors' numpy bodies bit for bit) |
//! | [`integrate`] | RK4, DOP853 with dense output, the Lie-group CF4 step, event location; fixed steps check their own error |
//! | [`dynamics`] | the four rolling models (2D/3D, viscous/inertial) as ODE systems |
//! | [`analysis`] | critical angle α*, 2D periods, accuracy tables, orbits through ∂Ω, return maps and their Floquet multipliers, lag-time fits; the 3D studies with plain parameters ([`analysis::studies::sphere`]) |
//! | [`simulate`] | one run: a body, a ramp, a start and an integrator in; sampled rows (or a typed [`simulate::Trajectory`]) and a [`simulate::Summary`] out |
//!
//! None of them reads the wall clock: the same inputs give the same numbers on every run and
//! thread count. The `rollphase` crate re-exports every module, so `rollphase::geometry::…`
//! paths work as well as `rollphase_core::geometry::…`.

#![warn(missing_docs)]

/// glam, whose `DQuat` and `DVec3` the API speaks (orientations, contact points, ω), so a caller
/// needs no glam dependency of their own.
pub use glam;

pub mod analysis;
pub mod dynamics;
pub mod geometry;
pub mod integrate;
pub mod numeric;
pub mod simulate;
