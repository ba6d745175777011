//! [`LiveRun`]: one scene advanced to a requested time and observed as a [`Snapshot`]; its
//! model state, health figures and period bookkeeping, and the scene's lesson timeline, whose
//! steps it applies when its time reaches them (so the app and headless mode play a lesson alike).

use crate::analysis::orbits::sphere_orbits::{Crossing, ball_point, settled_cycle};
use crate::analysis::verdict::{LIVE_REST_THRESHOLD, at_rest_within};
use crate::dynamics::validity::ContactWatch;
use crate::dynamics::{
    ContactForce, ModelKind, ModelVisitor, ModelVisitorMut, Observation, Ramp, RollingModel,
};
use crate::geometry::Body;
use crate::geometry::sphere::angles;
use crate::integrate::events::{Direction, crossings_in_last_step};
use crate::integrate::run::{Flow, Run};
use crate::integrate::{self, Detached, IntegrateError, Method};
use crate::scene::{ReplayEntry, SceneSetup, Step, ViewsSpec};
use crate::simulate::{ModelState, choose_model, locate_switch};

use super::history::Sample;
use super::snapshot::*;

mod snapshot_of;
use glam::{DQuat, DVec3};
use std::collections::VecDeque;

/// Crossings of the section kept for the period and its multiplicity: the 10k + 1 that
/// [`settled_cycle`] needs to call a cycle of k ≤ [`MAX_MULTIPLICITY`] steady, and one more.
const MAX_CROSSINGS_KEPT: usize = 10 * MAX_MULTIPLICITY + 2;
/// Step budget of one `advance_to` (a frame), against a stuck integrator.
const MAX_STEPS_PER_ADVANCE: u64 = 5_000_000;
/// How far ahead of the time shown the live run asks its steps to go (t0): farther than any
/// step goes, so the steps are the integrator's own, as in a `simulate` run up to a later end;
/// near enough that the integrator's smallest step, 16 ε of the span asked for, stays 4e-9.
const LOOK_AHEAD: f64 = 1e6;
/// Most switches (tips across a dented cylinder's flats) one advance may take.
const MAX_SWITCHES_PER_ADVANCE: usize = 100_000;

/// A target closer than this (relative to the time) to the current time counts as reached.
const NOW_RELATIVE: f64 = 1e-12;
/// Longest cycle of ∂Ω crossings the live display looks for.
const MAX_MULTIPLICITY: usize = 4;
/// Crossing points that agree to this (antipodes identified) repeat, for the live display: loose
/// enough to report an orbit while it still converges, tight against the 0.2–0.5 alternation of
/// a doubled orbit.
const MULTIPLICITY_TOL: f64 = 1e-3;

#[derive(Debug, Clone, Copy)]
struct TrailSample {
    t: f64,
    on_ramp: DVec3,
    in_body: DVec3,
    ball: Option<DQuat>,
}

/// One scene's simulation.
#[derive(Debug, Clone)]
pub struct LiveRun {
    setup: SceneSetup,
    ramp: Ramp,
    method: Method,
    t: f64,
    state: ModelState,
    trail: VecDeque<TrailSample>,
    trail_dt: f64,
    next_trail_t: f64,
    crossings: VecDeque<(f64, Option<DVec3>)>,
    health: Health,
    /// The overlay line of the failure that stopped the run, if one did.
    stopped: Option<String>,
    /// Set by `drive` when the integrator fails, taken by `advance_to`.
    last_failure: Option<String>,
    energy0: Option<f64>,
    track_ball: bool,
    /// Timeline steps applied so far.
    steps_done: usize,
    caption: Option<String>,
    /// A speed set by a timeline step, not yet taken by the player.
    speed_change: Option<f64>,
    /// The views when this run started (a lesson restarts with them).
    start_views: ViewsSpec,
    /// The contact force followed since the parameters last changed.
    contact: ContactWatch,
    /// Tips across a dented cylinder's flats and the energy they took (`None`: convex body).
    hull_tips: Option<(u64, f64)>,
    /// The plots' samples not yet taken ([`Self::take_plot_samples`]), one every
    /// [`PLOT_SAMPLE_DT`] from the run's start.
    plot_samples: VecDeque<Sample>,
    /// The index k of the next sample, at t = k · [`PLOT_SAMPLE_DT`].
    next_plot_k: u64,
    /// The integration in progress, put down between frames: its steps end where the
    /// integrator puts them (or at a timeline step, or a switch), never where a frame falls,
    /// and a frame shows the state at its time from the last step's interpolant. So the run is
    /// the same at any frame rate, paused or not, and the same as `simulate`'s. `None` until
    /// the first step, and after α, m/m0, the integrator or the drag law change.
    continuation: Option<Continuation>,
    /// α, m/m0, the drag law or the integrator were changed by hand ([`Self::set_parameters`]),
    /// not by the scene's timeline: the run no longer plays the scene as written, so a lesson's
    /// evidence computed ahead from the scene ([`super::evidence`]) is not this run's.
    off_script: bool,
    /// How this run got here, as a saved state's `[[replay]]` records it: its model at the
    /// start, then each hand change and resume (empty: a resumed run whose file had no replay,
    /// which cannot be replayed).
    replay: Vec<ReplayEntry>,
    /// The scene's other bodies on the ramp (`[[bodies]]`), each a run of its own on the same
    /// clock, α and integrator (`super::lanes`).
    pub(super) lanes: Vec<LiveRun>,
    /// For each of `lanes`, whether its body is this run's (the same shape).
    lanes_share_body: Vec<bool>,
}

