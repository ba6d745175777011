//! A run's fate, in the words every surface uses: rolling periodic, neutral (a round body: one
//! motion, no orbit attracts), halted, left the model (lift-off or slip), or undecided with what
//! would decide it. The decisions that several analyses share live here, so that they cannot
//! drift apart:
//! - [`at_rest`]: a body is at rest only where it is still *and* the ramp's torque on it
//!   vanishes (an equilibrium). |ω| alone is not enough: a very heavy body above α* starts with
//!   ω = 0 and speeds up over a time m/m0 (t0), and was called halted.
//! - [`Stability::of`]: an orbit attracts (every |μ| < 1 by more than its evidence resolves),
//!   is neutral (|μ| = 1 within the multipliers' accuracy, or so close that it neither attracts
//!   nor repels over the run's horizon), or repels. A perfect sphere's rolling motions have
//!   |μ| = 1 to round-off: they were listed as 32 "unstable" orbits.
//! - [`Undecided`]: why a run has no answer yet, and what would give it one.
//!
//! An orbit within the neutral band is a motion with no preferred member: starts that roll
//! near one are counted as [`Fate::Neutral`], not as undecided, whether or not their crossings
//! repeated within the runs' tolerance (a near-round printed ball attracts over ~1e5 periods).
//!
//! Imports only `dynamics` (a model's observation, the contact force's violations); the runs decide with
//! these and report a [`Fate`] per start, tallied by [`FateCounts`].

use glam::DVec3;
use serde::Serialize;

use crate::dynamics::validity::Violation;
use crate::dynamics::{Observation, RollingModel};

/// |ω| and the ramp's torque (units of F⟨r⟩, and of F⟨r⟩/γ for ω) below which a body is at rest.
pub const REST_THRESHOLD: f64 = 1e-9;

/// Whether a body with angular speed `angular_speed` under a ramp torque of size
/// `ramp_torque` (|r × F|, the torque of its weight about the contact) is at rest: both below
/// [`REST_THRESHOLD`]. In the viscous model ω is that torque over γ, so the two agree; with
/// inertia a body can be momentarily still where the torque is not zero (it starts from rest, or
/// turns back), and it is not at rest there.
///
/// # Example
/// ```
/// use rollphase_core::analysis::verdict::at_rest;
/// assert!(at_rest(1e-12, 1e-11));
/// // A heavy body released above α*: still, but pushed: it is speeding up, not halted.
/// assert!(!at_rest(1e-12, 0.05));
/// ```
pub fn at_rest(angular_speed: f64, ramp_torque: f64) -> bool {
    at_rest_within(angular_speed, ramp_torque, REST_THRESHOLD)
}

/// The live run's resolution of a rest ([`at_rest_within`]): it shows a body as halted once
/// still and unpushed to 1e-6 (a turn in ~6e6 t0, far below what the eye sees), where a run that
/// decides a fate waits for [`REST_THRESHOLD`]. A body that rolls above α* never slows that much
/// at the α a live control can set (its slowest |ω| grows like √(α − α*), and the finest step
/// of α there is 1e-5 rad), so the coarser resolution shows no false halt; a slow settling rest
/// shows as one hundreds of t0 earlier.
pub const LIVE_REST_THRESHOLD: f64 = 1e-6;

/// [`at_rest`] to the resolution `threshold`: both the angular speed and the weight's unbalanced
/// torque below it. The one rest rule; the resolution is the caller's.
///
/// # Example
/// ```
/// use rollphase_core::analysis::verdict::{LIVE_REST_THRESHOLD, at_rest_within};
/// assert!(at_rest_within(3e-7, 1e-7, LIVE_REST_THRESHOLD));
/// assert!(!at_rest_within(0.0, 0.2, LIVE_REST_THRESHOLD)); // still, but pushed
/// ```
pub fn at_rest_within(angular_speed: f64, ramp_torque: f64, threshold: f64) -> bool {
    angular_speed < threshold && ramp_torque < threshold
}

/// [`at_rest`] for `model` at state `y`: its angular speed and the weight's unbalanced torque
/// ([`crate::dynamics::Observation::ramp_torque`]), for any model. Every run that decides a rest
/// and the app's live run ask this.
///
/// # Example
/// ```
/// use rollphase_core::analysis::verdict::state_at_rest;
/// use rollphase_core::dynamics::{Ramp, SphereInertial};
/// use rollphase_core::geometry::Sphere;
/// use rollphase_core::glam::{DQuat, DVec3};
/// // A heavy ball released from rest: still, but the weight turns it: not at rest.
/// let ball = Sphere::perfect();
/// let model = SphereInertial::new(&ball, &Ramp::new(0.3, 1e6)?);
/// assert!(!state_at_rest(&model, &SphereInertial::initial_state(DQuat::IDENTITY, DVec3::ZERO)));
/// # Ok::<(), rollphase_core::dynamics::ModelError>(())
/// ```
pub fn state_at_rest<const N: usize, M: RollingModel<N>>(model: &M, y: &[f64; N]) -> bool {
    rest_measure(model, y) < REST_THRESHOLD
}

