//! What is wrong with a scene ([`SceneError`]), and the small checks that `setup` and
//! `timeline` both make (a file of its own, so that neither imports the other for them).

use std::path::PathBuf;

use thiserror::Error;

use crate::dynamics::ModelError;
use crate::geometry::ShapeError;
use crate::integrate::IntegrateError;

/// What is wrong with a scene.
#[derive(Debug, Error)]
pub enum SceneError {
    /// TOML syntax or an unknown/mistyped field (transparent, so the message is printed once).
    #[error(transparent)]
    Parse(#[from] toml::de::Error),
    /// A value out of range or fields that do not fit together.
    #[error("{0}")]
    Invalid(String),
    /// The body is bad.
    #[error(transparent)]
    Shape(#[from] ShapeError),
    /// α, m/m0 or drag out of range.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// Bad integrator settings.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
    /// The shape file could not be read.
    #[error("cannot read shape file {}: {reason}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: std::io::Error,
    },
    /// The scene file could not be read.
    #[error("cannot read scene file {}: {reason}", path.display())]
    SceneIo {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: std::io::Error,
    },
    /// No preset of that name.
    #[error("no preset named {0:?}; `rollphase scenes` lists them: {1}")]
    UnknownPreset(String, String),
}

pub(super) fn invalid(msg: impl Into<String>) -> SceneError {
    SceneError::Invalid(msg.into())
}

/// Checks a playback speed given as `field` (the scene's, or a timeline step's).
pub(super) fn check_speed(field: &str, speed: f64) -> Result<(), SceneError> {
    if speed.is_finite() && speed > 0.0 && speed <= 1e4 {
        Ok(())
    } else {
        Err(invalid(format!(
            "{field} = {speed} is not allowed (needs 0 < speed ≤ 10000 time units per second)"
        )))
    }
}