/// See [`LiveRun::continuation`].
#[derive(Debug, Clone)]
struct Continuation {
    /// The stepper, put down where its last step ended: at or past the time shown.
    stepper: Detached,
    /// A hybrid model's switch (a tip across a dented cylinder's flat) found in the last step
    /// and not yet reached by the time shown: its time and the state there, before it.
    switch: Option<(f64, Vec<f64>)>,
}

/// Simulation time between two samples of the plots' time series (θ(t), θ̇(θ), the health and
/// the contact force): taken here from the integrator's dense output, so the curves are the
/// same at any frame rate (sampled per drawn frame, a slow renderer cut the phase curve's
/// peaks by a fifth).
pub const PLOT_SAMPLE_DT: f64 = 0.1;

/// What a model gives the simulation at a state.
struct Observed {
    on_ramp: DVec3,
    in_body: DVec3,
    pose: BodyPose,
    ball: Option<DQuat>,
    angular_speed: f64,
    ramp_torque: f64,
    theta: Option<f64>,
    theta_dot: Option<f64>,
    quat_err: f64,
    normal_err: f64,
    energy: Option<f64>,
    measured: Measured,
    force: ContactForce,
}

impl LiveRun {
    /// A simulation at the scene's start (t = 0; call [`Self::advance_to`] to skip ahead), or
    /// at its saved state (`[resume]`): there the lesson's steps up to the saved time count as
    /// done, with their captions and views, but not their α or m/m0 (the saved scene's model is
    /// the one the run had).
    pub fn new(setup: SceneSetup) -> Self {
        let replay = match &setup.resume {
            None => vec![ReplayEntry::of(0.0, &setup.ramp, setup.method)],
            Some(r) if !setup.scene.replay.is_empty() => {
                let mut replay = setup.scene.replay.clone();
                replay.push(ReplayEntry {
                    resumed: true,
                    ..ReplayEntry::of(r.t, &setup.ramp, setup.method)
                });
                replay
            }
            Some(_) => Vec::new(),
        };
        let (t0, state) = match &setup.resume {
            Some(r) => (r.t, r.state.clone()),
            None => (0.0, ModelState::new(&setup.start, &setup.ramp)),
        };
        let playback = &setup.scene.playback;
        let trail_dt = (playback.trail_time / 3000.0).clamp(0.01, 1.0);
        let start_views = setup.scene.views.clone();
        let first = observe(&state, &setup.ramp);
        let setup_body_dented = match &setup.body {
            Body::Disk(d) => !d.hull().bridges().is_empty(),
            Body::Sphere(_) => false,
        };
        let contact = ContactWatch::new(setup.limits, t0, first.force);
        let lanes = setup.lanes.iter().cloned().map(LiveRun::new).collect();
        let own_shape = setup.body.to_shape();
        let lanes_share_body = setup
            .lanes
            .iter()
            .map(|l| l.body.to_shape() == own_shape)
            .collect();
        let mut sim = Self {
            ramp: setup.ramp,
            method: setup.method,
            track_ball: setup.scene.views.ball && matches!(setup.body, Body::Sphere(_)),
            setup,
            t: t0,
            state,
            trail: VecDeque::new(),
            trail_dt,
            next_trail_t: t0,
            crossings: VecDeque::new(),
            plot_samples: VecDeque::new(),
            next_plot_k: (t0 / PLOT_SAMPLE_DT).ceil() as u64,
            health: Health::default(),
            stopped: None,
            last_failure: None,
            energy0: None,
            steps_done: 0,
            caption: None,
            speed_change: None,
            start_views,
            contact,
            hull_tips: setup_body_dented.then_some((0, 0.0)),
            continuation: None,
            off_script: false,
            replay,
            lanes,
            lanes_share_body,
        };
        // The other bodies' orientations are followed while this scene's ball is shown.
        let views = sim.setup.scene.views.clone();
        sim.set_views(&views);
        let o = observe(&sim.state, &sim.ramp);
        sim.energy0 = o.energy;
        // What the model measures is known before the first step: a run reset while paused
        // showed the health plot of a model with nothing to measure (a cylinder's text).
        sim.health.measured = o.measured;
        sim.record(t0, &o);
        if t0 > 0.0 {
            sim.catch_up_steps(t0);
            return sim;
        }
        // Steps at t = 0 hold from the first frame; they were validated with the scene, so
        // applying them cannot fail.
        if let Err(e) = sim.advance_to(0.0) {
            sim.caption = Some(e.to_string());
        }
        sim
    }

