//! A lesson step's claim against the app's caption: once the step's evidence is measured, a
//! claim the run does not bear out is said under the caption ("this run does not show it: …"),
//! and a claim it bears out adds nothing.
#![cfg(feature = "app")]

use std::time::{Duration, Instant};

use rollphase::render::GpuContext;
use rollphase::render::gpu::{APP_FORMAT, OffscreenTarget};
use rollphase::scene::Scene;
use rollphase::ui::workbench::{Workbench, offscreen_input};

const SIZE: (u32, u32) = (640, 360);

/// The caption the app shows at the first step of the doubling lesson with `claim` on it, once
/// the step's evidence is measured.
fn first_caption(claim: &str) -> String {
    let text = Scene::preset("lesson-period-doubling")
        .unwrap()
        .to_toml()
        .unwrap()
        .replacen("claim = \"period-1\"", &format!("claim = \"{claim}\""), 1);
    let setup = Scene::from_toml(&text).unwrap().setup(None).unwrap();
    let gpu = GpuContext::headless().unwrap();
    let target = OffscreenTarget::with_format(&gpu.device, SIZE, APP_FORMAT);
    let mut bench = Workbench::new(&gpu.device, &gpu.queue, APP_FORMAT, 1, setup, None).unwrap();
    bench.sim.send(rollphase::live::SimCommand::Pause);
    let start = Instant::now();
    let mut t = 0.0;
    loop {
        t += 1.0 / 60.0;
        let frame = bench.run_ui(offscreen_input(SIZE, t, Vec::new()), SIZE);
        bench.paint(&gpu.device, &gpu.queue, &target.view, &frame);
        let caption = frame.status.snapshot.caption.clone().unwrap_or_default();
        let measured = !caption.contains("measuring this step's evidence");
        if frame.status.snapshot.lesson.is_some() && measured && t > 0.5 {
            return caption;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "timed out: {caption}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn a_claim_the_run_does_not_bear_out_is_said_under_the_caption() {
    let right = first_caption("period-1");
    assert!(
        right.contains("(period 1)") && !right.contains("does not show"),
        "{right}"
    );
    let wrong = first_caption("period-2");
    assert!(
        wrong.contains("this run does not show it: 1 settled crossing")
            || wrong.contains("this run does not show it: 1 distinct"),
        "{wrong}"
    );
}
