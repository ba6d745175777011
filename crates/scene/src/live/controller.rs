//! [`Controller`]: the app's simulation side as a clock-free state machine ([`SimCommand`]s in,
//! `tick(wall_seconds)` to advance).

use crate::dynamics::Ramp;
use crate::integrate::Method;
use crate::scene::{SceneSetup, ViewsSpec};

use super::LiveRun;

/// What the UI asks of the simulation (the app's controls; see [`Controller`]).
#[derive(Debug, Clone)]
pub enum SimCommand {
    /// New tilt α (radians), applied to the running state.
    SetAlpha(f64),
    /// New m/m0 (0: viscous), applied to the running state.
    SetMassRatio(f64),
    /// New value of a registered drag-law parameter (its key in
    /// [`crate::dynamics::drag::REGISTERED`]), applied to the running state.
    SetDragParameter(&'static str, f64),
    /// New integrator.
    SetMethod(Method),
    /// Simulation time per second of wall time.
    SetSpeed(f64),
    /// Stop advancing.
    Pause,
    /// Advance again.
    Play,
    /// While paused: advance by one video frame (speed / fps).
    Step,
    /// Back to the scene's start.
    Reset,
    /// Replace the scene.
    Load(Box<SceneSetup>),
    /// Start the same body again from another initial state (a click on the curvature map):
    /// like `Load`, but the scene stays the same one (its meshes and the α sweep's history are
    /// kept) and the playback speed is not reset.
    Restart(Box<SceneSetup>),
    /// Turn views on or off (the SO(3) trail is recorded only while the ball is shown).
    SetViews(ViewsSpec),
    /// A lesson: go on to its next step now (simulating up to it).
    NextStep,
    /// A lesson: go back to the start of the step before the current one (the run starts again
    /// and is simulated up to there; a lesson has no way back in time otherwise).
    PreviousStep,
}

/// The simulation's side of the app, free of threads and clocks so it can be tested as a state
/// machine: commands change it, `tick(wall_seconds)` advances it. A failure (the integrator
/// stopping, a refused parameter) becomes a message and, for failures while running, a paused
/// state; it never ends the program.
#[derive(Debug, Clone)]
pub struct Controller {
    sim: LiveRun,
    paused: bool,
    speed: f64,
    message: Option<String>,
    /// Information, not a failure: a lesson with no further step to go to.
    info: Option<String>,
    lagging: bool,
}

impl Controller {
    /// A controller running `setup` from its start, playing at the scene's speed.
    pub fn new(setup: SceneSetup) -> Self {
        let mut sim = LiveRun::new(setup);
        // A lesson's step at t = 0 may set the first speed.
        let speed = sim
            .take_speed_change()
            .unwrap_or(sim.setup().scene.playback.speed);
        Self {
            sim,
            paused: false,
            speed,
            message: None,
            info: None,
            lagging: false,
        }
    }

    /// The simulation.
    pub fn simulation(&self) -> &LiveRun {
        &self.sim
    }

    /// The plots' samples the simulation took since the last call.
    pub fn take_plot_samples(&mut self) -> Vec<super::history::Sample> {
        self.sim.take_plot_samples()
    }

    /// Paused or not.
    pub fn is_paused(&self) -> bool {
        self.paused
    }

    /// Simulation time per wall second.
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// The last failure or refusal, for the UI to show.
    pub fn message(&self) -> Option<&str> {
        self.message.as_deref()
    }

    /// What the last command had to say that is not a failure (shown as information, not in
    /// the error colour): the lesson has no next or previous step.
    ///
    /// # Example
    /// ```
    /// use rollphase_scene::live::{Controller, SimCommand};
    /// use rollphase_scene::scene::Scene;
    /// let setup = Scene::preset("sphere-cruising").unwrap().setup(None).unwrap();
    /// let mut c = Controller::new(setup);
    /// c.apply(SimCommand::NextStep);
    /// assert!(c.message().is_none() && c.info().unwrap().contains("no lesson timeline"));
    /// ```
    pub fn info(&self) -> Option<&str> {
        self.info.as_deref()
    }

    /// Whether the last tick could not keep up with the requested speed.
    pub fn is_lagging(&self) -> bool {
        self.lagging
    }

