//! `rollphase.simulate` and `rollphase.simulate_many`: one run, or many from an array of starts
//! in parallel, returned as a `Trajectory` of numpy arrays with the command line's summary.
//!
//! The start is built as `rollphase simulate` builds it from its flags (the same checks, named
//! by the Python argument), then the core's typed [`Simulation`] runs it: the numbers are the
//! command line's to the last digit.

use std::collections::BTreeMap;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use numpy::IntoPyArray;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{AllowTypeChange, PyArrayLikeDyn};
use pyo3::prelude::*;
use pyo3::pyclass::boolean_struct::True;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;
use rollphase_core::dynamics::{ContactForce, DragLaw};
use rollphase_core::geometry::Body as CoreBody;
use rollphase_core::glam::{DQuat, DVec3};
use rollphase_core::integrate::{Method, MethodKind, MethodParseError};
use rollphase_core::simulate::start::{Spelling, StartField, StartRequest, check_start};
use rollphase_core::simulate::{
    ContactLimits, InitialState, Model, OnViolation, Simulation, Summary, SummaryReport,
    Trajectory as CoreTrajectory, simulate_until,
};

use crate::body::Body;
use crate::errors::{Classified, input_error, internal_error, raise};
use crate::{interruptible, whole};

/// Beyond this many numbers in all a `simulate_many` result would not fit in memory on most
/// machines (8 bytes each, held twice while it is handed to numpy).
const MAX_VALUES: usize = 500_000_000;

/// What every run's samples have, as numpy arrays: t (sample times), and the ramp's force on
/// the body in units of the weight F: normal_force, friction (x downhill, y across; negative x
/// points uphill) and friction_needed, |friction|/normal_force (inf where the normal force is
/// ≤ 0). The base of `DiskTrajectory` and `SphereTrajectory` (simulate) and `SphereRuns`
/// (simulate_many); never made on its own.
#[pyclass(frozen, subclass, module = "rollphase", name = "Trajectory")]
pub struct Trajectory {
    columns: BTreeMap<&'static str, Py<PyAny>>,
    summary: Py<PyAny>,
    dimension: u32,
    order: &'static [&'static str],
}

/// The columns of each kind of trajectory, in the order `columns` lists them.
const DISK_COLUMNS: &[&str] = &[
    "t",
    "theta",
    "theta_dot",
    "psi",
    "x",
    "y",
    "normal_force",
    "friction",
    "friction_needed",
];
const SPHERE_COLUMNS: &[&str] = &[
    "t",
    "q",
    "contact",
    "omega",
    "com",
    "normal_force",
    "friction",
    "friction_needed",
];

impl Trajectory {
    /// A column this trajectory was made with: every getter of each subclass names one of its
    /// own columns, so a missing one is a bug.
    fn column(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        self.columns
            .get(name)
            .map(|c| c.clone_ref(py))
            .ok_or_else(|| internal_error(format!("the trajectory has no column {name}")))
    }

    /// The Python object: a `DiskTrajectory` or `SphereTrajectory` for one run, `SphereRuns`
    /// for many.
    fn into_python(self, py: Python<'_>, many: bool) -> PyResult<Py<PyAny>> {
        let dimension = self.dimension;
        let base = PyClassInitializer::from(self);
        Ok(match (many, dimension) {
            (true, _) => Py::new(py, base.add_subclass(SphereRuns))?.into_any(),
            (false, 3) => Py::new(py, base.add_subclass(SphereTrajectory))?.into_any(),
            (false, _) => Py::new(py, base.add_subclass(DiskTrajectory))?.into_any(),
        })
    }
}