/// The resolution of a rest that a run at relative tolerance `rtol` (an adaptive step's) can
/// show: [`REST_THRESHOLD`], or 10 rtol where that is coarser. The integrator keeps a resting
/// state only to its tolerance, so the weight's torque there stays at the integrator's error:
/// an inertial disk come to rest in its well had a torque near 1e-7 at rtol 1e-6, and the
/// 1e-9 rule called 2 of 32 halted disks undecided (seed-1 disk, α 0.5–1.5 α*, m/m0 0.5–50).
/// At rtol ≤ 1e-10 it is [`REST_THRESHOLD`] itself. The one rest rule ([`at_rest_within`]), at
/// the resolution the run has.
///
/// # Example
/// ```
/// use rollphase_core::analysis::verdict::{REST_THRESHOLD, rest_resolution};
/// assert_eq!(rest_resolution(1e-10), REST_THRESHOLD);
/// assert!((rest_resolution(1e-6) - 1e-5).abs() < 1e-20);
/// ```
pub fn rest_resolution(rtol: f64) -> f64 {
    REST_THRESHOLD.max(10.0 * rtol)
}

/// [`state_at_rest`] to the resolution of a run at relative tolerance `rtol`
/// ([`rest_resolution`]).
///
/// # Example
/// ```
/// use rollphase_core::analysis::verdict::state_at_rest_for;
/// use rollphase_core::dynamics::{Ramp, SphereInertial};
/// use rollphase_core::geometry::Sphere;
/// use rollphase_core::glam::{DQuat, DVec3};
/// let ball = Sphere::perfect();
/// let model = SphereInertial::new(&ball, &Ramp::new(0.3, 2.0)?);
/// // Released from rest on a ramp: pushed, at any resolution.
/// let y = SphereInertial::initial_state(DQuat::IDENTITY, DVec3::ZERO);
/// assert!(!state_at_rest_for(&model, &y, 1e-6));
/// # Ok::<(), rollphase_core::dynamics::ModelError>(())
/// ```
pub fn state_at_rest_for<const N: usize, M: RollingModel<N>>(
    model: &M,
    y: &[f64; N],
    rtol: f64,
) -> bool {
    rest_measure(model, y) < rest_resolution(rtol)
}

/// How far `model` at `y` is from rest: the larger of its angular speed and the weight's
/// unbalanced torque ([`at_rest`] is this below [`REST_THRESHOLD`]). What an undecided run
/// reports at its end, and what a run with its own rest threshold compares.
///
/// # Example
/// ```
/// use rollphase_core::analysis::verdict::rest_measure;
/// use rollphase_core::dynamics::{Ramp, SphereViscous};
/// use rollphase_core::geometry::Sphere;
/// use rollphase_core::glam::DQuat;
/// // The viscous unit ball rolls at |ω| = sin α, the weight's torque over γ.
/// let ball = Sphere::perfect();
/// let model = SphereViscous::new(&ball, &Ramp::new(0.3, 0.0)?);
/// let m = rest_measure(&model, &SphereViscous::initial_state(DQuat::IDENTITY));
/// assert!((m - 0.3f64.sin()).abs() < 1e-12);
/// # Ok::<(), rollphase_core::dynamics::ModelError>(())
/// ```
pub fn rest_measure<const N: usize, M: RollingModel<N>>(model: &M, y: &[f64; N]) -> f64 {
    observed_rest_measure(&model.observation(y))
}

/// [`rest_measure`] of an observation already made (a run that observes each step anyway).
///
/// # Example
/// ```
/// use rollphase_core::analysis::verdict::{observed_rest_measure, rest_measure};
/// use rollphase_core::dynamics::{Ramp, RollingModel, SphereInertial};
/// use rollphase_core::geometry::Sphere;
/// use rollphase_core::glam::{DQuat, DVec3};
/// let ball = Sphere::perfect();
/// let model = SphereInertial::new(&ball, &Ramp::new(0.3, 2.0)?);
/// let y = SphereInertial::initial_state(DQuat::IDENTITY, DVec3::new(0.0, 0.5, 0.0));
/// assert_eq!(observed_rest_measure(&model.observation(&y)), rest_measure(&model, &y));
/// # Ok::<(), rollphase_core::dynamics::ModelError>(())
/// ```
pub fn observed_rest_measure(o: &Observation) -> f64 {
    o.angular_speed.max(o.ramp_torque)
}

