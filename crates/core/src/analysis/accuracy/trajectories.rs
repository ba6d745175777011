//! The price of accuracy: each model run with each integrator setting and compared with a
//! converged reference (DOP853 at rtol 1e-13) at t = 100.
//!
//! Two errors are measured:
//! - **state error**: the larger of the orientation error (the rotation angle between the two
//!   bodies' orientations: |Δθ| in 2D, 2·acos|q·q_ref| in 3D) and the centre's position error;
//! - **period error**: the relative error of the orbit period, estimated as the mean interval
//!   between successive crossings of a section over (t_end/5, t_end]. 2D: θ passing θ₀ + 2πk
//!   (the period of 2π/T). 3D: q_w = 0, the boundary ∂Ω of the SO(3) ball where the paper's
//!   Poincaré map lives. Crossings are located on the dense output (Brent), so the estimate is
//!   as accurate as the trajectory.
//!
//! Work is counted here (right-hand-side evaluations, steps); wall time is measured by the
//! caller (`rollphase bench accuracy`), since the core never reads the clock.

use glam::{DQuat, DVec3};
use serde::Serialize;

use crate::dynamics::sphere3d::orientation_touching;
use crate::dynamics::{
    DiskInertial, DiskViscous, ModelKind, Ramp, RollingModel, SphereInertial, SphereViscous,
};
use crate::geometry::{Body, sphere::direction};
use crate::integrate::events::{self, Direction};
use crate::integrate::lie::quat_at;
use crate::integrate::run::{Flow, Run};
use crate::integrate::{IntegrateError, Method, Stats};

/// One model on one body with one start: what a row of the accuracy table measures.
#[derive(Debug, Clone)]
pub struct Case {
    /// The body.
    pub body: Body,
    /// Tilt and mass.
    pub ramp: Ramp,
    /// 2D: θ₀. 3D: contact (θ, φ) and spin of the start.
    pub start: [f64; 3],
    /// End time.
    pub t_end: f64,
}

/// What one run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// 2D: θ (orientation angle). 3D: unused (NaN).
    pub angle: f64,
    /// 3D: final q (w, x, y, z); zeros in 2D.
    pub quat: [f64; 4],
    /// Final centre position along the ramp (x, y); y = 0 in 2D (x is the rolled arc).
    pub position: [f64; 2],
    /// Section-crossing times.
    pub crossings: Vec<f64>,
    /// Work done.
    pub stats: Stats,
}

impl Case {
    /// The model this case runs: the body's dimension, viscous when m/m0 = 0.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::accuracy::trajectories::Case;
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// use rollphase_core::geometry::Body;
    /// let case = Case { body: Body::paper_disk(84, 0.12, 5)?, ramp: Ramp::new(0.2, 2.0)?, start: [0.0; 3], t_end: 10.0 };
    /// assert_eq!(case.model(), ModelKind::DiskInertial);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn model(&self) -> ModelKind {
        ModelKind::of(&self.body, &self.ramp)
    }
}

/// One row of the accuracy table.
#[derive(Debug, Clone, Serialize)]
pub struct AccuracyRow {
    /// The model.
    pub model: ModelKind,
    /// Integrator name.
    pub integrator: &'static str,
    /// Its step (RK4, CF4) or tolerance (DOP853).
    pub parameter: f64,
    /// State error at t_end (radians / length units); NaN if the run failed.
    pub state_error: f64,
    /// Relative period error; NaN when either run has fewer than two crossings in the window.
    pub period_error: f64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Accepted steps.
    pub steps: u64,
    /// Why the run failed, if it did.
    pub failure: Option<String>,
}

