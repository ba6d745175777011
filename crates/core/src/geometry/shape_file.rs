//! The JSON shape-file schema shared with other tools, exactly:
//! 2D `{"kind":"disk","modes":[{"l":2,"a":0.05,"phase":1.2},…]}`,
//! 3D `{"kind":"sphere","coeffs":[{"l":2,"m":-2,"re":0.1,"im":0.0},…]}` with A_lm = re + i·im.
//! Unknown kinds and unknown fields are rejected, with serde's line and column.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::{Body, DiskMode, ShapeError, SphereCoeff};

/// Why a shape file could not be loaded; each message names the file.
#[derive(Debug, Error)]
pub enum ShapeLoadError {
    /// The file could not be read.
    #[error("cannot read shape file {}: {reason}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        reason: std::io::Error,
    },
    /// Not JSON of the schema.
    #[error(
        "{} is not a valid shape file. Expected {{\"kind\":\"disk\",\"modes\":[{{\"l\":2,\"a\":0.05,\"phase\":1.2}}]}} \
         or {{\"kind\":\"sphere\",\"coeffs\":[{{\"l\":2,\"m\":-2,\"re\":0.1,\"im\":0.0}}]}}: {reason}",
        path.display()
    )]
    Parse {
        /// The file.
        path: PathBuf,
        /// serde's message with line and column.
        reason: serde_json::Error,
    },
    /// Parsed, but the values are out of range.
    #[error("bad shape file {}: {reason}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: ShapeError,
    },
}

/// A parsed shape file (not yet validated; see [`super::Body::from_shape`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeFile {
    /// A 2D body.
    Disk {
        /// Its Fourier modes.
        modes: Vec<DiskMode>,
        /// Millimetres per ⟨r⟩ of the real object (a body fitted to a mesh keeps its size here,
        /// so that predictions can speak in mm); absent for a body of the model alone.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        scale_mm: Option<f64>,
        /// The flat-sided section of the print the body was fitted to (`shape --from-mesh`
        /// keeps it unless told the facets are tessellation): what the print rests on.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        printed_section: Option<super::facets::PrintedSection>,
    },
    /// A 3D body.
    Sphere {
        /// Its spherical-harmonic coefficients.
        coeffs: Vec<SphereCoeff>,
        /// Millimetres per ⟨r⟩, as for a disk.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        scale_mm: Option<f64>,
    },
}

/// Largest shape or scene file read: both are a few kB, so anything near this is the wrong file.
pub const MAX_INPUT_FILE_BYTES: u64 = 1 << 20;

/// Reads a text file of at most `limit` bytes; a longer one (or an endless device such as
/// /dev/zero) is an error saying the limit, after reading only `limit` + 1 bytes.
///
/// # Example
/// ```
/// use rollphase_core::geometry::shape_file::read_text_capped;
/// // An endless device is refused after limit + 1 bytes.
/// let e = read_text_capped(std::path::Path::new("/dev/zero"), 1000).unwrap_err();
/// assert!(e.to_string().contains("1000"), "{e}");
/// ```
pub fn read_text_capped(path: &Path, limit: u64) -> std::io::Result<String> {
    use std::io::Read;
    let file = std::fs::File::open(path)?;
    let mut text = String::new();
    file.take(limit + 1).read_to_string(&mut text)?;
    if text.len() as u64 > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!(
                "it is larger than {} bytes, the most an input file of this kind may be",
                limit
            ),
        ));
    }
    Ok(text)
}

