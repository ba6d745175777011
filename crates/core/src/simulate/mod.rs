//! One simulation run: a body, a ramp, an initial state and an integrator in; sampled rows and a
//! summary of the numerical health out. The command line's `simulate` and the tests both use it.
//! [`simulate()`] and [`simulate_streaming`] are the same run with typed input ([`Simulation`],
//! [`Model`]) and output ([`Trajectory`], [`Sample`]).
//!
//! Health is measured at every accepted step, not only at the samples: |q| − 1, the
//! contact-normal error (3D), and the energy balance E + W − E(0) (inertial models), where W is
//! the work done by drag, so the figure is meaningful with drag on as well as off.
//! The wall clock is not read here (time is an argument); callers time the run if they wish.
//!
//! **The stiff corner (m/m0 → 0).** The inertial models relax to the viscous one on the time
//! scale τ = (I + m r²)/γ ≈ 1.4 m (3D) or 1.5 m (2D), which an explicit method must resolve:
//! measured with DOP853 at rtol 1e-8 over t = 0..100 (`rollphase bench stiff`), the cost grows
//! as 1/m below m ≈ 0.01, to 1.3 M (disk) and 5.9 M (sphere) evaluations at m = 1e-4, while the
//! inertial result differs from the viscous one by ≈ 0.45 m (sphere state at t = 100) and
//! ≈ 0.03 m (relative period). [`choose_model`] therefore
//! - runs the viscous model when m/m0 ≤ rtol: the inertial correction is then provably below the
//!   requested tolerance, and the run costs thousands of evaluations instead of millions;
//! - refuses a fixed-step method whose step exceeds RK4's stability limit 2.78 τ on the drag
//!   relaxation (with a margin: dt ≤ 2.5 τ), rather than let it blow up;
//! - otherwise runs the inertial model as asked: between m ≈ rtol and 1e-2 that is exact physics
//!   at a cost ∝ 1/m, which the summary's `rhs_evals` shows.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::{DQuat, DVec3};
use serde::Serialize;
use thiserror::Error;

mod model;
pub mod period;
pub mod start;
mod typed;
pub use crate::dynamics::validity::{
    ContactLimits, ContactReport, ContactWatch, OnViolation, Violation,
};
pub use model::{ModelState, Start};
pub use typed::{
    DiskSample, DiskTrajectory, Model, Sample, Simulation, SphereSample, SphereTrajectory,
    Trajectory, simulate, simulate_streaming, simulate_until,
};

use crate::analysis::verdict::{Fate, REST_THRESHOLD, Undecided, observed_rest_measure};
use crate::dynamics::{
    DragLaw, FORCE_COLUMNS, ModelError, ModelKind, ModelVisitor, Ramp, RollingModel, Switched,
};
use crate::geometry::{Body, ShapeError};
use crate::integrate::run::{Flow, Run};
use crate::integrate::{self, IntegrateError, Method, Stats};

/// CSV header of a 2D trajectory.
pub const DISK_HEADER: &str = "t,theta,theta_dot,psi,x,y";
/// CSV header of a 3D trajectory (u: contact point as a body-frame unit vector; w: lab ω).
pub const SPHERE_HEADER: &str = "t,qw,qx,qy,qz,ux,uy,uz,wx,wy,wz,x,y,z";
/// The contact-force columns [`run`] appends to every row after the model's
/// ([`crate::dynamics::ContactForce`], in units of the weight F).
pub const FORCE_HEADER: &str = FORCE_COLUMNS;

/// Where a run starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InitialState {
    /// 2D: contact angle and its rate (the rate is ignored by the viscous model).
    Disk {
        /// Contact angle θ₀.
        theta0: f64,
        /// θ̇₀.
        theta_dot0: f64,
    },
    /// 3D: orientation and lab angular velocity (ω ignored by the viscous model).
    Sphere {
        /// Orientation q₀ (body to lab; normalised when the run starts).
        q0: DQuat,
        /// Lab angular velocity ω₀.
        omega0: DVec3,
    },
}

/// Everything a run needs besides the body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSpec {
    /// Tilt, mass ratio and drag.
    pub ramp: Ramp,
    /// Start.
    pub initial: InitialState,
    /// Integrator.
    pub method: Method,
    /// End time (start is 0).
    pub t_end: f64,
    /// Number of equally spaced output rows from t = 0 to t_end inclusive.
    pub samples: usize,
    /// Step budget.
    pub max_steps: u64,
    /// The surface the run is checked against (lift-off always; slip when it has a μ) and
    /// what a violation does.
    pub limits: ContactLimits,
}

