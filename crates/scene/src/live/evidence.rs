//! A lesson's evidence, measured ahead of the live clock: the scene's own run, from its start to
//! its end at full speed on a worker thread, with the plots' points it collects (1/T against α,
//! the settled crossings of ∂Ω against m/m0) kept as they stand at the end of each step. While
//! the teacher's run plays the scene as written ([`super::Snapshot::off_script`] false), the
//! app shows a step's whole evidence as the step opens, however soon N is pressed: the caption's
//! claim and the points that back it are on the screen together. The run is the same one the
//! live run makes (a run does not depend on where its frames fall), so the points are the ones
//! the live run would collect by the step's end, only sooner.
//!
//! A step whose evidence is not measured yet is reported with how far the measurement has got,
//! so the app can say so under the caption instead of showing an empty plot under a claim.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use crate::scene::{Claim, SceneSetup};

use super::LiveRun;
use super::history::{PlotCheckpoint, PlotHistory, Regime};

/// Simulation time between the snapshots the evidence run takes in: far below the time between
/// two crossings of ∂Ω or two turns of a cylinder (several t0), so none is missed.
pub const EVIDENCE_DT: f64 = 0.25;

/// Simulation time a lesson's last step is measured for when its scene sets no
/// `playback.end_time`.
pub const LAST_STEP_SPAN: f64 = 600.0;

/// The simulation-time span of each step's evidence: step `d` (the state after `d` timeline
/// steps were applied, as [`super::LessonProgress::done`] counts) runs from the step before's
/// time to `ends[d]`, the next step's time (or the scene's end).
///
/// # Example
/// ```
/// use rollphase_scene::live::evidence::step_ends;
/// use rollphase_scene::scene::Scene;
/// let setup = Scene::preset("lesson-period-doubling")?.setup(None)?;
/// // Steps at 0, 400, 900, 2300 and 3700; the scene ends at 4300.
/// assert_eq!(step_ends(&setup), [0.0, 400.0, 900.0, 2300.0, 3700.0, 4300.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn step_ends(setup: &SceneSetup) -> Vec<f64> {
    let mut ends: Vec<f64> = setup.timeline.iter().map(|s| s.at).collect();
    let last = ends.last().copied().unwrap_or(0.0);
    ends.push(
        setup
            .scene
            .playback
            .end_time
            .filter(|&e| e > last)
            .unwrap_or(last + LAST_STEP_SPAN),
    );
    ends
}

/// What the evidence run has measured so far.
#[derive(Debug, Clone, Default)]
pub struct EvidenceState {
    /// The plots as they stand at the end of each step measured so far (index: steps done).
    pub steps: Vec<PlotCheckpoint>,
    /// Simulation time the run has reached.
    pub t_done: f64,
    /// The end of the last step's evidence.
    pub t_end: f64,
    /// Why the run stopped early, if it did (the steps measured before stay valid).
    pub failed: Option<String>,
}

/// Runs the lesson of `setup` from its start (its `[resume]` ignored) to the end of its last
/// step, taking a snapshot every [`EVIDENCE_DT`] into a [`PlotHistory`], and calls `publish`
/// with the state after each step's end and every `report_every` of simulation time. Stops
/// when `stop` is set. The same numbers on every run: the lesson's own run, stepped as the live
/// run steps it.
///
/// # Example
/// ```
/// use std::sync::atomic::AtomicBool;
/// use rollphase_scene::live::evidence::measure_evidence;
/// use rollphase_scene::scene::Scene;
/// let mut setup = Scene::preset("lesson-critical-angle")?.setup(None)?;
/// setup.scene.playback.end_time = Some(60.0); // a short lesson for the example
/// setup.timeline.retain(|s| s.at < 60.0);
/// let mut last = None;
/// measure_evidence(&setup, &AtomicBool::new(false), 1e9, |s| last = Some(s.clone()));
/// let state = last.unwrap();
/// assert_eq!(state.steps.len(), setup.timeline.len() + 1);
/// assert!(state.failed.is_none() && state.t_done >= 60.0 - 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn measure_evidence(
    setup: &SceneSetup,
    stop: &AtomicBool,
    report_every: f64,
    mut publish: impl FnMut(&EvidenceState),
) {
    let mut setup = setup.clone();
    setup.resume = None;
    // The claims are of the scene's own body's plots: the other bodies would only cost time.
    setup.lanes.clear();
    let ends = step_ends(&setup);
    let mut state = EvidenceState {
        t_end: *ends.last().unwrap_or(&0.0),
        ..EvidenceState::default()
    };
    let mut sim = LiveRun::new(setup);
    let mut history = PlotHistory::default();
    let mut next_report = report_every;
    for &end in &ends {
        // The snapshots up to the step's end, the step's own time left to the next step (a
        // step applies at its time, and its point belongs to the next step's evidence).
        loop {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            let t = (sim.time() + EVIDENCE_DT).min(end);
            if t >= end {
                break;
            }
            if let Err(e) = sim.advance_to(t) {
                state.failed = Some(e.to_string());
                publish(&state);
                return;
            }
            // The time series are the live run's own; only the sweep's points are kept here.
            sim.take_plot_samples();
            history.push(&sim.snapshot());
            state.t_done = t;
            if t >= next_report {
                next_report = t + report_every;
                publish(&state);
            }
        }
        state.steps.push(history.checkpoint());
        if let Err(e) = sim.advance_to(end) {
            state.failed = Some(e.to_string());
            publish(&state);
            return;
        }
        state.t_done = end;
        publish(&state);
    }
}