/// A column of the `Trajectory` under a subclass's object.
fn column_of<T>(slf: &Bound<'_, T>, name: &str) -> PyResult<Py<PyAny>>
where
    T: pyo3::PyClass<BaseType = Trajectory, Frozen = True> + Sync,
{
    slf.as_super().get().column(slf.py(), name)
}

/// The `<rollphase.Kind: …>` text of a subclass's object.
fn repr_of<T>(slf: &Bound<'_, T>, kind: &str) -> PyResult<String>
where
    T: pyo3::PyClass<BaseType = Trajectory, Frozen = True> + Sync,
{
    let base = slf.as_super().get();
    let len = base.column(slf.py(), "t")?.bind(slf.py()).len()?;
    Ok(format!(
        "<rollphase.{kind}: {len} samples, columns {}>",
        base.order.join(", ")
    ))
}

#[pymethods]
impl Trajectory {
    /// Sample times (S,).
    #[getter]
    fn t(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.column(py, "t")
    }
    /// The ramp's normal force on the body, in units of the weight F: (S,), or (N, S) from
    /// simulate_many.
    #[getter]
    fn normal_force(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.column(py, "normal_force")
    }
    /// The ramp's tangential (friction) force, x downhill and y across: (S, 2), or (N, S, 2).
    #[getter]
    fn friction(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.column(py, "friction")
    }
    /// The coefficient of friction rolling needs, |friction|/normal_force; inf where the
    /// normal force is ≤ 0: (S,), or (N, S).
    #[getter]
    fn friction_needed(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.column(py, "friction_needed")
    }
    /// 2 for a disk, 3 for a sphere.
    #[getter]
    fn dimension(&self) -> u32 {
        self.dimension
    }
    /// The names of the columns this trajectory has, each an attribute.
    #[getter]
    fn columns(&self) -> Vec<&'static str> {
        self.order.to_vec()
    }
    /// The number of samples S.
    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        self.column(py, "t")?.bind(py).len()
    }
}

/// One disk's run (simulate on a 2D body): each column (S,). theta is the contact angle in the
/// body, theta_dot its rate, psi the body's rotation, x the centre of mass downhill and y its
/// height above the ramp.
#[pyclass(frozen, extends = Trajectory, module = "rollphase", name = "DiskTrajectory")]
pub struct DiskTrajectory;

#[pymethods]
impl DiskTrajectory {
    /// Contact angles θ in the body (S,).
    #[getter]
    fn theta(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "theta")
    }
    /// θ̇ (S,).
    #[getter]
    fn theta_dot(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "theta_dot")
    }
    /// The body's rotation ψ (S,).
    #[getter]
    fn psi(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "psi")
    }
    /// Centre of mass downhill (S,).
    #[getter]
    fn x(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "x")
    }
    /// Centre of mass height above the ramp (S,).
    #[getter]
    fn y(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "y")
    }
    /// The run's summary: the command line's --summary keys (RunSummary in the stubs).
    #[getter]
    fn summary(slf: &Bound<'_, Self>) -> Py<PyAny> {
        slf.as_super().get().summary.clone_ref(slf.py())
    }
    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        repr_of(slf, "DiskTrajectory")
    }
}

/// One sphere's run (simulate on a 3D body): q (S, 4) orientations w, x, y, z (body-to-lab,
/// Hamilton), contact (S, 3) the contact point as a body-frame unit vector, omega (S, 3) the
/// lab angular velocity, com (S, 3) the centre of mass (x downhill, z above the ramp).
#[pyclass(frozen, extends = Trajectory, module = "rollphase", name = "SphereTrajectory")]
pub struct SphereTrajectory;

#[pymethods]
impl SphereTrajectory {
    /// Orientations (S, 4), w, x, y, z.
    #[getter]
    fn q(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "q")
    }
    /// Contact points in the body frame (S, 3).
    #[getter]
    fn contact(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "contact")
    }
    /// Lab angular velocities (S, 3).
    #[getter]
    fn omega(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "omega")
    }
    /// Centres of mass (S, 3), x downhill, z above the ramp.
    #[getter]
    fn com(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "com")
    }
    /// The run's summary: the command line's --summary keys (RunSummary in the stubs).
    #[getter]
    fn summary(slf: &Bound<'_, Self>) -> Py<PyAny> {
        slf.as_super().get().summary.clone_ref(slf.py())
    }
    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        repr_of(slf, "SphereTrajectory")
    }
}

