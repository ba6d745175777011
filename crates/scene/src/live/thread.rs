//! [`SimThread`]: a [`Controller`] on its own thread, reading the wall clock, catching panics and
//! publishing [`SimStatus`] for the UI.

use crate::integrate::Method;
use crate::scene::SceneSetup;
use std::collections::VecDeque;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::history::{MAX_SAMPLES, Sample};
use super::{Controller, SimCommand, Snapshot};

/// What the simulation thread publishes after each tick: the latest snapshot and the state of
/// the controls, as one immutable value the UI reads without waiting.
#[derive(Debug, Clone)]
pub struct SimStatus {
    /// What the body looks like now.
    pub snapshot: Snapshot,
    /// The scene being simulated (the UI rebuilds its meshes when `scene_id` changes).
    pub setup: Arc<SceneSetup>,
    /// Counts scene loads (the UI rebuilds meshes and clears all plots when it changes).
    pub scene_id: u64,
    /// Counts loads and resets (the UI clears the time series when it changes).
    pub run_id: u64,
    /// Paused or playing.
    pub paused: bool,
    /// Requested simulation time per wall second.
    pub speed: f64,
    /// Simulation time per wall second actually delivered over the last second of playing, or
    /// over the last tick when one tick takes longer (`None` until a quarter of a second has
    /// been measured).
    pub delivered_speed: Option<f64>,
    /// The simulation cannot deliver the requested speed (below 90% of it).
    pub lagging: bool,
    /// The last failure, refusal or caught panic.
    pub message: Option<String>,
    /// Information from the last command that is not a failure (a lesson's last step reached).
    pub info: Option<String>,
    /// The integrator setting, as the UI shows it.
    pub method: Method,
    /// Wall-clock time of the last tick's integration, seconds.
    pub tick_seconds: f64,
}

/// How often the simulation thread ticks while playing.
pub const TICK_INTERVAL: Duration = Duration::from_millis(8);

/// Longest wall-clock gap one tick makes up for: after a stall (the machine busy, a debugger)
/// the simulation continues from where it was instead of jumping ahead.
const MAX_TICK_WALL: f64 = 0.1;

/// The simulation thread: owns a [`Controller`], takes [`SimCommand`]s through a channel and
/// publishes an `Arc<SimStatus>` after each tick. The UI does not wait for it (reading the status
/// clones an `Arc` under a lock held for that long only; only a frame that sent a load polls,
/// briefly, for the new run to draw it) and it never waits for a frame. A panic
/// inside the simulation is caught and becomes a message and a paused state.
pub struct SimThread {
    commands: Sender<SimCommand>,
    status: Arc<Mutex<Arc<SimStatus>>>,
    samples: Arc<Mutex<PlotSamples>>,
    handle: Option<JoinHandle<()>>,
}

/// The plots' samples the simulation took and the UI has not yet collected, of one run
/// ((scene_id, run_id)); at most [`MAX_SAMPLES`] wait (the history keeps no more).
#[derive(Debug, Default)]
struct PlotSamples {
    run: (u64, u64),
    samples: VecDeque<Sample>,
}

impl SimThread {
    /// Starts the thread on `setup`, playing; the OS's error if no thread can be started (a
    /// simulation that never runs must not look like a paused one).
    pub fn spawn(setup: SceneSetup) -> std::io::Result<Self> {
        let (commands, inbox) = mpsc::channel();
        let mut worker = SimWorker::new(setup);
        let status = Arc::new(Mutex::new(Arc::new(worker.status())));
        let samples = Arc::new(Mutex::new(PlotSamples::default()));
        let published = status.clone();
        let taken = samples.clone();
        let handle = std::thread::Builder::new()
            .name("rollphase-sim".into())
            .spawn(move || worker.run(&inbox, &published, &taken))?;
        Ok(Self {
            commands,
            status,
            samples,
            handle: Some(handle),
        })
    }

    /// The plots' samples taken since the last call, oldest first, with the run they belong to
    /// ((scene_id, run_id) of [`SimStatus`]): sampled by the simulation every
    /// [`PLOT_SAMPLE_DT`](super::PLOT_SAMPLE_DT) of its time, however often this is called.
    pub fn take_plot_samples(&self) -> ((u64, u64), Vec<Sample>) {
        let mut queue = match self.samples.lock() {
            Ok(q) => q,
            Err(poisoned) => poisoned.into_inner(),
        };
        (queue.run, queue.samples.drain(..).collect())
    }

    /// Queues a command; it takes effect at the thread's next tick.
    pub fn send(&self, command: SimCommand) {
        // A send fails only when the thread has ended, which `status` then reports.
        let _ = self.commands.send(command);
    }

    /// The latest published status.
    pub fn status(&self) -> Arc<SimStatus> {
        match self.status.lock() {
            Ok(s) => s.clone(),
            Err(poisoned) => poisoned.into_inner().clone(),
        }
    }

