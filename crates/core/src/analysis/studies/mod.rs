//! Questions asked over many starts or parameters, each run in parallel with the same numbers
//! for any thread count.
//!
//! | file | what it owns |
//! |---|---|
//! | [`sphere`] | the paper's 3D studies with plain parameters: the Poincaré map over starts, the cruising fraction, the period counts at one m/m0, the period-1 orbits the starts settle on |
//! | [`disk`] | the 2D studies: lag times near α*, the inertial disk's hysteresis sweep, the fixed points of its (θ, θ̇) flow |
//! | [`contact_tube`] | the tube of orbits through one contact point (SI Fig. S3), checked against the closed form |
//! | [`sweep`] | the general scan bodies × α × m/m0 × orientations × integrators that `rollphase sweep` shards |

pub mod contact_tube;
pub mod disk;
pub mod sphere;
pub mod sweep;