/// Many runs of one sphere (simulate_many), one row per start: t (S,) shared; q (N, S, 4),
/// contact, omega and com (N, S, 3), normal_force and friction_needed (N, S), friction
/// (N, S, 2); summaries, one per start.
#[pyclass(frozen, extends = Trajectory, module = "rollphase", name = "SphereRuns")]
pub struct SphereRuns;

#[pymethods]
impl SphereRuns {
    /// Orientations (N, S, 4), w, x, y, z.
    #[getter]
    fn q(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "q")
    }
    /// Contact points in the body frame (N, S, 3).
    #[getter]
    fn contact(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "contact")
    }
    /// Lab angular velocities (N, S, 3).
    #[getter]
    fn omega(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "omega")
    }
    /// Centres of mass (N, S, 3), x downhill, z above the ramp.
    #[getter]
    fn com(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        column_of(slf, "com")
    }
    /// Each run's summary, in the order of the starts (a list of RunSummary).
    #[getter]
    fn summaries(slf: &Bound<'_, Self>) -> Py<PyAny> {
        slf.as_super().get().summary.clone_ref(slf.py())
    }
    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let runs = column_of(slf, "q")?.bind(slf.py()).len()?;
        Ok(format!(
            "{} from {runs} starts>",
            repr_of(slf, "SphereRuns")?.trim_end_matches('>')
        ))
    }
}

/// The integrator named `name` with its settings, read and checked by the core's one parser
/// (the command line's, scenes' and sweep specs' names and messages).
fn method(name: &str, rtol: f64, atol: Option<f64>, dt: f64) -> PyResult<Method> {
    let kind: MethodKind = name
        .parse()
        .map_err(|e: MethodParseError| input_error(format!("integrator={e}")))?;
    kind.with(rtol, atol, dt).map_err(raise)
}

fn finite_list(name: &str, v: &[f64], n: usize, names: &str) -> PyResult<Vec<f64>> {
    if v.len() != n {
        return Err(input_error(format!(
            "{name} expects {n} numbers {names}, got {}",
            v.len()
        )));
    }
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        return Err(input_error(format!(
            "{name}: {bad} is not a finite number (expected {names})"
        )));
    }
    Ok(v.to_vec())
}

/// The start arguments of `simulate`, as the command line's flags.
pub struct StartArgs {
    pub mass_ratio: f64,
    pub q0: Option<Vec<f64>>,
    pub contact: Option<Vec<f64>>,
    pub spin: Option<f64>,
    pub omega0: Option<Vec<f64>>,
    pub theta0: Option<f64>,
    pub theta_dot0: Option<f64>,
}

/// Python's names of the start's fields, for the core's messages: the core's own names.
fn argument(f: StartField) -> &'static str {
    f.name()
}

/// The initial state, checked by the core as the command line's is ([`check_start`]).
fn initial_state(py: Python<'_>, a: &StartArgs, body: &CoreBody) -> PyResult<InitialState> {
    let list = |v: &Option<Vec<f64>>, n: usize, f: StartField, names: &str| {
        v.as_deref()
            .map(|v| finite_list(argument(f), v, n, names))
            .transpose()
    };
    let q0 = list(&a.q0, 4, StartField::Q0, "w, x, y, z")?;
    let contact = list(&a.contact, 2, StartField::Contact, "θ, φ")?;
    let omega0 = list(&a.omega0, 3, StartField::Omega0, "x, y, z")?;
    let request = StartRequest {
        q0: q0.map(|v| [v[0], v[1], v[2], v[3]]),
        contact: contact.map(|v| [v[0], v[1]]),
        spin: a.spin,
        omega0: omega0.map(|v| [v[0], v[1], v[2]]),
        theta0: a.theta0,
        theta_dot0: a.theta_dot0,
    };
    checked_start(py, body, a.mass_ratio, &request)
}

