//! 3D orbits through the boundary ∂Ω of the SO(3) ball (paper Fig. 3–4, SI §2G).
//!
//! An orientation q (q and −q the same) is drawn as the vector part of ±q with q_w ≥ 0, a point of
//! the unit ball Ω; q_w = 0 is its boundary ∂Ω, where antipodal points are identified. Every
//! crossing of q_w = 0 is located on the dense output (Brent), giving a boundary point p (unit
//! vector, sign irrelevant). The Poincaré map P sends one crossing to the next; V = P(p) − p
//! (with the sign of P(p) chosen nearest p) is the paper's vector field on ∂Ω. A fixed point of P
//! is a closed, period-1 orbit; a cycle of P of length k a period-k orbit (period doubling:
//! k = 2).
//!
//! A fate found with a fast integrator is an answer of that integrator, not of the model: a step
//! of 0.8 (or DOP853 at rtol 1e-4) gets the paper body's fates at α = 0.2, m/m0 = 6 wrong. So
//! [`settle_checked`] re-decides every fate that a setting coarser than the reference (DOP853 at
//! [`Settle::rtol`]) reports before it is given out: a period-1 cycle is followed on from its
//! last crossing with the reference until the reference closes its own cycle (cheap: a few
//! periods after the fast run's transient); a cycle of k ≥ 2, a halt, or a run undecided at
//! `t_max` is run again from the start with the reference (a halt cannot be checked from the
//! rest point it ended at, and near a flip the k the settle criterion finds depends on where
//! the transient stands). The reported fate is the reference's, with [`AnswerCheck`] saying
//! whether the fast one agreed.
//!
//! A cycle of k ≥ 2 is an answer only once it is steady ([`steady_cycle`]): a run spiralling
//! onto a period-1 orbit looks like a cycle of 2 or 3 crossings long before its crossings
//! repeat one by one. Until 2026-11-26 [`settle`] called such transients answers: the "false
//! period doublings" of RK4 at dt 0.4–0.5 and DOP853 at rtol 1e-6 on the m/m0 = 6 case, and a
//! "period 3" (96.57 = 3 × 32.19) that DOP853 at rtol 1e-12 itself gave the paper body at
//! α = 0.2014, m/m0 = 6, were all transients of period-1 orbits.

use glam::{DQuat, DVec3};
use serde::Serialize;

use crate::analysis::verdict::{Fate, Undecided, rest_measure, state_at_rest};
use crate::dynamics::ModelKind;
use crate::dynamics::sphere3d::SphereObservation;
use crate::dynamics::validity::{ContactLimits, ContactReport, ContactWatch};
use crate::dynamics::{Ramp, RollingModel, SphereInertial, SphereViscous};
use crate::geometry::Sphere;
use crate::integrate::events::{Direction, crossings_in_last_step};
use crate::integrate::run::{Flow, Run, Samples};
use crate::integrate::{self, IntegrateError, Method, Stats};

/// Expands `$run` for the body's 3D model (viscous if m/m0 = 0, else inertial from rest),
/// with `$sys` the model and `$y0` its initial state (a macro rather than a closure: the two models' states differ in size, a const generic a closure cannot take).
macro_rules! on_model {
    ($body:expr, $ramp:expr, $q0:expr, |$sys:ident, $y0:ident| $run:expr) => {
        match ModelKind::for_dimension(3, $ramp) {
            ModelKind::SphereViscous => {
                let model = SphereViscous::new($body, $ramp);
                let $sys = &model;
                let $y0 = SphereViscous::initial_state($q0);
                $run
            }
            ModelKind::SphereInertial => {
                let model = SphereInertial::new($body, $ramp);
                let $sys = &model;
                let $y0 = SphereInertial::initial_state($q0, DVec3::ZERO);
                $run
            }
            other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => other.wrong_dimension(3),
        }
    };
}

/// Two solved periodic orbits (Newton on the return map, to ~1e-9 on ∂Ω) are one when their
/// crossings of ∂Ω agree to this (antipodes identified): a thousand times the solve's error, and
/// far below the distance between distinct orbits of the bodies rolled here (≥ 0.1 on the
/// paper's). The one "same orbit" of solved orbits: `predict`, the study of the orbits the
/// starts settle on, and the figures' attractors ask it.
pub const SAME_ORBIT: f64 = 1e-6;

/// Runs that settled on a cycle (their crossings repeating to [`Decide::tol`], 1e-5, where a
/// slow multiplier can leave the last crossing ~1e-4 off the orbit) are on one orbit when their
/// last crossings agree to this: they seed one Newton solve, whose orbit [`SAME_ORBIT`] then
/// compares. The one "same orbit" of settled runs: `predict`, the studies, the orbit diagram
/// and the `sphere-orbits` figure ask it.
pub const SETTLED_ON_SAME_ORBIT: f64 = 1e-3;

/// Distance between two boundary points with antipodes identified.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::boundary_distance;
/// use rollphase_core::glam::DVec3;
/// // q and −q are one orientation: antipodes are the same point of ∂Ω.
/// assert_eq!(boundary_distance(DVec3::X, -DVec3::X), 0.0);
/// assert!((boundary_distance(DVec3::X, DVec3::Y) - 2f64.sqrt()).abs() < 1e-15);
/// ```
pub fn boundary_distance(a: DVec3, b: DVec3) -> f64 {
    (a - b).length().min((a + b).length())
}

