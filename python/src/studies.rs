//! The paper's analyses from Python with plain arguments: α*, the 2D period, the Poincaré map
//! on ∂Ω, the cruising fraction, the period-1 orbits with their Floquet multipliers, the
//! period-doubling statistics and the orbit diagram in m/m0 (`mass_bifurcation`). Each is the
//! core's function of the same name (`rollphase_core::analysis`), run with the GIL released and
//! stopped by Ctrl-C.

use numpy::ndarray::{Array1, Array2};
use numpy::{AllowTypeChange, Complex64, IntoPyArray, PyArray1, PyArray2, PyArrayLikeDyn};
use pyo3::exceptions::PyRuntimeWarning;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rollphase_core::analysis::orbits::orbit_diagram::{
    DirectRuns, RunWindow, mass_bifurcation_until,
};
use rollphase_core::analysis::orbits::sphere_orbits::Decide;
use rollphase_core::analysis::orbits::sphere_return_map::PeriodicOrbit;
use rollphase_core::analysis::studies::sphere::{
    cruising_fraction_until, period_counts_until, periodic_orbits_until, poincare_map_until,
};
use rollphase_core::analysis::verdict::Fate;
use rollphase_core::dynamics::Ramp;
use rollphase_core::geometry::Body as CoreBody;
use rollphase_core::glam::DVec3;
use rollphase_core::integrate::MAX_SPAN;
use rollphase_core::simulate::InitialState;
use rollphase_core::simulate::period::PeriodPlan;
use rollphase_core::simulate::start::StartRequest;

use crate::body::Body;
use crate::errors::{ErrorClass, input_error, internal_error, raise};
use crate::run::checked_start;
use crate::{interruptible, whole};

/// The critical angle α* = atan max |∇ ln r| of `body` (rad): a viscous body released at
/// α ≤ α* comes to rest; above it a disk rolls for ever. The same as body.alpha_star.
#[pyfunction]
pub fn critical_angle(body: &Body) -> f64 {
    body.body.alpha_star()
}

/// The period T of a disk rolling at ramp angle `alpha` (rad): the time for its contact angle
/// to advance 2π, or None when it comes to rest. mass_ratio = 0 (viscous): T = ∫ dθ/θ̇ by
/// adaptive quadrature, and the disk halts iff α ≤ α*. mass_ratio > 0 (inertial): simulated
/// from (theta0, theta_dot0) until successive periods agree to 1e-8, at most t_max; with
/// inertia a disk can keep rolling below α* (hysteresis). Where T is not measurable (too close
/// to α*, or no steady period by t_max) it returns nan with a RuntimeWarning saying why. The
/// same numbers as `rollphase period`.
/// Further keywords are the drag law's parameters by their keys (`drag_parameters()` lists
/// them, with their ranges and what they mean).
#[pyfunction]
#[pyo3(signature = (body, alpha, *, mass_ratio = 0.0, theta0 = 0.0, theta_dot0 = 0.0,
    t_max = 5000.0, rtol = 1e-10, **drag_law))]