    /// A resumed lesson: the steps at or before `t` are done, the last caption and the views
    /// they set hold, and their model changes are left out (the saved model is the current one).
    fn catch_up_steps(&mut self, t: f64) {
        while let Some(step) = self
            .setup
            .timeline
            .get(self.steps_done)
            .filter(|s| s.at <= t)
            .cloned()
        {
            self.steps_done += 1;
            if let Some(change) = &step.views {
                let views = change.applied_to(&self.setup.scene.views);
                self.set_views(&views);
            }
            if let Some(caption) = &step.caption {
                self.caption = (!caption.is_empty()).then(|| caption.clone());
            }
            if step.speed.is_some() {
                self.speed_change = step.speed;
            }
        }
    }

    /// The same scene from its start again: a lesson with the views it started with, any other
    /// scene with the views as they are now (the user's toggles survive a reset).
    pub fn restarted(&self) -> Self {
        let mut setup = self.setup.clone();
        if !setup.timeline.is_empty() {
            setup.scene.views = self.start_views.clone();
        }
        Self::new(setup)
    }

    /// Simulation time of the next timeline step, if one is left.
    pub fn next_step_time(&self) -> Option<f64> {
        self.setup.timeline.get(self.steps_done).map(|s| s.at)
    }

    /// Simulation time of the next timeline step that sets the playback speed.
    pub fn next_speed_step_time(&self) -> Option<f64> {
        self.setup.timeline[self.steps_done.min(self.setup.timeline.len())..]
            .iter()
            .find(|s| s.speed.is_some())
            .map(|s| s.at)
    }

    /// Timeline steps applied so far.
    pub fn steps_done(&self) -> usize {
        self.steps_done
    }

    /// The playback speed the last applied timeline step set, once: the player (the app's
    /// controller) takes it over from there.
    pub fn take_speed_change(&mut self) -> Option<f64> {
        self.speed_change.take()
    }

    fn apply_step(&mut self, step: &Step) -> Result<(), SimError> {
        self.steps_done += 1;
        if step.changes_model() {
            let ramp = Ramp::with_drag(
                step.alpha_rad.unwrap_or(self.ramp.alpha_rad),
                step.mass_ratio.unwrap_or(self.ramp.mass_ratio),
                self.ramp.drag,
            )
            .map_err(|e| SimError::Refused(format!("timeline step at t = {}: {e}", step.at)))?
            .with_drag_law(self.ramp.drag_law);
            self.change_parameters(ramp, step.method.unwrap_or(self.method))?;
            self.lanes_follow(ramp.alpha_rad, self.method);
        }
        if let Some(change) = &step.views {
            let views = change.applied_to(&self.setup.scene.views);
            self.set_views(&views);
        }
        if step.speed.is_some() {
            self.speed_change = step.speed;
        }
        if let Some(caption) = &step.caption {
            self.caption = (!caption.is_empty()).then(|| caption.clone());
        }
        Ok(())
    }