/// `b` or `−b`, whichever is nearer `a`.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::nearest_sign;
/// use rollphase_core::glam::DVec3;
/// assert_eq!(nearest_sign(DVec3::Z, DVec3::new(0.1, 0.0, -1.0)), DVec3::new(-0.1, 0.0, 1.0));
/// ```
pub fn nearest_sign(a: DVec3, b: DVec3) -> DVec3 {
    if (a - b).length() <= (a + b).length() {
        b
    } else {
        -b
    }
}

/// The ball point of an orientation: vector part of ±q with q_w ≥ 0.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::ball_point;
/// use rollphase_core::glam::{DQuat, DVec3};
/// // A rotation by π about x lies on ∂Ω at x; the identity at the centre.
/// let p = ball_point(DQuat::from_rotation_x(std::f64::consts::PI));
/// assert!((p - DVec3::X).length() < 1e-15);
/// assert_eq!(ball_point(DQuat::IDENTITY), DVec3::ZERO);
/// assert_eq!(ball_point(-DQuat::from_rotation_y(0.4)), ball_point(DQuat::from_rotation_y(0.4)));
/// ```
pub fn ball_point(q: DQuat) -> DVec3 {
    let q = if q.w < 0.0 { -q } else { q };
    DVec3::new(q.x, q.y, q.z)
}

/// A crossing of ∂Ω.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Crossing {
    /// Time.
    pub t: f64,
    /// Boundary point (unit vector; sign arbitrary).
    pub point: [f64; 3],
}

/// How a settle run ended, with its evidence: when it came to rest, the cycle it closed (its
/// duration, length and a point of it), or how far from rest it still was at its cap. Not a
/// second kind of fate: what a surface reports is the verdict's ([`crate::analysis::verdict::Fate`]
/// and its words, which `ScanRun::fate_word` gives a sweep's row, with the contact force's
/// lift-off before any of these).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Settlement {
    /// Came to rest (`verdict::rest_measure` below the threshold) at time `t`.
    Halts {
        /// When.
        t: f64,
    },
    /// Settled on a cycle of the Poincaré map of length `k` (k = 1: period-1 orbit).
    Periodic {
        /// Time for the orbit to close (k crossings).
        period: f64,
        /// Cycle length in crossings.
        k: usize,
        /// One boundary point of the cycle.
        point: [f64; 3],
        /// When the cycle was recognised.
        t: f64,
    },
    /// Neither within the time limit; |ω| at the end tells a slow approach to rest from wandering.
    Undecided {
        /// |ω| at t_max (with inertia, or the weight's torque about the contact if larger: what
        /// still keeps it from rest).
        omega_end: f64,
    },
}

impl Settlement {
    /// The run's fate in the verdict's words (the contact force's lift-off or slip, which a
    /// caller that watched it puts before this, aside): halted, periodic with multiplicity k,
    /// or undecided at `settle`'s cap.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::orbits::sphere_orbits::{Settle, Settlement};
    /// use rollphase_core::analysis::verdict::Fate;
    /// let s = Settle::default();
    /// assert_eq!(Settlement::Halts { t: 3.0 }.fate(&s), Fate::Halted { t: Some(3.0) });
    /// let cycle = Settlement::Periodic { period: 64.8, k: 2, point: [1.0, 0.0, 0.0], t: 900.0 };
    /// assert_eq!(cycle.fate(&s).name(), "periodic");
    /// assert_eq!(Settlement::Undecided { omega_end: 0.1 }.fate(&s).name(), "undecided");
    /// ```
    pub fn fate(&self, settle: &Settle) -> Fate {
        match *self {
            Settlement::Halts { t } => Fate::Halted { t: Some(t) },
            Settlement::Periodic { k, .. } => Fate::Periodic { multiplicity: k },
            Settlement::Undecided { omega_end } => Fate::Undecided {
                why: Undecided::NoCycle {
                    t_cap: settle.t_max,
                    from_rest: omega_end,
                    max_k: settle.max_k,
                },
            },
        }
    }
}

/// Settling criteria.
#[derive(Debug, Clone, Copy)]
pub struct Settle {
    /// Longest simulated time.
    pub t_max: f64,
    /// Periodic when the cycle's boundary points repeat to this distance ([`settled_cycle`], the
    /// one test of a repeat that every run of this module asks).
    pub point_tol: f64,
    /// Two runs' cycles are the same answer when their periods agree to this relative
    /// tolerance ([`same_answer`]: a fast setting's against the reference's).
    pub period_rtol: f64,
    /// Longest cycle searched.
    pub max_k: usize,
    /// DOP853 tolerance: the reference integrator ([`settle`]'s, and the one that
    /// [`settle_checked`] re-decides a faster setting's fate with).
    pub rtol: f64,
}

