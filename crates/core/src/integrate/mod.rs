//! Time steppers for the rolling models, and the error control they need.
//!
//! Owns: the [`OdeSystem`] contract, the one stepping loop every run goes through ([`run`]; no
//! stepper can be built or stepped outside this module, see [`Stepper`]),
//! fixed-step RK4 ([`rk4`]), adaptive DOP853 with 7th-order
//! dense output ([`dop853`]), the commutator-free Lie-group RK4 step that keeps a unit
//! quaternion on the unit sphere to round-off ([`lie`]), event location on dense output
//! ([`events`]), uniform sample times, and recording the states a run evaluates
//! ([`record`], for timing a right-hand side as a run calls it). Imports only `std`, `glam` and `thiserror`.
//!
//! Why we wrote DOP853 ourselves: no maintained Rust crate offers DOP853 with dense output *and*
//! correct event location for small fixed-size states (see `STACK.md`: ode_solvers has no dense
//! output, differential-equations located events wrongly, diffsol has no DOP853). The method is
//! Hairer's, with his coefficients and step-size controller (Hairer, Nørsett & Wanner, *Solving
//! ODEs I*, §II.10), checked against analytic solutions in `tests/physics/integrator_order.rs`.
//!
//! States are plain `[f64; N]` arrays: no allocation per step, and the compiler unrolls the
//! stage loops, which is what makes a 3D run of 100 time units take milliseconds.

mod classical;
pub mod dop853;
pub mod events;
pub mod lie;
pub mod record;
pub mod rk4;
pub mod run;
pub mod spec;

pub use spec::{MethodKind, MethodParseError};

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The smallest absolute tolerance DOP853 accepts (see [`Method::validate`]).
pub const MIN_ATOL: f64 = 1e-20;

/// The longest time span one integration may cover: DOP853's smallest step is 16 ε times the
/// span, so past this the steps an orbit needs (~0.01) fall below what it can resolve.
pub const MAX_SPAN: f64 = 1e9;

/// A first-order system y' = f(t, y) on a fixed-size state.
pub trait OdeSystem<const N: usize> {
    /// The right-hand side f(t, y). May return non-finite values; steppers turn them into
    /// [`IntegrateError::NonFinite`].
    fn rhs(&self, t: f64, y: &[f64; N]) -> [f64; N];

    /// f(t, y) for a look aside the steps (the dense output's extra stages, built only when a
    /// sample or an observer asks): the same value, but a system that warm-starts an inner
    /// solve from its last evaluation must leave that start as it was, so that asking for
    /// dense output never moves the steps that follow. The default is [`Self::rhs`], for
    /// systems with no such state.
    fn rhs_aside(&self, t: f64, y: &[f64; N]) -> [f64; N] {
        self.rhs(t, y)
    }

    /// What the right-hand side remembers between calls (an inner solve's warm start, which
    /// moves the last bits of the next evaluation), as numbers: a run put down ([`Detached`])
    /// keeps it, so that taken up on a new copy of the system it goes on bit for bit. Empty
    /// (the default) for systems that remember nothing.
    fn memory(&self) -> Vec<f64> {
        Vec::new()
    }

    /// Restores what [`Self::memory`] gave (ignored where it does not fit).
    fn restore_memory(&self, _memory: &[f64]) {}

    /// Index of the first of four slots holding an orientation quaternion (w, x, y, z) that
    /// evolves as q̇ = ½ ω q, if the state has one. Lie-group steps use it to advance q by an
    /// exponential map; adaptive steps use it to report and control |q| − 1.
    fn quaternion_slot(&self) -> Option<usize> {
        None
    }
}

/// Which integrator to use, with its one accuracy parameter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Method {
    /// Classical fixed-step fourth-order Runge–Kutta, step `dt`.
    Rk4 {
        /// The step.
        dt: f64,
    },
    /// Adaptive 8(5,3) Dormand–Prince with relative tolerance `rtol` and absolute `atol`.
    Dop853 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// Fixed-step commutator-free Lie-group RK4 (CF4): the quaternion moves by exponentials, so
    /// |q| = 1 holds to round-off without projection; other components get classical RK4.
    Cf4 {
        /// The step.
        dt: f64,
    },
}

