//! What is computed from bodies and trajectories, grouped by what it is. Every analysis steps
//! its runs through the one loop (`integrate::run`) and takes a run's fate from [`verdict`].
//! Pure math: no GPU or UI imports.
//!
//! | module | what it owns |
//! |---|---|
//! | [`verdict`] | a run's fate in the words every surface uses, and the decisions the runs share (rest, stability, steady drift) |
//! | [`rest`] | where a body can stop: the critical angle α* and its maximiser, the halting loops Q = tan α and their stability |
//! | [`orbits`] | periodic motion: a disk's period, return maps with their fixed points and Floquet multipliers, orbits through ∂Ω (viscous) and the inertial return map, the orbit diagram in m/m0 |
//! | [`studies`] | questions asked over many starts or parameters: the 3D studies (Poincaré map over starts, cruising fraction, period counts), the 2D lag / hysteresis / flow analyses, the tube through one contact point, the general sweep |
//! | [`experiment`] | the bridge to the lab: predictions in the lab's terms, fits of measured lag times, filmed tracks read as measurements and compared with the model |
//! | [`design`] | bodies designed for a property (a critical angle, a window of hysteresis) under a printer's constraints, checked over the band a bench brings |
//! | [`accuracy`] | the price of accuracy: trajectory errors per integrator setting, and the answers (fates, multiplicities, orbit counts) each setting gets |
//! | [`fit`] | least-squares lines and power laws shared by the figures and the studies |

pub mod accuracy;
pub mod design;
pub mod experiment;
pub mod fit;
pub mod orbits;
pub mod rest;
pub mod studies;
pub mod verdict;

pub use orbits::disk_period::{
    PeriodResult, inertial_disk_period, inertial_disk_period_until, viscous_disk_period,
    viscous_disk_period_with,
};
pub use rest::critical_angle::{CriticalAngle, critical_angle};