/// Whether a run's fate was checked against the reference integrator ([`settle_checked`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum AnswerCheck {
    /// The run's own integrator is at least as precise as the reference: its fate is reported.
    Reference,
    /// The reference gave the same fate: the same kind, and for a cycle the same length k and
    /// a period within the settle tolerance.
    Confirmed,
    /// The reference gave another fate, which is the one reported; `fast` is what the run's own
    /// integrator said.
    Corrected {
        /// The run's integrator's fate.
        fast: Settlement,
    },
}

impl AnswerCheck {
    /// "reference", "confirmed" or "corrected".
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::orbits::sphere_orbits::{AnswerCheck, Settlement};
    /// let c = AnswerCheck::Corrected { fast: Settlement::Halts { t: 1.0 } };
    /// assert_eq!(c.name(), "corrected");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            AnswerCheck::Reference => "reference",
            AnswerCheck::Confirmed => "confirmed",
            AnswerCheck::Corrected { .. } => "corrected",
        }
    }
}

/// A run's checked fate ([`settle_checked`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Settled {
    /// The fate: the reference integrator's.
    pub fate: Settlement,
    /// Whether the run's own integrator agreed.
    pub check: AnswerCheck,
    /// The ∂Ω crossings of the run as its own integrator followed it.
    pub crossings: Vec<Crossing>,
    /// Work done, the reference's re-decision included.
    pub stats: Stats,
    /// The contact force along the run (the reference's where it re-ran from the start; the
    /// run's own and the reference's continuation where it continued a cycle): whether the body
    /// stays on the ramp and how much friction it needs.
    pub contact: ContactReport,
}

/// Cycles the reference follows a fast run's cycle for, at the least, to re-decide it (the
/// settle window `t_max` is extended to that when the fast run decided late).
pub const VERIFY_CYCLES: f64 = 40.0;

/// Whether two fates are the same answer: the same kind, and for cycles the same length with
/// periods within `period_rtol` (halt times and the end |ω| of undecided runs are not compared).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::{Settlement, same_answer};
/// let cycle = |period, k| Settlement::Periodic { period, k, point: [1.0, 0.0, 0.0], t: 100.0 };
/// assert!(same_answer(&cycle(32.419, 1), &cycle(32.4190001, 1), 1e-5));
/// assert!(!same_answer(&cycle(32.419, 1), &cycle(64.84, 2), 1e-5));
/// assert!(same_answer(&Settlement::Halts { t: 3.0 }, &Settlement::Halts { t: 9.0 }, 1e-5));
/// ```
pub fn same_answer(a: &Settlement, b: &Settlement, period_rtol: f64) -> bool {
    match (a, b) {
        (Settlement::Halts { .. }, Settlement::Halts { .. }) => true,
        (Settlement::Undecided { .. }, Settlement::Undecided { .. }) => true,
        (
            Settlement::Periodic {
                period: pa, k: ka, ..
            },
            Settlement::Periodic {
                period: pb, k: kb, ..
            },
        ) => ka == kb && (pa - pb).abs() <= period_rtol.max(1e-12) * pa.abs().max(pb.abs()),
        _ => false,
    }
}

impl Default for Settle {
    fn default() -> Self {
        Self {
            t_max: 3000.0,
            point_tol: 1e-7,
            period_rtol: 1e-7,
            max_k: 1,
            rtol: 1e-10,
        }
    }
}

/// Follows the 3D model (viscous if m/m0 = 0, else inertial from rest) from q0 and returns its
/// fate and all ∂Ω crossings (for plots).
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::{Settlement, Settle, settle};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DQuat;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let (fate, _crossings) = settle(&s, &Ramp::new(0.15, 0.0)?, DQuat::IDENTITY, &Settle::default())?;
/// assert!(matches!(fate, Settlement::Periodic { k: 1, .. })); // above α*, a closed orbit
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn settle(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    s: &Settle,
) -> Result<(Settlement, Vec<Crossing>), IntegrateError> {
    settle_with(body, ramp, q0, s, Method::dop853(s.rtol)).map(|(f, c, _)| (f, c))
}

/// [`settle`] with any integrator in place of DOP853 at `s.rtol`; also returns the work done.
/// The fate is that integrator's alone, unchecked: a coarse setting can report a cycle of the
/// wrong length, or a halt the model does not make. [`settle_checked`] gives the checked one.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::{Settlement, Settle, settle_with};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DQuat;
/// use rollphase_core::integrate::Method;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let (fate, _, stats) = settle_with(&s, &Ramp::new(0.15, 0.0)?, DQuat::IDENTITY, &Settle::default(), Method::dop853(1e-8))?;
/// assert!(matches!(fate, Settlement::Periodic { k: 1, .. }));
/// assert!(stats.rhs_evals > 0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn settle_with(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    s: &Settle,
    method: Method,
) -> Result<(Settlement, Vec<Crossing>, Stats), IntegrateError> {
    on_model!(body, ramp, q0, |sys, y0| {
        follow(sys, 0.0, y0, s.t_max, s, method, Watch::Not).map(|f| (f.fate, f.crossings, f.stats))
    })
}