/// Numerical health of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Which model ran (serialised as disk-viscous, disk-inertial, sphere-viscous or
    /// sphere-inertial).
    pub model: ModelKind,
    /// Integrator name.
    pub integrator: &'static str,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// max ||q| − 1| over all steps (3D).
    pub max_quat_norm_error: Option<f64>,
    /// max |n_lab − (0, 0, −1)| over all steps (3D).
    pub max_contact_normal_error: Option<f64>,
    /// max |E + W − E(0)| over all steps (inertial models).
    pub energy_drift: Option<f64>,
    /// Final time reached.
    pub t_end: f64,
    /// Why the model run differs from the one asked for (the stiff-corner policy), if it does.
    pub model_note: Option<String>,
    /// The contact force over the run: its extremes, and when the body would leave the ramp
    /// or slip ([`validity`](ContactWatch)).
    #[serde(flatten)]
    pub contact: Option<ContactReport>,
    /// A dented 2D body rolling on its convex hull: its tips across bridges and the energy they
    /// cost, and when it came to rest on one (`None` for a convex body or a sphere).
    #[serde(flatten)]
    pub hull: Option<HullReport>,
    /// What became of the body, in the verdict's words (`fate`, and `violation`, `t` or `why`):
    /// `left_model` when it left the ramp or slipped (the first violation; nothing after it is
    /// claimed), `halted` when it came to rest (`verdict::rest_measure` below the threshold at
    /// every step's end from `t` on, or on a flat of its hull), else `undecided` with why: a
    /// fixed-time run does not look for a cycle (`period`, `predict` do).
    #[serde(flatten)]
    pub fate: Fate,
}

/// What a dented 2D body did on its hull's bridges during a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct HullReport {
    /// Tips across a bridge (each an impact in the inertial model).
    pub tips: u64,
    /// Kinetic energy the impacts took, in all (units of F⟨r⟩; 0 in the viscous model).
    pub tip_energy_lost: f64,
    /// When the body came to rest on a bridge, if it did.
    pub rested_t: Option<f64>,
}

impl Summary {
    /// The warnings a run that went on past a violation owes its user, one sentence each.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{Model, Simulation, simulate};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let sim = Simulation::new(1.0, 40.0).model(Model::Inertial { mass_ratio: 10.0 });
    /// let (_, summary) = simulate(&body, &sim)?;
    /// assert!(summary.validity_warnings()[0].contains("leaves the ramp at t = 20.2"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn validity_warnings(&self) -> Vec<String> {
        self.contact
            .map(|c| c.violations().iter().map(Violation::describe).collect())
            .unwrap_or_default()
    }
}

/// What `rollphase simulate --summary` writes and Python's `Trajectory.summary` holds: the
/// run's [`Summary`] with its wall time and the ramp, one definition for both.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SummaryReport {
    /// Numerical health and work.
    #[serde(flatten)]
    pub summary: Summary,
    /// Wall-clock seconds for the run.
    pub wall_seconds: f64,
    /// RHS evaluations per wall second.
    pub rhs_evals_per_second: f64,
    /// α (rad).
    pub alpha: f64,
    /// m/m0.
    pub mass_ratio: f64,
    /// The drag law: one field per registered parameter, named by its key.
    #[serde(flatten)]
    pub drag_law: DragLaw,
}

impl SummaryReport {
    /// The report of a run that took `wall_seconds` at `alpha` and `mass_ratio` with
    /// `drag_law`.
    ///
    /// ```
    /// use rollphase_core::dynamics::{DragLaw, ModelKind};
    /// use rollphase_core::simulate::{Summary, SummaryReport};
    /// let mut summary = Summary::new(ModelKind::SphereViscous);
    /// summary.rhs_evals = 1000;
    /// let report = SummaryReport::new(summary, 0.5, 0.15, 0.0, DragLaw::LINEAR);
    /// assert_eq!(report.rhs_evals_per_second, 2000.0);
    /// ```
    pub fn new(
        summary: Summary,
        wall_seconds: f64,
        alpha: f64,
        mass_ratio: f64,
        drag_law: DragLaw,
    ) -> Self {
        Self {
            rhs_evals_per_second: summary.rhs_evals as f64 / wall_seconds.max(1e-12),
            summary,
            wall_seconds,
            alpha,
            mass_ratio,
            drag_law,
        }
    }
}

impl Summary {
    /// An empty summary of a run of `model`, filled in as the run goes.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ModelKind;
    /// use rollphase_core::simulate::Summary;
    /// let s = Summary::new(ModelKind::DiskInertial);
    /// assert_eq!((s.rhs_evals, s.energy_drift), (0, None));
    /// ```
    pub fn new(model: ModelKind) -> Self {
        Self {
            model,
            integrator: "",
            rhs_evals: 0,
            steps: 0,
            rejected: 0,
            max_quat_norm_error: None,
            max_contact_normal_error: None,
            energy_drift: None,
            t_end: 0.0,
            model_note: None,
            contact: None,
            hull: None,
            fate: Fate::Undecided {
                why: Undecided::NotSettled {
                    t_end: 0.0,
                    from_rest: f64::NAN,
                },
            },
        }
    }
}