impl Method {
    /// DOP853 with `atol = rtol`, the setting used throughout the paper's reproductions.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::Method;
    /// assert!(matches!(Method::dop853(1e-9), Method::Dop853 { rtol, atol } if rtol == 1e-9 && atol == 1e-9));
    /// ```
    pub fn dop853(rtol: f64) -> Self {
        Method::Dop853 { rtol, atol: rtol }
    }

    /// Checks the accuracy parameter: steps and tolerances must be finite and positive.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::Method;
    /// assert!(Method::Rk4 { dt: 0.01 }.validate().is_ok());
    /// assert!(Method::Rk4 { dt: -0.01 }.validate().is_err());
    /// assert!(Method::dop853(f64::NAN).validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), IntegrateError> {
        let (name, value, ok) = match *self {
            Method::Rk4 { dt } | Method::Cf4 { dt } => ("dt", dt, dt.is_finite() && dt > 0.0),
            Method::Dop853 { rtol, atol } => {
                // rtol first: the command line defaults atol to rtol, so a bad --rtol must be
                // reported as itself.
                if !(1e-15..1.0).contains(&rtol) {
                    return Err(IntegrateError::BadParameter {
                        name: "rtol",
                        value: rtol,
                        allowed: "1e-15 ≤ rtol < 1",
                    });
                }
                if !(atol.is_finite() && atol >= MIN_ATOL) {
                    return Err(IntegrateError::BadParameter {
                        name: "atol",
                        value: atol,
                        allowed: "1e-20 ≤ atol: the state's components are of order 1, and an \
                                  absolute tolerance far below double precision's 2.2e-16 \
                                  resolution makes the first step vanish",
                    });
                }
                ("rtol", rtol, (1e-15..1.0).contains(&rtol))
            }
        };
        if ok {
            Ok(())
        } else {
            Err(IntegrateError::BadParameter {
                name,
                value,
                allowed: if name == "rtol" {
                    "1e-15 ≤ rtol < 1"
                } else {
                    "a finite number > 0"
                },
            })
        }
    }

    /// Short human name, as used on the command line.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::Method;
    /// assert_eq!(Method::Cf4 { dt: 0.05 }.name(), "cf4");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Method::Rk4 { .. } => "rk4",
            Method::Dop853 { .. } => "dop853",
            Method::Cf4 { .. } => "cf4",
        }
    }
}

/// "DOP853 rtol 1e-8", "RK4 dt 0.01": how the app, the overlay and the benchmarks name a setting.
impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Method::Dop853 { rtol, .. } => write!(f, "DOP853 rtol {rtol:.0e}"),
            Method::Rk4 { dt } => write!(f, "RK4 dt {}", readable(dt)),
            Method::Cf4 { dt } => write!(f, "CF4 dt {}", readable(dt)),
        }
    }
}