/// [`settle_with`], with the fate checked against the reference integrator (DOP853 at `s.rtol`)
/// whenever `method` is coarser (see the module doc): the reported fate never depends on the
/// setting picked for speed. Which of two coexisting orbits a start reaches can still differ
/// between settings (a basin boundary moves with the error); `bench accuracy` measures that.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::{AnswerCheck, Settlement, Settle, settle_checked};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DQuat;
/// use rollphase_core::integrate::Method;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let ramp = Ramp::new(0.15, 0.0)?;
/// let run = settle_checked(&s, &ramp, DQuat::IDENTITY, &Settle::default(), Method::dop853(1e-8))?;
/// assert!(matches!(run.fate, Settlement::Periodic { k: 1, .. }));
/// assert_eq!(run.check, AnswerCheck::Confirmed);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn settle_checked(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    s: &Settle,
    method: Method,
) -> Result<Settled, IntegrateError> {
    on_model!(body, ramp, q0, |sys, y0| {
        follow_checked(sys, y0, s, method)
    })
}

/// Whether `method` is at least as precise as the reference of `s`.
fn is_reference(method: Method, s: &Settle) -> bool {
    matches!(method, Method::Dop853 { rtol, atol } if rtol <= s.rtol && atol <= s.rtol)
}

/// One integrator's run to its fate, and the state at its last ∂Ω crossing.
struct Followed<const N: usize> {
    fate: Settlement,
    crossings: Vec<Crossing>,
    stats: Stats,
    last_crossing: Option<(f64, [f64; N])>,
    /// The contact force along it, when watched.
    contact: Option<ContactReport>,
}

/// Whether [`follow`] watches the contact force (a few force evaluations a step).
#[derive(Clone, Copy, PartialEq)]
enum Watch {
    Contact,
    Not,
}

#[allow(clippy::too_many_arguments)]
fn follow<const N: usize, S: RollingModel<N>>(
    sys: &S,
    t0: f64,
    y0: [f64; N],
    t_end: f64,
    s: &Settle,
    method: Method,
    watch: Watch,
) -> Result<Followed<N>, IntegrateError> {
    let mut run = Run::new(sys, t0, y0, method)?;
    let mut times = Vec::new();
    let mut crossings: Vec<Crossing> = Vec::new();
    let mut last_crossing = None;
    let mut contact = (watch == Watch::Contact)
        .then(|| ContactWatch::new(ContactLimits::default(), t0, sys.contact_force(&y0)));
    let mut fate = None;
    run.until::<IntegrateError>(t_end, u64::MAX, |st| {
        if let Some(w) = contact.as_mut() {
            let end = (st.t(), *st.y());
            w.step_along(st, end, |y| sys.contact_force(y));
        }
        times.clear();
        crossings_in_last_step(
            st,
            &|_t, y: &[f64; N]| sys.section(y),
            Direction::Both,
            &mut times,
        );
        for &t in &times {
            let y = st.dense(t);
            crossings.push(Crossing {
                t,
                point: section_point(sys, &y),
            });
            last_crossing = Some((t, y));
            if let Some(cycle) = periodic(&crossings, s) {
                fate = Some(cycle);
                return Ok(Flow::Stop);
            }
        }
        // At rest by the verdict's one rule: still, and the weight's torque gone (a heavy body
        // is still at first and speeds up over m/m0 t0).
        if state_at_rest(sys, st.y()) {
            fate = Some(Settlement::Halts { t: st.t() });
            return Ok(Flow::Stop);
        }
        Ok(Flow::Continue)
    })?;
    let fate = fate.unwrap_or_else(|| Settlement::Undecided {
        omega_end: rest_measure(sys, run.y()),
    });
    Ok(Followed {
        fate,
        crossings,
        stats: run.stats(),
        last_crossing,
        contact: contact.map(|w| w.report()),
    })
}

/// Where a crossing of `sys`'s section is, as a unit vector of ∂Ω (the model's own
/// [`RollingModel::section_point`]; the origin for a model without one, which no 3D model is).
fn section_point<const N: usize, S: RollingModel<N>>(sys: &S, y: &[f64; N]) -> [f64; 3] {
    sys.section_point(y).unwrap_or(DVec3::ZERO).to_array()
}