/// Why a run could not be done.
#[derive(Debug, Error)]
pub enum RunError {
    /// Bad α, m/m0 or drag.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A bad or non-convex body.
    #[error(transparent)]
    Shape(#[from] ShapeError),
    /// The integration failed.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
    /// Inputs that do not fit together.
    #[error("{0}")]
    Mismatch(String),
    /// A fixed step too large for the run: the state left the rolling constraint.
    #[error(
        "fixed step dt = {dt} is too large for this run: by t = {t:.4} ||q| − 1| = {} and the \
         contact-normal error = {} (the limit is 1e-3: beyond it the state no longer describes a \
         body rolling on the plane); use a smaller dt or the adaptive dop853",
        fmt_health(*quat_norm_error),
        fmt_health(*contact_normal_error)
    )]
    Unhealthy {
        /// The step.
        dt: f64,
        /// When the limit was passed.
        t: f64,
        /// Worst ||q| − 1| so far (3D).
        quat_norm_error: Option<f64>,
        /// Worst contact-normal error so far (3D).
        contact_normal_error: Option<f64>,
    },
    /// A fixed step longer than the stability limit of the inertial model's drag relaxation.
    #[error(
        "{method} with dt = {dt} is unstable for m/m0 = {mass_ratio}: the drag relaxation time is \
         {tau:.3e}, so dt must be ≤ {dt_max:.3e}; use a smaller step, the adaptive dop853, or \
         m/m0 = 0 for the viscous limit"
    )]
    UnstableStep {
        /// The integrator ("rk4" or "cf4").
        method: &'static str,
        /// The step asked for.
        dt: f64,
        /// m/m0.
        mass_ratio: f64,
        /// The shortest drag relaxation time m(I/m + r_min²)/γ.
        tau: f64,
        /// The largest stable step, 2.5 τ.
        dt_max: f64,
    },
    /// An initial state of the other dimension (an angle for a sphere, an orientation for a disk).
    #[error("{body} starts from {wanted}, and the initial state given is {given}")]
    InitialStateDoesNotFit {
        /// "a 2D disk" or "a 3D sphere".
        body: &'static str,
        /// What it starts from.
        wanted: &'static str,
        /// What was given.
        given: &'static str,
    },
    /// Stopped on request ([`run_until`]) before the end.
    #[error("the run was stopped at t = {t} before its end")]
    Stopped {
        /// When.
        t: f64,
    },
    /// The motion stopped being rollable and the run was asked to stop there
    /// ([`OnViolation::Stop`]).
    #[error("the run stopped where the rolling model stops holding: the body {}", .violation.describe())]
    LeftModel {
        /// What happened, when.
        violation: Violation,
        /// The contact force up to there.
        report: ContactReport,
    },
    /// A sampled value was not finite.
    #[error(
        "the run produced a non-finite value at t = {t} in column {column}; nothing after it is trustworthy"
    )]
    NonFiniteOutput {
        /// When.
        t: f64,
        /// Which column.
        column: &'static str,
    },
}

/// Which model a run uses, and why when it differs from what was asked.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelChoice {
    /// The ramp actually simulated (mass set to 0 when the viscous limit is taken).
    pub ramp: Ramp,
    /// Why the model differs from the request, if it does.
    pub note: Option<String>,
}

/// Whether m/m0 = `mass_ratio` under `method` runs the viscous model ([`choose_model`]'s rule):
/// at 0, or at or below an adaptive method's rtol, where the inertial correction is below the
/// requested tolerance. Whatever reports a run by its m/m0 (a lesson's claim, a plot's regime)
/// files such a run under 0, as the run itself is.
///
/// # Example
/// ```
/// use rollphase_core::integrate::Method;
/// use rollphase_core::simulate::runs_viscous;
/// assert!(runs_viscous(1e-9, Method::dop853(1e-8)));
/// assert!(!runs_viscous(1e-6, Method::dop853(1e-8)));
/// assert!(runs_viscous(0.0, Method::Rk4 { dt: 0.01 }));
/// ```
pub fn runs_viscous(mass_ratio: f64, method: Method) -> bool {
    !crate::dynamics::models::asks_for_inertia(mass_ratio)
        || matches!(method, Method::Dop853 { rtol, .. } if mass_ratio <= rtol)
}

