//! What a live run shows: the [`Snapshot`] the app and the headless renderer draw (pose, contact,
//! trails, period, health, lesson progress), the numerical [`Health`] and which of its figures a
//! model measures, and why a run stopped ([`SimError`]). Plain data: [`super::LiveRun`] fills it.

use crate::dynamics::validity::ContactReport;
use crate::dynamics::{ContactForce, ModelKind, Ramp};
use crate::scene::ViewsSpec;
use glam::{DQuat, DVec3};
use thiserror::Error;

/// Why the simulation stopped.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    /// The integrator failed (too many steps, step underflow, non-finite values).
    #[error("the integrator stopped at t = {t:.6}: {message}")]
    Integrate {
        /// When.
        t: f64,
        /// Why.
        message: String,
    },
    /// A parameter change was refused.
    #[error("{0}")]
    Refused(String),
}

/// The numerical health so far (worst values since the start).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Health {
    /// max ||q| − 1| (3D).
    pub quat_norm_error: f64,
    /// max |n_lab − (0, 0, −1)| (3D).
    pub contact_normal_error: f64,
    /// max |E + W − E(0)| (inertial models), measured from the last (re)start of the model.
    pub energy_drift: f64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Which of the three the running model measures (the model says: |q| and the contact
    /// normal are a sphere's, the energy balance an inertial model's); the others stay 0.
    pub measured: Measured,
}

/// Which health quantities a model has.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Measured {
    /// ||q| − 1|.
    pub quat_norm: bool,
    /// The contact normal's error.
    pub contact_normal: bool,
    /// |E + W − E(0)|.
    pub energy: bool,
}

/// Pose of the body in the ramp frame (x downhill, y across, z the ramp's normal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyPose {
    /// Body-to-ramp rotation.
    pub rotation: DQuat,
    /// Centre of mass.
    pub centre: DVec3,
}

/// What a frame shows of the simulation: plain data, cheap to clone and send.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Simulation time.
    pub t: f64,
    /// The model's whole state vector at `t` ([`crate::simulate::ModelState::vector`]): what Save state writes.
    pub state: Vec<f64>,
    /// Which model runs.
    pub model: ModelKind,
    /// The integrator's name.
    pub integrator: &'static str,
    /// Tilt.
    pub alpha_rad: f64,
    /// Critical angle of the body.
    pub alpha_star: f64,
    /// m/m0 (0: viscous).
    pub mass_ratio: f64,
    /// The drag law running.
    pub drag_law: crate::dynamics::DragLaw,
    /// Pose.
    pub pose: BodyPose,
    /// Contact point on the ramp (z = 0).
    pub contact_on_ramp: DVec3,
    /// Contact point in the body frame.
    pub contact_in_body: DVec3,
    /// Past contact points on the ramp, oldest first.
    pub ramp_trail: Vec<DVec3>,
    /// Past contact points in the body frame, oldest first.
    pub body_trail: Vec<DVec3>,
    /// The orientation's path in the SO(3) ball, split where it jumps to the antipode (3D with
    /// the ball view only).
    pub ball_trail: Vec<Vec<DVec3>>,
    /// The current ball point (3D).
    pub ball_point: Option<DVec3>,
    /// Time between the last two full turns (2D) or crossings of ∂Ω (3D), once measured.
    pub period: Option<f64>,
    /// 3D: the period k of the crossing sequence of ∂Ω (1: closed orbit, 2: doubled), once the
    /// last 2k + 1 crossings repeat to 1e-3 and, for k ≥ 2, the cycle is steady over the last
    /// 10k + 1 (`settled_cycle`, the one test `predict` uses too); `None` before that, or in 2D.
    pub period_multiplicity: Option<usize>,
    /// 3D: the time the decided cycle takes to repeat, its k crossings of ∂Ω (`period` is the
    /// last one's, which alternates on a doubled cycle); `None` while undecided.
    pub cycle_period: Option<f64>,
    /// 3D: the crossings of ∂Ω that decided `period_multiplicity` k, the last 2k + 1 (time,
    /// boundary point; sign arbitrary), oldest first; empty while it is undecided. All of them,
    /// not only the latest: a frame may come several crossings after the one before it.
    pub cycle_crossings: Vec<(f64, DVec3)>,
    /// When the run last crossed its section (a full turn in 2D, ∂Ω in 3D) since α, m/m0 or
    /// the integrator last changed: a measuring sweep counts crossings by it.
    pub last_crossing_t: Option<f64>,
    /// The body is at rest: still, and the weight's torque about the contact zero, to
    /// `verdict::LIVE_REST_THRESHOLD` (`verdict::at_rest_within`, the rest every command
    /// decides by). A heavy body released from rest above α* is still at first, but pushed, and
    /// not halted.
    pub halted: bool,
    /// Angular speed |ω| (3D) or |θ̇| (2D).
    pub angular_speed: f64,
    /// 2D: the signed θ̇ (for the phase plot θ̇(θ)); `None` in 3D.
    pub theta_dot: Option<f64>,
    /// 2D: the contact angle θ (not wrapped), for the app's plots; `None` in 3D.
    pub theta: Option<f64>,
    /// Numerical health.
    pub health: Health,
    /// Why the integration stopped (one overlay line, shown in red), until the settings change.
    pub stopped: Option<String>,
    /// The ramp's force on the body now, in units of the weight F.
    pub contact_force: ContactForce,
    /// The contact force since the parameters last changed: its extremes, and when the body
    /// left the ramp or slipped on the scene's surface.
    pub contact: ContactReport,
    /// The first way the motion stopped being rollable since the parameters last changed (one
    /// overlay line, in red): the model's numbers go on, but no real body moves so.
    pub validity: Option<String>,
    /// A dented cylinder on its hull: tips across its flats so far, and the kinetic energy
    /// their impacts took; `None` for a convex body.
    pub hull_tips: Option<(u64, f64)>,
    /// The views in force (the scene's, as changed by the user or the timeline).
    pub views: ViewsSpec,
    /// The lesson's caption in force, if any.
    pub caption: Option<String>,
    /// Where the lesson is; `None` for a scene without a timeline.
    pub lesson: Option<LessonProgress>,
    /// Which Poincaré field the view should show now: decided here, once, for the app and the
    /// headless frames alike (they only fetch and draw it).
    pub poincare_field: FieldWanted,
    /// α, m/m0, the drag law or the integrator were changed by hand: the run no longer plays
    /// its scene (a lesson's evidence computed ahead is not this run's).
    pub off_script: bool,
    /// How the run got here, for a saved state's `[[replay]]` (see
    /// [`super::LiveRun::replayed`]); empty where it cannot be replayed.
    pub replay: Vec<crate::scene::ReplayEntry>,
    /// The body's name: the scene's name for its own body, a `[[bodies]]` entry's label (or
    /// "body N") for another.
    pub label: String,
    /// The scene's other bodies (`[[bodies]]`) at the same time, each as its own run shows it.
    pub lanes: Vec<Snapshot>,
    /// Whether this body is the scene's own body's shape (always, for the scene's own; for
    /// another body, when its entry takes the scene's body or one equal to it): its contact
    /// path then belongs on the scene's body's contact map.
    pub shares_body: bool,
    /// The rotational drag γ the run has, in units of γ0.
    pub drag_gamma: f64,
}