    /// Whether the thread is still running.
    pub fn is_running(&self) -> bool {
        self.handle.as_ref().is_some_and(|h| !h.is_finished())
    }
}

impl Drop for SimThread {
    fn drop(&mut self) {
        // Closing the channel ends the loop.
        let (closed, _) = mpsc::channel();
        self.commands = closed;
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

/// The thread's side: the controller plus the wall-clock bookkeeping.
struct SimWorker {
    controller: Controller,
    setup: Arc<SceneSetup>,
    scene_id: u64,
    run_id: u64,
    /// Simulation time against wall time over the last second of playing.
    window: SpeedWindow,
    tick_seconds: f64,
}

impl SimWorker {
    fn new(setup: SceneSetup) -> Self {
        Self {
            setup: Arc::new(setup.clone()),
            controller: Controller::new(setup),
            scene_id: 0,
            run_id: 0,
            window: SpeedWindow::default(),
            tick_seconds: 0.0,
        }
    }

    fn status(&self) -> SimStatus {
        let delivered = self.window.delivered();
        let speed = self.controller.speed();
        SimStatus {
            snapshot: self.controller.simulation().snapshot(),
            setup: self.setup.clone(),
            scene_id: self.scene_id,
            run_id: self.run_id,
            paused: self.controller.is_paused(),
            speed,
            delivered_speed: delivered,
            lagging: !self.controller.is_paused() && delivered.is_some_and(|d| d < 0.9 * speed),
            message: self.controller.message().map(str::to_string),
            info: self.controller.info().map(str::to_string),
            method: self.controller.simulation().method(),
            tick_seconds: self.tick_seconds,
        }
    }

    /// Runs `f` on the controller; a panic becomes a message and a paused state.
    fn guarded(&mut self, what: &str, f: impl FnOnce(&mut Controller)) {
        let result =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(&mut self.controller)));
        if let Err(payload) = result {
            let why = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            self.controller.fail(format!(
                "the simulation panicked while {what}: {why}; paused (press Reset or load a scene)"
            ));
        }
    }

    /// Hands the samples the simulation took to the UI's queue, emptied when the run changed.
    fn hand_over_samples(&mut self, queue: &Mutex<PlotSamples>) {
        let taken = self.controller.take_plot_samples();
        let mut queue = match queue.lock() {
            Ok(q) => q,
            Err(poisoned) => poisoned.into_inner(),
        };
        let run = (self.scene_id, self.run_id);
        if queue.run != run {
            queue.run = run;
            queue.samples.clear();
        }
        queue.samples.extend(taken);
        while queue.samples.len() > MAX_SAMPLES {
            queue.samples.pop_front();
        }
    }

    fn run(
        &mut self,
        inbox: &Receiver<SimCommand>,
        published: &Mutex<Arc<SimStatus>>,
        samples: &Mutex<PlotSamples>,
    ) {
        let start = Instant::now();
        let mut last = start;
        loop {
            // Paused: sleep until a command comes; playing: take what is queued and tick.
            let first = if self.controller.is_paused() {
                match inbox.recv_timeout(Duration::from_millis(100)) {
                    Ok(c) => Some(c),
                    Err(RecvTimeoutError::Timeout) => None,
                    Err(RecvTimeoutError::Disconnected) => return,
                }
            } else {
                match inbox.try_recv() {
                    Ok(c) => Some(c),
                    Err(TryRecvError::Empty) => None,
                    Err(TryRecvError::Disconnected) => return,
                }
            };
            for command in first.into_iter().chain(inbox.try_iter()) {
                // A jump to the next step is not playback: its simulated time is not delivered.
                let is_speed = matches!(command, SimCommand::SetSpeed(_) | SimCommand::NextStep);
                let restarts = matches!(
                    command,
                    SimCommand::Reset
                        | SimCommand::Load(_)
                        | SimCommand::Restart(_)
                        | SimCommand::PreviousStep
                );
                match &command {
                    SimCommand::Load(setup) => {
                        self.setup = Arc::new((**setup).clone());
                        self.scene_id += 1;
                    }
                    SimCommand::Restart(setup) => self.setup = Arc::new((**setup).clone()),
                    _ => {}
                }
                self.guarded("applying a command", |c| c.apply(command));
                if restarts {
                    self.run_id += 1;
                }
                // The delivered speed is measured afresh: "92.76 of 70.00 t per s" right
                // after a change mixed the old speed into the new one's measurement.
                if restarts || is_speed {
                    self.window.clear();
                }
            }
            let now = Instant::now();
            let wall = (now - last).as_secs_f64().min(MAX_TICK_WALL);
            last = now;
            if self.controller.is_paused() {
                self.window.clear();
            } else {
                let t0 = Instant::now();
                self.guarded("integrating", |c| c.tick(wall, u64::MAX));
                self.tick_seconds = t0.elapsed().as_secs_f64();
                let elapsed = (Instant::now() - start).as_secs_f64();
                self.window
                    .push(elapsed, self.controller.simulation().time());
            }
            self.hand_over_samples(samples);
            let status = Arc::new(self.status());
            match published.lock() {
                Ok(mut s) => *s = status,
                Err(poisoned) => *poisoned.into_inner() = status,
            }
            if !self.controller.is_paused() {
                let spent = now.elapsed();
                if spent < TICK_INTERVAL {
                    std::thread::sleep(TICK_INTERVAL - spent);
                }
            }
        }
    }
}