    /// The scene this simulation runs.
    pub fn setup(&self) -> &SceneSetup {
        &self.setup
    }

    /// Current simulation time.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The integrated state.
    pub fn state(&self) -> &ModelState {
        &self.state
    }

    /// The ramp being simulated.
    pub fn ramp(&self) -> Ramp {
        self.ramp
    }

    /// The integrator.
    pub fn method(&self) -> Method {
        self.method
    }

    /// Changes α, m/m0 and the integrator from now on, keeping the body's pose (and, between
    /// inertial settings, its angular velocity): what a user sweeping α or m/m0 expects.
    /// Going from inertial to viscous drops the velocity; from viscous to inertial the body
    /// starts from rest.
    pub fn set_parameters(&mut self, ramp: Ramp, method: Method) -> Result<(), SimError> {
        self.change_parameters(ramp, method)?;
        self.lanes_follow(ramp.alpha_rad, method);
        self.off_script = true;
        if !self.replay.is_empty() {
            self.replay.push(ReplayEntry::of(self.t, &ramp, method));
        }
        Ok(())
    }

    /// Whether α, m/m0, the drag law or the integrator were changed by hand since the run
    /// started: it then no longer plays its scene as written.
    pub fn off_script(&self) -> bool {
        self.off_script
    }

    /// Forgets the plots' samples and the trail recorded past `now` (by a step that reached
    /// beyond it), so that the next steps take them again on the same grid.
    fn drop_recorded_after(&mut self, now: f64) {
        while self.plot_samples.back().is_some_and(|s| s.t > now) {
            self.plot_samples.pop_back();
        }
        // The first grid time after `now`: k · dt > now.
        let mut k = (now / PLOT_SAMPLE_DT).floor().max(0.0) as u64;
        while k as f64 * PLOT_SAMPLE_DT <= now {
            k += 1;
        }
        self.next_plot_k = self.next_plot_k.min(k);
        let mut first_dropped = None;
        while self.trail.back().is_some_and(|s| s.t > now) {
            first_dropped = self.trail.pop_back().map(|s| s.t);
        }
        if let Some(t) = first_dropped {
            self.next_trail_t = self.next_trail_t.min(t);
        }
    }

    /// Whether the run stopped (an integration failure, a refused change).
    pub fn is_stopped(&self) -> bool {
        self.stopped.is_some()
    }

    /// Stops the run with `why` on its line (a body on a lane that cannot follow the ramp).
    pub(super) fn stop_with(&mut self, why: String) {
        self.stopped = Some(why);
    }

    /// [`Self::set_parameters`] for a hand change, a timeline step, or a body on a lane taking
    /// the ramp's new α or integrator (`super::lanes`) alike.
    pub(super) fn change_parameters(&mut self, ramp: Ramp, method: Method) -> Result<(), SimError> {
        let choice = choose_model(&self.setup.body, ramp, method)
            .map_err(|e| SimError::Refused(e.to_string()))?;
        method
            .validate()
            .map_err(|e| SimError::Refused(e.to_string()))?;
        let ramp = choice.ramp;
        self.stopped = None;
        // A new model or integrator from the time shown: the run in progress ends there, and
        // what its last step recorded past the time shown (the plots' samples, the trail) was
        // the old model's: dropped, to be taken again from the new run.
        self.continuation = None;
        self.drop_recorded_after(self.t);
        self.state = self.state.clone().for_ramp(&ramp);
        self.ramp = ramp;
        self.method = method;
        self.crossings.clear();
        let o = observe(&self.state, &ramp);
        self.energy0 = o.energy;
        self.health.measured = o.measured;
        // A new regime: the force is followed afresh from here.
        self.contact = ContactWatch::new(self.setup.limits, self.t, o.force);
        Ok(())
    }

    /// Turns views on or off from now on (the app's toggles): the SO(3) trail is recorded only
    /// while the ball is shown, so switching it on starts an empty trail.
    pub fn set_views(&mut self, views: &ViewsSpec) {
        self.setup.scene.views = views.clone();
        self.track_ball = views.ball && matches!(self.setup.body, Body::Sphere(_));
        // The other bodies' paths are drawn in the same ball.
        for lane in &mut self.lanes {
            lane.track_ball = self.track_ball && matches!(lane.setup.body, Body::Sphere(_));
        }
    }