/// [`check_start`] with Python's argument names, warning when θ0 is reduced (`simulate`,
/// `simulate_many` and `period`).
pub(crate) fn checked_start(
    py: Python<'_>,
    body: &CoreBody,
    mass_ratio: f64,
    request: &StartRequest,
) -> PyResult<InitialState> {
    let spelling = Spelling {
        field: argument,
        mass: "mass_ratio",
        viscous: "mass_ratio=0",
        body: "this body",
    };
    let start =
        check_start(body, mass_ratio, request).map_err(|e| input_error(e.explain(&spelling)))?;
    if let Some((given, reduced)) = start.reduced_theta0 {
        let message = std::ffi::CString::new(format!(
            "theta0 {given:e} reduced modulo 2π to {reduced} (beyond ±1e6 rad an angle has too \
             few digits left to advance)"
        ))
        .unwrap_or_default();
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        PyErr::warn(py, category.as_any(), &message, 1)?;
    }
    Ok(start.initial)
}

/// The summary as the command line's `--summary` JSON ([`SummaryReport`]), as a dict.
fn summary_dict<'py>(
    py: Python<'py>,
    summary: &Summary,
    wall: f64,
    alpha: f64,
    mass_ratio: f64,
    law: DragLaw,
) -> PyResult<Bound<'py, PyDict>> {
    let report = SummaryReport::new(summary.clone(), wall, alpha, mass_ratio, law);
    let value = serde_json::to_value(&report).map_err(internal_error)?;
    let d = PyDict::new(py);
    if let serde_json::Value::Object(map) = value {
        for (k, v) in map {
            d.set_item(k, json_to_py(py, &v)?)?;
        }
    }
    Ok(d)
}

/// A JSON value as the Python value `json.loads` would give.
pub(crate) fn json_to_py(py: Python<'_>, v: &serde_json::Value) -> PyResult<Py<PyAny>> {
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None(),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any().unbind(),
        Value::Number(n) => match n.as_u64() {
            Some(u) => u.into_pyobject(py)?.into_any().unbind(),
            None => n
                .as_f64()
                .unwrap_or(f64::NAN)
                .into_pyobject(py)?
                .into_any()
                .unbind(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        Value::Array(a) => {
            let items: Vec<Py<PyAny>> = a
                .iter()
                .map(|x| json_to_py(py, x))
                .collect::<PyResult<_>>()?;
            PyList::new(py, items)?.into_any().unbind()
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any().unbind()
        }
    })
}

