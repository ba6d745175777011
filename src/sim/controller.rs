//! [`Controller`]: the app's simulation side as a clock-free state machine ([`SimCommand`]s in,
//! `tick(wall_seconds)` to advance).

use crate::dynamics::Ramp;
use crate::integrate::Method;
use crate::scene::{SceneSetup, ViewsSpec};

use super::Simulation;

/// What the UI asks of the simulation (the app's controls; see [`Controller`]).
#[derive(Debug, Clone)]
pub enum SimCommand {
    /// New tilt α (radians), applied to the running state.
    SetAlpha(f64),
    /// New m/m0 (0: viscous), applied to the running state.
    SetMassRatio(f64),
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
    /// Panics inside the simulation: fault injection for the tests of [`SimThread`]'s panic
    /// path. The UI never sends it.
    #[doc(hidden)]
    InjectPanic,
}

/// The simulation's side of the app, free of threads and clocks so it can be tested as a state
/// machine: commands change it, `tick(wall_seconds)` advances it. A failure (the integrator
/// stopping, a refused parameter) becomes a message and, for failures while running, a paused
/// state; it never ends the program.
#[derive(Debug, Clone)]
pub struct Controller {
    sim: Simulation,
    paused: bool,
    speed: f64,
    message: Option<String>,
    lagging: bool,
}

impl Controller {
    /// A controller running `setup` from its start, playing at the scene's speed.
    pub fn new(setup: SceneSetup) -> Self {
        let speed = setup.scene.playback.speed;
        Self {
            sim: Simulation::new(setup),
            paused: false,
            speed,
            message: None,
            lagging: false,
        }
    }

    /// The simulation.
    pub fn simulation(&self) -> &Simulation {
        &self.sim
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

    /// Whether the last tick could not keep up with the requested speed.
    pub fn is_lagging(&self) -> bool {
        self.lagging
    }

    /// Applies one command. A refused command leaves the state as it was and sets the message.
    pub fn apply(&mut self, command: SimCommand) {
        let result = match command {
            SimCommand::SetAlpha(alpha) => self.set_ramp(alpha, self.sim.ramp().mass_ratio),
            SimCommand::SetMassRatio(m) => self.set_ramp(self.sim.ramp().alpha_rad, m),
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
                self.sim.advance_to(t).map_err(|e| e.to_string())
            }
            SimCommand::Reset => {
                self.sim = Simulation::new(self.sim.setup().clone());
                Ok(())
            }
            SimCommand::Load(setup) => {
                self.speed = setup.scene.playback.speed;
                self.sim = Simulation::new(*setup);
                Ok(())
            }
            SimCommand::Restart(setup) => {
                self.sim = Simulation::new(*setup);
                Ok(())
            }
            SimCommand::SetViews(views) => {
                self.sim.set_views(&views);
                Ok(())
            }
            SimCommand::InjectPanic => panic!("fault injected by SimCommand::InjectPanic"),
        };
        self.message = result.err();
    }

    /// Pauses with `message` (the simulation thread reports a caught panic this way).
    pub fn fail(&mut self, message: String) {
        self.paused = true;
        self.message = Some(message);
    }

    fn set_ramp(&mut self, alpha_rad: f64, mass_ratio: f64) -> Result<(), String> {
        let ramp = Ramp::with_drag(alpha_rad, mass_ratio, self.sim.ramp().drag)
            .map_err(|e| e.to_string())?;
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
        let target = self.sim.time() + self.speed * wall_seconds;
        match self.sim.advance_to(target) {
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