/// The four models on the bundled bodies, at the angles the paper's figures use.
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::trajectories::default_cases;
/// use rollphase_core::dynamics::models::REGISTERED;
/// use rollphase_core::geometry::Body;
/// let (disk, sphere) = (Body::paper_disk(84, 0.12, 5)?, Body::paper_sphere(219, 0.25, 5)?);
/// let cases = default_cases(&disk, &disk, &sphere);
/// // One case per registered model, in the registry's order.
/// let models: Vec<_> = REGISTERED.iter().map(|m| m.kind).collect();
/// assert_eq!(cases.iter().map(|c| c.model()).collect::<Vec<_>>(), models);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn default_cases(disk: &Body, disk_inertial: &Body, sphere: &Body) -> Vec<Case> {
    let ramp = |a: f64, m: f64| Ramp::new(a, m).expect("fixed valid parameters");
    vec![
        Case {
            body: disk.clone(),
            ramp: ramp(0.25, 0.0),
            start: [0.0; 3],
            t_end: 100.0,
        },
        Case {
            body: disk_inertial.clone(),
            ramp: ramp(0.2, 2.0),
            start: [0.0; 3],
            t_end: 100.0,
        },
        Case {
            body: sphere.clone(),
            ramp: ramp(0.3, 0.0),
            start: [1.0, 2.0, 0.5],
            t_end: 100.0,
        },
        Case {
            body: sphere.clone(),
            ramp: ramp(0.3, 2.0),
            start: [1.0, 2.0, 0.5],
            t_end: 100.0,
        },
    ]
}

/// The settings tabulated for a case: RK4 and (3D) CF4 at several steps, DOP853 at several
/// tolerances.
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::trajectories::{default_cases, default_settings};
/// use rollphase_core::geometry::Body;
/// let (disk, sphere) = (Body::paper_disk(84, 0.12, 5)?, Body::paper_sphere(219, 0.25, 5)?);
/// let cases = default_cases(&disk, &disk, &sphere);
/// // 2D: six RK4 steps and five DOP853 tolerances; 3D adds six CF4 steps.
/// assert_eq!((default_settings(&cases[0]).len(), default_settings(&cases[2]).len()), (11, 17));
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn default_settings(case: &Case) -> Vec<Method> {
    let mut v = Vec::new();
    for dt in [0.4, 0.2, 0.1, 0.05, 0.02, 0.01] {
        v.push(Method::Rk4 { dt });
    }
    if case.body.dimension() == 3 {
        for dt in [0.4, 0.2, 0.1, 0.05, 0.02, 0.01] {
            v.push(Method::Cf4 { dt });
        }
    }
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        v.push(Method::dop853(rtol));
    }
    v
}

/// The converged reference setting.
pub const REFERENCE: Method = Method::Dop853 {
    rtol: 1e-13,
    atol: 1e-13,
};

/// The Poincaré section whose crossings time the orbit.
#[derive(Debug, Clone, Copy)]
enum Section {
    /// State component `slot` passing θ₀ + 2πk (2D).
    Turns { slot: usize, theta0: f64 },
    /// The model's own section (q_w = 0, the boundary of the SO(3) ball, in 3D).
    BallBoundary,
}

fn drive<const N: usize, S: RollingModel<N>>(
    sys: &S,
    y0: [f64; N],
    method: Method,
    t_end: f64,
    section: Section,
) -> Result<([f64; N], Vec<f64>, Stats), IntegrateError> {
    let mut run = Run::new(sys, 0.0, y0, method)?;
    let mut crossings = Vec::new();
    let mut target = match section {
        Section::Turns { theta0, .. } => theta0 + std::f64::consts::TAU,
        Section::BallBoundary => 0.0,
    };
    run.until::<IntegrateError>(t_end, 50_000_000, |st| {
        match section {
            Section::Turns { slot, .. } => events::turns_in_last_step(
                st,
                slot,
                &mut target,
                std::f64::consts::TAU,
                &mut crossings,
            ),
            Section::BallBoundary => events::crossings_in_last_step(
                st,
                &|_t, y: &[f64; N]| sys.section(y),
                Direction::Both,
                &mut crossings,
            ),
        }
        Ok(Flow::Continue)
    })?;
    Ok((*run.y(), crossings, run.stats()))
}