    /// Integrates from the current time to `t_target`, applying the timeline steps on the way
    /// at their times (a step at exactly `t_target` included). No-op if `t_target` is earlier.
    pub fn advance_to(&mut self, t_target: f64) -> Result<(), SimError> {
        let result = self.advance_through_steps(t_target);
        if let Err(SimError::Integrate { .. }) = &result {
            self.stopped = self.last_failure.take();
        }
        result
    }

    fn advance_through_steps(&mut self, t_target: f64) -> Result<(), SimError> {
        while let Some(step) = self
            .setup
            .timeline
            .get(self.steps_done)
            .filter(|s| s.at <= t_target)
            .cloned()
        {
            self.integrate_to(step.at)?;
            self.lanes_to(step.at);
            self.apply_step(&step)?;
        }
        self.integrate_to(t_target)?;
        self.lanes_to(t_target);
        Ok(())
    }

    fn integrate_to(&mut self, t_target: f64) -> Result<(), SimError> {
        // NaN targets fall through here too: nothing to do.
        if t_target.partial_cmp(&self.t) != Some(std::cmp::Ordering::Greater) {
            return Ok(());
        }
        // A target within rounding of now (a tick that ends a hair after a step time) is now:
        // no integrator step can resolve an interval of a few ulps, and trying fails.
        if t_target - self.t <= NOW_RELATIVE * self.t.abs().max(1.0) {
            return Ok(());
        }
        let ramp = self.ramp;
        // The body is borrowed from a copy of the state while `drive` updates `self`.
        let mut state = self.state.clone();
        state.visit_mut(
            &ramp,
            Integrate {
                sim: self,
                t_target,
            },
        )?;
        self.state = state;
        Ok(())
    }

    /// Steps `model` on to `t_target` and returns the state shown there, recording crossings of
    /// its section, the trails and the health as the steps go. The steps are the run's own
    /// ([`Self::continuation`]): they go on from the last frame's and end where the integrator
    /// puts them, so a frame reads its state from the last step's interpolant. A dented
    /// cylinder's switches (a tip across a flat of its hull, a rest on one) start the next
    /// stepper from the state after the switch, as `simulate::run` does.
    fn drive<const N: usize, M: RollingModel<N>>(
        &mut self,
        model: &M,
        y_shown: [f64; N],
        t_target: f64,
    ) -> Result<[f64; N], SimError> {
        let result = self.drive_on(model, y_shown, t_target);
        if result.is_err() {
            self.continuation = None;
        }
        let trail_horizon = self.t - self.setup.scene.playback.trail_time;
        while self.trail.front().is_some_and(|s| s.t < trail_horizon) {
            self.trail.pop_front();
        }
        result
    }