/// Crossings of ∂Ω this far apart (rad) are different points of a cycle; closer, one point
/// settling. A period-2 cycle's two crossings are 0.2–0.5 rad apart on the bundled lesson,
/// a settled period-1 cycle's repeat to 1e-3 (the history keeps no two closer).
pub const DISTINCT_CROSSINGS: f64 = 1e-2;

/// How many of the latest crossings at one m/m0 make its settled cycle (the earlier ones are
/// its transient): more than a period-2 cycle's two, few enough to be settled.
pub const SETTLED_CROSSINGS: usize = 6;

/// The distinct crossings of ∂Ω ([`DISTINCT_CROSSINGS`] apart) among the last
/// [`SETTLED_CROSSINGS`] under `regime` (its m/m0 and drag law), newest first: what the plot
/// shows of the run's settled cycle (one for period 1, two for period 2). Not a test of a repeat
/// of its own: the plot takes a crossing only once the run has decided its cycle, and a claim is
/// checked against that decision ([`PlotCheckpoint::cycle_at`]).
pub fn settled_branches(evidence: &PlotCheckpoint, regime: &Regime) -> Vec<f64> {
    let mut found: Vec<f64> = Vec::new();
    for &angle in evidence
        .crossings_at(regime)
        .iter()
        .rev()
        .take(SETTLED_CROSSINGS)
    {
        if found
            .iter()
            .all(|&f| (f - angle).abs() > DISTINCT_CROSSINGS)
        {
            found.push(angle);
        }
    }
    found
}

/// How far a point may lie from the √-law fit for a `claim = "sqrt-law"` to hold: each fitted
/// point's T within 2 % of the fit's T at its α. The points are periods measured to far better
/// than that (crossing times on the dense output); the law is asymptotic, so what the fit's
/// offset b cannot absorb shows up as a trend in the residuals, and 2 % is about a marker's
/// width on the lesson's plot (12 px of a 1/T axis some 600 px tall): a point off by more is
/// seen off the curve, and "the plot fits" would be more than the plot shows.
pub const SQRT_LAW_FIT_TOL: f64 = 0.02;

/// Where a lesson step stands, for its claim: its α and m/m0 as the steps before it leave them,
/// the scene's drag law (a step does not change it) and the body's critical angle α*.
#[derive(Debug, Clone, PartialEq)]
pub struct StepAt {
    /// The ramp's angle (rad).
    pub alpha: f64,
    /// m/m0.
    pub mass_ratio: f64,
    /// The drag law in words ([`crate::dynamics::DragLaw::label`]).
    pub drag: String,
    /// The body's critical angle (rad).
    pub alpha_star: f64,
    /// The step's time: a cycle last seen settled before it is an earlier step's.
    pub from: f64,
    /// Where its evidence ends ([`step_ends`]): the next step's time or the scene's end.
    pub to: f64,
}

