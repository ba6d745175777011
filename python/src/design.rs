//! `rollphase.design`: a printable body with a chosen α*, hysteresis window or period doubling,
//! and `rollphase.check_design`, what a design would say of a body you have; the core's
//! `analysis::design` (the search, then the check over the bench's band), run with the GIL
//! released, its report the command line's `--json`.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use rollphase_core::analysis::design::{
    Band, DEFAULT_SCALE_MM, DesignError, DesignOptions, DesignSpace, Spelling, Target, TargetError,
    TargetRequest, check_budget, design_until, evaluate, with_budget,
};

use crate::body::Body;
use crate::errors::{Classified, ErrorClass, internal_error, raise};
use crate::run::json_to_py;
use crate::{interruptible, whole};

impl Classified for TargetError {
    fn class(&self) -> ErrorClass {
        match self {
            TargetError::Integrate(e) => e.class(),
            TargetError::Study(e) => e.class(),
            TargetError::NotACylinder | TargetError::NotASphere | TargetError::Model(_) => {
                ErrorClass::Input
            }
            TargetError::NoOrbit { .. } | TargetError::NeverRolled { .. } => ErrorClass::Run,
        }
    }
}

impl Classified for DesignError {
    fn class(&self) -> ErrorClass {
        match self {
            DesignError::BadInput { .. } | DesignError::Request(_) | DesignError::Shape(_) => {
                ErrorClass::Input
            }
            DesignError::Target(e) => e.class(),
            DesignError::Optimiser(_) => ErrorClass::Internal,
        }
    }
}

/// The targets the keywords name.
fn targets(request: &TargetRequest) -> PyResult<Vec<Target>> {
    request
        .targets(&Spelling {
            alpha: "alpha=",
            mass: "mass_ratio",
            share: "share",
            targets: "alpha_star=, hysteresis=(M, F), or doubling=, drift= or orbits= with alpha=",
        })
        .map_err(raise)
}

/// The request from the keywords shared by design() and check_design().
#[allow(clippy::too_many_arguments)]
fn request(
    alpha_star: Option<f64>,
    hysteresis: Option<(f64, f64)>,
    doubling: Option<f64>,
    drift: Option<f64>,
    orbits: Option<i128>,
    share: Option<f64>,
    mass_ratio: Option<f64>,
    alpha: Option<f64>,
) -> PyResult<TargetRequest> {
    Ok(TargetRequest {
        alpha_star,
        hysteresis,
        doubling,
        drift,
        orbits: orbits.map(|k| whole("orbits", k)).transpose()?,
        share,
        mass: mass_ratio,
        alpha,
    })
}

/// The check's band from the keywords.
fn band(
    alpha_band: f64,
    mass_band: f64,
    surface_mm: f64,
    draws: i128,
    seed: i128,
) -> PyResult<Band> {
    Ok(Band {
        delta_alpha: alpha_band,
        mass_fraction: mass_band,
        surface_mm,
        draws: whole("draws", draws)?,
        seed: whole("seed", seed)?,
    })
}

/// The body and the report, as `rollphase design --json` prints it.
fn result<'py>(
    py: Python<'py>,
    design: rollphase_core::analysis::design::Design,
    scale_mm: f64,
    what: String,
) -> PyResult<(Body, Bound<'py, PyDict>)> {
    let report = PyDict::new(py);
    report.set_item("holds", design.holds())?;
    report.set_item("why_not", design.why_not(&|s| format!("{s}=")))?;
    report.set_item("scale_mm", scale_mm)?;
    let value = serde_json::to_value(&design).map_err(internal_error)?;
    report.set_item("design", json_to_py(py, &value)?)?;
    Ok((Body::designed(design.body, scale_mm, what), report))
}

/// A printable body that does what the targets say, as `rollphase design` finds it: alpha_star
/// (α* in rad within 1e-4), hysteresis=(M, F) (2D: at m/m0 = M it keeps rolling down to F·α*),
/// doubling=M with alpha=A (3D: period 2 at m/m0 = M on a ramp at A rad), drift=D with alpha=A
/// and mass_ratio (3D: every stable orbit moves D across per unit down), orbits=K with alpha=A
/// and mass_ratio (3D: exactly K stable orbits, each reached from at least `share` of the
/// starts, default 1/(2K)). The search (CMA-ES,
/// seeded: the same body for any thread count) keeps the body convex, its radii of curvature
/// ≥ min_radius_mm at scale_mm mm per ⟨r⟩ (default: the start body's own, else 10) and its amplitudes ≤ max_amplitude, starting from
/// `start` (a Body) or the first convex random body from `seed`; the body found is then checked
/// at the precise setting over α ± alpha_band, m/m0 ± mass_band × m/m0 and `draws` print errors of
/// ± surface_mm. Returns (Body, report): report["holds"] says whether every target holds over
/// the band, and report["why_not"] why not (one reason each, as `rollphase design` gives them); report["design"] has the achieved values, margins, constraints (and which bind),
/// the check, for doubling the flip window and multipliers, and in "predicted" what the body
/// does on each target's ramp in mm and s at scale_mm. A design that does not hold
/// is returned too, not raised: read report["holds"]. budget (seconds, as `--budget`) ends the
/// search early with the best body so far, checked as any other (report["design"]["ended"] is
/// "stopped"); Ctrl+C raises KeyboardInterrupt.
#[pyfunction]
// Literal defaults, as Python's signature shows them: the core's DEFAULT_MODES, DEFAULT_SEED,
// DEFAULT_GENERATIONS, DEFAULT_MIN_RADIUS_MM, DEFAULT_MAX_AMPLITUDE and DEFAULT_BAND, which
// `rollphase design`'s flags use (python/tests/test_design.py holds the two equal).
#[pyo3(signature = (dim, *, alpha_star = None, hysteresis = None, doubling = None, drift = None,
    orbits = None, share = None, mass_ratio = None, alpha = None, modes = 4, scale_mm = None,
    min_radius_mm = 0.4, max_amplitude = 1.0, start = None, seed = 1, generations = 400,
    alpha_band = 0.005, mass_band = 0.2, surface_mm = 0.05, draws = 16, budget = None))]