pub fn period(
    py: Python<'_>,
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    theta0: f64,
    theta_dot0: f64,
    t_max: f64,
    rtol: f64,
    drag_law: Option<&Bound<'_, PyDict>>,
) -> PyResult<Option<f64>> {
    let CoreBody::Disk(_) = body.rollable()? else {
        return Err(input_error(
            "this body is a 3D sphere; period is for disks. A sphere's orbits are found by \
             simulation: use simulate, or periodic_orbits",
        ));
    };
    let ramp = Ramp::new(alpha, mass_ratio)
        .map_err(raise)?
        .with_drag_law(crate::drag_law::from_keywords("period", drag_law)?);
    if !(t_max.is_finite() && t_max > 0.0 && t_max <= MAX_SPAN) {
        return Err(input_error(format!(
            "t_max = {t_max} is not allowed (needs 0 < t_max ≤ {MAX_SPAN:e}: past that the \
             integrator's smallest step, 16 ε × t_max, exceeds the steps an orbit needs)"
        )));
    }
    // The start checked as `simulate` checks it: theta_dot0 with mass_ratio=0 is an error, not
    // ignored (the viscous period does not depend on where the disk starts).
    let request = StartRequest {
        theta0: Some(theta0),
        theta_dot0: Some(theta_dot0).filter(|v| *v != 0.0),
        ..StartRequest::default()
    };
    let InitialState::Disk { theta0, theta_dot0 } =
        checked_start(py, &body.body, mass_ratio, &request)?
    else {
        return Err(input_error("period is for a 2D disk"));
    };
    // The model as the command line chooses it (the viscous limit at m/m0 ≤ rtol). Ctrl-C sets
    // the stop flag: a stiff run (m/m0 = 1e-9) ends at once instead of after minutes. A stopped
    // run's outcome is never read: the interrupt is raised instead.
    let plan = PeriodPlan::new(&body.body, ramp, rtol).map_err(raise)?;
    // What the command line says before and after the run, as warnings here: a stiff run's
    // cost, the viscous limit taken, a period known to less than 1e-9.
    let warn = |text: String| -> PyResult<()> {
        let message = std::ffi::CString::new(text).unwrap_or_default();
        PyErr::warn(py, py.get_type::<PyRuntimeWarning>().as_any(), &message, 1)
    };
    if plan.model.is_inertial()
        && rollphase_core::simulate::is_stiff_run(&body.body, &plan.ramp, t_max)
    {
        warn(format!(
            "mass_ratio = {mass_ratio:?} relaxes to the viscous model on τ ≈ {:.1e}, which an \
             explicit integrator must follow: about {:.0e} right-hand-side evaluations over t_max \
             = {t_max} (minutes or more). mass_ratio=0 runs the viscous limit, which differs by \
             O(m/m0); an rtol above m/m0 chooses it for you",
            rollphase_core::simulate::relaxation_time(&body.body, &plan.ramp),
            rollphase_core::simulate::stiff_work_estimate(&body.body, &plan.ramp, t_max),
        ))?;
    }
    if let Some(note) = &plan.note {
        warn(note.clone())?;
    }
    let p = interruptible(py, move |stop| plan.run(theta0, theta_dot0, t_max, stop))?
        .map_err(raise)?
        .ok_or_else(|| ErrorClass::Run.err("the period run was stopped"))?;
    // The fate decides, as `rollphase period` decides it: a period still changing when the run
    // ends is a transient, undecided, never returned as T.
    let fate = p.fate;
    if let Some(caveat) = &p.caveat {
        warn(caveat.clone())?;
    }
    match (fate, p.period) {
        (Fate::Periodic { .. }, Some(t)) => Ok(Some(t)),
        (Fate::Halted { .. }, _) => Ok(None),
        (fate, _) => {
            let why = match fate {
                Fate::Undecided { why } => format!(
                    "{}{}",
                    why.what_would_decide(),
                    rollphase_core::analysis::orbits::disk_period::coarse_rtol_hint(
                        &why, rtol, "rtol ="
                    )
                ),
                _ => "no period was found".to_string(),
            };
            warn(format!("T is undecided: {why}"))?;
            Ok(Some(f64::NAN))
        }
    }
}