/// Applies the stiff-corner policy (module doc) to a request for `body`.
///
/// ```
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::integrate::Method;
/// use rollphase_core::simulate::{RunError, choose_model};
/// let body = Body::paper_disk(1, 0.25, 5)?;
/// // m/m0 below DOP853's tolerance: the viscous limit is run, and the summary says why.
/// let choice = choose_model(&body, Ramp::new(0.3, 1e-12)?, Method::dop853(1e-8))?;
/// assert_eq!(choice.ramp.mass_ratio, 0.0);
/// assert!(choice.note.unwrap().contains("viscous"));
/// // A fixed step far longer than the inertial relaxation time is refused, not run unstable.
/// let refused = choose_model(&body, Ramp::new(0.3, 1e-4)?, Method::Rk4 { dt: 0.1 });
/// assert!(matches!(refused, Err(RunError::UnstableStep { .. })));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn choose_model(body: &Body, ramp: Ramp, method: Method) -> Result<ModelChoice, RunError> {
    let m = ramp.mass_ratio;
    if m == 0.0 || ramp.drag == 0.0 {
        return Ok(ModelChoice { ramp, note: None });
    }
    match method {
        Method::Dop853 { rtol, .. } if runs_viscous(m, method) => {
            let viscous =
                Ramp::with_drag(ramp.alpha_rad, 0.0, ramp.drag)?.with_drag_law(ramp.drag_law);
            Ok(ModelChoice {
                ramp: viscous,
                note: Some(format!(
                    "m/m0 = {m:e} ≤ rtol = {rtol:e}: ran the viscous model, which differs from the \
                     inertial one by O(m/m0) (≈ 0.45·m/m0 in the state, 0.03·m/m0 in the period), \
                     below the requested tolerance"
                )),
            })
        }
        Method::Rk4 { dt } | Method::Cf4 { dt } => {
            let tau = relaxation_time(body, &ramp);
            if dt > 2.5 * tau {
                return Err(RunError::UnstableStep {
                    method: method.name(),
                    dt,
                    mass_ratio: m,
                    tau,
                    dt_max: 2.5 * tau,
                });
            }
            Ok(ModelChoice { ramp, note: None })
        }
        _ => Ok(ModelChoice { ramp, note: None }),
    }
}

/// The shortest time on which the inertial model relaxes to the viscous one, τ = m (I/m + r²)/γ
/// (over γ g' with a drag law, [`crate::dynamics::drag`]) at the smallest contact radius (I = m/2 in 2D, 2m/5 in 3D): what an explicit integrator must
/// resolve (module doc). Infinite for the viscous model (nothing to resolve).
///
/// # Example
/// ```
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::{Body, Sphere};
/// use rollphase_core::simulate::relaxation_time;
/// let ball = Body::Sphere(Sphere::perfect());
/// // The unit ball: (2/5 + 1) m/m0 with γ = 1.
/// let tau = relaxation_time(&ball, &Ramp::new(0.3, 1e-3)?);
/// assert!((tau - 1.4e-3).abs() < 1e-12);
/// assert!(relaxation_time(&ball, &Ramp::new(0.3, 0.0)?).is_infinite());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn relaxation_time(body: &Body, ramp: &Ramp) -> f64 {
    let m = ramp.mass_ratio;
    if m == 0.0 || ramp.drag == 0.0 {
        return f64::INFINITY;
    }
    let (inertia_factor, r_min) = match body {
        Body::Disk(d) => (
            0.5,
            (0..720)
                .map(|i| d.jet(i as f64 * std::f64::consts::TAU / 720.0).r)
                .fold(f64::INFINITY, f64::min),
        ),
        Body::Sphere(s) => (
            0.4,
            crate::geometry::sphere::fibonacci_sphere(2000)
                .into_iter()
                .map(|u| s.radius(u))
                .fold(f64::INFINITY, f64::min),
        ),
    };
    // A drag law stiffens the relaxation by its slope g' at the speed the body cruises at
    // (the unit ball's, g⁻¹(sin α/γ)); 1 for the linear drag.
    let law = ramp.drag_law;
    let slope = law.slope(law.speed_for(ramp.alpha_rad.sin() / ramp.drag));
    m * (inertia_factor + r_min * r_min) / (ramp.drag * slope)
}

/// Right-hand-side evaluations an explicit integrator needs at the least to follow the inertial
/// model over `span` when its relaxation time τ is short (the stiff corner): its stable step is
/// a few τ, so about 4 evaluations per τ. Measured (`bench stiff`, DOP853 rtol 1e-8): 5.9 M at
/// m/m0 = 1e-4 over t = 100 on the sphere, where this says 2.9 M; 2.3·10⁸ at m/m0 = 1e-8 over
/// t = 0.5, where it says 1.4·10⁸. A command warns before a run this says takes minutes.
///
/// # Example
/// ```
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::{Body, Sphere};
/// use rollphase_core::simulate::stiff_work_estimate;
/// let ball = Body::Sphere(Sphere::perfect());
/// let heavy = stiff_work_estimate(&ball, &Ramp::new(0.3, 1.0)?, 100.0);
/// let light = stiff_work_estimate(&ball, &Ramp::new(0.3, 1e-8)?, 0.5);
/// assert!(heavy < 1e3 && light > 1e8);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn stiff_work_estimate(body: &Body, ramp: &Ramp, span: f64) -> f64 {
    4.0 * span / relaxation_time(body, ramp)
}