impl StepAt {
    /// Each timeline step of `setup`, in order. An m/m0 the run takes as 0 (at or below an
    /// adaptive integrator's rtol: the viscous model, `simulate::runs_viscous`) is 0 here too,
    /// as the plots file its points.
    pub fn each_of(setup: &SceneSetup) -> Vec<StepAt> {
        let (mut alpha, mut mass_ratio) = (setup.ramp.alpha_rad, setup.ramp.mass_ratio);
        let mut method = setup.method;
        let ends = step_ends(setup);
        setup
            .timeline
            .iter()
            .zip(&ends[1..])
            .map(|(step, &to)| {
                alpha = step.alpha_rad.unwrap_or(alpha);
                mass_ratio = step.mass_ratio.unwrap_or(mass_ratio);
                method = step.method.unwrap_or(method);
                StepAt {
                    alpha,
                    mass_ratio: if crate::simulate::runs_viscous(mass_ratio, method) {
                        0.0
                    } else {
                        mass_ratio
                    },
                    drag: setup.ramp.drag_law.label(),
                    alpha_star: setup.alpha_star,
                    from: step.at,
                    to,
                }
            })
            .collect()
    }

    /// The plots' regime of the step: its m/m0 under its drag law.
    pub fn regime(&self) -> Regime {
        Regime::labelled(self.mass_ratio, &self.drag)
    }
}

/// Whether a step's `claim` holds in its `evidence` (the plots at the step's end) where the step
/// stands (`at`: its α, m/m0 and drag law; only the points of that m/m0 and law count): `Ok`
/// with what shows it, or `Err` with what the plot shows instead.
///
/// # Example
/// ```
/// use std::sync::atomic::AtomicBool;
/// use rollphase_scene::live::evidence::{StepAt, check_claim, measure_evidence};
/// use rollphase_scene::scene::{Claim, Scene};
/// let setup = Scene::preset("lesson-period-doubling")?.setup(None)?;
/// let mut last = None;
/// measure_evidence(&setup, &AtomicBool::new(false), 1e9, |s| last = Some(s.clone()));
/// let state = last.unwrap();
/// // After the third step (m/m0 = 4.5): period 2, not period 1.
/// let at = &StepAt::each_of(&setup)[2];
/// assert!(check_claim(Claim::Period2, &state.steps[3], at).is_ok());
/// assert!(check_claim(Claim::Period1, &state.steps[3], at).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn check_claim(claim: Claim, evidence: &PlotCheckpoint, at: &StepAt) -> Result<String, String> {
    let regime = at.regime();
    let (alpha, mass_ratio) = (at.alpha, at.mass_ratio);
    let rates = evidence.rates_at(alpha, &regime);
    // The point of the branch the sweep is moving along, where α was met both ways.
    let now = rates
        .iter()
        .find(|r| Some(r.0) == evidence.direction())
        .or(rates.last());
    let at_words = format!("α = {alpha:.5}, m/m0 = {}", short(mass_ratio));
    let no_point = || format!("the 1/T plot has no point at {at_words}");
    match claim {
        Claim::Halted | Claim::Rolling => {
            let &(_, rate) = now.ok_or_else(no_point)?;
            match (claim, rate == 0.0) {
                (Claim::Halted, true) => Ok(format!("1/T = 0 at {at_words}")),
                (Claim::Rolling, false) => Ok(format!("1/T = {rate:.5} at {at_words}")),
                (Claim::Halted, false) => Err(format!("1/T = {rate:.5} at {at_words}: it rolls")),
                _ => Err(format!("1/T = 0 at {at_words}: it halted")),
            }
        }
        Claim::SqrtLaw => sqrt_law_shown(evidence, &regime, at.alpha_star),
        Claim::Period1 | Claim::Period2 => {
            let want = if claim == Claim::Period1 { 1 } else { 2 };
            // The run's own verdict decides (the one test of a repeat, `settled_cycle`), as
            // last seen at the step's α and m/m0 and within the step; the points are its
            // cycle's crossings, which the plot shows.
            let cycle = evidence.cycle_at(alpha, &regime);
            match cycle {
                Some(c) if c.seen_at >= at.from => {
                    let shown = c
                        .angles
                        .iter()
                        .map(|x| format!("{x:.3}"))
                        .collect::<Vec<_>>()
                        .join(", ");
                    if c.multiplicity == want {
                        Ok(format!(
                            "period {want} at {at_words}: settled crossing(s) at {shown} rad"
                        ))
                    } else {
                        Err(format!(
                            "the run settled on period {}, not {want}, at {at_words} \
                             (crossings at {shown} rad)",
                            c.multiplicity
                        ))
                    }
                }
                _ => Err(if let Some(why) = evidence.left_model_at(alpha, &regime) {
                    format!("the body left the model at {at_words}: it {why}")
                } else if let Some(c) = cycle {
                    format!(
                        "the run has not settled on a cycle at {at_words} during the step (from \
                         t = {}): it last did at t = {:.1}, before it",
                        short(at.from),
                        c.seen_at
                    )
                } else {
                    format!(
                        "the run has not settled on a cycle at {at_words} from t = {} to t = {}",
                        short(at.from),
                        short(at.to)
                    )
                }),
            }
        }
    }
}

