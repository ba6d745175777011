//! The bridge to the lab: what a body will do in the lab's terms, and measured data read as
//! measurements.
//!
//! | file | what it owns |
//! |---|---|
//! | [`prediction`] | the periodic motions a body settles into from rest, in the lab's terms, with their contact forces and fractions of starts |
//! | [`lag_times`] | fits of measured lag times t_lag = A (α − α*)^β, per run and with one shared exponent |
//! | [`lag_calibration`] | how often `fit-lag`'s stated intervals hold the true exponent, on synthetic runs shaped like the authors' |
//! | [`mesh_calibration`] | how often the mesh fit's stated errors of ⟨r⟩ and α* hold the truth, on noisy icospheres of a known body |
//! | [`tracking`] | a filmed run's centre track cleaned, its period with evidence, the folded track, the markers' reading, the trackers' tables (`table`), and the comparison with the model |

pub mod lag_calibration;
pub mod lag_times;
pub mod mesh_calibration;
pub mod prediction;
pub mod tracking;