/// Right-hand-side evaluations above which a command warns before it starts (about a minute at
/// the few million evaluations per second of one core).
pub const STIFF_WARNING_EVALS: f64 = 1e8;

/// m/m0 below which a run is in the stiff corner (the module doc: below m ≈ 0.01 the cost grows
/// as 1/m). Above it the step follows the motion, not the relaxation, and
/// [`stiff_work_estimate`] says nothing of the run's cost.
pub const STIFF_BELOW_MASS: f64 = 1e-2;

/// Whether a run of `span` on `ramp` is a stiff one that takes minutes: m/m0 below
/// [`STIFF_BELOW_MASS`] and over [`STIFF_WARNING_EVALS`] evaluations estimated. The commands and
/// Python warn of it before they start. (A heavy body over a long span was warned of, with
/// advice that cannot apply: m/m0 = 10 over 1e9 t0, a helper found, 2026-12-02.)
///
/// # Example
/// ```
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::{Body, Sphere};
/// use rollphase_core::simulate::is_stiff_run;
/// let ball = Body::Sphere(Sphere::perfect());
/// assert!(is_stiff_run(&ball, &Ramp::new(0.3, 1e-8)?, 100.0));
/// assert!(!is_stiff_run(&ball, &Ramp::new(0.3, 10.0)?, 1e9));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn is_stiff_run(body: &Body, ramp: &Ramp, span: f64) -> bool {
    ramp.mass_ratio < STIFF_BELOW_MASS
        && stiff_work_estimate(body, ramp, span) > STIFF_WARNING_EVALS
}

/// A fixed-step run stops when ||q| − 1| or the contact-normal error exceeds this: an error of
/// 1e-3 already shifts the drawn contact point by 1e-3 ⟨r⟩, and beyond it the numbers are no
/// longer a rolling body's (DOP853 keeps both near 1e-15).
pub const FIXED_STEP_HEALTH_LIMIT: f64 = 1e-3;

fn fmt_health(v: Option<f64>) -> String {
    v.map_or_else(|| "n/a".into(), |v| format!("{v:.1e}"))
}

/// Most output rows of one run (a CSV of 10⁷ rows is about 1.4 GB).
pub const MAX_SAMPLES: usize = 10_000_000;

/// Runs `spec` on `body`, calling `row(&values)` for each sample: the model's columns (as in
/// [`DISK_HEADER`] or [`SPHERE_HEADER`]) then [`FORCE_HEADER`]'s.
///
/// ```
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::integrate::Method;
/// use rollphase_core::simulate::{InitialState, RunSpec, run};
/// let body = Body::random_disk(3, 0.08, 10)?;
/// let spec = RunSpec {
///     ramp: Ramp::new(0.3, 0.0)?,
///     initial: InitialState::at_rest(&body),
///     method: Method::dop853(1e-10),
///     t_end: 50.0,
///     samples: 11,
///     max_steps: 1_000_000,
///     limits: Default::default(),
/// };
/// let mut rows = 0;
/// let summary = run(&body, &spec, |row| {
///     // t, θ, θ̇, ψ, x, y, then the contact force: N, f_x, f_y, μ needed.
///     assert_eq!(row.len(), 10);
///     rows += 1;
/// })?;
/// assert_eq!((rows, summary.model.to_string().as_str()), (11, "disk-viscous"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run(body: &Body, spec: &RunSpec, row: impl FnMut(&[f64])) -> Result<Summary, RunError> {
    run_until(body, spec, &AtomicBool::new(false), row)
}