/// A number as people read it: Rust's shortest form between 1e-4 and 1e6, exponent form
/// outside (so 1e308 is not printed with 309 digits).
///
/// # Example
/// ```
/// use rollphase_core::integrate::readable;
/// assert_eq!(readable(0.25), "0.25");
/// assert_eq!(readable(1e308), "1e308");
/// ```
pub fn readable(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// What went wrong while integrating, and where.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum IntegrateError {
    /// The state or its derivative stopped being finite.
    #[error(
        "integration failed at t = {t}: the state became non-finite (NaN or infinite); \
         the model left its domain (a non-convex body, or a step too large for a fixed-step method)"
    )]
    NonFinite {
        /// When.
        t: f64,
    },
    /// The adaptive step fell below what floating point can resolve.
    #[error(
        "integration failed at t = {t}: the step size fell to {h:e}, below what double precision \
         resolves; the problem is stiff or singular here"
    )]
    StepTooSmall {
        /// When.
        t: f64,
        /// The step it fell to.
        h: f64,
    },
    /// A fixed step whose own error estimate (step doubling) is above the tolerance.
    #[error(
        "{method} with dt = {} is too coarse here: at t = {} the step's error estimate (step \
         doubling) is {estimate:.1e}, above the tolerance {tolerance:e}, so the run would be \
         silently wrong; use dt ≤ {} (a step whose estimate is near 2e-7, where the paper's \
         answers are kept: docs/guide/accuracy.md), or the adaptive dop853",
        readable(*dt), readable(*t), readable(*suggested)
    )]
    StepTooCoarse {
        /// When.
        t: f64,
        /// "rk4" or "cf4".
        method: &'static str,
        /// The step.
        dt: f64,
        /// The step-doubling error estimate.
        estimate: f64,
        /// The tolerance it exceeded.
        tolerance: f64,
        /// A step that would pass and keep the answers ([`rk4::ANSWER_STEP_ESTIMATE`]).
        suggested: f64,
    },
    /// More steps than the caller allowed.
    #[error("integration stopped at t = {t}: more than {max_steps} steps were needed")]
    TooManySteps {
        /// Where it stopped.
        t: f64,
        /// The budget.
        max_steps: u64,
    },
    /// An integrator parameter out of range.
    #[error("integrator parameter {name} = {} is not allowed (needs {allowed})", readable(*value))]
    BadParameter {
        /// Which parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}

/// Work counters of one run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Stats {
    /// Right-hand-side evaluations, dense-output stages included.
    pub rhs_evals: u64,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps (adaptive methods only).
    pub rejected: u64,
}

/// A stepper put down without its system: every number its next step and its last step's
/// interpolant depend on (time, state, proposed step, stages, interpolant, counters), so that
/// taken up again by [`run::Run::resume`] it continues bit for bit as if it had never stopped.
/// The app's live run keeps one between frames, so where the frames fall never moves the steps.
#[derive(Debug, Clone, PartialEq)]
pub struct Detached {
    pub(crate) method: Method,
    pub(crate) dimension: usize,
    pub(crate) numbers: Vec<f64>,
    /// The system's own memory ([`OdeSystem::memory`]).
    pub(crate) memory: Vec<f64>,
    pub(crate) dense_ready: bool,
    pub(crate) stats: Stats,
}

impl Detached {
    /// The time the stepper had reached.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Line;
    /// impl OdeSystem<1> for Line {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [1.0]
    ///     }
    /// }
    /// let mut run = Run::new(&Line, 0.0, [0.0], Method::Rk4 { dt: 0.5 })?;
    /// run.until::<IntegrateError>(1.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// assert_eq!(run.detach().t(), 1.0);
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn t(&self) -> f64 {
        self.numbers[0]
    }

    /// The method it steps with.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::Run;
    /// use rollphase_core::integrate::{Method, OdeSystem};
    /// struct Still;
    /// impl OdeSystem<1> for Still {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [0.0]
    ///     }
    /// }
    /// let run = Run::new(&Still, 0.0, [1.0], Method::Cf4 { dt: 0.1 })?;
    /// assert_eq!(run.detach().method(), Method::Cf4 { dt: 0.1 });
    /// # Ok::<(), rollphase_core::integrate::IntegrateError>(())
    /// ```
    pub fn method(&self) -> Method {
        self.method
    }
}

/// Takes up a [`Detached`] stepper on `system`; `None` when it was put down by a stepper of
/// another state size.
fn attach<'a, S, const N: usize>(
    system: &'a S,
    detached: &Detached,
) -> Option<Box<dyn Advance<N> + 'a>>
where
    S: OdeSystem<N>,
{
    if detached.dimension != N {
        return None;
    }
    system.restore_memory(&detached.memory);
    Some(match detached.method {
        Method::Dop853 { .. } => Box::new(dop853::Dop853::attach(system, detached)?),
        Method::Rk4 { .. } | Method::Cf4 { .. } => {
            Box::new(rk4::FixedStep::attach(system, detached)?)
        }
    })
}