/// The accuracy of a Floquet multiplier's modulus from the return map's finite differences
/// (`OrbitSolve::default`: map to ~1e-9, step 1e-5, so ~1e-4).
pub const MULTIPLIER_ACCURACY: f64 = 1e-4;

/// Whether a periodic orbit attracts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stability {
    /// Every |μ| below 1 by more than the band of [`Stability::of`].
    Stable,
    /// The largest |μ| within the band around 1: one member of a family of motions (a round
    /// body rolls straight on any great circle), none of which attracts within the horizon.
    Neutral,
    /// The largest |μ| above 1 by more than the band.
    Unstable,
}

impl Stability {
    /// The stability of an orbit of period `period` whose largest multiplier has modulus
    /// `max_modulus`, judged over `horizon` (the runs' length, t0). The band around |μ| = 1 is
    /// the larger of [`MULTIPLIER_ACCURACY`] and `period / horizon`: within it the evidence
    /// cannot tell attraction from neutrality, or a perturbation changes by less than a factor
    /// e over the horizon (|μ|^(horizon/period) ≈ e^(±(|μ|−1)·horizon/period)).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::verdict::Stability;
    /// assert_eq!(Stability::of(0.98, 30.0, 20_000.0), Stability::Stable);
    /// // A perfect sphere: |μ| = 1 to round-off.
    /// assert_eq!(Stability::of(1.0000000000014, 21.26, 20_000.0), Stability::Neutral);
    /// // 1 − |μ| = 1e-5 takes 1e5 periods to act: neutral over 20 000 t0.
    /// assert_eq!(Stability::of(0.99999, 21.0, 20_000.0), Stability::Neutral);
    /// assert_eq!(Stability::of(1.2, 30.0, 20_000.0), Stability::Unstable);
    /// ```
    pub fn of(max_modulus: f64, period: f64, horizon: f64) -> Stability {
        let band = MULTIPLIER_ACCURACY.max(period / horizon);
        if max_modulus < 1.0 - band {
            Stability::Stable
        } else if max_modulus <= 1.0 + band {
            Stability::Neutral
        } else {
            Stability::Unstable
        }
    }

    /// "stable", "neutral" or "unstable".
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::verdict::Stability;
    /// assert_eq!(Stability::Neutral.name(), "neutral");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Stability::Stable => "stable",
            Stability::Neutral => "neutral",
            Stability::Unstable => "unstable",
        }
    }
}

/// The largest step between successive section points (antipodes identified) below which a
/// steady drift counts as neutral ([`steady_drift`]).
pub const NEUTRAL_DRIFT: f64 = 1e-3;

/// Whether section points `points` (one per crossing, oldest first) drift steadily and slowly:
/// the step between the last two below [`NEUTRAL_DRIFT`], and within a factor e of the step
/// halfway through the run, so the motion neither settles nor departs over the run: the sign
/// of a neutral family (a near-round body, whose orbits attract over ~1e5 periods), where
/// Newton's method on the return map may find no fixed point, the map being the identity to
/// its accuracy. Returns the last step; `None` with fewer than 8 points or otherwise.
///
/// # Example
/// ```
/// use rollphase_core::analysis::verdict::steady_drift;
/// use rollphase_core::glam::DVec3;
/// // A point creeping along a great circle by 1e-5 a crossing.
/// let creep: Vec<DVec3> = (0..100).map(|i| DVec3::new((1e-5 * i as f64).cos(), (1e-5 * i as f64).sin(), 0.0)).collect();
/// assert!(steady_drift(&creep).is_some_and(|d| (d - 1e-5).abs() < 1e-9));
/// // A point settling geometrically: its steps shrink by far more than e over the run.
/// let settling: Vec<DVec3> = (0..100).map(|i| DVec3::new(1.0, 0.5f64.powi(i), 0.0).normalize()).collect();
/// assert_eq!(steady_drift(&settling), None);
/// ```
pub fn steady_drift(points: &[DVec3]) -> Option<f64> {
    let n = points.len();
    if n < 8 {
        return None;
    }
    let step = |i: usize| {
        let (a, b) = (points[i], points[i - 1]);
        (a - b).length().min((a + b).length())
    };
    let (last, middle) = (step(n - 1), step(n / 2));
    let steady =
        last < NEUTRAL_DRIFT && last > 0.0 && middle > 0.0 && (last / middle).ln().abs() <= 1.0;
    steady.then_some(last)
}

