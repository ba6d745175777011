//! Periodic motion and its stability: orbits, return maps and their multipliers.
//!
//! | file | what it owns |
//! |---|---|
//! | [`disk_period`] | a rolling disk's period T (quadrature in the viscous model, event location with inertia) and its fate |
//! | [`return_map`] | fixed points of a return map, their multipliers, flip bifurcations (model-free) |
//! | [`sphere_orbits`] | ∂Ω of the SO(3) ball: crossings, cycles, settling with its answer check |
//! | [`poincare_field`] | the viscous Poincaré map on ∂Ω and its field V = P(p) − p |
//! | [`sphere_return_map`] | the inertial return map on ∂Ω × ω, its periodic orbits and Floquet multipliers |
//! | [`orbit_diagram`] | the orbit diagram in m/m0: runs per mass, the period-1 orbit continued, flips, windows of period 2 |

pub mod disk_period;
pub mod orbit_diagram;
pub mod poincare_field;
pub mod return_map;
pub mod sphere_orbits;
pub mod sphere_return_map;
