//! A lesson step's claim against the app's caption: once the step's evidence is measured, a
//! claim the run does not bear out is said under the caption, named ("this run does not show
//! \"period-2\": …"),
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
        wrong.contains(
            "this run does not show \"period-2\": the run settled on period 1, not 2, at α = \
             0.15000, m/m0 = 0"
        ),
        "{wrong}"
    );
}

/// A headless clip of a lesson says the same: the frames of a step whose claim the run does not
/// bear out carry "(this run does not show \"rolling\": …)" under the caption, and the command warns on
/// standard error (a false claim went into a clip unnoticed).
#[test]
fn a_headless_clip_says_under_the_caption_what_the_run_does_not_show() {
    use rollphase::headless::HeadlessRenderer;
    use rollphase::render::types::PanelItem;
    // The critical-angle lesson's first step (0.9 α*, it halts) made to claim that it rolls.
    let text = Scene::preset("lesson-critical-angle")
        .unwrap()
        .to_toml()
        .unwrap()
        .replacen("claim = \"halted\"", "claim = \"rolling\"", 1);
    let setup = Scene::from_toml(&text).unwrap().setup(None).unwrap();
    let mut hr = HeadlessRenderer::new(setup, (640, 360), 1).unwrap();
    let said = hr.check_claims();
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(
        said[0].starts_with("timeline[0]: claims \"rolling\", but 1/T = 0"),
        "{said:?}"
    );
    let frame = hr.frame_data(0).unwrap();
    let texts: Vec<String> = frame
        .panels
        .iter()
        .flat_map(|p| &p.items)
        .filter_map(|item| match item {
            PanelItem::Text { text, .. } => Some(text.clone()),
            _ => None,
        })
        .collect();
    // The caption wraps over several lines.
    assert!(
        texts
            .join(" ")
            .contains("(this run does not show \"rolling\": 1/T"),
        "{texts:?}"
    );
    // The bundled lesson, as written, says nothing of the kind.
    let setup = Scene::preset("lesson-critical-angle")
        .unwrap()
        .setup(None)
        .unwrap();
    let mut hr = HeadlessRenderer::new(setup, (640, 360), 1).unwrap();
    assert!(hr.check_claims().is_empty());
    // The command line warns.
    let dir = crate::cli::scratch("false-claim-clip");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("lesson.toml");
    let shape = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/disk.json");
    std::fs::write(&scene, text.replace("../shapes/disk.json", shape)).unwrap();
    let o = crate::cli::rollphase([
        "--headless",
        "--scene",
        scene.to_str().unwrap(),
        "--frames",
        "2",
        "--size",
        "160x90",
        "--msaa",
        "1",
        "--out",
        dir.join("frames").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    std::fs::remove_dir_all(&dir).ok();
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(
            "warning: the lesson's run does not bear out its caption: timeline[0]: claims \
             \"rolling\""
        ),
        "{err}"
    );
}
