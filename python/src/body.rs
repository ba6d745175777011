//! `rollphase.Body`: a star-shaped body, built from the paper's generator (numpy seeds, bit for
//! bit the authors' bodies), from rollphase's own generator, or from a shape file; its α*,
//! convexity and radius over numpy arrays; written back to a shape file through the output
//! layer.

use std::path::PathBuf;

use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{AllowTypeChange, IntoPyArray, PyArrayDyn, PyArrayLikeDyn};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use rollphase_core::geometry::{Body as CoreBody, ShapeFile};
use rollphase_core::glam::DVec3;
use rollphase_output::output::{self, OutputError};

use crate::errors::{bad_input, input_error, internal_error};
use crate::whole;

/// A rolling body: a disk (2D, r(θ) = 1 + Σ a_l/l² sin(l(θ − θ_l))) or a sphere (3D,
/// r(u) = 1 + Re Σ A_lm/(l(l+1)) Y_lm(u)), with mean radius 1.
///
/// Build one with Body.paper_sphere(219) (the paper's own body), Body.paper_disk,
/// Body.random_sphere, Body.random_disk or Body.from_file.
#[pyclass(frozen, module = "rollphase", name = "Body")]
pub struct Body {
    pub(crate) body: CoreBody,
    origin: String,
    /// Millimetres per ⟨r⟩ of the real object (a body fitted to a mesh, or a shape file's
    /// scale_mm).
    pub(crate) scale_mm: Option<f64>,
    /// The mesh fit's report as JSON (Body.from_mesh).
    fit: Option<String>,
}

impl Body {
    fn made(body: Result<CoreBody, impl std::fmt::Display>, origin: String) -> PyResult<Self> {
        Ok(Body {
            body: body.map_err(bad_input)?,
            origin,
            scale_mm: None,
            fit: None,
        })
    }

    /// A body `design` made, at `scale_mm` millimetres per ⟨r⟩.
    pub(crate) fn designed(body: CoreBody, scale_mm: f64, what: String) -> Self {
        Body {
            body,
            origin: what,
            scale_mm: Some(scale_mm),
            fit: None,
        }
    }

    /// The core body, refusing a non-convex one the way a run does.
    pub(crate) fn convex(&self) -> PyResult<&CoreBody> {
        self.body.check_convex().map_err(bad_input)?;
        Ok(&self.body)
    }

    /// The core body, refusing one that cannot roll even on its hull (`period` and `predict`,
    /// as on the command line: a dented cylinder or a print's outline rolls on its flats).
    pub(crate) fn rollable(&self) -> PyResult<&CoreBody> {
        self.body.check_rollable().map_err(bad_input)?;
        Ok(&self.body)
    }
}

#[pymethods]
impl Body {
    /// The paper's 3D body for a numpy seed (the authors' generator, bit for bit): seed 219,
    /// sigma 0.25, modes 5 is the body of the paper's Figs. 3 and 4. modes is the highest degree
    /// l, as the authors' L.
    #[staticmethod]
    #[pyo3(signature = (seed, *, sigma = 0.25, modes = 5))]
    fn paper_sphere(seed: i128, sigma: f64, modes: i128) -> PyResult<Self> {
        let (seed, modes): (u64, u32) = (whole("seed", seed)?, whole("modes", modes)?);
        Body::made(
            CoreBody::paper_sphere(seed, sigma, modes),
            format!("paper sphere (numpy seed {seed}, sigma {sigma}, l <= {modes})"),
        )
    }

    /// The paper's 2D body for a numpy seed (the authors' generator, bit for bit). modes is the
    /// highest degree l; the authors' get_r(seed, num_modes, std) covers l = 2 … num_modes + 1,
    /// so their num_modes = 8 is modes=9 here.
    #[staticmethod]
    #[pyo3(signature = (seed, *, sigma = 0.08, modes = 10))]
    fn paper_disk(seed: i128, sigma: f64, modes: i128) -> PyResult<Self> {
        let (seed, modes): (u64, u32) = (whole("seed", seed)?, whole("modes", modes)?);
        Body::made(
            CoreBody::paper_disk(seed, sigma, modes),
            format!("paper disk (numpy seed {seed}, sigma {sigma}, l <= {modes})"),
        )
    }

    /// A random sphere from rollphase's own generator (seeded, the same on every machine).
    #[staticmethod]
    #[pyo3(signature = (seed, *, sigma = 0.25, modes = 5))]
    fn random_sphere(seed: i128, sigma: f64, modes: i128) -> PyResult<Self> {
        let (seed, modes): (u64, u32) = (whole("seed", seed)?, whole("modes", modes)?);
        Body::made(
            CoreBody::random_sphere(seed, sigma, modes),
            format!("random sphere (seed {seed}, sigma {sigma}, l <= {modes})"),
        )
    }