/// [`run`] that stops, with [`RunError::Stopped`], at the first accepted step after `stop` is
/// set (from another thread: a Ctrl-C handler, a UI, Python's signal check). Rows already handed
/// out stay handed out.
///
/// ```
/// use std::sync::atomic::AtomicBool;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::simulate::{RunError, Simulation, run_until};
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let spec = Simulation::new(0.15, 100.0).spec(&body)?;
/// let stopped = run_until(&body, &spec, &AtomicBool::new(true), |_| {});
/// assert!(matches!(stopped, Err(RunError::Stopped { .. })));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_until(
    body: &Body,
    spec: &RunSpec,
    stop: &AtomicBool,
    mut row: impl FnMut(&[f64]),
) -> Result<Summary, RunError> {
    if !(spec.t_end.is_finite() && spec.t_end > 0.0 && spec.t_end <= integrate::MAX_SPAN) {
        return Err(RunError::Mismatch(format!(
            "t_end = {} is not allowed (needs 0 < t_end ≤ {}: past that the integrator's \
             smallest step, 16 ε × t_end, exceeds the steps an orbit needs)",
            integrate::readable(spec.t_end),
            integrate::readable(integrate::MAX_SPAN)
        )));
    }
    if !(2..=MAX_SAMPLES).contains(&spec.samples) {
        return Err(RunError::Mismatch(format!(
            "samples = {} is not allowed (needs 2 ≤ samples ≤ {MAX_SAMPLES}: t = 0, t_end and rows \
             between)",
            spec.samples
        )));
    }
    if let Method::Rk4 { dt } | Method::Cf4 { dt } = spec.method {
        if dt > spec.t_end {
            return Err(RunError::Mismatch(format!(
                "a fixed step dt = {} is longer than the whole run (t_end = {}): it would silently \
                 become one step of t_end; use dt ≤ t_end (and small enough to be accurate), or \
                 DOP853",
                integrate::readable(dt),
                integrate::readable(spec.t_end)
            )));
        }
        let steps = (spec.t_end / dt).ceil();
        if steps > spec.max_steps as f64 {
            return Err(RunError::Mismatch(format!(
                "a fixed step dt = {dt:e} needs {steps:.3e} steps to reach t_end = {}, more than \
                 the step budget max_steps = {}; use a larger step, a shorter run, or DOP853",
                spec.t_end, spec.max_steps
            )));
        }
    }
    spec.limits.validate().map_err(RunError::Mismatch)?;
    // A dented 2D body rolls on its convex hull (the models' switches); anything else must be
    // strictly convex.
    body.check_rollable()?;
    let choice = choose_model(body, spec.ramp, spec.method)?;
    let spec = &RunSpec {
        ramp: choice.ramp,
        ..*spec
    };
    let times = integrate::uniform_times(0.0, spec.t_end, spec.samples);
    let start = Start::new(body, spec.initial)?;
    let model = ModelState::new(&start, &spec.ramp);
    let summary = model.visit(
        &spec.ramp,
        Drive {
            spec,
            times: &times,
            stop,
            row: &mut row,
        },
    )?;
    Ok(Summary {
        model_note: choice.note,
        ..summary
    })
}

/// One run of whichever model [`ModelState::visit`] hands it: integrates from its state over
/// `times`, writing a row per sample (checked against the model's columns) and measuring the
/// model's health after every accepted step.
struct Drive<'a, F: FnMut(&[f64])> {
    spec: &'a RunSpec,
    times: &'a [f64],
    stop: &'a AtomicBool,
    row: &'a mut F,
}

/// Why one stepper's run ended early: an error, or a switch of a hybrid model at (t, y) (a
/// dented body reaching a bridge of its hull), after which a new stepper starts.
enum Halt<const N: usize> {
    Run(RunError),
    Switch(f64, [f64; N]),
}

impl<const N: usize> From<IntegrateError> for Halt<N> {
    fn from(e: IntegrateError) -> Self {
        Halt::Run(e.into())
    }
}

impl<const N: usize> From<RunError> for Halt<N> {
    fn from(e: RunError) -> Self {
        Halt::Run(e)
    }
}

/// Most switches (tips and impacts) one run may take: beyond it the rocking is not settling (a
/// 30-sided print tips 30 times a turn: a million is 33 000 turns).
pub const MAX_SWITCHES: u64 = 1_000_000;

