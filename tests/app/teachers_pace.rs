//! A teacher's pace (issue 60): every bundled lesson played in presentation mode (F5) at
//! 1280×720 and at 1920×1080, N pressed every 4 s of wall time with the pointer left resting
//! over the 3D view, as a teacher with a clicker plays it. At every step, from what the app's
//! plots hold (its own plot history, the points drawn, not the evidence run's state):
//!
//! - the step's claim holds from the frame its evidence is in until the next click, and until
//!   then the caption says the evidence is being measured (never an empty plot under a claim);
//! - the evidence is in before the next click;
//! - no caption says the run does not bear its claim out;
//! - the lesson's plot is on the screen with text of at least 24 px, and the resting pointer
//!   shows no values on it.
//!
//! The 3D view's text sizes and layout at every step and size are `presentation.rs`'s (the
//! overlay of each step, at seven sizes); the plot's markers' floor is the viewer's
//! `LESSON_MARKER_PX`. The six lessons-at-a-size run together, so the test takes one lesson's
//! length (8 steps, 32 s), not six; it prints, for each step, how long after the click its
//! evidence was on the plot.
#![cfg(feature = "app")]

use std::time::{Duration, Instant};

use rollphase::live::evidence::{StepAt, check_claim};
use rollphase::render::GpuContext;
use rollphase::render::gpu::{APP_FORMAT, OffscreenTarget};
use rollphase::scene::{Claim, Scene};
use rollphase::ui::workbench::Workbench;

use crate::app_ui::{key, zoomed_input};

/// A teacher's click interval.
const PACE: Duration = Duration::from_secs(4);

/// One lesson played at one size.
struct Class {
    name: &'static str,
    size: (u32, u32),
    bench: Workbench,
    target: OffscreenTarget,
    /// Each step's claim, and where it stands.
    steps: Vec<(Option<Claim>, StepAt)>,
    /// The step on the screen (0-based) and when its click was made.
    step: usize,
    clicked: Instant,
    /// When each step's evidence was first on the plot, after its click.
    ready_after: Vec<Option<Duration>>,
    /// Input for the next frame.
    events: Vec<egui::Event>,
}

impl Class {
    fn what(&self) -> String {
        format!(
            "{} step {} of {} at {}×{}",
            self.name,
            self.step + 1,
            self.steps.len(),
            self.size.0,
            self.size.1
        )
    }

    /// One frame, and what it shows checked against the step on the screen.
    fn frame(&mut self, gpu: &GpuContext, paint: bool) {
        let events = std::mem::take(&mut self.events);
        let frame = self
            .bench
            .run_ui(zoomed_input(&self.bench, self.size, events), self.size);
        if paint {
            self.bench
                .paint(&gpu.device, &gpu.queue, &self.target.view, &frame);
        }
        let what = self.what();
        let snap = &frame.status.snapshot;
        let done = snap.lesson.as_ref().map_or(0, |l| l.done);
        // The click's jump has not landed yet: the step before is still shown.
        if done != self.step + 1 {
            return;
        }
        let caption = snap.caption.clone().unwrap_or_default();
        assert!(
            !caption.contains("this run does not show"),
            "{what}: the run does not bear the claim out: {caption}"
        );
        assert!(!snap.off_script, "{what}: N played off the lesson's script");
        if caption.contains("measuring this step's evidence") {
            return;
        }
        let (claim, at) = &self.steps[self.step];
        if let Some(claim) = *claim {
            let plotted = self.bench.ui.history().checkpoint();
            if let Err(why) = check_claim(claim, &plotted, at) {
                panic!(
                    "{what}: the caption claims {} but the plot shows {why}: {caption}",
                    claim.name()
                );
            }
        }
        self.ready_after[self.step].get_or_insert(self.clicked.elapsed());
    }

    /// The checks at the end of a step's 4 s, before the next click.
    fn end_of_step(&mut self) {
        let what = self.what();
        assert!(
            self.ready_after[self.step].is_some(),
            "{what}: the evidence was not on the plot {PACE:?} after the click"
        );
        let (_, text_px) = self
            .bench
            .ui
            .lesson_plot_rect
            .unwrap_or_else(|| panic!("{what}: no lesson plot"));
        assert!(text_px >= 24.0 - 1e-3, "{what}: plot text {text_px} px");
        assert!(
            !self.bench.ui.plot_hover_shown(),
            "{what}: values under the resting pointer"
        );
    }
}

#[test]
fn every_lesson_step_shows_its_claims_evidence_at_a_teachers_pace() {
    let gpu = GpuContext::headless().unwrap();
    let mut classes: Vec<Class> = Vec::new();
    for name in [
        "lesson-critical-angle",
        "lesson-inertia-hysteresis",
        "lesson-period-doubling",
    ] {
        for size in [(1280, 720), (1920, 1080)] {
            let setup = Scene::preset(name).unwrap().setup(None).unwrap();
            let mut bench =
                Workbench::new(&gpu.device, &gpu.queue, APP_FORMAT, 1, setup.clone(), None)
                    .unwrap();
            bench.ui.present_on_start();
            let steps: Vec<(Option<Claim>, StepAt)> = setup
                .timeline
                .iter()
                .map(|step| step.claim)
                .zip(StepAt::each_of(&setup))
                .collect();
            classes.push(Class {
                name,
                size,
                target: OffscreenTarget::with_format(&gpu.device, size, APP_FORMAT),
                ready_after: vec![None; steps.len()],
                steps,
                bench,
                step: 0,
                clicked: Instant::now(),
                // The pointer comes to rest over the 3D view and stays there.
                events: vec![egui::Event::PointerMoved(egui::pos2(200.0, 200.0))],
            });
        }
    }
    let longest = classes.iter().map(|c| c.steps.len()).max().unwrap();
    for step in 0..longest {
        let started = Instant::now();
        for class in classes.iter_mut().filter(|c| step < c.steps.len()) {
            class.step = step;
            class.clicked = started;
            if step > 0 {
                class.events = key(egui::Key::N);
            }
        }
        let mut painted = false;
        while started.elapsed() < PACE {
            // The frame before the click is painted too (the renderer draws what the step
            // shows); the others are laid out only, to keep the pace on a CPU renderer.
            let paint = !painted && started.elapsed() > PACE - Duration::from_millis(600);
            for class in classes.iter_mut().filter(|c| step < c.steps.len()) {
                class.frame(&gpu, paint);
            }
            painted |= paint;
            std::thread::sleep(Duration::from_millis(20));
        }
        for class in classes.iter_mut().filter(|c| step < c.steps.len()) {
            class.end_of_step();
        }
    }
    for class in &classes {
        let ready: Vec<String> = class
            .ready_after
            .iter()
            .map(|d| format!("{:.2}", d.unwrap().as_secs_f64()))
            .collect();
        eprintln!(
            "{} at {}×{}: each step's evidence on the plot after its click (s): {}",
            class.name,
            class.size.0,
            class.size.1,
            ready.join(", ")
        );
    }
}