/// poincare_map's (ends, times).
type MapImages<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// The viscous Poincaré map P on ∂Ω, the boundary of the SO(3) ball (rotations by π), at ramp
/// angle `alpha`. starts: an (N, 4) array of quaternions w, x, y, z with w = 0 (points of ∂Ω;
/// the vector part is normalised here). Returns (ends, times): ends (N, 4), the next crossing
/// of ∂Ω from each start (w = 0, the sign nearest the start, since q and −q are one
/// orientation), and times (N,), the time to it; rows of nan where the body comes to rest first
/// or does not return by t_max. DOP853 at rtol, in parallel; the numbers of `rollphase figure
/// sphere-poincare`'s field.
#[pyfunction]
#[pyo3(signature = (body, alpha, *, starts, t_max = 2000.0, rtol = 1e-10))]
pub fn poincare_map<'py>(
    py: Python<'py>,
    body: &Body,
    alpha: f64,
    starts: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    t_max: f64,
    rtol: f64,
) -> PyResult<MapImages<'py>> {
    let core = body.convex()?;
    let starts = crate::two_dimensional(
        "starts",
        "(N, 4) array of quaternions w, x, y, z with w = 0",
        starts.as_array(),
    )?;
    let (n, width) = starts.dim();
    if width != 4 {
        return Err(input_error(format!(
            "starts must be an (N, 4) array of quaternions w, x, y, z on ∂Ω (w = 0), not shape \
             ({n}, {width})"
        )));
    }
    if !(rtol.is_finite() && rtol > 0.0 && rtol < 1.0) {
        return Err(input_error(format!(
            "rtol = {rtol} is not allowed (needs 0 < rtol < 1)"
        )));
    }
    let mut points = Vec::with_capacity(n);
    for (i, q) in starts.outer_iter().enumerate() {
        let p = DVec3::new(q[1], q[2], q[3]);
        if !(q[0].is_finite() && q[0].abs() <= 1e-9 * p.length()) {
            return Err(input_error(format!(
                "starts[{i}] = {:?} is not on ∂Ω: points of ∂Ω are rotations by π, w = 0",
                q.to_vec()
            )));
        }
        points.push(p);
    }
    let images = interruptible(py, |stop| {
        poincare_map_until(core, alpha, &points, t_max, rtol, stop)
    })?
    .map_err(raise)?;
    let mut ends = Vec::with_capacity(4 * n);
    let mut times = Vec::with_capacity(n);
    for image in images {
        match image {
            Some((p, t)) => {
                ends.extend([0.0, p.x, p.y, p.z]);
                times.push(t);
            }
            None => {
                ends.extend([f64::NAN; 4]);
                times.push(f64::NAN);
            }
        }
    }
    let ends = Array2::from_shape_vec((n, 4), ends).map_err(internal_error)?;
    Ok((
        ends.into_pyarray(py),
        Array1::from_vec(times).into_pyarray(py),
    ))
}

/// The fraction of `orientations` random orientations (seeded, the same on every machine)
/// released from rest at ramp angle `alpha` with the viscous model that cruise (reach a closed
/// orbit, or still roll at t = 2000) rather than halt: the paper's Fig. 3b, and `rollphase
/// figure sphere-cruising`'s numbers. Returns a dict: cruising, halted, undecided, fraction.
#[pyfunction]
#[pyo3(signature = (body, alpha, *, orientations = 1000, seed = 1))]
pub fn cruising_fraction<'py>(
    py: Python<'py>,
    body: &Body,
    alpha: f64,
    orientations: i128,
    seed: i128,
) -> PyResult<Bound<'py, PyDict>> {
    let (orientations, seed): (usize, u64) =
        (whole("orientations", orientations)?, whole("seed", seed)?);
    let core = body.convex()?;
    let c = interruptible(py, |stop| {
        cruising_fraction_until(core, alpha, orientations, seed, stop)
    })?
    .map_err(raise)?;
    let d = PyDict::new(py);
    d.set_item("cruising", c.cruising)?;
    d.set_item("halted", c.halted)?;
    d.set_item("undecided", c.undecided)?;
    d.set_item("fraction", c.fraction)?;
    Ok(d)
}

fn decide(t_min: f64, t_cap: f64, max_k: usize, tol: f64) -> Decide {
    Decide {
        t_min,
        t_cap,
        max_k,
        tol,
    }
}