impl ShapeFile {
    /// Parses JSON text; errors carry serde's line and column.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::ShapeFile;
    /// let file = ShapeFile::from_json(r#"{"kind": "disk", "modes": [{"l": 2, "a": 0.3, "phase": 0.0}]}"#)?;
    /// assert!(matches!(file, ShapeFile::Disk { ref modes, .. } if modes.len() == 1));
    /// // A misspelt key is named.
    /// let e = ShapeFile::from_json(r#"{"kind": "disk", "mode": []}"#).unwrap_err();
    /// assert!(e.to_string().contains("`mode`"), "{e}");
    /// # Ok::<(), serde_json::Error>(())
    /// ```
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }

    /// Reads, parses and validates the shape file at `path` (ranges and finiteness, not
    /// convexity: see [`Body::check_convex`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{ShapeFile, ShapeLoadError};
    /// use std::path::Path;
    /// let shapes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/shapes");
    /// let body = ShapeFile::load(&shapes.join("paper-sphere.json"))?;
    /// assert_eq!(body.dimension(), 3);
    /// // A file that is not there is an error naming it.
    /// let missing = ShapeFile::load(&shapes.join("no-such-body.json")).unwrap_err();
    /// assert!(matches!(missing, ShapeLoadError::Read { .. }));
    /// assert!(missing.to_string().contains("no-such-body.json"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn load(path: &Path) -> Result<Body, ShapeLoadError> {
        Ok(Self::load_scaled(path)?.0)
    }

    /// [`ShapeFile::load`] that also gives the file's `scale_mm` (millimetres per ⟨r⟩), when it
    /// has one.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::ShapeFile;
    /// use std::path::Path;
    /// let shapes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/shapes");
    /// let (body, scale) = ShapeFile::load_scaled(&shapes.join("paper-sphere.json"))?;
    /// assert_eq!((body.dimension(), scale), (3, None));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn load_scaled(path: &Path) -> Result<(Body, Option<f64>), ShapeLoadError> {
        let text = read_text_capped(path, MAX_INPUT_FILE_BYTES).map_err(|reason| {
            ShapeLoadError::Read {
                path: path.to_owned(),
                reason,
            }
        })?;
        let file = Self::from_json(&text).map_err(|reason| ShapeLoadError::Parse {
            path: path.to_owned(),
            reason,
        })?;
        let body = Body::from_shape(&file).map_err(|reason| ShapeLoadError::Invalid {
            path: path.to_owned(),
            reason,
        })?;
        Ok((body, file.scale_mm()))
    }

    /// Millimetres per ⟨r⟩ of the real object, when the file says (a body fitted to a mesh).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::ShapeFile;
    /// let file = ShapeFile::from_json(r#"{"kind": "disk", "modes": [], "scale_mm": 10.0}"#)?;
    /// assert_eq!(file.scale_mm(), Some(10.0));
    /// # Ok::<(), serde_json::Error>(())
    /// ```
    pub fn scale_mm(&self) -> Option<f64> {
        match self {
            ShapeFile::Disk { scale_mm, .. } | ShapeFile::Sphere { scale_mm, .. } => *scale_mm,
        }
    }

    /// This file with `scale_mm` set.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let file = Body::paper_disk(0, 0.1, 6)?.to_shape().with_scale_mm(Some(10.0));
    /// assert_eq!(file.scale_mm(), Some(10.0));
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn with_scale_mm(self, scale: Option<f64>) -> Self {
        match self {
            ShapeFile::Disk {
                modes,
                printed_section,
                ..
            } => ShapeFile::Disk {
                modes,
                scale_mm: scale,
                printed_section,
            },
            ShapeFile::Sphere { coeffs, .. } => ShapeFile::Sphere {
                coeffs,
                scale_mm: scale,
            },
        }
    }

    /// This disk file with `printed_section` set (a sphere's is returned as it is).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Body, ShapeFile};
    /// let file = Body::paper_disk(0, 0.1, 6)?.to_shape().with_printed_section(None);
    /// assert!(matches!(file, ShapeFile::Disk { printed_section: None, .. }));
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn with_printed_section(self, section: Option<super::facets::PrintedSection>) -> Self {
        match self {
            ShapeFile::Disk {
                modes, scale_mm, ..
            } => ShapeFile::Disk {
                modes,
                scale_mm,
                printed_section: section,
            },
            sphere => sphere,
        }
    }

    /// Pretty JSON text.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::ShapeFile;
    /// let text = r#"{"kind": "disk", "modes": [{"l": 3, "a": 0.1, "phase": 1.0}]}"#;
    /// let file = ShapeFile::from_json(text)?;
    /// assert_eq!(ShapeFile::from_json(&file.to_json()?)?, file);
    /// # Ok::<(), serde_json::Error>(())
    /// ```
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        serde_json::to_string_pretty(self)
    }
}