/// (wall seconds, simulation time) samples over about the last second of playing, from which
/// the delivered speed is read.
#[derive(Debug, Default)]
struct SpeedWindow {
    samples: VecDeque<(f64, f64)>,
}

impl SpeedWindow {
    /// How much wall time the window spans.
    const SPAN_S: f64 = 1.0;
    /// The shortest span worth a measurement.
    const MIN_SPAN_S: f64 = 0.25;

    fn push(&mut self, wall_s: f64, sim_time: f64) {
        self.samples.push_back((wall_s, sim_time));
        // The sample before the newest always stays: when one tick takes longer than the span
        // (the slowest, most lagging case) the window still measures that tick.
        while self.samples.len() > 2 && self.samples[1].0 <= wall_s - Self::SPAN_S {
            self.samples.pop_front();
        }
    }

    fn clear(&mut self) {
        self.samples.clear();
    }

    /// Simulation time per wall second over the window, once it spans a quarter of a second.
    fn delivered(&self) -> Option<f64> {
        match (self.samples.front(), self.samples.back()) {
            (Some(a), Some(b)) if b.0 - a.0 >= Self::MIN_SPAN_S => Some((b.1 - a.1) / (b.0 - a.0)),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{SimCommand, SimWorker, SpeedWindow};
    use crate::scene::Scene;

    /// The panic path of the thread, driven directly: what the worker does with a panic while
    /// applying a command or ticking (`run` wraps every one in `guarded`). No fault-injecting
    /// command is needed in the production enum.
    #[test]
    fn a_panic_in_the_simulation_is_a_message_and_a_pause_and_reset_recovers() {
        let setup = Scene::preset("sphere-cruising")
            .unwrap()
            .setup(None)
            .unwrap();
        let mut worker = SimWorker::new(setup);
        worker.guarded("ticking", |c| c.tick(0.05, u64::MAX));
        let t_before = worker.status().snapshot.t;
        assert!(t_before > 0.0);
        worker.guarded("applying a command", |_| panic!("a fault"));
        let s = worker.status();
        assert!(s.paused);
        let m = s.message.unwrap();
        assert!(
            m.contains("panicked") && m.contains("a fault") && m.contains("Reset"),
            "{m}"
        );
        worker.guarded("applying a command", |c| c.apply(SimCommand::Reset));
        worker.guarded("applying a command", |c| c.apply(SimCommand::Play));
        worker.guarded("ticking", |c| c.tick(0.05, u64::MAX));
        let s = worker.status();
        assert!(!s.paused && s.message.is_none(), "{:?}", s.message);
        assert!(s.snapshot.t > 0.0);
    }

    #[test]
    fn the_window_measures_the_last_second_of_fast_ticks() {
        let mut w = SpeedWindow::default();
        w.push(0.0, 0.0);
        assert_eq!(w.delivered(), None, "one sample measures nothing");
        w.push(0.1, 1.0);
        assert_eq!(w.delivered(), None, "0.1 s is too short to measure");
        // 10 t/s for 2 s, then 20 t/s: after a further second only the new rate is seen.
        for k in 2..=20 {
            w.push(0.1 * k as f64, k as f64);
        }
        for k in 1..=10 {
            w.push(2.0 + 0.1 * k as f64, 20.0 + 2.0 * k as f64);
        }
        let d = w.delivered().unwrap();
        assert!((d - 20.0).abs() < 1e-9, "delivered {d}");
        w.clear();
        assert_eq!(w.delivered(), None);
    }

    #[test]
    fn a_tick_longer_than_the_window_is_still_measured() {
        // Each tick takes 3 s of wall time and advances 100 time units: the delivered speed must
        // read 33.3 t/s rather than vanish (which hid "cannot keep up" when lagging worst).
        let mut w = SpeedWindow::default();
        for k in 0..4 {
            w.push(3.0 * k as f64, 100.0 * k as f64);
        }
        let d = w.delivered().expect("measured");
        assert!((d - 100.0 / 3.0).abs() < 1e-9, "delivered {d}");
    }
}