/// The first time in the last step where the model's switching function passes from ≥ 0 to
/// < 0, and the state there (from the step's dense output, to 1e-13 in time); `None` for a step
/// without one, and always for a smooth model. `run` and the app's simulation restart their
/// integration there, from the model's [`RollingModel::switch`].
///
/// # Example
/// ```
/// use rollphase_core::dynamics::{DiskViscous, Ramp, RollingModel};
/// use rollphase_core::geometry::Body;
/// use rollphase_core::integrate::run::{Flow, Run};
/// use rollphase_core::integrate::{IntegrateError, Method};
/// use rollphase_core::simulate::locate_switch;
/// // The printed σ = 0.5 cylinder rolls onto a flat of its hull within a few time units.
/// let Body::Disk(disk) = Body::paper_disk(219, 0.5, 9)? else { unreachable!() };
/// let model = DiskViscous::new(&disk, &Ramp::new(0.45, 0.0)?);
/// let mut run = Run::new(&model, 0.0, [4.5, 0.0], Method::dop853(1e-10))?;
/// let mut found = None;
/// run.until::<IntegrateError>(100.0, u64::MAX, |st| {
///     found = locate_switch(st, &model);
///     Ok(if found.is_some() { Flow::Stop } else { Flow::Continue })
/// })?;
/// let (t, y) = found.expect("a switch within 100 time units");
/// assert!(model.switching(&y).unwrap().abs() < 1e-9 && t > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn locate_switch<const N: usize, M: RollingModel<N>>(
    st: &mut dyn integrate::Stepper<N>,
    model: &M,
) -> Option<(f64, [f64; N])> {
    let g0 = model.switching(st.y_prev())?;
    let g1 = model.switching(st.y())?;
    if !(g0 >= 0.0 && g1 < 0.0) {
        return None;
    }
    let (t0, t1) = (st.t_prev(), st.t());
    const PARTS: usize = 16;
    let mut prev = (t0, g0);
    for k in 1..=PARTS {
        let t = if k == PARTS {
            t1
        } else {
            t0 + (t1 - t0) * k as f64 / PARTS as f64
        };
        let g = model.switching(&st.dense(t)).unwrap_or(g1);
        if g < 0.0 {
            let root = crate::numeric::roots::brent(
                |t| model.switching(&st.dense(t)).unwrap_or(g1),
                prev.0,
                t,
                prev.1,
                g,
                1e-13 * t1.abs().max(1.0),
            );
            return Some((root, st.dense(root)));
        }
        prev = (t, g);
    }
    None
}

