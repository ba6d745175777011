//! What is computed from bodies and trajectories: the critical angle α* and its maximiser,
//! 2D periods (by quadrature in the viscous model, by simulation with event location in the
//! inertial one), and the quadrature they use. Pure math: no GPU or UI imports.

pub mod accuracy;
pub mod critical_angle;
pub mod disk_dynamics;
pub mod fit;
pub mod lag_fit;
pub mod period;
pub mod quadrature;
pub mod sphere_orbits;

pub use critical_angle::{CriticalAngle, critical_angle};
pub use period::{PeriodResult, inertial_disk_period, viscous_disk_period};