/// [`settle_checked`] on one model.
fn follow_checked<const N: usize, S: RollingModel<N>>(
    sys: &S,
    y0: [f64; N],
    s: &Settle,
    method: Method,
) -> Result<Settled, IntegrateError> {
    let fast = follow(sys, 0.0, y0, s.t_max, s, method, Watch::Contact)?;
    let fast_contact = fast.contact.unwrap_or_else(|| unreachable!("watched"));
    if is_reference(method, s) {
        return Ok(Settled {
            fate: fast.fate,
            check: AnswerCheck::Reference,
            crossings: fast.crossings,
            stats: fast.stats,
            contact: fast_contact,
        });
    }
    let reference = Method::dop853(s.rtol);
    let checked = match (&fast.fate, fast.last_crossing) {
        // A period-1 cycle can be wrong by its period, or by hiding a doubling: the reference
        // followed on from its last crossing shows both, in a few periods.
        (Settlement::Periodic { period, k: 1, .. }, Some((t_c, y_c))) => {
            let t_end = s.t_max.max(t_c + VERIFY_CYCLES * period);
            follow(sys, t_c, y_c, t_end, s, reference, Watch::Contact)?
        }
        // A cycle of k ≥ 2 is what a coarse step invents (its error moves a flip), and near a
        // flip the settle criterion's k depends on where the transient stands when it fires;
        // a halt ends at a rest point, where every integrator rests. Both are re-decided from
        // the start, as the reference alone decides them.
        _ => follow(sys, 0.0, y0, s.t_max, s, reference, Watch::Contact)?,
    };
    let checked_contact = checked.contact.unwrap_or_else(|| unreachable!("watched"));
    let contact = match &fast.fate {
        Settlement::Periodic { k: 1, .. } if fast.last_crossing.is_some() => {
            fast_contact.merged(&checked_contact)
        }
        _ => checked_contact,
    };
    let mut stats = fast.stats;
    stats.rhs_evals += checked.stats.rhs_evals;
    stats.steps += checked.stats.steps;
    stats.rejected += checked.stats.rejected;
    let check = if same_answer(&fast.fate, &checked.fate, s.period_rtol) {
        AnswerCheck::Confirmed
    } else {
        AnswerCheck::Corrected {
            fast: fast.fate.clone(),
        }
    };
    // A confirmed halt or undecided run reports the reference's time and |ω|; a cycle the
    // reference's period and point.
    Ok(Settled {
        fate: checked.fate,
        check,
        crossings: fast.crossings,
        stats,
        contact,
    })
}

/// The run's cycle by [`settled_cycle`] at `s.point_tol`: the one test of a repeat, which
/// [`decided_run`] asks too. (Its own test also asked the cycle's duration to repeat to
/// `period_rtol`, and no distinct alternation of a 2-cycle: two crossings closing twice in a row
/// to 1e-7 repeat their durations to the same order, the flow being smooth, and the alternation
/// rule is what keeps a slow approach to a flip from passing for period 2.)
fn periodic(c: &[Crossing], s: &Settle) -> Option<Settlement> {
    let (k, period) = settled_cycle(c, s.max_k, s.point_tol)?;
    let last = c.last()?;
    Some(Settlement::Periodic {
        period,
        k,
        point: last.point,
        t: last.t,
    })
}

/// Clusters unit vectors (antipodes identified) within `tol`; returns (representative, count).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::cluster_antipodal;
/// use rollphase_core::glam::DVec3;
/// let clusters = cluster_antipodal(&[DVec3::X, -DVec3::X, DVec3::Y], 1e-6);
/// assert_eq!(clusters.iter().map(|c| c.1).collect::<Vec<_>>(), [2, 1]);
/// ```
pub fn cluster_antipodal(points: &[DVec3], tol: f64) -> Vec<(DVec3, usize)> {
    let mut clusters: Vec<(DVec3, usize)> = Vec::new();
    for &p in points {
        match clusters
            .iter_mut()
            .find(|(c, _)| boundary_distance(*c, p) < tol)
        {
            Some(c) => c.1 += 1,
            None => clusters.push((p, 1)),
        }
    }
    clusters.sort_by_key(|c| std::cmp::Reverse(c.1));
    clusters
}

/// A run of the 3D model (viscous if m/m0 = 0, else inertial from rest) to `t_end`: all ∂Ω
/// crossings, and the contact point (body frame) at `samples` times evenly spread over
/// [`t_from`, `t_to`].
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::late_run;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DQuat;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let (crossings, path) = late_run(&s, &Ramp::new(0.15, 0.0)?, DQuat::IDENTITY, 500.0, 400.0, 500.0, 11, 1e-9)?;
/// assert_eq!(path.len(), 11);
/// assert!(crossings.len() > 2 && crossings.last().unwrap().t <= 500.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn late_run(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    t_end: f64,
    t_from: f64,
    t_to: f64,
    samples: usize,
    rtol: f64,
) -> Result<(Vec<Crossing>, Vec<DVec3>), IntegrateError> {
    let r = decided_run(
        body,
        ramp,
        q0,
        &Decide {
            t_min: t_end,
            t_cap: t_end,
            max_k: 0,
            tol: 0.0,
        },
        (t_from, t_to, samples),
        rtol,
    )?;
    Ok((r.crossings, r.path))
}

/// When a run's fate counts as decided ([`decided_run`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decide {
    /// Run at least this long (the transient, and the sampled window).
    pub t_min: f64,
    /// Never longer than this: a run still undecided here is reported as undecided.
    pub t_cap: f64,
    /// The longest cycle, in crossings of ∂Ω, that decides a run ([`settled_cycle`]); 0 never
    /// decides one by its cycle (the run goes to `t_cap`).
    pub max_k: usize,
    /// The crossing points' closeness for [`settled_cycle`].
    pub tol: f64,
}

impl Decide {
    /// Why a run that `self` left undecided at its cap is: no turn (no crossing of ∂Ω, and not
    /// at rest: `angular_speed` at the end), or no cycle among its `crossings`. The one wording
    /// of a decided run's undecided fate, for `decided_run` and `predict`'s inertial runs alike.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::orbits::sphere_orbits::Decide;
    /// use rollphase_core::analysis::verdict::Undecided;
    /// let decide = Decide { t_min: 100.0, t_cap: 400.0, max_k: 4, tol: 1e-5 };
    /// assert!(matches!(decide.undecided(0, 1e-3), Undecided::NoTurn { .. }));
    /// assert_eq!(decide.undecided(9, 0.2), Undecided::NoRepeat { t_cap: 400.0, crossings: 9, max_k: 4 });
    /// ```
    pub fn undecided(&self, crossings: usize, angular_speed: f64) -> Undecided {
        if crossings == 0 {
            Undecided::NoTurn {
                t_cap: self.t_cap,
                angular_speed,
            }
        } else {
            Undecided::NoRepeat {
                t_cap: self.t_cap,
                crossings,
                max_k: self.max_k,
            }
        }
    }
}