    fn drive_on<const N: usize, M: RollingModel<N>>(
        &mut self,
        model: &M,
        y_shown: [f64; N],
        t_target: f64,
    ) -> Result<[f64; N], SimError> {
        // Only a timeline step (a change of the model at its time) ends a step early; else the
        // steps look ahead a span no step reaches (the integrator's smallest step is relative
        // to how far it is asked to go, so the span is finite).
        let horizon = self
            .next_step_time()
            .filter(|&at| at > self.t)
            .unwrap_or(f64::INFINITY)
            .min(self.t + LOOK_AHEAD);
        let mut switches = 0usize;
        let mut cont = self.continuation.take();
        loop {
            if let Some((ts, y_at)) = cont.as_ref().and_then(|c| c.switch.clone())
                && ts <= t_target
            {
                let y_at = as_state::<N>(&y_at)?;
                self.t = ts;
                let Some((after, what)) = model.switch(&y_at) else {
                    return Ok(y_at);
                };
                if let Some((tips, lost)) = self.hull_tips.as_mut() {
                    *lost += what.energy_lost();
                    if let crate::dynamics::Switched::Tip { .. } = what {
                        *tips += 1;
                    }
                }
                // A tip can jump over the section (a flat that spans θ = 0 mod 2π): the
                // crossing is then at the tip.
                if model.section(&y_at).signum() != model.section(&after).signum() {
                    self.crossings.push_back((ts, model.section_point(&after)));
                    if self.crossings.len() > MAX_CROSSINGS_KEPT {
                        self.crossings.pop_front();
                    }
                }
                self.contact.jump(ts, model.contact_force(&after));
                switches += 1;
                if switches > MAX_SWITCHES_PER_ADVANCE {
                    let e = IntegrateError::TooManySteps {
                        t: ts,
                        max_steps: MAX_SWITCHES_PER_ADVANCE as u64,
                    };
                    self.last_failure = Some(overlay_line(&e));
                    return Err(SimError::Integrate {
                        t: ts,
                        message: e.to_string(),
                    });
                }
                let run = self.start(model, ts, after)?;
                cont = Some(Continuation {
                    stepper: run.detach(),
                    switch: None,
                });
                continue;
            }
            let mut run = match &cont {
                Some(c) => Run::resume(model, &c.stepper).ok_or_else(|| SimError::Integrate {
                    t: self.t,
                    message: "internal error: the run in progress is of another model".into(),
                })?,
                None => {
                    // A body resting on a flat lies as the statics of the current ramp say (α
                    // may have changed since): it tips if its weight has left the flat.
                    self.start(model, self.t, model.placed(y_shown))?
                }
            };
            let switch_ahead = cont.as_ref().and_then(|c| c.switch.clone());
            if switch_ahead.is_some() || run.t() >= t_target {
                // The time shown lies within the last step (before its switch, if it has one).
                let y = if run.t() == t_target {
                    *run.y()
                } else {
                    run.dense(t_target)
                };
                self.t = t_target;
                self.continuation = Some(Continuation {
                    stepper: run.detach(),
                    switch: switch_ahead,
                });
                return Ok(y);
            }
            let switch = self.step_past(model, &mut run, horizon, t_target)?;
            cont = Some(Continuation {
                stepper: run.detach(),
                switch: switch.map(|(t, y)| (t, y.to_vec())),
            });
        }
    }