/// Runs `case` with `method`.
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::trajectories::{Case, run_case, state_error};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::integrate::Method;
/// let case = Case { body: Body::paper_sphere(219, 0.25, 5)?, ramp: Ramp::new(0.3, 0.0)?, start: [1.0, 2.0, 0.5], t_end: 20.0 };
/// let reference = run_case(&case, Method::dop853(1e-12))?;
/// let coarse = run_case(&case, Method::Rk4 { dt: 0.1 })?;
/// // RK4 at dt = 0.1 is close to the reference, but not to round-off.
/// let e = state_error(&coarse, &reference);
/// assert!(e > 1e-12 && e < 1e-3, "{e}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_case(case: &Case, method: Method) -> Result<Outcome, IntegrateError> {
    match &case.body {
        Body::Disk(d) => {
            let theta0 = case.start[0];
            let section = Section::Turns { slot: 0, theta0 };
            match ModelKind::for_dimension(2, &case.ramp) {
                ModelKind::DiskViscous => {
                    let m = DiskViscous::new(d, &case.ramp);
                    let (y, c, s) = drive(&m, [theta0, 0.0], method, case.t_end, section)?;
                    Ok(Outcome {
                        angle: y[0],
                        quat: [0.0; 4],
                        position: [y[1], 0.0],
                        crossings: c,
                        stats: s,
                    })
                }
                ModelKind::DiskInertial => {
                    let m = DiskInertial::new(d, &case.ramp);
                    let (y, c, s) =
                        drive(&m, [theta0, 0.0, 0.0, 0.0], method, case.t_end, section)?;
                    Ok(Outcome {
                        angle: y[0],
                        quat: [0.0; 4],
                        position: [y[2], 0.0],
                        crossings: c,
                        stats: s,
                    })
                }
                other @ (ModelKind::SphereViscous | ModelKind::SphereInertial) => {
                    other.wrong_dimension(2)
                }
            }
        }
        Body::Sphere(s) => {
            let q0 =
                orientation_touching(s, direction(case.start[0], case.start[1]), case.start[2]);
            let section = Section::BallBoundary;
            match ModelKind::for_dimension(3, &case.ramp) {
                ModelKind::SphereViscous => {
                    let m = SphereViscous::new(s, &case.ramp);
                    let (y, c, st) = drive(
                        &m,
                        SphereViscous::initial_state(q0),
                        method,
                        case.t_end,
                        section,
                    )?;
                    Ok(Outcome {
                        angle: f64::NAN,
                        quat: [y[0], y[1], y[2], y[3]],
                        position: [y[4], y[5]],
                        crossings: c,
                        stats: st,
                    })
                }
                ModelKind::SphereInertial => {
                    let m = SphereInertial::new(s, &case.ramp);
                    let y0 = SphereInertial::initial_state(q0, DVec3::ZERO);
                    let (y, c, st) = drive(&m, y0, method, case.t_end, section)?;
                    Ok(Outcome {
                        angle: f64::NAN,
                        quat: [y[0], y[1], y[2], y[3]],
                        position: [y[7], y[8]],
                        crossings: c,
                        stats: st,
                    })
                }
                other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => {
                    other.wrong_dimension(3)
                }
            }
        }
    }
}

/// Mean interval between crossings in (t_end/5, t_end], if there are at least two.
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::trajectories::period_estimate;
/// // Crossings every 2.5 time units; only those after t_end/5 = 2 count.
/// assert_eq!(period_estimate(&[0.5, 3.0, 5.5, 8.0, 10.5], 10.5), Some(2.5));
/// assert_eq!(period_estimate(&[9.0], 10.0), None);
/// ```
pub fn period_estimate(crossings: &[f64], t_end: f64) -> Option<f64> {
    let w: Vec<f64> = crossings
        .iter()
        .copied()
        .filter(|&t| t > 0.2 * t_end)
        .collect();
    (w.len() >= 2).then(|| (w[w.len() - 1] - w[0]) / (w.len() - 1) as f64)
}