/// A run from [`decided_run`].
#[derive(Debug, Clone, PartialEq)]
pub struct DecidedRun {
    /// Every ∂Ω crossing.
    pub crossings: Vec<Crossing>,
    /// The contact point (body frame) at the sampled times.
    pub path: Vec<DVec3>,
    /// The cycle found: (k, its duration), as [`settled_cycle`] gives it: the evidence of a
    /// periodic fate.
    pub cycle: Option<(usize, f64)>,
    /// Its fate in the verdict's words: the body left the ramp (its cycle or rest is then the
    /// model's past the lift-off), else periodic (its crossings closed a steady cycle of k ≤
    /// `max_k`), halted (`verdict::state_at_rest`, and no crossing for the last `t_min`), or
    /// undecided at `t_cap` (no turn, or no cycle among its crossings).
    pub fate: Fate,
    /// When it ended.
    pub t_end: f64,
    /// |ω| at its end.
    pub angular_speed: f64,
    /// The contact force along it with inertia (whether the body stayed on the ramp); `None`
    /// in the viscous model, which presses with N = cos α throughout.
    pub contact: Option<ContactReport>,
}

impl DecidedRun {
    /// Whether the body left the ramp (N ≤ 0) during the run: its cycle or rest is then the
    /// model's past the lift-off, not a motion the body makes.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::orbits::sphere_orbits::{Decide, decided_run};
    /// use rollphase_core::dynamics::Ramp;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::glam::DQuat;
    /// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
    /// let decide = Decide { t_min: 100.0, t_cap: 400.0, max_k: 4, tol: 1e-5 };
    /// // Very heavy on a steep ramp: it bounces off.
    /// let run = decided_run(&s, &Ramp::new(0.5, 300.0)?, DQuat::IDENTITY, &decide, (0.0, 0.0, 0), 1e-9)?;
    /// assert!(run.left_model());
    /// let light = decided_run(&s, &Ramp::new(0.15, 0.0)?, DQuat::IDENTITY, &decide, (0.0, 0.0, 0), 1e-9)?;
    /// assert!(!light.left_model());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn left_model(&self) -> bool {
        matches!(self.fate, Fate::LeftModel { .. })
    }

    /// The run's period multiplicity: k for a cycle of k crossings, 0 at rest, `None` when still
    /// undecided or when the body left the ramp (the statistic of paper Fig. 4e).
    ///
    /// ```
    /// use rollphase_core::analysis::orbits::sphere_orbits::{Decide, decided_run};
    /// use rollphase_core::dynamics::Ramp;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::glam::DQuat;
    /// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
    /// let decide = Decide { t_min: 1200.0, t_cap: 6000.0, max_k: 4, tol: 1e-5 };
    /// let run = decided_run(&s, &Ramp::new(0.15, 6.0)?, DQuat::IDENTITY, &decide, (0.0, 0.0, 0), 1e-9)?;
    /// assert_eq!(run.multiplicity(), Some(2));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn multiplicity(&self) -> Option<usize> {
        match self.fate {
            Fate::Periodic { multiplicity } => Some(multiplicity),
            Fate::Halted { .. } => Some(0),
            Fate::Neutral | Fate::LeftModel { .. } | Fate::Undecided { .. } => None,
        }
    }
}

/// A run of the 3D model (viscous if m/m0 = 0, else inertial from rest) that goes on until its
/// fate is decided: at least `decide.t_min`, then until its crossings close a steady cycle
/// ([`settled_cycle`] with `decide.max_k`, `decide.tol`, checked at each new crossing) or it comes
/// to rest, and at most `decide.t_cap`. The contact point (body frame) is sampled at `samples`
/// times evenly spread over [`t_from`, `t_to`] (`sampling` = (t_from, t_to, samples)), cut at
/// the run's end.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::{Decide, decided_run};
/// use rollphase_core::analysis::verdict::Fate;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DQuat;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let decide = Decide { t_min: 1200.0, t_cap: 6000.0, max_k: 4, tol: 1e-5 };
/// let run = decided_run(&s, &Ramp::new(0.15, 6.0)?, DQuat::IDENTITY, &decide, (0.0, 0.0, 0), 1e-9)?;
/// assert_eq!(run.fate, Fate::Periodic { multiplicity: 2 }, "period doubling at m/m0 = 6");
/// assert!(run.cycle.is_some_and(|(k, duration)| k == 2 && duration > 0.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn decided_run(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    decide: &Decide,
    sampling: (f64, f64, usize),
    rtol: f64,
) -> Result<DecidedRun, IntegrateError> {
    match ModelKind::for_dimension(3, ramp) {
        ModelKind::SphereViscous => {
            let m = SphereViscous::new(body, ramp);
            record(
                &m,
                SphereViscous::initial_state(q0),
                decide,
                sampling,
                rtol,
                |y| m.observe(y),
            )
        }
        ModelKind::SphereInertial => {
            let m = SphereInertial::new(body, ramp);
            record(
                &m,
                SphereInertial::initial_state(q0, DVec3::ZERO),
                decide,
                sampling,
                rtol,
                |y| m.observe(y),
            )
        }
        other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => other.wrong_dimension(3),
    }
}