/// The period-1 orbits that `orientations` random starts released from rest settle on at ramp
/// angle `alpha` and `mass_ratio` (0: viscous), each refined as a fixed point of the return map
/// on ∂Ω by Newton's method, with its Floquet multipliers (2 for the viscous map, 5 for the
/// inertial one). Each run goes on for at least t_min, then until its crossings of ∂Ω repeat
/// (to tol) or it comes to rest, at most t_cap. Returns a list, most-visited first, of dicts:
/// point (3,) (the crossing on ∂Ω, sign arbitrary), omega (3,) (ω there), period,
/// multipliers (complex array, largest modulus first), max_modulus, stable (max_modulus < 1),
/// starts (how many starts settled on it), newton_steps. On the paper's body at α = 0.15 the
/// viscous model gives the paper's two stable orbits (Fig. 3d).
#[pyfunction]
#[pyo3(signature = (body, alpha, *, mass_ratio = 0.0, orientations = 64, seed = 1, t_min = 2000.0,
    t_cap = 20000.0, tol = 1e-5))]
pub fn periodic_orbits<'py>(
    py: Python<'py>,
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    orientations: i128,
    seed: i128,
    t_min: f64,
    t_cap: f64,
    tol: f64,
) -> PyResult<Bound<'py, PyList>> {
    let (orientations, seed): (usize, u64) =
        (whole("orientations", orientations)?, whole("seed", seed)?);
    let core = body.convex()?;
    let rule = decide(t_min, t_cap, 1, tol);
    let found = interruptible(py, |stop| {
        periodic_orbits_until(core, alpha, mass_ratio, orientations, seed, &rule, stop)
    })?
    .map_err(raise)?;
    let list = PyList::empty(py);
    for f in found {
        let o = &f.orbit;
        let d = PyDict::new(py);
        d.set_item("point", Array1::from_vec(o.point.to_vec()).into_pyarray(py))?;
        d.set_item("omega", Array1::from_vec(o.omega.to_vec()).into_pyarray(py))?;
        d.set_item("period", o.period)?;
        let multipliers: Vec<Complex64> = o
            .multipliers
            .iter()
            .map(|&[re, im]| Complex64::new(re, im))
            .collect();
        d.set_item(
            "multipliers",
            Array1::from_vec(multipliers).into_pyarray(py),
        )?;
        d.set_item("max_modulus", o.max_modulus)?;
        d.set_item("stable", o.max_modulus < 1.0)?;
        d.set_item("starts", f.starts)?;
        d.set_item("newton_steps", o.newton_steps)?;
        list.append(d)?;
    }
    Ok(list)
}

/// How `orientations` runs released from rest at random orientations end at one mass ratio:
/// the period-doubling statistics of the paper's Fig. 4e (`rollphase figure sphere-doubling`
/// counts the same). Each run goes on for at least t_min, then until its crossings of ∂Ω close a
/// steady cycle of k ≤ max_k crossings (to tol) or it comes to rest, at most t_cap. Returns a
/// dict: cycle_counts (array of 5: runs with period k = 1, 2, 3, 4, then runs with none),
/// at_rest and undecided (of those with none), left_model (runs whose body left the ramp,
/// counted with none: no cycle is claimed for them), longest_run (the longest a run went on).
#[pyfunction]
#[pyo3(signature = (body, alpha, *, mass_ratio, orientations = 100, seed = 1, t_min = 2000.0,
    t_cap = 20000.0, max_k = 4, tol = 1e-5))]
pub fn period_counts<'py>(
    py: Python<'py>,
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    orientations: i128,
    seed: i128,
    t_min: f64,
    t_cap: f64,
    max_k: i128,
    tol: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let (orientations, seed, max_k): (usize, u64, usize) = (
        whole("orientations", orientations)?,
        whole("seed", seed)?,
        whole("max_k", max_k)?,
    );
    let core = body.convex()?;
    let rule = decide(t_min, t_cap, max_k, tol);
    let c = interruptible(py, |stop| {
        period_counts_until(core, alpha, mass_ratio, orientations, seed, &rule, stop)
    })?
    .map_err(raise)?;
    let d = PyDict::new(py);
    let counts: Vec<u64> = c.cycle_counts.iter().map(|&k| k as u64).collect();
    d.set_item("cycle_counts", Array1::from_vec(counts).into_pyarray(py))?;
    d.set_item("at_rest", c.at_rest)?;
    d.set_item("undecided", c.undecided)?;
    d.set_item("left_model", c.left_model)?;
    d.set_item("longest_run", c.longest_run)?;
    Ok(d)
}