    /// Applies one command. A refused command leaves the state as it was and sets the message.
    pub fn apply(&mut self, command: SimCommand) {
        self.info = None;
        let result = match command {
            SimCommand::SetAlpha(alpha) => self.set_ramp(alpha, self.sim.ramp().mass_ratio),
            SimCommand::SetMassRatio(m) => self.set_ramp(self.sim.ramp().alpha_rad, m),
            SimCommand::SetDragParameter(key, value) => {
                let now = self.sim.ramp();
                now.drag_law
                    .with(key, value)
                    .map_err(|e| e.to_string())
                    .and_then(|law| {
                        self.sim
                            .set_parameters(now.with_drag_law(law), self.sim.method())
                            .map_err(|e| e.to_string())
                    })
            }
            SimCommand::SetMethod(method) => self
                .sim
                .set_parameters(self.sim.ramp(), method)
                .map_err(|e| e.to_string()),
            SimCommand::SetSpeed(s) => {
                if s.is_finite() && s > 0.0 && s <= 1e4 {
                    self.speed = s;
                    Ok(())
                } else {
                    Err(format!(
                        "speed {s} is not allowed (needs 0 < speed ≤ 10000 time units per second)"
                    ))
                }
            }
            SimCommand::Pause => {
                self.paused = true;
                Ok(())
            }
            SimCommand::Play => {
                self.paused = false;
                Ok(())
            }
            SimCommand::Step => {
                self.paused = true;
                let dt = self.speed / self.sim.setup().scene.playback.fps;
                let t = self.sim.time() + dt;
                self.advance(t)
            }
            SimCommand::Reset => {
                // The whole scene as it started, its playback speed included.
                self.sim = self.sim.restarted();
                self.speed = self.sim.setup().scene.playback.speed;
                self.follow_lesson_speed();
                Ok(())
            }
            SimCommand::NextStep => match self.sim.next_step_time() {
                Some(at) => self.advance(at),
                None => {
                    self.info = Some(self.no_step_message("next"));
                    Ok(())
                }
            },
            SimCommand::PreviousStep => {
                let done = self.sim.steps_done();
                if self.sim.setup().timeline.is_empty() {
                    self.info = Some(self.no_step_message("previous"));
                    Ok(())
                } else {
                    // The start of the step before the current one, or the lesson's start.
                    let target = match done {
                        0 | 1 => 0.0,
                        n => self.sim.setup().timeline[n - 2].at,
                    };
                    self.sim = self.sim.restarted();
                    let result = self.advance(target);
                    self.follow_lesson_speed();
                    result
                }
            }
            SimCommand::Load(setup) => {
                self.speed = setup.scene.playback.speed;
                self.sim = LiveRun::new(*setup);
                self.follow_lesson_speed();
                Ok(())
            }
            SimCommand::Restart(setup) => {
                self.sim = LiveRun::new(*setup);
                self.follow_lesson_speed();
                Ok(())
            }
            SimCommand::SetViews(views) => {
                self.sim.set_views(&views);
                Ok(())
            }
        };
        self.message = result.err();
    }

    /// Pauses with `message` (the simulation thread reports a caught panic this way).
    pub fn fail(&mut self, message: String) {
        self.paused = true;
        self.message = Some(message);
    }

    fn no_step_message(&self, which: &str) -> String {
        if self.sim.setup().timeline.is_empty() {
            "this scene has no lesson timeline ([[timeline]] steps); the lessons are in the \
             Presets menu"
                .into()
        } else {
            format!("the lesson has no {which} step")
        }
    }

    /// A lesson plays at the speed its steps set, from where the run now is.
    fn follow_lesson_speed(&mut self) {
        self.sim.take_speed_change();
        if !self.sim.setup().timeline.is_empty() {
            self.speed = self.sim.setup().speed_at(self.sim.time());
        }
    }

    /// Advances the simulation to `t` and takes over a speed a timeline step set on the way.
    fn advance(&mut self, t: f64) -> Result<(), String> {
        let result = self.sim.advance_to(t).map_err(|e| e.to_string());
        if let Some(speed) = self.sim.take_speed_change() {
            self.speed = speed;
        }
        result
    }

    fn set_ramp(&mut self, alpha_rad: f64, mass_ratio: f64) -> Result<(), String> {
        let now = self.sim.ramp();
        let ramp = Ramp::with_drag(alpha_rad, mass_ratio, now.drag)
            .map_err(|e| e.to_string())?
            .with_drag_law(now.drag_law);
        self.sim
            .set_parameters(ramp, self.sim.method())
            .map_err(|e| e.to_string())
    }

    /// Advances by `speed × wall_seconds` of simulation time if playing. `max_rhs_evals` is the
    /// work the caller can afford per tick (it converts its frame budget into evaluations, so
    /// the state machine stays clock-free); exceeding it sets [`Self::is_lagging`], which the
    /// UI reports as "cannot keep up with the requested speed".
    pub fn tick(&mut self, wall_seconds: f64, max_rhs_evals: u64) {
        if self.paused || !(wall_seconds.is_finite() && wall_seconds > 0.0) {
            return;
        }
        let before = self.sim.snapshot().health.rhs_evals;
        // A timeline step that changes the speed splits the tick: the wall time up to the step
        // at the old speed, the rest at the new one (as the headless frame clock does).
        let mut wall_left = wall_seconds;
        let outcome = loop {
            let t = self.sim.time();
            let target = t + self.speed * wall_left;
            // A step within rounding of the tick's end is reached in this tick, so a tick
            // boundary that lands on a step time does not leave the rest of a tick unplayed.
            let reach = target + 1e-12 * target.abs().max(1.0);
            match self.sim.next_speed_step_time().filter(|&at| at <= reach) {
                Some(at) => {
                    let speed = self.speed;
                    if let Err(e) = self.advance(at) {
                        break Err(e);
                    }
                    wall_left = (wall_left - (at - t) / speed).max(0.0);
                }
                None => break self.advance(target),
            }
        };
        match outcome {
            Ok(()) => {
                let used = self.sim.snapshot().health.rhs_evals - before;
                self.lagging = used > max_rhs_evals;
            }
            Err(e) => {
                self.paused = true;
                self.message = Some(format!("simulation paused: {e}"));
            }
        }
    }
}