/// State error between two outcomes (see the module doc).
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::trajectories::{Case, run_case, state_error};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::integrate::Method;
/// let case = Case { body: Body::paper_disk(84, 0.12, 5)?, ramp: Ramp::new(0.25, 0.0)?, start: [0.0; 3], t_end: 10.0 };
/// let run = run_case(&case, Method::dop853(1e-10))?;
/// assert_eq!(state_error(&run, &run), 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn state_error(a: &Outcome, reference: &Outcome) -> f64 {
    let orientation = if a.angle.is_nan() {
        let qa = quat_at(&a.quat, 0).normalize();
        let qr = quat_at(&reference.quat, 0).normalize();
        2.0 * qa.dot(qr).abs().min(1.0).acos()
    } else {
        (a.angle - reference.angle).abs()
    };
    let dx = a.position[0] - reference.position[0];
    let dy = a.position[1] - reference.position[1];
    orientation.max((dx * dx + dy * dy).sqrt())
}

/// Builds a table row from a run (or its failure) and the reference.
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::trajectories::{Case, row, run_case};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::integrate::{IntegrateError, Method};
/// let case = Case { body: Body::paper_disk(84, 0.12, 5)?, ramp: Ramp::new(0.25, 0.0)?, start: [0.0; 3], t_end: 10.0 };
/// let reference = run_case(&case, Method::dop853(1e-12))?;
/// let r = row(&case, Method::Rk4 { dt: 0.05 }, &run_case(&case, Method::Rk4 { dt: 0.05 }), &reference);
/// assert_eq!((r.integrator, r.parameter), ("rk4", 0.05));
/// // A failed run is a row with its reason, not a panic.
/// let failed: Result<_, IntegrateError> = Err(IntegrateError::NonFinite { t: 1.0 });
/// assert!(row(&case, Method::Rk4 { dt: 9.0 }, &failed, &reference).failure.is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn row(
    case: &Case,
    method: Method,
    run: &Result<Outcome, IntegrateError>,
    reference: &Outcome,
) -> AccuracyRow {
    let parameter = match method {
        Method::Rk4 { dt } | Method::Cf4 { dt } => dt,
        Method::Dop853 { rtol, .. } => rtol,
    };
    match run {
        Ok(o) => {
            let period_error = match (
                period_estimate(&o.crossings, case.t_end),
                period_estimate(&reference.crossings, case.t_end),
            ) {
                (Some(p), Some(r)) => ((p - r) / r).abs(),
                _ => f64::NAN,
            };
            AccuracyRow {
                model: case.model(),
                integrator: method.name(),
                parameter,
                state_error: state_error(o, reference),
                period_error,
                rhs_evals: o.stats.rhs_evals,
                steps: o.stats.steps,
                failure: None,
            }
        }
        Err(e) => AccuracyRow {
            model: case.model(),
            integrator: method.name(),
            parameter,
            state_error: f64::NAN,
            period_error: f64::NAN,
            rhs_evals: 0,
            steps: 0,
            failure: Some(e.to_string()),
        },
    }
}

/// The unit quaternion of an outcome (3D), for callers that need it.
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::trajectories::{Case, outcome_quat, run_case};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::integrate::Method;
/// let case = Case { body: Body::paper_sphere(219, 0.25, 5)?, ramp: Ramp::new(0.3, 2.0)?, start: [1.0, 2.0, 0.5], t_end: 5.0 };
/// let q = outcome_quat(&run_case(&case, Method::dop853(1e-10))?);
/// assert!((q.length() - 1.0).abs() < 1e-8);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn outcome_quat(o: &Outcome) -> DQuat {
    quat_at(&o.quat, 0)
}