fn record<const N: usize, S: RollingModel<N>>(
    sys: &S,
    y0: [f64; N],
    decide: &Decide,
    (t_from, t_to, samples): (f64, f64, usize),
    rtol: f64,
    observe: impl Fn(&[f64; N]) -> SphereObservation,
) -> Result<DecidedRun, IntegrateError> {
    let times = integrate::uniform_times(t_from, t_to.min(decide.t_cap), samples);
    // The contact-force watch, with inertia (an observer: it reads the dense output, never
    // moves the run); the viscous model presses with N = cos α throughout.
    let mut watch = S::KIND
        .is_inertial()
        .then(|| ContactWatch::lift_off_only(0.0, sys.contact_force(&y0)));
    let mut run = Run::new(sys, 0.0, y0, Method::dop853(rtol))?;
    let mut found = Vec::new();
    let mut crossings = Vec::new();
    let mut path = Vec::with_capacity(times.len());
    let mut sampled = Samples::new(&times);
    let mut cycle = None;
    let mut rested = false;
    run.until::<IntegrateError>(decide.t_cap, u64::MAX, |st| {
        found.clear();
        crossings_in_last_step(
            st,
            &|_t, y: &[f64; N]| sys.section(y),
            Direction::Both,
            &mut found,
        );
        for &t in &found {
            let y = st.dense(t);
            crossings.push(Crossing {
                t,
                point: section_point(sys, &y),
            });
        }
        sampled.take(st, |_, y| path.push(observe(y).contact_dir));
        if let Some(w) = watch.as_mut() {
            let now = (st.t(), *st.y());
            w.step_along(st, now, |y| sys.contact_force(y));
        }
        if st.t() >= decide.t_min && sampled.done() {
            if decide.max_k > 0 && (!found.is_empty() || cycle.is_none()) {
                cycle = settled_cycle(&crossings, decide.max_k, decide.tol);
                if cycle.is_some() {
                    return Ok(Flow::Stop);
                }
            }
            let quiet = crossings
                .last()
                .is_none_or(|c| st.t() - c.t >= decide.t_min);
            if decide.max_k > 0 && quiet && state_at_rest(sys, st.y()) {
                rested = true;
                return Ok(Flow::Stop);
            }
        }
        Ok(Flow::Continue)
    })?;
    let contact = watch.map(|w| w.report());
    let angular_speed = observe(run.y()).omega.length();
    let fate = match (
        contact
            .as_ref()
            .and_then(|c| c.violations().first().copied()),
        cycle,
    ) {
        (Some(violation), _) => Fate::LeftModel { violation },
        (None, Some((k, _))) => Fate::Periodic { multiplicity: k },
        (None, None) if rested => Fate::Halted { t: Some(run.t()) },
        (None, None) => Fate::Undecided {
            why: decide.undecided(crossings.len(), angular_speed),
        },
    };
    Ok(DecidedRun {
        crossings,
        path,
        cycle,
        fate,
        t_end: run.t(),
        angular_speed,
        contact,
    })
}

/// [`late_cycle`], where a cycle of k ≥ 2 must also be steady: the alternation |p_n − p_{n−1}|
/// equal, to 2·`tol`, to the same distance 10k crossings earlier (so the sequence must hold at
/// least 10k + 1 crossings). Near a flip a period-1 orbit with multiplier μ ≈ −1 attracts so
/// slowly that its alternation shrinks by only |μ|^{2} every two crossings; then p_n ≈ p_{n−2}
/// while p_n and p_{n−1} are still far apart, and [`late_cycle`] alone would call it period 2.
/// Over 10k crossings the alternation of such an orbit shrinks by about 10k(1 − |μ|), which this
/// sees for 1 − |μ| above ~1e-3 (with `tol` = 1e-4 and an alternation of 1e-2).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::{Crossing, settled_cycle};
/// // A steady 2-cycle: the points alternate between two places, 40 crossings long.
/// let (a, b) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// let c: Vec<Crossing> = (0..40).map(|i| Crossing { t: 10.0 * i as f64, point: if i % 2 == 0 { a } else { b } }).collect();
/// assert_eq!(settled_cycle(&c, 4, 1e-6), Some((2, 20.0)));
/// // Too short to be called steady.
/// assert_eq!(settled_cycle(&c[..12], 4, 1e-6), None);
/// ```
pub fn settled_cycle(c: &[Crossing], max_k: usize, tol: f64) -> Option<(usize, f64)> {
    let (k, d) = late_cycle(c, max_k, tol)?;
    steady_cycle(c, k, tol).then_some((k, d))
}