    /// A new stepper of `model` from (t, y).
    fn start<'m, const N: usize, M: RollingModel<N>>(
        &mut self,
        model: &'m M,
        t: f64,
        y: [f64; N],
    ) -> Result<Run<'m, N>, SimError> {
        Run::new(model, t, y, self.method).map_err(|e| {
            self.last_failure = Some(overlay_line(&e));
            SimError::Integrate {
                t,
                message: e.to_string(),
            }
        })
    }

    /// Steps `run` (towards `horizon`, so the steps are the integrator's own) until a step
    /// ends at or past `t_target`, or a hybrid model's switch is found in one, whose time and
    /// state (before it) it returns. Each step is observed in full as it is taken: crossings of
    /// the section, the trails, the plots' samples, the contact force and the health, read
    /// from the step's interpolant; what lies past the time shown waits for its frame.
    #[allow(clippy::type_complexity)]
    fn step_past<const N: usize, M: RollingModel<N>>(
        &mut self,
        model: &M,
        run: &mut Run<'_, N>,
        horizon: f64,
        t_target: f64,
    ) -> Result<Option<(f64, [f64; N])>, SimError> {
        let section = |y: &[f64; N]| model.section(y);
        let section_point = |y: &[f64; N]| model.section_point(y);
        let observe = |y: &[f64; N]| Observed::of(model, y);
        let evals_before = run.stats().rhs_evals;
        let mut crossing_times = Vec::new();
        let mut switch = None;
        let stepped = run.until(horizon, MAX_STEPS_PER_ADVANCE, |st| {
            if st.y().iter().any(|v| !v.is_finite()) {
                return Err(IntegrateError::NonFinite { t: st.t() });
            }
            let found = locate_switch(st, model);
            let (t_now, y_now) = found.unwrap_or((st.t(), *st.y()));
            crossing_times.clear();
            crossings_in_last_step(
                st,
                &|_t, y: &[f64; N]| section(y),
                Direction::Both,
                &mut crossing_times,
            );
            for &tc in crossing_times.iter().filter(|&&tc| tc <= t_now) {
                let point = section_point(&st.dense(tc));
                self.crossings.push_back((tc, point));
                if self.crossings.len() > MAX_CROSSINGS_KEPT {
                    self.crossings.pop_front();
                }
            }
            while self.next_trail_t <= t_now {
                let ts = self.next_trail_t.max(st.t_prev());
                let o = observe(&st.dense(ts));
                self.record(ts, &o);
                self.next_trail_t += self.trail_dt;
            }
            loop {
                // k · dt, not a running sum: the grid is the same however the run is cut up.
                let ts = self.next_plot_k as f64 * PLOT_SAMPLE_DT;
                if ts > t_now {
                    break;
                }
                if ts >= st.t_prev() {
                    let o = observe(&st.dense(ts));
                    self.push_plot_sample(ts, &o);
                }
                self.next_plot_k += 1;
            }
            self.contact
                .step_along(st, (t_now, y_now), |y| model.contact_force(y));
            let o = observe(&y_now);
            self.health.measured = o.measured;
            self.health.quat_norm_error = self.health.quat_norm_error.max(o.quat_err);
            self.health.contact_normal_error = self.health.contact_normal_error.max(o.normal_err);
            if let (Some(e), Some(e0)) = (o.energy, self.energy0) {
                self.health.energy_drift = self.health.energy_drift.max((e - e0).abs());
            }
            if found.is_some() {
                switch = found;
                return Ok(Flow::Stop);
            }
            Ok(if st.t() >= t_target {
                Flow::Stop
            } else {
                Flow::Continue
            })
        });
        self.health.rhs_evals += run.stats().rhs_evals - evals_before;
        if let Err(e) = stepped {
            self.last_failure = Some(overlay_line(&e));
            return Err(SimError::Integrate {
                t: run.t(),
                message: e.to_string(),
            });
        }
        Ok(switch)
    }

    fn record(&mut self, t: f64, o: &Observed) {
        self.trail.push_back(TrailSample {
            t,
            on_ramp: o.on_ramp,
            in_body: o.in_body,
            ball: if self.track_ball { o.ball } else { None },
        });
    }

    /// The plots' samples taken since the last call, oldest first (at most
    /// [`history::MAX_SAMPLES`](super::history::MAX_SAMPLES) are kept waiting).
    pub fn take_plot_samples(&mut self) -> Vec<Sample> {
        // Samples past the time shown (the last step reaches beyond it) wait for their frame.
        let shown = self.plot_samples.partition_point(|s| s.t <= self.t);
        let mut samples: Vec<Sample> = self.plot_samples.drain(..shown).collect();
        self.take_lane_samples(&mut samples);
        samples
    }

    fn push_plot_sample(&mut self, t: f64, o: &Observed) {
        let (theta, phi) = match o.theta {
            Some(theta) => (theta, 0.0),
            None => angles(o.in_body),
        };
        self.plot_samples.push_back(Sample {
            t,
            theta,
            rate: o.theta_dot.unwrap_or(o.angular_speed),
            phi,
            quat_norm_error: self.health.quat_norm_error.max(o.quat_err),
            contact_normal_error: self.health.contact_normal_error.max(o.normal_err),
            energy_drift: self.health.energy_drift,
            normal_force: o.force.normal,
            friction_needed: o.force.friction_needed(),
            body: 0,
        });
        while self.plot_samples.len() > super::history::MAX_SAMPLES {
            self.plot_samples.pop_front();
        }
    }

    /// See [`Snapshot::poincare_field`].
    pub fn field_wanted(&self) -> FieldWanted {
        let shown = self.setup.scene.views.poincare;
        match (shown, ModelKind::of(&self.setup.body, &self.ramp)) {
            (true, ModelKind::SphereViscous) => FieldWanted::Ramp(self.ramp),
            (true, ModelKind::SphereInertial) => FieldWanted::NeedsViscous,
            (true, ModelKind::DiskViscous | ModelKind::DiskInertial) | (false, _) => {
                FieldWanted::Off
            }
        }
    }
}

/// What `state` looks like on `ramp`.
/// One overlay line for an integration failure: a fixed step too coarse says which, by how much
/// and what to use; anything else its message, cut to a line.
fn overlay_line(e: &IntegrateError) -> String {
    match e {
        IntegrateError::StepTooCoarse {
            method,
            dt,
            estimate,
            tolerance,
            suggested,
            ..
        } => format!(
            "STOPPED: {} dt {} too coarse (error estimate {estimate:.1e} > {tolerance:e}); use dt ≤ {} or DOP853",
            method.to_uppercase(),
            integrate::readable(*dt),
            integrate::readable(*suggested)
        ),
        other => {
            let text = format!("STOPPED: {other}");
            match text.char_indices().nth(100) {
                Some((cut, _)) => format!("{}…", &text[..cut]),
                None => text,
            }
        }
    }
}