/// Why a run has no answer yet.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Undecided {
    /// It never completed a turn (no crossing of the section) and is not at rest: a heavy body
    /// still speeding up, or one creeping towards a rest point too slowly to reach it.
    NoTurn {
        /// The run's length (t0).
        t_cap: f64,
        /// |ω| at its end.
        angular_speed: f64,
    },
    /// It keeps rolling, but its section crossings close no cycle of at most `max_k` within
    /// the tolerance: a long transient, a longer cycle, or a motion that never repeats.
    NoRepeat {
        /// The run's length (t0).
        t_cap: f64,
        /// Crossings of the section it made.
        crossings: usize,
        /// The longest cycle looked for, in crossings.
        max_k: usize,
    },
    /// A viscous cylinder so close above its critical angle that its period, which grows as
    /// (α − α*)^−½, is not known to 1 %: α* is found to a few ulps, or 1/θ̇ overflows at the
    /// contact angle of α*.
    AtThreshold {
        /// α − α* (rad).
        alpha_above: f64,
    },
    /// Followed for a fixed time and still moving there: a run that only follows the body
    /// (`simulate`) decides a lift-off, a slip and a rest, and does not look for a cycle.
    NotSettled {
        /// The run's end (t0).
        t_end: f64,
        /// How far from rest it was there ([`rest_measure`]).
        from_rest: f64,
    },
    /// A settle run (a sweep's, a figure's) still moving at its cap without closing a cycle of
    /// at most `max_k` crossings of ∂Ω within the settle tolerance.
    NoCycle {
        /// The run's length (t0).
        t_cap: f64,
        /// How far from rest it was there ([`rest_measure`]).
        from_rest: f64,
        /// The longest cycle looked for, in crossings.
        max_k: usize,
    },
}

impl Undecided {
    /// What would decide it, in one sentence for a user.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::verdict::Undecided;
    /// let u = Undecided::NoTurn { t_cap: 20_000.0, angular_speed: 2e-6 };
    /// assert!(u.what_would_decide().contains("longer run"));
    /// ```
    pub fn what_would_decide(&self) -> String {
        match *self {
            Undecided::NoTurn {
                t_cap,
                angular_speed,
            } => format!(
                "no full turn by t = {t_cap}{}, and not at rest: a longer run would tell (a heavy \
                 body speeds up over about m/m0 t0)",
                if angular_speed.is_finite() {
                    format!(" (|ω| = {angular_speed:.3e} at the end)")
                } else {
                    String::new()
                }
            ),
            Undecided::NoRepeat {
                t_cap,
                crossings,
                max_k,
            } => format!(
                "still rolling at t = {t_cap} after {crossings} crossings of the section (∂Ω in \
                 3D, a whole turn in 2D), with no cycle of ≤ {max_k} crossings: a longer run may \
                 settle it; the motion may also never repeat"
            ),
            Undecided::AtThreshold { alpha_above } => format!(
                "α − α* = {alpha_above:.3e} is too close to α* for a period to be known (T grows \
                 as (α − α*)^−½, and α* itself is found to a few ulps, which this close leaves \
                 T over 1 % uncertain): a larger α would decide it"
            ),
            Undecided::NotSettled { t_end, from_rest } => format!(
                "still moving at t = {t_end} (|ω| or the weight's torque {from_rest:.3e}); a \
                 fixed-time run does not look for a cycle: `rollphase period` (a cylinder) or \
                 `rollphase predict` (a sphere) decides whether the motion repeats"
            ),
            Undecided::NoCycle {
                t_cap,
                from_rest,
                max_k,
            } => format!(
                "still moving at t = {t_cap} (|ω| or the weight's torque {from_rest:.3e}) with \
                 no cycle of ≤ {max_k} crossings of ∂Ω: a longer t_max may settle it; the \
                 motion may also never repeat"
            ),
        }
    }

    /// Its short name, as JSON writes it ("no_turn", "no_repeat").
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::verdict::Undecided;
    /// let u = Undecided::NoRepeat { t_cap: 1.0, crossings: 3, max_k: 2 };
    /// assert_eq!(u.name(), "no_repeat");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Undecided::NoTurn { .. } => "no_turn",
            Undecided::NoRepeat { .. } => "no_repeat",
            Undecided::AtThreshold { .. } => "at_threshold",
            Undecided::NotSettled { .. } => "not_settled",
            Undecided::NoCycle { .. } => "no_cycle",
        }
    }
}