/// Whether a cycle of `k` crossings closing at the end of `c` is steady, not the transient of a
/// shorter one: always for k = 1; for k ≥ 2 the step |p_n − p_{n−1}| must equal, to 2·`tol`, the
/// same step 10k crossings earlier. A run spiralling onto a period-1 orbit whose multipliers turn
/// by ~2π/k a crossing has p_n ≈ p_{n−k} long before p_n ≈ p_{n−1}, while its steps still shrink;
/// a true k-cycle's do not. The one test [`settled_cycle`] and [`settle`] share.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::{Crossing, steady_cycle};
/// // Points turning by 2π/3 a crossing about a centre while closing in by 0.999 a crossing:
/// // every third point nearly repeats, but the steps shrink.
/// let c: Vec<Crossing> = (0..80)
///     .map(|i| {
///         let (a, r) = (2.0 * std::f64::consts::PI / 3.0 * i as f64, 0.01 * 0.999f64.powi(i));
///         Crossing { t: 30.0 * i as f64, point: [r * a.cos(), r * a.sin(), 1.0] }
///     })
///     .collect();
/// assert!(!steady_cycle(&c, 3, 1e-5));
/// assert!(steady_cycle(&c, 1, 1e-5));
/// ```
pub fn steady_cycle(c: &[Crossing], k: usize, tol: f64) -> bool {
    if k == 1 {
        return true;
    }
    let n = c.len();
    let back = 10 * k;
    if n <= back + 1 {
        return false;
    }
    let p = |i: usize| DVec3::from_array(c[i].point);
    let now = boundary_distance(p(n - 1), p(n - 2));
    let then = boundary_distance(p(n - 1 - back), p(n - 2 - back));
    (now - then).abs() < 2.0 * tol
}

/// The shortest cycle of the crossing sequence at its end: the smallest k ≤ `max_k` with
/// p_n ≈ p_{n−k} and p_{n−k} ≈ p_{n−2k} (antipodes identified, within `tol`); returns
/// (k, duration of the cycle). A cycle of k ≥ 2 also needs p_n and p_{n−1} at least 100·tol
/// apart: a run still converging onto a period-1 orbit with multiplier μ < 0 moves by d between
/// crossings but only by |1 + μ|·d between every second one, so it could pass for a doubled orbit
/// while the alternation is still large; with this rule that happens only within |1 + μ| < 1/100
/// of the flip itself.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::{Crossing, late_cycle};
/// let p = [0.0, 0.0, 1.0];
/// let c: Vec<Crossing> = (0..3).map(|i| Crossing { t: 43.5 * i as f64, point: p }).collect();
/// assert_eq!(late_cycle(&c, 4, 1e-6), Some((1, 43.5)));
/// ```
pub fn late_cycle(c: &[Crossing], max_k: usize, tol: f64) -> Option<(usize, f64)> {
    let n = c.len();
    let p = |i: usize| DVec3::from_array(c[i].point);
    (1..=max_k).find_map(|k| {
        (n > 2 * k).then_some(())?;
        let (a, b, d) = (n - 1, n - 1 - k, n - 1 - 2 * k);
        let distinct = k == 1 || boundary_distance(p(a), p(a - 1)) >= 100.0 * tol;
        (distinct && boundary_distance(p(a), p(b)) < tol && boundary_distance(p(b), p(d)) < tol)
            .then(|| (k, c[a].t - c[b].t))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Crossings p_n = c + a·μⁿ·e (a period-1 orbit attracting with multiplier μ < 0 when
    /// |μ| < 1, an exact 2-cycle when μ = −1), one every 50 time units.
    fn alternating(mu: f64, a: f64, n: usize) -> Vec<Crossing> {
        let (c, e) = (DVec3::new(0.6, 0.0, 0.8), DVec3::new(0.8, 0.0, -0.6));
        (0..n)
            .map(|i| Crossing {
                t: 50.0 * i as f64,
                point: (c + a * mu.powi(i as i32) * e).normalize().to_array(),
            })
            .collect()
    }

    #[test]
    fn a_slowly_attracting_orbit_is_not_called_period_two() {
        // μ = −0.999: p_n and p_{n−2} differ by ~2e-3·a, below the tolerance for a = 0.02,
        // while p_n and p_{n−1} are 0.04 apart: late_cycle alone calls it a 2-cycle.
        let c = alternating(-0.999, 0.02, 60);
        assert_eq!(late_cycle(&c, 4, 1e-4).map(|x| x.0), Some(2));
        assert_eq!(settled_cycle(&c, 4, 1e-4), None);
    }

    #[test]
    fn a_true_two_cycle_and_a_settled_orbit_are_decided() {
        let two = alternating(-1.0, 0.02, 30);
        assert_eq!(settled_cycle(&two, 4, 1e-4).map(|x| x.0), Some(2));
        assert_eq!(settled_cycle(&two, 4, 1e-4).map(|x| x.1), Some(100.0));
        let one = alternating(-0.5, 0.02, 40);
        assert_eq!(settled_cycle(&one, 4, 1e-4).map(|x| x.0), Some(1));
        // Too short to see the alternation steady: not decided yet.
        assert_eq!(settled_cycle(&two[..15], 4, 1e-4), None);
    }
}