fn flat3(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

fn flat4(v: &[DQuat]) -> Vec<f64> {
    v.iter().flat_map(|q| [q.w, q.x, q.y, q.z]).collect()
}

/// The surface from simulate's friction and on_invalid arguments.
fn contact_limits(friction: Option<f64>, on_invalid: &str) -> PyResult<ContactLimits> {
    let on_violation = match on_invalid {
        "warn" => OnViolation::Warn,
        "stop" => OnViolation::Stop,
        other => {
            return Err(input_error(format!(
                "on_invalid={other:?} is not one of \"warn\" (go on, with a RuntimeWarning and \
                 the summary's lift_off_t / slip_t) or \"stop\" (raise LeftModelError at the first \
                 lift-off or slip)"
            )));
        }
    };
    let limits = ContactLimits {
        friction,
        on_violation,
    };
    limits.validate().map_err(input_error)?;
    Ok(limits)
}

/// A RuntimeWarning for each way a run left the rolling model (on_invalid="warn").
fn warn_validity(py: Python<'_>, summary: &Summary, which: &str) -> PyResult<()> {
    for w in summary.validity_warnings() {
        let message = std::ffi::CString::new(format!("{which}the body {w}")).unwrap_or_default();
        let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
        PyErr::warn(py, category.as_any(), &message, 1)?;
    }
    Ok(())
}

/// The force columns: normal (S,), friction (S, 2) flattened, friction needed (S,).
fn force_columns(f: &[ContactForce]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    (
        f.iter().map(|f| f.normal).collect(),
        f.iter().flat_map(|f| f.friction).collect(),
        f.iter().map(ContactForce::friction_needed).collect(),
    )
}

fn arr1(py: Python<'_>, v: Vec<f64>) -> Py<PyAny> {
    Array1::from_vec(v).into_pyarray(py).into_any().unbind()
}

fn arr2(py: Python<'_>, v: Vec<f64>, n: usize, k: usize) -> PyResult<Py<PyAny>> {
    Ok(Array2::from_shape_vec((n, k), v)
        .map_err(internal_error)?
        .into_pyarray(py)
        .into_any()
        .unbind())
}

fn arr3(py: Python<'_>, v: Vec<f64>, shape: (usize, usize, usize)) -> PyResult<Py<PyAny>> {
    Ok(Array3::from_shape_vec(shape, v)
        .map_err(internal_error)?
        .into_pyarray(py)
        .into_any()
        .unbind())
}

/// Simulates one run of `body` on a ramp at angle `alpha` (rad) from t = 0 to `t_end`.
///
/// mass_ratio: m/m0; 0 is the viscous model (first order), > 0 the inertial one.
/// Start (sphere): q0 = (w, x, y, z), or contact = (θ, φ) (the body point at polar angle θ,
/// azimuth φ put on the ramp) then turned by spin (rad) about the ramp's normal; by default the
/// south pole touches, turned by spin; omega0 = (x, y, z) for an inertial run (default at rest).
/// Start (disk): theta0 (contact angle, default 0), theta_dot0 (inertial only).
/// integrator: "dop853" (rtol, atol = rtol by default), "rk4" or "cf4" (fixed step dt).
/// samples: equally spaced samples from 0 to t_end inclusive.
/// Returns a Trajectory (numpy arrays) with .summary, the command line's --summary keys; the
/// numbers equal `rollphase simulate`'s to the last digit. Ctrl-C stops it (KeyboardInterrupt).
/// Further keywords are the drag law's parameters by their keys (`drag_parameters()` lists
/// them, with their ranges and what they mean).
#[pyfunction]
#[pyo3(signature = (body, alpha, t_end, *, mass_ratio = 0.0, q0 = None, contact = None, spin = None,
    omega0 = None, theta0 = None, theta_dot0 = None, integrator = "dop853", rtol = 1e-10,
    atol = None, dt = 0.01, samples = 1001, drag = 1.0, max_steps = 100_000_000, friction = None,
    on_invalid = "warn", **drag_law))]
pub fn simulate(
    py: Python<'_>,
    body: &Body,
    alpha: f64,
    t_end: f64,
    mass_ratio: f64,
    q0: Option<Vec<f64>>,
    contact: Option<Vec<f64>>,
    spin: Option<f64>,
    omega0: Option<Vec<f64>>,
    theta0: Option<f64>,
    theta_dot0: Option<f64>,
    integrator: &str,
    rtol: f64,
    atol: Option<f64>,
    dt: f64,
    samples: i128,
    drag: f64,
    max_steps: i128,
    friction: Option<f64>,
    on_invalid: &str,
    drag_law: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let (samples, max_steps): (usize, u64) = (
        crate::sample_count(samples)?,
        whole("max_steps", max_steps)?,
    );
    let core = &body.body;
    let method = method(integrator, rtol, atol, dt)?;
    let limits = contact_limits(friction, on_invalid)?;
    let law = crate::drag_law::from_keywords("simulate", drag_law)?;
    let start = StartArgs {
        mass_ratio,
        q0,
        contact,
        spin,
        omega0,
        theta0,
        theta_dot0,
    };
    let initial = initial_state(py, &start, core)?;
    let mut sim = Simulation::new(alpha, t_end)
        .model(Model::from_mass_ratio(mass_ratio))
        .drag(drag)
        .drag_law(law)
        .method(method)
        .samples(samples)
        .initial(initial)
        .limits(limits);
    sim.max_steps = max_steps;
    // Every argument is checked (the ramp, the sampling, the step) before the worker starts.
    sim.spec(core).map_err(raise)?;
    let clock = Instant::now();
    let (trajectory, summary) =
        interruptible(py, |stop| simulate_until(core, &sim, stop))?.map_err(raise)?;
    let wall = clock.elapsed().as_secs_f64();
    warn_validity(py, &summary, "")?;
    let summary = summary_dict(py, &summary, wall, alpha, mass_ratio, law)?;
    let mut columns = BTreeMap::new();
    let n = trajectory.len();
    let (normal, friction, needed) = force_columns(trajectory.forces());
    columns.insert("normal_force", arr1(py, normal));
    columns.insert("friction", arr2(py, friction, n, 2)?);
    columns.insert("friction_needed", arr1(py, needed));
    match trajectory {
        CoreTrajectory::Sphere(s) => {
            let n = s.t.len();
            columns.insert("t", arr1(py, s.t));
            columns.insert("q", arr2(py, flat4(&s.q), n, 4)?);
            columns.insert("contact", arr2(py, flat3(&s.contact), n, 3)?);
            columns.insert("omega", arr2(py, flat3(&s.omega), n, 3)?);
            columns.insert("com", arr2(py, flat3(&s.com), n, 3)?);
        }
        CoreTrajectory::Disk(d) => {
            columns.insert("t", arr1(py, d.t));
            columns.insert("theta", arr1(py, d.theta));
            columns.insert("theta_dot", arr1(py, d.theta_dot));
            columns.insert("psi", arr1(py, d.psi));
            columns.insert("x", arr1(py, d.x));
            columns.insert("y", arr1(py, d.y));
        }
    }
    let order = if core.dimension() == 3 {
        SPHERE_COLUMNS
    } else {
        DISK_COLUMNS
    };
    Trajectory {
        columns,
        summary: summary.into_any().unbind(),
        dimension: core.dimension(),
        order,
    }
    .into_python(py, false)
}