/// The stepper of a run as an observer sees it after each accepted step: the state, the last
/// step's interpolant and the work done. It has no way to take a step: only [`run::Run`] moves
/// a trajectory (the one-loop rule, held by the compiler: the method that steps is on a trait
/// private to `integrate`, and so are [`Dop853`](dop853::Dop853)'s and the fixed steps'
/// constructors).
///
/// An observer that tried to step would not compile:
/// ```compile_fail,E0599
/// use rollphase_core::integrate::run::{Flow, Run};
/// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
/// struct Decay;
/// impl OdeSystem<1> for Decay {
///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
///         [-y[0]]
///     }
/// }
/// let mut run = Run::new(&Decay, 0.0, [1.0], Method::dop853(1e-9)).unwrap();
/// run.until::<IntegrateError>(1.0, u64::MAX, |st| {
///     st.step(2.0)?; // no such method: an observer never moves the run
///     Ok(Flow::Continue)
/// });
/// ```
/// Nor would a stepper built outside a run:
/// ```compile_fail,E0603
/// use rollphase_core::integrate::{Method, OdeSystem, stepper};
/// struct Decay;
/// impl OdeSystem<1> for Decay {
///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
///         [-y[0]]
///     }
/// }
/// let _ = stepper(&Decay, 0.0, [1.0], Method::dop853(1e-9));
/// ```
/// ```compile_fail,E0624
/// use rollphase_core::integrate::dop853::Dop853;
/// use rollphase_core::integrate::OdeSystem;
/// struct Decay;
/// impl OdeSystem<1> for Decay {
///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
///         [-y[0]]
///     }
/// }
/// let _ = Dop853::new(&Decay, 0.0, [1.0], 1e-9, 1e-12);
/// ```
pub trait Stepper<const N: usize> {
    /// Current time.
    fn t(&self) -> f64;
    /// Current state.
    fn y(&self) -> &[f64; N];
    /// Time at the start of the last accepted step.
    fn t_prev(&self) -> f64;
    /// State at the start of the last accepted step.
    fn y_prev(&self) -> &[f64; N];
    /// State at `t` in `[t_prev, t]` from the interpolant of the last step.
    fn dense(&mut self, t: f64) -> [f64; N];
    /// Work done so far.
    fn stats(&self) -> Stats;
    /// Puts the stepper down without its system ([`Detached`]).
    fn detach(&self) -> Detached;
    /// The largest local error estimate a fixed-step method has checked so far (relative to
    /// 1 + |y|, see [`rk4`]); `None` for adaptive methods, which control their error.
    fn largest_error_estimate(&self) -> Option<f64> {
        None
    }
}

/// The one thing an observer's [`Stepper`] cannot do: take a step. Private to `integrate`, so
/// the only loop that calls it is [`run`]'s.
trait Advance<const N: usize>: Stepper<N> {
    /// Takes one accepted step, never past `t_limit`.
    fn step(&mut self, t_limit: f64) -> Result<(), IntegrateError>;
}

/// Builds the stepper for `method` starting at (t0, y0): for [`run::Run::new`] alone.
fn stepper<'a, S, const N: usize>(
    system: &'a S,
    t0: f64,
    y0: [f64; N],
    method: Method,
) -> Result<Box<dyn Advance<N> + 'a>, IntegrateError>
where
    S: OdeSystem<N>,
{
    method.validate()?;
    if y0.iter().any(|v| !v.is_finite()) {
        return Err(IntegrateError::NonFinite { t: t0 });
    }
    Ok(match method {
        Method::Rk4 { dt } => Box::new(rk4::FixedStep::new(system, rk4::Scheme::Rk4, t0, y0, dt)),
        Method::Dop853 { rtol, atol } => Box::new(dop853::Dop853::new(system, t0, y0, rtol, atol)),
        Method::Cf4 { dt } => Box::new(rk4::FixedStep::new(system, rk4::Scheme::Cf4, t0, y0, dt)),
    })
}