/// The orbit diagram of 3D rolling in m/m0 (beyond the paper's Fig. 4e; `rollphase figure
/// sphere-bifurcation` computes the same): at ramp angle `alpha`, `starts` random orientations
/// per mass (seed `seed`) released from rest at every m/m0 in `masses` (ascending, the first
/// 0), each run going on for at least t_min, then until its crossings of ∂Ω close a cycle or it
/// rests, at most t_cap (10 t_min when not given). The period-1 orbits found at masses[1] are
/// continued up the grid by Newton's method on the return map, with their five Floquet
/// multipliers, and the masses where a multiplier passes −1 (flips) are found by bisection.
/// Returns a dict: masses, period_counts ((n, 5): runs with period 1, 2, 3, 4, none),
/// orbits (a list of dicts: mass_ratio (k,), period (k,), multipliers (k, 5) complex,
/// most_negative_real (k,), nan where none), flips (a list of dicts: orbit, mass_ratio,
/// loses_stability), windows (the period-2 windows the runs show: orbit, onset_mass, end_mass,
/// flip_onset_mass, flip_end_mass; None where absent), undecided_runs, longest_run.
#[pyfunction]
#[pyo3(signature = (body, alpha, *, masses, starts = 4, seed = 1, t_min = 1500.0, t_cap = None))]
#[allow(clippy::too_many_arguments)]
pub fn mass_bifurcation<'py>(
    py: Python<'py>,
    body: &Body,
    alpha: f64,
    masses: Vec<f64>,
    starts: i128,
    seed: i128,
    t_min: f64,
    t_cap: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (starts, seed): (usize, u64) = (whole("starts", starts)?, whole("seed", seed)?);
    let CoreBody::Sphere(sphere) = body.convex()? else {
        return Err(input_error(
            "mass_bifurcation needs a 3D body (a sphere); this one is a 2D disk",
        ));
    };
    let window = RunWindow {
        t_min,
        t_cap: t_cap.unwrap_or(10.0 * t_min),
    };
    let b = interruptible(py, |stop| {
        mass_bifurcation_until(sphere, alpha, &masses, starts, seed, window, stop)
    })?
    .map_err(raise)?;
    let d = PyDict::new(py);
    d.set_item("masses", Array1::from_vec(masses.clone()).into_pyarray(py))?;
    let counts: Vec<u64> = b
        .diagram
        .masses
        .iter()
        .flat_map(|m| m.period_counts.iter().map(|&k| k as u64))
        .collect();
    let counts = Array2::from_shape_vec((masses.len(), 5), counts).map_err(internal_error)?;
    d.set_item("period_counts", counts.into_pyarray(py))?;
    let orbits = PyList::empty(py);
    for o in &b.orbits {
        let od = PyDict::new(py);
        let col =
            |f: &dyn Fn(&PeriodicOrbit) -> f64| -> Vec<f64> { o.solutions.iter().map(f).collect() };
        od.set_item("orbit", o.orbit)?;
        od.set_item(
            "mass_ratio",
            Array1::from_vec(col(&|s| s.mass_ratio)).into_pyarray(py),
        )?;
        od.set_item(
            "period",
            Array1::from_vec(col(&|s| s.period)).into_pyarray(py),
        )?;
        od.set_item(
            "most_negative_real",
            Array1::from_vec(col(&|s| s.most_negative_real.unwrap_or(f64::NAN))).into_pyarray(py),
        )?;
        let mu: Vec<Complex64> = o
            .solutions
            .iter()
            .flat_map(|s| s.multipliers.iter().map(|&[re, im]| Complex64::new(re, im)))
            .collect();
        let width = o.solutions.first().map_or(0, |s| s.multipliers.len());
        let mu = Array2::from_shape_vec((o.solutions.len(), width), mu).map_err(internal_error)?;
        od.set_item("multipliers", mu.into_pyarray(py))?;
        orbits.append(od)?;
    }
    d.set_item("orbits", orbits)?;
    let flips = PyList::empty(py);
    for f in &b.flips {
        let fd = PyDict::new(py);
        fd.set_item("orbit", f.orbit)?;
        fd.set_item("mass_ratio", f.mass_ratio)?;
        fd.set_item("loses_stability", f.loses_stability)?;
        flips.append(fd)?;
    }
    d.set_item("flips", flips)?;
    let windows = PyList::empty(py);
    for w in &b.windows {
        let wd = PyDict::new(py);
        wd.set_item("orbit", w.orbit)?;
        wd.set_item("onset_mass", w.onset_mass)?;
        wd.set_item("end_mass", w.end_mass)?;
        wd.set_item("flip_onset_mass", w.flip_onset_mass)?;
        wd.set_item("flip_end_mass", w.flip_end_mass)?;
        windows.append(wd)?;
    }
    d.set_item("windows", windows)?;
    let grid = DirectRuns::new(&masses, starts, &b.runs).map_err(raise)?;
    d.set_item("undecided_runs", grid.undecided(window.t_cap))?;
    d.set_item("longest_run", grid.longest())?;
    Ok(d)
}

