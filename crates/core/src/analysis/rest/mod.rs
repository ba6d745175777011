//! Where a body can stop.
//!
//! | file | what it owns |
//! |---|---|
//! | [`critical_angle`] | α* = atan max |∇ ln r| and where the maximum is (2D and 3D), exact to round-off |
//! | [`halting`] | the halting loops Q = tan α of viscous 3D rolling and their stability (SI §2D–2E) |

pub mod critical_angle;
pub mod halting;