/// The √ law's claim: the fit the 1/T plot draws (`analysis::fit::sqrt_law`, the rolling points
/// with α* < α ≤ [`SQRT_LAW_REACH`](crate::analysis::fit::SQRT_LAW_REACH) α*) exists, and
/// every point it is fitted to lies within
/// [`SQRT_LAW_FIT_TOL`] of it.
fn sqrt_law_shown(
    evidence: &PlotCheckpoint,
    regime: &Regime,
    alpha_star: f64,
) -> Result<String, String> {
    let mass_ratio = regime.mass_ratio();
    let points = evidence.points_at(regime);
    let near: Vec<[f64; 2]> = points
        .iter()
        .filter(|[alpha, rate]| {
            *alpha > alpha_star
                && *alpha <= crate::analysis::fit::SQRT_LAW_REACH * alpha_star
                && *rate > 0.0
        })
        .copied()
        .collect();
    let m = short(mass_ratio);
    let Some((a, b)) = crate::analysis::fit::sqrt_law(&points, alpha_star) else {
        return Err(format!(
            "the 1/T plot has {} rolling point(s) with α* < α ≤ {} α* at m/m0 = {m}; the \
             √-law fit needs 3 that diverge towards α*",
            near.len(),
            crate::analysis::fit::SQRT_LAW_REACH
        ));
    };
    let (worst_alpha, worst) = near
        .iter()
        .map(|&[alpha, rate]| {
            (
                alpha,
                ((a / (alpha - alpha_star).sqrt() + b) * rate - 1.0).abs(),
            )
        })
        .fold((f64::NAN, 0.0), |w, p| if p.1 > w.1 { p } else { w });
    let fit = format!("T = {a:.3}/√(α−α*) + {b:.1}");

    if worst <= SQRT_LAW_FIT_TOL {
        Ok(format!(
            "{fit} through {} points near α* at m/m0 = {m}, each within {:.1} %",
            near.len(),
            100.0 * worst
        ))
    } else {
        Err(format!(
            "{fit} misses the point at α = {:.4} α* by {:.1} % of T (allowed {:.0} %)",
            worst_alpha / alpha_star,
            100.0 * worst,
            100.0 * SQRT_LAW_FIT_TOL
        ))
    }
}