    /// A random disk from rollphase's own generator (seeded, the same on every machine).
    #[staticmethod]
    #[pyo3(signature = (seed, *, sigma = 0.08, modes = 10))]
    fn random_disk(seed: i128, sigma: f64, modes: i128) -> PyResult<Self> {
        let (seed, modes): (u64, u32) = (whole("seed", seed)?, whole("modes", modes)?);
        Body::made(
            CoreBody::random_disk(seed, sigma, modes),
            format!("random disk (seed {seed}, sigma {sigma}, l <= {modes})"),
        )
    }

    /// A body from a shape file (JSON, as `rollphase shape` writes).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let origin = format!("shape file {}", path.display());
        let (body, scale_mm) = ShapeFile::load_scaled(&path).map_err(bad_input)?;
        Ok(Body {
            scale_mm,
            ..Body::made(Ok::<_, String>(body), origin)?
        })
    }

    /// A body fitted to a printed or scanned mesh (.stl binary or ASCII, .obj, .ply; in mm
    /// unless mm_per_unit says otherwise), as `rollphase shape --from-mesh` fits it: the radius
    /// about the volume centroid by real spherical harmonics (3D), or an extruded cylinder's
    /// section by a Fourier series (2D, found from the mesh or dim=2; axis=(x, y, z) gives the
    /// cylinder's axis). modes is the degree (None: the smallest whose rms residual is within
    /// 10 % of the best fit's, or under 5e-5 of the mean radius). The fit's report (residuals in
    /// mm and relative, scale_mm, the l = 1 part left out, alpha_star, warnings) is
    /// body.mesh_fit; a mesh that is open, not star-shaped about its centroid, or fits no
    /// convex body raises ValueError naming the place. coat_mm coats the fitted body with that
    /// many mm of uniform thickness (the rubber of the viscous experiments) and fits the coated
    /// surface again; mesh_fit["coat"] then gives ⟨r⟩ and α* before and after.
    /// ignore_facets=True treats a 2D section's flat facets as an export's tessellation of a
    /// round body: the body then keeps no printed section (see `rollphase shape
    /// --ignore-facets`); in 3D it skips mesh_fit["solid_hull"] (the mesh's own hull and the
    /// α* its facets give) and its warning.
    #[staticmethod]
    #[pyo3(signature = (path, *, modes = None, dim = None, axis = None, mm_per_unit = 1.0, coat_mm = None, ignore_facets = false))]
    #[allow(clippy::too_many_arguments)]
    fn from_mesh(
        py: Python<'_>,
        path: PathBuf,
        modes: Option<i128>,
        dim: Option<i128>,
        axis: Option<[f64; 3]>,
        mm_per_unit: f64,
        coat_mm: Option<f64>,
        ignore_facets: bool,
    ) -> PyResult<Self> {
        use rollphase_core::geometry::mesh_fit::{FitOptions, coat, fit_mesh};
        if let Some(c) = coat_mm
            && !(c.is_finite() && c > 0.0)
        {
            return Err(crate::errors::input_error(format!(
                "coat_mm = {c} is not allowed (needs a positive thickness in mm, at most half the \
                 body's mean radius)"
            )));
        }
        use rollphase_core::geometry::mesh_read::MeshSource;
        let modes: Option<u32> = modes.map(|m| whole("modes", m)).transpose()?;
        let dim: Option<u32> = dim.map(|d| whole("dim", d)).transpose()?;
        let options = FitOptions {
            dim: if axis.is_some() { Some(2) } else { dim },
            modes,
            axis: axis.map(DVec3::from_array),
            mm_per_unit,
            ignore_facets,
            errors: true,
        };
        let fit = py
            .detach(|| {
                let source = MeshSource::open(&path)?;
                let fit = fit_mesh(&source, &options, &|_, _, _| {})?;
                match coat_mm {
                    Some(c) => coat(&fit, c, &|_, _, _| {}).map(|(coated, _)| coated),
                    None => Ok(fit),
                }
            })
            .map_err(bad_input)?;
        for w in &fit.report.warnings {
            pyo3::PyErr::warn(
                py,
                &py.get_type::<pyo3::exceptions::PyUserWarning>(),
                &std::ffi::CString::new(w.as_str()).unwrap_or_default(),
                1,
            )?;
        }
        let report = serde_json::to_string(&fit.report).map_err(internal_error)?;
        Ok(Body {
            body: fit.body,
            origin: format!(
                "mesh {} (fitted, l <= {})",
                path.display(),
                fit.report.modes
            ),
            scale_mm: fit.shape.scale_mm(),
            fit: Some(report),
        })
    }

    /// Millimetres per mean radius of the real object: set for a body fitted to a mesh or read
    /// from a shape file that has scale_mm; None otherwise.
    #[getter]
    fn scale_mm(&self) -> Option<f64> {
        self.scale_mm
    }

    /// The mesh fit's report (a dict: rms_residual, rms_residual_mm, max_residual,
    /// max_residual_mm, max_residual_at, l1_part, l1_offset_mm, scale_mm and its standard error
    /// scale_mm_error, modes, modes_rule, degree_residuals, convex, alpha_star with
    /// alpha_star_error and alpha_star_bias (how far the mesh's scatter raises a fit's α*),
    /// error_blocks, warnings, …) for a body from Body.from_mesh; None otherwise. The errors are
    /// None for a mesh too coarse to tell its scatter from its facets.
    #[getter]
    fn mesh_fit<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        match &self.fit {
            Some(text) => Ok(Some(py.import("json")?.call_method1("loads", (text,))?)),
            None => Ok(None),
        }
    }

    /// Writes the body as a shape file (JSON) that Body.from_file and the command line read.
    /// The file is written whole or not at all; a link stays a link.
    fn to_file(&self, path: PathBuf) -> PyResult<()> {
        if path.as_os_str() == "-" {
            return Err(input_error(
                "to_file needs a file path; \"-\" (standard output) is for the command line",
            ));
        }
        // Opening a FIFO for writing waits for a reader, holding the GIL and deaf to Ctrl-C;
        // a socket cannot be opened at all. Both are for streams: write body.to_json() there.
        {
            use std::os::unix::fs::FileTypeExt;
            if let Ok(m) = std::fs::metadata(&path)
                && (m.file_type().is_fifo() || m.file_type().is_socket())
            {
                return Err(input_error(format!(
                    "{} is a pipe or socket, not a file; to_file writes files (write \
                     body.to_json() to a stream yourself)",
                    path.display()
                )));
            }
        }
        let text = self
            .body
            .to_shape()
            .with_scale_mm(self.scale_mm)
            .to_json()
            .map_err(internal_error)?
            + "\n";
        output::write_bytes(&path, text.as_bytes(), &output::Inputs::none()).map_err(|e| match e {
            OutputError::Io { .. } | OutputError::Stdout(_) => PyOSError::new_err(e.to_string()),
            _ => input_error(e.to_string()),
        })
    }

    /// The critical angle α* = atan max |∇ ln r| (rad): below it a viscous body halts.
    #[getter]
    fn alpha_star(&self) -> f64 {
        self.body.alpha_star()
    }

    /// 2 for a disk, 3 for a sphere.
    #[getter]
    fn dimension(&self) -> u32 {
        self.body.dimension()
    }

    /// Whether the body is convex (the rolling models need it; runs refuse a non-convex body).
    #[getter]
    fn is_convex(&self) -> bool {
        self.body.is_convex()
    }

    /// The body's radius: for a disk r(θ) at each angle of an array of any shape (the same
    /// shape back); for a sphere r(u) at each direction of an (N, 3) array (normalised here;
    /// N radii back), or of one (3,) direction (one radius back, as a 0-d array).
    fn radius<'py>(
        &self,
        py: Python<'py>,
        points: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let points = points.as_array();
        if let Some(bad) = points.iter().find(|v| !v.is_finite()) {
            return Err(input_error(format!("radius: {bad} is not a finite number")));
        }
        match &self.body {
            CoreBody::Disk(disk) => Ok(points.mapv(|theta| disk.jet(theta).r).into_pyarray(py)),
            CoreBody::Sphere(sphere) => {
                let shape = points.shape();
                let (n, out_shape) = match shape {
                    [3] => (1, vec![]),
                    [n, 3] => (*n, vec![*n]),
                    _ => {
                        return Err(input_error(format!(
                            "radius of a sphere takes directions as an (N, 3) array (or one (3,) \
                             direction), not shape {shape:?}"
                        )));
                    }
                };
                let flat: Vec<f64> = points.iter().copied().collect();
                let mut radii = Vec::with_capacity(n);
                for (i, u) in flat.chunks_exact(3).enumerate() {
                    let u = DVec3::from_slice(u);
                    if u.length() < 1e-300 {
                        return Err(input_error(format!(
                            "radius: direction {i} is the zero vector, which has no direction"
                        )));
                    }
                    radii.push(sphere.radius(u.normalize()));
                }
                let out = ArrayD::from_shape_vec(IxDyn(&out_shape), radii)
                    .map_err(|e| input_error(e.to_string()))?;
                Ok(out.into_pyarray(py))
            }
        }
    }

    /// The shape file's JSON text.
    fn to_json(&self) -> PyResult<String> {
        self.body
            .to_shape()
            .with_scale_mm(self.scale_mm)
            .to_json()
            .map_err(internal_error)
    }

    fn __repr__(&self) -> String {
        format!(
            "<rollphase.Body: {}, alpha_star = {:.6}>",
            self.origin,
            self.body.alpha_star()
        )
    }
}