/// What a stated period T spans ([`Snapshot::stated_period`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PeriodSpan {
    /// A cylinder's full turn.
    FullTurn,
    /// A sphere's decided cycle: its `crossings` crossings of ∂Ω (1 on a closed orbit, 2 on a
    /// doubled one).
    Cycle {
        /// Crossings of ∂Ω in one repeat.
        crossings: usize,
    },
    /// A sphere whose cycle is not decided yet: the time between its last two crossings of ∂Ω,
    /// a first look, not yet a period.
    LastCrossings,
}

impl Snapshot {
    /// The period to state as T, and what it spans: a cylinder's full turn; a sphere's whole
    /// cycle once its multiplicity is decided, as the verdict's period is (`predict`, a lane's
    /// fate); before that the time between its last two crossings of ∂Ω. On a doubled cycle
    /// that time alternates (44.19 and 45.15 on the paper's body at m/m0 = 6) and is neither
    /// the period (89.33) nor steady, so a 1/T point or line taken from it would flicker
    /// between two wrong values. `None` before two turns (crossings).
    pub fn stated_period(&self) -> Option<(f64, PeriodSpan)> {
        if self.theta.is_some() {
            return self.period.map(|t| (t, PeriodSpan::FullTurn));
        }
        match (self.period_multiplicity, self.cycle_period) {
            (Some(crossings), Some(t)) => Some((t, PeriodSpan::Cycle { crossings })),
            _ => self.period.map(|t| (t, PeriodSpan::LastCrossings)),
        }
    }
}

/// What the Poincaré-field view needs at a moment of the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldWanted {
    /// The view is off (or the body is a cylinder: the map on ∂Ω is of 3D orientations).
    Off,
    /// The view is on but the model has inertia: the map on ∂Ω is of orientations alone, so
    /// there is no field to draw (the UI says so).
    NeedsViscous,
    /// The field of this viscous ramp; a field drawn for another ramp is stale.
    Ramp(Ramp),
}

/// How far a lesson has got.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LessonProgress {
    /// Steps applied so far.
    pub done: usize,
    /// Steps in the timeline.
    pub steps: usize,
    /// Simulation time of the next step, if one is left.
    pub next_at: Option<f64>,
}
