//! The JSON shape-file schema shared with other tools, exactly:
//! 2D `{"kind":"disk","modes":[{"l":2,"a":0.05,"phase":1.2},…]}`,
//! 3D `{"kind":"sphere","coeffs":[{"l":2,"m":-2,"re":0.1,"im":0.0},…]}` with A_lm = re + i·im.
//! Unknown kinds and unknown fields are rejected, with serde's line and column.

use serde::{Deserialize, Serialize};

use super::{DiskMode, SphereCoeff};

/// A parsed shape file (not yet validated; see [`super::Body::from_file`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeFile {
    /// A 2D body.
    Disk {
        /// Its Fourier modes.
        modes: Vec<DiskMode>,
    },
    /// A 3D body.
    Sphere {
        /// Its spherical-harmonic coefficients.
        coeffs: Vec<SphereCoeff>,
    },
}

impl ShapeFile {
    /// Parses JSON text; errors carry serde's line and column.
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }

    /// Pretty JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}