/// What became of one start.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "fate", rename_all = "snake_case")]
pub enum Fate {
    /// It settled on a periodic orbit that attracts.
    Periodic {
        /// Crossings of the section per repeat (1, or 2 for a doubled orbit).
        multiplicity: usize,
    },
    /// It rolls on a neutral orbit: one of a family, none attracting.
    Neutral,
    /// It came to rest (still, and the ramp's torque zero), at `t`.
    Halted {
        /// When (t0), where the run knows it (a viscous disk's rest is found without a run).
        t: Option<f64>,
    },
    /// The rolling model stopped holding: the body leaves the ramp or slips.
    LeftModel {
        /// What happened, and when.
        violation: Violation,
    },
    /// No answer within the run.
    Undecided {
        /// Why, and what would decide it.
        why: Undecided,
    },
}

impl Fate {
    /// Its word, as JSON and CSV write it: "periodic", "neutral", "halted", "left_model" or
    /// "undecided".
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::verdict::Fate;
    /// assert_eq!(Fate::Halted { t: Some(3.0) }.name(), "halted");
    /// assert_eq!(Fate::Periodic { multiplicity: 2 }.name(), "periodic");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Fate::Periodic { .. } => "periodic",
            Fate::Neutral => "neutral",
            Fate::Halted { .. } => "halted",
            Fate::LeftModel { .. } => "left_model",
            Fate::Undecided { .. } => "undecided",
        }
    }
}

/// How the starts of a study ended, as fractions of all starts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FateCounts {
    /// Settled on an attracting orbit.
    pub periodic: f64,
    /// Rolling on a neutral orbit.
    pub neutral: f64,
    /// At rest.
    pub halted: f64,
    /// Left the ramp or slipped.
    pub left_model: f64,
    /// No answer.
    pub undecided: f64,
    /// Each reason a start is undecided, with the fraction of starts it holds (largest first)
    /// and what would decide it.
    pub undecided_reasons: Vec<UndecidedShare>,
    /// The first violation seen among the starts that left the model.
    pub first_violation: Option<Violation>,
}

/// One reason for undecided starts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UndecidedShare {
    /// "no_turn", "no_repeat", "at_threshold" or "not_settled".
    pub reason: &'static str,
    /// Fraction of all starts.
    pub fraction: f64,
    /// What would decide them (from one of them).
    pub what_would_decide: String,
}

impl FateCounts {
    /// Tallies `fates`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::verdict::{Fate, FateCounts, Undecided};
    /// let fates = [
    ///     Fate::Periodic { multiplicity: 1 },
    ///     Fate::Halted { t: Some(40.0) },
    ///     Fate::Undecided { why: Undecided::NoTurn { t_cap: 100.0, angular_speed: 1e-3 } },
    ///     Fate::Periodic { multiplicity: 2 },
    /// ];
    /// let c = FateCounts::of(&fates);
    /// assert_eq!((c.periodic, c.halted, c.undecided), (0.5, 0.25, 0.25));
    /// assert_eq!(c.undecided_reasons[0].reason, "no_turn");
    /// ```
    pub fn of(fates: &[Fate]) -> FateCounts {
        let n = fates.len().max(1) as f64;
        let share = |f: &dyn Fn(&Fate) -> bool| fates.iter().filter(|x| f(x)).count() as f64 / n;
        let mut reasons: Vec<UndecidedShare> = Vec::new();
        for f in fates {
            if let Fate::Undecided { why } = f {
                match reasons.iter_mut().find(|r| r.reason == why.name()) {
                    Some(r) => r.fraction += 1.0 / n,
                    None => reasons.push(UndecidedShare {
                        reason: why.name(),
                        fraction: 1.0 / n,
                        what_would_decide: why.what_would_decide(),
                    }),
                }
            }
        }
        reasons.sort_by(|a, b| b.fraction.total_cmp(&a.fraction));
        let first_violation = fates
            .iter()
            .filter_map(|f| match f {
                Fate::LeftModel { violation } => Some(*violation),
                _ => None,
            })
            .min_by(|a, b| a.t().total_cmp(&b.t()));
        FateCounts {
            periodic: share(&|f| matches!(f, Fate::Periodic { .. })),
            neutral: share(&|f| matches!(f, Fate::Neutral)),
            halted: share(&|f| matches!(f, Fate::Halted { .. })),
            left_model: share(&|f| matches!(f, Fate::LeftModel { .. })),
            undecided: share(&|f| matches!(f, Fate::Undecided { .. })),
            undecided_reasons: reasons,
            first_violation,
        }
    }
}