/// A number as people read it: four decimals at most, in powers of ten beyond 1e6 or below
/// 1e-4 (a 301-digit m/m0 ran off the frame).
fn short(x: f64) -> String {
    if x != 0.0 && !(1e-4..1e6).contains(&x.abs()) {
        return format!("{x:.3e}");
    }
    let s = format!("{x:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Each step's claim checked against its evidence, as (step index in the timeline, claim,
/// verdict), for the steps that make one and whose evidence is measured.
pub fn claims_checked(
    setup: &SceneSetup,
    state: &EvidenceState,
) -> Vec<(usize, Claim, Result<String, String>)> {
    let mut out = Vec::new();
    for (k, (step, at)) in setup
        .timeline
        .iter()
        .zip(StepAt::each_of(setup))
        .enumerate()
    {
        // Step k is shown once k + 1 steps are done; its evidence is the plots then.
        if let (Some(claim), Some(evidence)) = (step.claim, state.steps.get(k + 1)) {
            out.push((k, claim, check_claim(claim, evidence, &at)));
        }
    }
    out
}

/// What is said under a caption whose `claim` the run does not bear out (`why`: what the plot
/// shows instead), in the app and in headless frames alike: the claim named, so that "(1/T = 0)"
/// in a caption is not followed by a note that seems to deny it.
///
/// ```
/// use rollphase_scene::live::evidence::claim_not_shown;
/// use rollphase_scene::scene::Claim;
/// assert_eq!(
///     claim_not_shown(Claim::Rolling, "1/T = 0 at α = 0.04401, m/m0 = 0: it halted"),
///     "this run does not show \"rolling\": 1/T = 0 at α = 0.04401, m/m0 = 0: it halted"
/// );
/// ```
pub fn claim_not_shown(claim: Claim, why: &str) -> String {
    format!("this run does not show \"{}\": {why}", claim.name())
}

/// A lesson's evidence measured on a worker thread ([`measure_evidence`]), for the setup it
/// was started on; dropped, it stops the worker.
#[derive(Debug)]
pub struct LessonEvidence {
    setup: Arc<SceneSetup>,
    shared: Arc<Mutex<EvidenceState>>,
    stop: Arc<AtomicBool>,
}

impl LessonEvidence {
    /// Starts measuring `setup`'s lesson; `None` for a scene without a timeline, a resumed one
    /// (its run did not start at the lesson's start), or where no thread can be started.
    pub fn start(setup: Arc<SceneSetup>) -> Option<Self> {
        if setup.timeline.is_empty() || setup.resume.is_some() {
            return None;
        }
        let shared = Arc::new(Mutex::new(EvidenceState::default()));
        let stop = Arc::new(AtomicBool::new(false));
        let (s, sh, st) = (setup.clone(), shared.clone(), stop.clone());
        std::thread::Builder::new()
            .name("lesson-evidence".into())
            .spawn(move || {
                measure_evidence(&s, &st, 20.0, |state| {
                    if let Ok(mut shared) = sh.lock() {
                        *shared = state.clone();
                    }
                });
            })
            .ok()?;
        Some(Self {
            setup,
            shared,
            stop,
        })
    }

    /// Whether this is the evidence of `setup` (the same scene and start: a restart from a
    /// picked point is another run).
    pub fn is_for(&self, setup: &Arc<SceneSetup>) -> bool {
        Arc::ptr_eq(&self.setup, setup)
    }

    /// The plots at the end of step `done`, once measured.
    pub fn step(&self, done: usize) -> Option<PlotCheckpoint> {
        self.shared.lock().ok()?.steps.get(done).cloned()
    }

    /// The claim of the step shown once `done` steps are done, checked against its measured
    /// evidence ([`check_claim`]); `None` while unmeasured or where the step claims nothing.
    pub fn claim(&self, done: usize) -> Option<Result<String, String>> {
        let state = self.shared.lock().ok()?;
        let k = done.checked_sub(1)?;
        claims_checked(&self.setup, &state)
            .into_iter()
            .find(|c| c.0 == k)
            .map(|c| c.2)
    }

    /// The period (1 or 2) the step shown once `done` steps are done claims, where its
    /// measured evidence bears the claim out: what the overlay says while the live run, the
    /// same run, has not yet settled onto the cycle (it finds the lesson's period 2 about
    /// 560 t0 into its 700 t0 step, later than a teacher's click). `None` for a step that
    /// claims no period, one still being measured, or one whose evidence does not show it.
    pub fn period_shown(&self, done: usize) -> Option<usize> {
        let k = done.checked_sub(1)?;
        let period = match self.setup.timeline.get(k)?.claim? {
            Claim::Period1 => 1,
            Claim::Period2 => 2,
            Claim::Halted | Claim::Rolling | Claim::SqrtLaw => return None,
        };
        self.claim(done)?.ok().map(|_| period)
    }

    /// The 1/T (0: halted) that the step shown once `done` steps are done measured at its α
    /// and m/m0, where the step claims the body rolls, halts, follows the √ law or settles on a
    /// period (then 1/T of the settled cycle, whole) and its evidence bears the claim out: what
    /// the overlay says, marked as measured ahead, while the live run, the same run, has not
    /// yet made the two turns its own 1/T needs (near α* a turn takes 260 t0, minutes at a
    /// lesson's speed, while the plot already shows the point). Of the sweep's points at that
    /// α, the one measured in the direction the sweep last moved.
    pub fn rate_shown(&self, done: usize) -> Option<f64> {
        let k = done.checked_sub(1)?;
        let claim = self.setup.timeline.get(k)?.claim?;
        self.claim(done)?.ok()?;
        let at = StepAt::each_of(&self.setup).into_iter().nth(k)?;
        let evidence = self.step(done)?;
        if let Claim::Period1 | Claim::Period2 = claim {
            // The cycle the claim was checked against, whole: a doubled orbit's T spans both
            // of its crossings.
            return evidence
                .cycle_at(at.alpha, &at.regime())
                .map(|c| 1.0 / c.period);
        }
        let rates = evidence.rates_at(at.alpha, &at.regime());
        let direction = evidence.direction();
        rates
            .iter()
            .find(|(branch, _)| Some(*branch) == direction)
            .or(rates.first())
            .map(|&(_, rate)| rate)
    }

    /// How far the measurement of step `done` has got, 0 to 1 (1: measured): the share of the
    /// run from the lesson's start to the step's end that is done (the steps before it are run
    /// first, so a share of the step alone sat at 0 while they ran), and why it stopped if it
    /// failed first.
    pub fn progress(&self, done: usize) -> (f64, Option<String>) {
        let Ok(state) = self.shared.lock() else {
            return (0.0, Some("the evidence thread stopped".into()));
        };
        if done < state.steps.len() {
            return (1.0, None);
        }
        let ends = step_ends(&self.setup);
        let end = ends.get(done).copied().unwrap_or(state.t_end);
        let fraction = (state.t_done / end.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        (fraction, state.failed.clone())
    }
}

impl Drop for LessonEvidence {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::DragLaw;
    use crate::scene::ResumeSpec;

    /// A 1/T plot holding `points` (α, 1/T) at m/m0 = 0.
    fn plot_of(points: &[[f64; 2]]) -> PlotCheckpoint {
        let resume = ResumeSpec {
            alpha_sweep: points.iter().map(|&[a, r]| [a, r, 0.0, 1.0]).collect(),
            ..ResumeSpec::default()
        };
        PlotHistory::resumed(&resume, 0.2, &DragLaw::default()).checkpoint()
    }

    /// A step at α and m/m0 under linear drag, on a body of critical angle `alpha_star`.
    fn at(alpha: f64, mass_ratio: f64, alpha_star: f64) -> StepAt {
        StepAt {
            alpha,
            mass_ratio,
            drag: DragLaw::default().label(),
            alpha_star,
            from: 0.0,
            to: 600.0,
        }
    }

    /// Points of T = 6/√(α − α*) + 100 exactly, at α*·(1 + e) for each e.
    fn law_points(star: f64, offsets: &[f64]) -> Vec<[f64; 2]> {
        offsets
            .iter()
            .map(|e| {
                let alpha = star * (1.0 + e);
                [alpha, 1.0 / (6.0 / (alpha - star).sqrt() + 100.0)]
            })
            .collect()
    }

    #[test]
    fn the_sqrt_law_holds_where_the_fit_goes_through_every_point_near_alpha_star() {
        let star = 0.12;
        let mut points = law_points(star, &[0.003, 0.01, 0.02, 0.03]);
        // Points past the law's reach are not fitted, so they cannot refute its claim.
        points.push([1.1 * star, 0.02]);
        points.push([1.3 * star, 0.03]);
        points.push([0.9 * star, 0.0]);
        let said = check_claim(
            Claim::SqrtLaw,
            &plot_of(&points),
            &at(1.3 * star, 0.0, star),
        )
        .unwrap();
        assert!(said.contains("through 4 points"), "{said}");
    }

    #[test]
    fn the_sqrt_law_is_refuted_by_a_point_off_the_fit_or_too_few_points() {
        let star = 0.12;
        let mut points = law_points(star, &[0.003, 0.01, 0.02, 0.03]);
        // T 6 % longer at 1.03 α*: the fit (least squares over all four) misses some point by
        // more than 2 %.
        points[3][1] /= 1.06;
        let why = check_claim(Claim::SqrtLaw, &plot_of(&points), &at(0.13, 0.0, star)).unwrap_err();
        assert!(why.contains("misses the point at α = "), "{why}");
        let why = check_claim(
            Claim::SqrtLaw,
            &plot_of(&law_points(star, &[0.01, 0.03, 0.1])),
            &at(0.13, 0.0, star),
        )
        .unwrap_err();
        assert!(why.contains("has 2 rolling point(s)"), "{why}");
        // Points at another m/m0 are another series: none at m/m0 = 0.5.
        let near = law_points(star, &[0.003, 0.01, 0.03]);
        let why = check_claim(Claim::SqrtLaw, &plot_of(&near), &at(0.13, 0.5, star)).unwrap_err();
        assert!(why.contains("has 0 rolling point(s)"), "{why}");
        // And points under another drag law are another series: none under n = 2.
        let other_law = StepAt {
            drag: "drag_exponent = 2".into(),
            ..at(0.13, 0.0, star)
        };
        let why = check_claim(Claim::SqrtLaw, &plot_of(&near), &other_law).unwrap_err();
        assert!(why.contains("has 0 rolling point(s)"), "{why}");
    }
}
