//! What is computed from bodies and trajectories: the critical angle α* and its maximiser,
//! 2D periods (by quadrature in the viscous model, by simulation with event location in the
//! inertial one), and return maps with their multipliers (nalgebra).
//! Pure math: no GPU or UI imports.

pub mod accuracy;
pub mod answers;
pub mod contact_tube;
pub mod critical_angle;
pub mod disk_dynamics;
pub mod fit;
pub mod halting;
pub mod lag_fit;
pub mod orbit_diagram;
pub mod period;
pub mod prediction;
pub mod return_map;
pub mod scan;
pub mod sphere_orbits;
pub mod sphere_return_map;
pub mod studies;
pub mod tracking;
pub mod verdict;

pub use critical_angle::{CriticalAngle, critical_angle};
pub use period::{
    PeriodResult, inertial_disk_period, inertial_disk_period_until, viscous_disk_period,
    viscous_disk_period_with,
};