/// `n` equally spaced times from `t0` to `t_end` inclusive (n ≥ 2), or just `[t_end]` for n = 1.
///
/// # Example
/// ```
/// use rollphase_core::integrate::uniform_times;
/// assert_eq!(uniform_times(0.0, 1.0, 5), [0.0, 0.25, 0.5, 0.75, 1.0]);
/// assert_eq!(uniform_times(0.0, 1.0, 1), [1.0]);
/// ```
pub fn uniform_times(t0: f64, t_end: f64, n: usize) -> Vec<f64> {
    match n {
        0 => Vec::new(),
        1 => vec![t_end],
        _ => (0..n)
            .map(|i| {
                if i + 1 == n {
                    t_end
                } else {
                    t0 + (t_end - t0) * i as f64 / (n - 1) as f64
                }
            })
            .collect(),
    }
}

/// Returns the time step ≤ `dt` that divides `span` into a whole number of steps, so a
/// fixed-step method lands exactly on `t_end`.
pub(crate) fn fitted_step(span: f64, dt: f64) -> f64 {
    if span <= 0.0 {
        return dt;
    }
    let n = (span / dt).ceil().max(1.0);
    span / n
}

/// Cubic Hermite interpolation between (y0, f0) at θ = 0 and (y1, f1) at θ = 1 over a step h.
pub(crate) fn hermite<const N: usize>(
    y0: &[f64; N],
    f0: &[f64; N],
    y1: &[f64; N],
    f1: &[f64; N],
    h: f64,
    theta: f64,
) -> [f64; N] {
    let t2 = theta * theta;
    let t3 = t2 * theta;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + theta;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    std::array::from_fn(|i| h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i])
}

pub(crate) fn all_finite<const N: usize>(y: &[f64; N]) -> bool {
    y.iter().all(|v| v.is_finite())
}

/// The three named accuracy settings offered to users (the app's fast / balanced / precise),
/// chosen from `rollphase bench accuracy` (docs/accuracy): all DOP853, because an adaptive step
/// copes with the extremes (α → π/2, small m/m0) where a fixed step fails or wastes work.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    /// rtol 1e-6: ~1.6k RHS evaluations per 100 time units.
    Fast,
    /// rtol 1e-8: ~2.5k RHS evaluations per 100 time units.
    Balanced,
    /// rtol 1e-12: ~7k RHS evaluations per 100 time units.
    Precise,
}

impl Preset {
    /// All presets, fastest first.
    pub const ALL: [Preset; 3] = [Preset::Fast, Preset::Balanced, Preset::Precise];

    /// The integrator setting.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::{Method, Preset};
    /// assert_eq!(Preset::Balanced.method(), Method::dop853(1e-8));
    /// ```
    pub fn method(self) -> Method {
        Method::dop853(match self {
            Preset::Fast => 1e-6,
            Preset::Balanced => 1e-8,
            Preset::Precise => 1e-12,
        })
    }

    /// Expected state error at t = 100: the largest measured over the four models on the bundled
    /// bodies (orientation in rad, position in ⟨r⟩), rounded up. `tests/command_line/presets.rs` re-measures it.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::Preset;
    /// // More precise presets promise smaller errors.
    /// assert!(Preset::Precise.expected_state_error() < Preset::Fast.expected_state_error());
    /// ```
    pub fn expected_state_error(self) -> f64 {
        match self {
            Preset::Fast => 6e-5,
            Preset::Balanced => 1e-5,
            Preset::Precise => 5e-11,
        }
    }

    /// Expected relative error of the orbit period, measured likewise.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::Preset;
    /// assert!(Preset::Precise.expected_period_error() < Preset::Balanced.expected_period_error());
    /// ```
    pub fn expected_period_error(self) -> f64 {
        match self {
            Preset::Fast => 2e-6,
            Preset::Balanced => 1e-6,
            Preset::Precise => 2e-12,
        }
    }

    /// Lower-case name.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::Preset;
    /// assert_eq!(Preset::Fast.name(), "fast");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Preset::Fast => "fast",
            Preset::Balanced => "balanced",
            Preset::Precise => "precise",
        }
    }
}