/// A state kept as a vector, back as the model's array.
fn as_state<const N: usize>(y: &[f64]) -> Result<[f64; N], SimError> {
    y.try_into().map_err(|_| SimError::Integrate {
        t: f64::NAN,
        message: "internal error: a switch's state is of another model".into(),
    })
}

fn observe(state: &ModelState, ramp: &Ramp) -> Observed {
    state.visit(ramp, ObserveState)
}

/// Steps the run's model ([`ModelState::visit_mut`]) to a time.
struct Integrate<'a> {
    sim: &'a mut LiveRun,
    t_target: f64,
}

impl ModelVisitorMut for Integrate<'_> {
    type Output = Result<(), SimError>;

    fn visit<const N: usize, M: RollingModel<N>>(
        self,
        model: &M,
        y: &mut [f64; N],
    ) -> Self::Output {
        *y = self.sim.drive(model, *y, self.t_target)?;
        Ok(())
    }
}

/// What the run's state looks like ([`ModelState::visit`]).
struct ObserveState;

impl ModelVisitor for ObserveState {
    type Output = Observed;

    fn visit<const N: usize, M: RollingModel<N>>(self, model: &M, y: &[f64; N]) -> Observed {
        Observed::of(model, y)
    }
}

impl Observed {
    /// What `model` shows at `y`, its contact force included.
    fn of<const N: usize, M: RollingModel<N>>(model: &M, y: &[f64; N]) -> Self {
        let mut o = Observed::from(model.observation(y));
        o.force = model.contact_force(y);
        o
    }
}

impl From<Observation> for Observed {
    fn from(o: Observation) -> Self {
        Observed {
            on_ramp: o.contact_on_ramp,
            in_body: o.contact_in_body,
            pose: BodyPose {
                rotation: o.rotation,
                centre: o.centre,
            },
            ball: o.orientation,
            angular_speed: o.angular_speed,
            ramp_torque: o.ramp_torque,
            theta: o.theta,
            theta_dot: o.theta_dot,
            quat_err: o.health.quat_norm_error.unwrap_or(0.0),
            normal_err: o.health.contact_normal_error.unwrap_or(0.0),
            energy: o.health.energy,
            measured: Measured {
                quat_norm: o.health.quat_norm_error.is_some(),
                contact_normal: o.health.contact_normal_error.is_some(),
                energy: o.health.energy.is_some(),
            },
            force: ContactForce {
                normal: f64::NAN,
                friction: [f64::NAN; 2],
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_health_a_model_measures_is_known_before_its_first_step() {
        let setup = crate::scene::Scene::preset("sphere-cruising")
            .unwrap()
            .setup(None)
            .unwrap();
        let h = LiveRun::new(setup).snapshot().health.measured;
        assert!(h.quat_norm && h.contact_normal && !h.energy, "{h:?}");
        let setup = crate::scene::Scene::preset("cylinder-hysteresis")
            .unwrap()
            .setup(None)
            .unwrap();
        let h = LiveRun::new(setup).snapshot().health.measured;
        assert!(!h.quat_norm && !h.contact_normal && h.energy, "{h:?}");
    }

    #[test]
    fn a_heavy_body_released_above_its_critical_angle_is_not_halted() {
        let mut setup = crate::scene::Scene::preset("sphere-cruising")
            .unwrap()
            .setup(None)
            .unwrap();
        let ramp = Ramp::new(0.3, 1e4).unwrap();
        let mut run = LiveRun::new(setup.clone());
        run.set_parameters(ramp, Method::dop853(1e-8)).unwrap();
        let snap = run.snapshot();
        assert_eq!(snap.angular_speed, 0.0);
        assert!(
            !snap.halted,
            "still at t = 0 but pushed downhill: not a rest"
        );
        // Below α* it does come to rest, and is then halted.
        setup.ramp = Ramp::new(0.05, 0.0).unwrap();
        let mut run = LiveRun::new(setup);
        run.advance_to(400.0).unwrap();
        let snap = run.snapshot();
        assert!(
            snap.halted,
            "t = {}: |ω| = {:e}, α = {}",
            snap.t, snap.angular_speed, snap.alpha_rad
        );
    }
}