pub fn design<'py>(
    py: Python<'py>,
    dim: i128,
    alpha_star: Option<f64>,
    hysteresis: Option<(f64, f64)>,
    doubling: Option<f64>,
    drift: Option<f64>,
    orbits: Option<i128>,
    share: Option<f64>,
    mass_ratio: Option<f64>,
    alpha: Option<f64>,
    modes: i128,
    scale_mm: Option<f64>,
    min_radius_mm: f64,
    max_amplitude: f64,
    start: Option<PyRef<'py, Body>>,
    seed: i128,
    generations: i128,
    alpha_band: f64,
    mass_band: f64,
    surface_mm: f64,
    draws: i128,
    budget: Option<f64>,
) -> PyResult<(Body, Bound<'py, PyDict>)> {
    // A refined body keeps the scale its file was printed at unless scale_mm is given.
    let scale_mm = scale_mm
        .or(start.as_ref().and_then(|b| b.scale_mm))
        .unwrap_or(DEFAULT_SCALE_MM);
    let options = DesignOptions {
        space: DesignSpace {
            dimension: whole("dim", dim)?,
            modes: whole("modes", modes)?,
        },
        targets: targets(&request(
            alpha_star, hysteresis, doubling, drift, orbits, share, mass_ratio, alpha,
        )?)?,
        scale_mm,
        min_radius_mm,
        max_amplitude,
        start: start.as_ref().map(|b| b.body.clone()),
        seed: whole("seed", seed)?,
        max_generations: whole("generations", generations)?,
        band: band(alpha_band, mass_band, surface_mm, draws, seed)?,
    };
    options.validate().map_err(raise)?;
    check_budget(budget).map_err(raise)?;
    let found = interruptible(py, |stop| {
        with_budget(stop, budget, || design_until(&options, stop, &|_| {}))
    })?
    .map_err(raise)?;
    result(py, found, scale_mm, format!("designed (seed {seed})"))
}

/// What `design` says of a body you have, without a search (`rollphase design --check-only`):
/// the same keywords as design(), `body` in place of start; scale_mm defaults to the body's own
/// (a shape file's or a mesh fit's), else 10. Returns (Body, report) as design().
#[pyfunction]
#[pyo3(signature = (body, *, alpha_star = None, hysteresis = None, doubling = None, drift = None,
    orbits = None, share = None, mass_ratio = None, alpha = None, scale_mm = None,
    min_radius_mm = 0.4, max_amplitude = 1.0, alpha_band = 0.005, mass_band = 0.2,
    surface_mm = 0.05, draws = 16, seed = 1))]
pub fn check_design<'py>(
    py: Python<'py>,
    body: PyRef<'py, Body>,
    alpha_star: Option<f64>,
    hysteresis: Option<(f64, f64)>,
    doubling: Option<f64>,
    drift: Option<f64>,
    orbits: Option<i128>,
    share: Option<f64>,
    mass_ratio: Option<f64>,
    alpha: Option<f64>,
    scale_mm: Option<f64>,
    min_radius_mm: f64,
    max_amplitude: f64,
    alpha_band: f64,
    mass_band: f64,
    surface_mm: f64,
    draws: i128,
    seed: i128,
) -> PyResult<(Body, Bound<'py, PyDict>)> {
    let core = body.body.clone();
    let scale_mm = scale_mm.or(body.scale_mm).unwrap_or(DEFAULT_SCALE_MM);
    let options = DesignOptions {
        space: DesignSpace::of(&core),
        targets: targets(&request(
            alpha_star, hysteresis, doubling, drift, orbits, share, mass_ratio, alpha,
        )?)?,
        scale_mm,
        min_radius_mm,
        max_amplitude,
        start: Some(core),
        seed: whole("seed", seed)?,
        max_generations: 1,
        band: band(alpha_band, mass_band, surface_mm, draws, seed)?,
    }
    .for_check()
    .map_err(raise)?;
    let checked = interruptible(py, |_| evaluate(&options))?.map_err(raise)?;
    result(py, checked, scale_mm, "checked".into())
}