impl<F: FnMut(&[f64])> ModelVisitor for Drive<'_, F> {
    type Output = Result<Summary, RunError>;

    #[expect(
        clippy::too_many_lines,
        reason = "one loop over the steps of a run and over the restarts a hybrid model's switches \
                  make, with the rows, the health, the contact force and the switches kept in \
                  step; split, each piece would need all of that state handed to it"
    )]
    fn visit<const N: usize, M: RollingModel<N>>(self, model: &M, y0: &[f64; N]) -> Self::Output {
        let Drive {
            spec,
            times,
            stop,
            row,
        } = self;
        let mut summary = Summary::new(M::KIND);
        // A dented body started on a flat lies as the statics say (the identity otherwise).
        let placed = model.placed(*y0);
        let y0 = &placed;
        let mut values = Vec::with_capacity(20);
        let mut put = |t: f64, y: &[f64; N]| -> Result<(), RunError> {
            model.row(t, y, &mut values);
            check_row(t, &values, M::COLUMNS)?;
            let f = model.contact_force(y);
            // The friction needed is infinite where N ≤ 0; the forces themselves must be finite.
            let forces = [f.normal, f.friction[0], f.friction[1]];
            check_row(t, &forces, FORCE_HEADER)?;
            values.extend(forces);
            values.push(f.friction_needed());
            row(&values);
            Ok(())
        };
        let mut watch = ContactWatch::new(spec.limits, 0.0, model.contact_force(y0));
        if let (OnViolation::Stop, Some(v)) = (
            spec.limits.on_violation,
            watch.report().violations().first(),
        ) {
            return Err(RunError::LeftModel {
                violation: *v,
                report: watch.report(),
            });
        }
        let e0 = model.health(y0).energy;
        // Since when the body has been at rest at every step's end, and how far from rest it
        // was at the last: the evidence of the run's fate (the observation gives the health too).
        let mut rest_since: Option<f64> = None;
        let mut from_rest = f64::NAN;
        let mut track = |t: f64, y: &[f64; N], s: &mut Summary| {
            let o = model.observation(y);
            from_rest = observed_rest_measure(&o);
            if from_rest < REST_THRESHOLD {
                rest_since.get_or_insert(t);
            } else {
                rest_since = None;
            }
            let h = o.health;
            let max_opt = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) => Some(a.max(b)),
                (a, None) => a,
                (None, b) => b,
            };
            s.max_quat_norm_error = max_opt(s.max_quat_norm_error, h.quat_norm_error);
            s.max_contact_normal_error =
                max_opt(s.max_contact_normal_error, h.contact_normal_error);
            if let (Some(e), Some(e0)) = (h.energy, e0) {
                s.energy_drift = max_opt(s.energy_drift, Some((e - e0).abs()));
            }
        };
        track(0.0, y0, &mut summary);
        let mut hull = model.switching(y0).map(|g| HullReport {
            // Started on a flat, where its weight falls between the ends: at rest from t = 0.
            rested_t: (g < 0.0).then_some(0.0),
            ..HullReport::default()
        });
        let mut next = 0;
        while next < times.len() && times[next] <= 0.0 {
            put(times[next], y0)?;
            next += 1;
        }
        let t_end = *times.last().unwrap_or(&0.0);
        let method = spec.method;
        let (mut t_start, mut y_start) = (0.0, *y0);
        let mut stats = Stats::default();
        loop {
            // The step budget is the whole run's, restarts included: a body chattering across
            // its hull's flats (one step, one switch, again) must end at max_steps too.
            if stats.steps >= spec.max_steps {
                return Err(RunError::Integrate(IntegrateError::TooManySteps {
                    t: t_start,
                    max_steps: spec.max_steps,
                }));
            }
            let mut run = Run::new(model, t_start, y_start, method)?;
            let budget = spec.max_steps - stats.steps;
            let ran = run.until(t_end, budget, |st| {
                if stop.load(Ordering::Relaxed) {
                    return Err(Halt::Run(RunError::Stopped { t: st.t() }));
                }
                let switch = locate_switch(st, model);
                let (t_now, y_now) = switch.unwrap_or((st.t(), *st.y()));
                track(t_now, &y_now, &mut summary);
                let stopped = watch.step_along(st, (t_now, y_now), |y| model.contact_force(y));
                if let Some(violation) = stopped {
                    // The rows up to the violation, then the error.
                    while next < times.len() && times[next] <= violation.t() {
                        let ys = st.dense(times[next]);
                        put(times[next], &ys)?;
                        next += 1;
                    }
                    return Err(Halt::Run(RunError::LeftModel {
                        violation,
                        report: watch.report(),
                    }));
                }
                if let Method::Rk4 { dt } | Method::Cf4 { dt } = method {
                    let worst = summary
                        .max_quat_norm_error
                        .unwrap_or(0.0)
                        .max(summary.max_contact_normal_error.unwrap_or(0.0));
                    if worst > FIXED_STEP_HEALTH_LIMIT || !worst.is_finite() {
                        return Err(Halt::Run(RunError::Unhealthy {
                            dt,
                            t: st.t(),
                            quat_norm_error: summary.max_quat_norm_error,
                            contact_normal_error: summary.max_contact_normal_error,
                        }));
                    }
                }
                while next < times.len() && times[next] <= t_now {
                    let ys = if switch.is_none() && times[next] == t_now {
                        y_now
                    } else {
                        st.dense(times[next])
                    };
                    put(times[next], &ys)?;
                    next += 1;
                }
                match switch {
                    Some((t, y)) => Err(Halt::Switch(t, y)),
                    None => Ok(Flow::Continue),
                }
            });
            let done = run.stats();
            stats.rhs_evals += done.rhs_evals;
            stats.steps += done.steps;
            stats.rejected += done.rejected;
            match ran {
                Ok(_) => {
                    summary.t_end = run.t();
                    break;
                }
                Err(Halt::Run(e)) => return Err(e),
                Err(Halt::Switch(t, y)) => {
                    let Some((after, what)) = model.switch(&y) else {
                        return Err(RunError::Mismatch(format!(
                            "internal error: a switch at t = {t} that the model does not take"
                        )));
                    };
                    let report = hull.get_or_insert_with(HullReport::default);
                    match what {
                        Switched::Tip { energy_lost } => {
                            report.tips += 1;
                            report.tip_energy_lost += energy_lost;
                        }
                        Switched::Rest { energy_lost } => {
                            report.tip_energy_lost += energy_lost;
                            report.rested_t.get_or_insert(t);
                        }
                    }
                    if report.tips > MAX_SWITCHES {
                        return Err(RunError::Mismatch(format!(
                            "more than {MAX_SWITCHES} tips across the hull's bridges by t = {t}: \
                             the body rocks without settling"
                        )));
                    }
                    watch.jump(t, model.contact_force(&after));
                    track(t, &after, &mut summary);
                    if t >= t_end {
                        summary.t_end = t;
                        break;
                    }
                    (t_start, y_start) = (t, after);
                }
            }
        }
        let report = watch.report();
        summary.fate = match (report.violations().first(), hull.and_then(|h| h.rested_t)) {
            (Some(violation), _) => Fate::LeftModel {
                violation: *violation,
            },
            (None, Some(t)) => Fate::Halted { t: Some(t) },
            (None, None) => match rest_since {
                Some(t) => Fate::Halted { t: Some(t) },
                None => Fate::Undecided {
                    why: Undecided::NotSettled {
                        t_end: summary.t_end,
                        from_rest,
                    },
                },
            },
        };
        summary.contact = Some(report);
        summary.hull = hull;
        Ok(finish(summary, stats, method))
    }
}

fn finish(mut s: Summary, stats: Stats, method: Method) -> Summary {
    s.rhs_evals = stats.rhs_evals;
    s.steps = stats.steps;
    s.rejected = stats.rejected;
    s.integrator = method.name();
    s
}

fn check_row(t: f64, values: &[f64], header: &'static str) -> Result<(), RunError> {
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        let column = header.split(',').nth(i).unwrap_or("?");
        return Err(RunError::NonFiniteOutput { t, column });
    }
    Ok(())
}