/// Simulates a sphere from each orientation of `q0s`, an (N, 4) array of quaternions w, x, y,
/// z (normalised, as simulate's q0), in parallel with the GIL released. The other arguments are
/// simulate's, the same for every run. Returns one Trajectory whose arrays are stacked: t (S,),
/// q (N, S, 4), contact, omega and com (N, S, 3), and .summary a list of N dicts. Each run
/// equals simulate(body, alpha, t_end, q0=q0s[i], …). Ctrl-C stops it (KeyboardInterrupt).
/// Further keywords are the drag law's parameters by their keys (`drag_parameters()` lists
/// them, with their ranges and what they mean).
#[pyfunction]
#[pyo3(signature = (body, alpha, t_end, *, q0s, mass_ratio = 0.0, omega0 = None,
    integrator = "dop853", rtol = 1e-10, atol = None, dt = 0.01, samples = 1001, drag = 1.0,
    max_steps = 100_000_000, friction = None, on_invalid = "warn", **drag_law))]
pub fn simulate_many(
    py: Python<'_>,
    body: &Body,
    alpha: f64,
    t_end: f64,
    q0s: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
    mass_ratio: f64,
    omega0: Option<Vec<f64>>,
    integrator: &str,
    rtol: f64,
    atol: Option<f64>,
    dt: f64,
    samples: i128,
    drag: f64,
    max_steps: i128,
    friction: Option<f64>,
    on_invalid: &str,
    drag_law: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let (samples, max_steps): (usize, u64) = (
        crate::sample_count(samples)?,
        whole("max_steps", max_steps)?,
    );
    let limits = contact_limits(friction, on_invalid)?;
    let law = crate::drag_law::from_keywords("simulate_many", drag_law)?;
    let core = &body.body;
    if !matches!(core, CoreBody::Sphere(_)) {
        return Err(input_error(
            "simulate_many runs a sphere from many orientations; this body is a 2D disk (call \
             simulate for each theta0)",
        ));
    }
    let q0s = crate::two_dimensional(
        "q0s",
        "(N, 4) array of quaternions w, x, y, z",
        q0s.as_array(),
    )?;
    let (n, width) = q0s.dim();
    if width != 4 {
        return Err(input_error(format!(
            "q0s must be an (N, 4) array of quaternions w, x, y, z, not shape ({n}, {width})"
        )));
    }
    if n == 0 {
        return Err(input_error("q0s is empty: give at least one start"));
    }
    let values = n.saturating_mul(samples).saturating_mul(18);
    if values > MAX_VALUES {
        return Err(input_error(format!(
            "{n} runs × {samples} samples would return {values:.3e} numbers ({:.1} GB), more \
             than the {MAX_VALUES:.0e} allowed; use fewer samples or split the starts",
            values as f64 * 8e-9
        )));
    }
    let method = method(integrator, rtol, atol, dt)?;
    let mut sims = Vec::with_capacity(n);
    for (i, row) in q0s.outer_iter().enumerate() {
        let start = StartArgs {
            mass_ratio,
            q0: Some(row.to_vec()),
            contact: None,
            spin: None,
            omega0: omega0.clone(),
            theta0: None,
            theta_dot0: None,
        };
        let initial = initial_state(py, &start, core)
            .map_err(|e| input_error(format!("q0s[{i}]: {}", e.value(py))))?;
        let mut sim = Simulation::new(alpha, t_end)
            .model(Model::from_mass_ratio(mass_ratio))
            .drag(drag)
            .drag_law(law)
            .method(method)
            .samples(samples)
            .initial(initial)
            .limits(limits);
        sim.max_steps = max_steps;
        sims.push(sim);
    }
    sims[0].spec(core).map_err(raise)?;
    let results = interruptible(py, |stop: &AtomicBool| {
        sims.par_iter()
            .enumerate()
            .map(|(i, sim)| {
                let started = Instant::now();
                simulate_until(core, sim, stop)
                    .map(|r| (r, started.elapsed().as_secs_f64()))
                    .map_err(|e| (i, e))
            })
            .collect::<Result<Vec<_>, _>>()
    })?;
    let runs =
        results.map_err(|(i, e)| e.class().err(format!("the run from q0s[{i}] failed: {e}")))?;
    let s = samples;
    let mut t = Vec::new();
    let (mut q, mut contact, mut omega, mut com) = (
        Vec::with_capacity(n * s * 4),
        Vec::with_capacity(n * s * 3),
        Vec::with_capacity(n * s * 3),
        Vec::with_capacity(n * s * 3),
    );
    let (mut normal, mut friction, mut needed) = (
        Vec::with_capacity(n * s),
        Vec::with_capacity(n * s * 2),
        Vec::with_capacity(n * s),
    );
    let summaries = PyList::empty(py);
    for (i, ((trajectory, summary), wall)) in runs.into_iter().enumerate() {
        let (a, b, c) = force_columns(trajectory.forces());
        normal.extend(a);
        friction.extend(b);
        needed.extend(c);
        warn_validity(py, &summary, &format!("the run from q0s[{i}]: "))?;
        let CoreTrajectory::Sphere(path) = trajectory else {
            unreachable!("a sphere's runs are sphere trajectories")
        };
        if t.is_empty() {
            t = path.t.clone();
        }
        q.extend(flat4(&path.q));
        contact.extend(flat3(&path.contact));
        omega.extend(flat3(&path.omega));
        com.extend(flat3(&path.com));
        summaries.append(summary_dict(py, &summary, wall, alpha, mass_ratio, law)?)?;
    }
    let mut columns = BTreeMap::new();
    columns.insert("t", arr1(py, t));
    columns.insert("q", arr3(py, q, (n, s, 4))?);
    columns.insert("contact", arr3(py, contact, (n, s, 3))?);
    columns.insert("omega", arr3(py, omega, (n, s, 3))?);
    columns.insert("com", arr3(py, com, (n, s, 3))?);
    columns.insert("normal_force", arr2(py, normal, n, s)?);
    columns.insert("friction", arr3(py, friction, (n, s, 2))?);
    columns.insert("friction_needed", arr2(py, needed, n, s)?);
    Trajectory {
        columns,
        summary: summaries.into_any().unbind(),
        dimension: 3,
        order: SPHERE_COLUMNS,
    }
    .into_python(py, true)
}