/// What `body` does on a ramp at angle `alpha` and `mass_ratio` (0: viscous), as
/// `rollphase predict` answers: runs from rest at `starts` random orientations (3D) or equally
/// spaced contact angles (2D) until each settles on a periodic motion or comes to rest (at most
/// t_cap). Returns a dict: model (its registry name, `models()`), alpha, mass_ratio, alpha_star, starts, halts and undecided (fractions),
/// fates (every start's fate: periodic, neutral, halted, left_model, undecided, with
/// undecided_reasons and first_violation), scale_mm (the body's, or None), and orbits, most
/// visited first, each a dict: stability ("stable", "neutral" or "unstable"), members (orbits
/// a neutral family stands for), min_normal_force and lift_off_t (inertial: the contact force
/// along it; None in the viscous model), period (t0),
/// repeat (1, or 2 for a doubled orbit: period and advances are then per repeat), advance_down
/// and advance_across (mean radii per repeat), advance_down_mm and advance_across_mm (None
/// without a scale), speed, stable, multipliers (complex array: 2 for 3D viscous, 5 for 3D
/// inertial, none for a disk or a doubled orbit), max_modulus, fraction, starts, crossing and
/// omega (3D: where the orbit crosses ∂Ω), and path, an (N, 2) array of the centre's
/// (down, across) for a sphere or (down, height) for a disk over three repeats.
/// Further keywords are the drag law's parameters by their keys (`drag_parameters()` lists
/// them, with their ranges and what they mean).
#[pyfunction]
#[pyo3(signature = (body, alpha, *, mass_ratio = 0.0, starts = 32, seed = 1, t_cap = 20000.0,
    **drag_law))]
pub fn predict<'py>(
    py: Python<'py>,
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    starts: i128,
    seed: i128,
    t_cap: f64,
    drag_law: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    use rollphase_core::analysis::experiment::prediction::{PredictOptions, predict_until};
    let law = crate::drag_law::from_keywords("predict", drag_law)?;
    let (starts, seed): (usize, u64) = (whole("starts", starts)?, whole("seed", seed)?);
    let core = body.rollable()?;
    if !(t_cap.is_finite() && (10.0..=MAX_SPAN).contains(&t_cap)) {
        return Err(input_error(format!(
            "t_cap = {t_cap} is not allowed (needs 10 ≤ t_cap ≤ {MAX_SPAN:e})"
        )));
    }
    let options = PredictOptions {
        starts,
        seed,
        decide: decide(600f64.min(t_cap), t_cap, 2, 1e-5),
        drag_law: law,
        ..PredictOptions::default()
    };
    let p = interruptible(py, |stop| {
        predict_until(core, alpha, mass_ratio, &options, stop)
    })?
    .map_err(raise)?;
    let d = PyDict::new(py);
    d.set_item("model", p.model.name())?;
    d.set_item("dimension", p.dimension)?;
    d.set_item("alpha", p.alpha)?;
    d.set_item("mass_ratio", p.mass_ratio)?;
    for (parameter, value) in p.drag_law.parameters() {
        d.set_item(parameter.key, value)?;
    }
    d.set_item("alpha_star", p.alpha_star)?;
    d.set_item("starts", p.starts)?;
    d.set_item("halts", p.halts)?;
    d.set_item("undecided", p.undecided)?;
    d.set_item("fates", fates_dict(py, &p.fates)?)?;
    d.set_item("scale_mm", body.scale_mm)?;
    let list = PyList::empty(py);
    for o in &p.orbits {
        let e = PyDict::new(py);
        e.set_item("period", o.period)?;
        e.set_item("repeat", o.repeat)?;
        e.set_item("advance_down", o.advance_down)?;
        e.set_item("advance_across", o.advance_across)?;
        e.set_item("advance_down_mm", body.scale_mm.map(|s| s * o.advance_down))?;
        e.set_item(
            "advance_across_mm",
            body.scale_mm.map(|s| s * o.advance_across),
        )?;
        e.set_item("speed", o.speed)?;
        e.set_item("stable", o.stable)?;
        e.set_item("stability", o.stability.name())?;
        e.set_item("members", o.members)?;
        e.set_item("min_normal_force", o.contact.map(|c| c.min_normal_force))?;
        e.set_item("lift_off_t", o.contact.and_then(|c| c.lift_off_t))?;
        let multipliers: Vec<Complex64> = o
            .multipliers
            .iter()
            .map(|&[re, im]| Complex64::new(re, im))
            .collect();
        e.set_item(
            "multipliers",
            Array1::from_vec(multipliers).into_pyarray(py),
        )?;
        e.set_item("max_modulus", o.max_modulus)?;
        e.set_item("fraction", o.fraction)?;
        e.set_item("starts", o.starts)?;
        e.set_item(
            "crossing",
            o.crossing
                .map(|c| Array1::from_vec(c.to_vec()).into_pyarray(py)),
        )?;
        e.set_item(
            "omega",
            o.omega
                .map(|c| Array1::from_vec(c.to_vec()).into_pyarray(py)),
        )?;
        let flat: Vec<f64> = o.path.iter().flatten().copied().collect();
        let path = Array2::from_shape_vec((o.path.len(), 2), flat).map_err(internal_error)?;
        e.set_item("path", path.into_pyarray(py))?;
        list.append(e)?;
    }
    d.set_item("orbits", list)?;
    Ok(d)
}

/// `predict`'s fates as a dict: the fractions periodic, neutral, halted, left_model and
/// undecided, undecided_reasons (a list of dicts: reason, fraction, what_would_decide) and
/// first_violation (None, or a dict: kind, t).
fn fates_dict<'py>(
    py: Python<'py>,
    f: &rollphase_core::analysis::verdict::FateCounts,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("periodic", f.periodic)?;
    d.set_item("neutral", f.neutral)?;
    d.set_item("halted", f.halted)?;
    d.set_item("left_model", f.left_model)?;
    d.set_item("undecided", f.undecided)?;
    let reasons = PyList::empty(py);
    for u in &f.undecided_reasons {
        let r = PyDict::new(py);
        r.set_item("reason", u.reason)?;
        r.set_item("fraction", u.fraction)?;
        r.set_item("what_would_decide", &u.what_would_decide)?;
        reasons.append(r)?;
    }
    d.set_item("undecided_reasons", reasons)?;
    let violation = match f.first_violation {
        Some(v) => {
            let r = PyDict::new(py);
            r.set_item(
                "kind",
                match v {
                    rollphase_core::dynamics::validity::Violation::LiftOff { .. } => "lift_off",
                    rollphase_core::dynamics::validity::Violation::Slip { .. } => "slip",
                },
            )?;
            r.set_item("t", v.t())?;
            Some(r)
        }
        None => None,
    };
    d.set_item("first_violation", violation)?;
    Ok(d)
}
