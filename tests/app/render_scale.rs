//! The 3D view drawn at a lower resolution (`--render-scale`, the automatic scale on a CPU
//! renderer): the panels around it are the same pixels, the view itself is the same picture
//! (its body as many coloured pixels, its colours close), the status bar says the scale, and
//! screenshots are drawn in full whatever the scale.
#![cfg(feature = "app")]

use std::time::{Duration, Instant};

use image::RgbaImage;
use rollphase::render::GpuContext;
use rollphase::render::gpu::{APP_FORMAT, OffscreenTarget};
use rollphase::scene::Scene;
use rollphase::ui::render_scale::{RenderScale, RenderScaleMode};
use rollphase::ui::workbench::{UiFrame, Workbench, offscreen_input};

use crate::common;

const SIZE: (u32, u32) = (1280, 720);

fn painted(
    bench: &mut Workbench,
    gpu: &GpuContext,
    target: &OffscreenTarget,
    frame: &UiFrame,
) -> RgbaImage {
    bench.paint(&gpu.device, &gpu.queue, &target.view, frame);
    let pixels = target.read(&gpu.device, &gpu.queue).unwrap();
    RgbaImage::from_raw(SIZE.0, SIZE.1, pixels).unwrap()
}

/// Pixels of `a` and `b` in the rectangle `inside` (x, y, w, h) but not in `except` that differ
/// at all, and the mean absolute difference of their channels there.
fn differences(
    a: &RgbaImage,
    b: &RgbaImage,
    inside: [u32; 4],
    except: Option<[u32; 4]>,
) -> (usize, f64) {
    let within = |r: [u32; 4], x: u32, y: u32| {
        (r[0]..r[0] + r[2]).contains(&x) && (r[1]..r[1] + r[3]).contains(&y)
    };
    let (mut over, mut sum, mut n) = (0, 0.0, 0usize);
    for (x, y, p) in a.enumerate_pixels() {
        if !within(inside, x, y) || except.is_some_and(|r| within(r, x, y)) {
            continue;
        }
        let q = b.get_pixel(x, y);
        over += usize::from(p.0 != q.0);
        sum += (0..3)
            .map(|c| f64::from(p.0[c].abs_diff(q.0[c])))
            .sum::<f64>()
            / 3.0;
        n += 1;
    }
    (over, sum / n.max(1) as f64)
}

#[test]
fn half_scale_draws_the_same_view_and_leaves_panels_and_screenshots_in_full() {
    let gpu = GpuContext::headless().unwrap();
    let target = OffscreenTarget::with_format(&gpu.device, SIZE, APP_FORMAT);
    let setup = Scene::preset("sphere-cruising")
        .unwrap()
        .setup(None)
        .unwrap();
    let mut bench = Workbench::new(&gpu.device, &gpu.queue, APP_FORMAT, 1, setup, None).unwrap();
    // Paused a little way in, so every paint below shows the same state.
    let start = Instant::now();
    let mut t = 0.0;
    loop {
        t += 1.0 / 60.0;
        let frame = bench.run_ui(offscreen_input(SIZE, t, Vec::new()), SIZE);
        bench.paint(&gpu.device, &gpu.queue, &target.view, &frame);
        if bench.sim.status().snapshot.t > 0.2 {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(20), "timed out");
        std::thread::sleep(Duration::from_millis(10));
    }
    bench.sim.send(rollphase::live::SimCommand::Pause);
    while !bench.sim.status().paused {
        std::thread::sleep(Duration::from_millis(5));
    }

    bench.set_render_scale(RenderScale::new(RenderScaleMode::Fixed(0.5), true));
    let frame = bench.run_ui(offscreen_input(SIZE, t + 0.1, Vec::new()), SIZE);
    assert_eq!(
        bench.ui.render_scale_note.as_deref(),
        Some("3D at 50\u{a0}%"),
        "the status bar says the scale"
    );
    assert_eq!(bench.render_scale(), 0.5);
    let half = painted(&mut bench, &gpu, &target, &frame);
    let shot = bench.capture(&gpu.device, &gpu.queue, &frame).unwrap();
    // The same UI frame painted again in full.
    bench.set_render_scale(RenderScale::new(RenderScaleMode::Fixed(1.0), true));
    let full = painted(&mut bench, &gpu, &target, &frame);
    if let Some(dir) = std::env::var_os("ROLLPHASE_KEEP_IMAGES") {
        let dir = std::path::Path::new(&dir);
        half.save(dir.join("render-scale-half.png")).unwrap();
        full.save(dir.join("render-scale-full.png")).unwrap();
    }

    // A screenshot is drawn in full whatever the window's scale.
    let all = [0, 0, SIZE.0, SIZE.1];
    let (changed, _) = differences(&full, &shot, all, None);
    assert_eq!(
        changed, 0,
        "{changed} pixels of the screenshot differ from a full frame"
    );
    // Everything around the 3D view (controls, plots, status bar) is the same pixels.
    let view = frame.scene_rect;
    let (changed, _) = differences(&full, &half, all, Some(view));
    assert_eq!(changed, 0, "{changed} pixels outside the 3D view changed");
    // The view: the same picture, softer.
    let (_, mean) = differences(&full, &half, view, None);
    assert!(
        mean > 0.0 && mean < 6.0,
        "mean difference {mean:.2} of 255 in the 3D view"
    );
    let columns = view[0]..view[0] + view[2];
    let body_full = common::frames::curvature_coloured_pixels(&full, columns.clone());
    let body_half = common::frames::curvature_coloured_pixels(&half, columns);
    assert!(body_full > 2000, "{body_full} body pixels");
    let ratio = body_half as f64 / body_full as f64;
    assert!(
        (0.9..1.1).contains(&ratio),
        "body: {body_half} coloured pixels at half scale, {body_full} in full"
    );

    // View ▸ 3D at full resolution overrides the scale.
    bench.set_render_scale(RenderScale::new(RenderScaleMode::Fixed(0.5), true));
    bench.ui.full_resolution = true;
    let _ = bench.run_ui(offscreen_input(SIZE, t + 0.3, Vec::new()), SIZE);
    assert_eq!(bench.render_scale(), 1.0);
    assert_eq!(bench.ui.render_scale_note, None);
}

#[test]
fn a_render_scale_outside_half_to_one_is_refused_by_name_before_any_window() {
    for bad in ["0.3", "0", "-1", "1.5", "NaN", "inf", "", "full"] {
        for args in [
            vec!["app", "--render-scale", bad],
            vec!["bench", "app", "--seconds", "0.1", "--render-scale", bad],
        ] {
            let out = crate::cli::rollphase(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{args:?} succeeded");
            assert!(
                err.contains("--render-scale") && err.contains("0.5 to 1"),
                "{args:?}: {err}"
            );
        }
    }
}

#[test]
fn headless_frames_refuse_the_window_s_render_scale_and_step() {
    for (args, flag) in [
        (
            vec!["--headless", "--frames", "1", "--render-scale", "0.5"],
            "--render-scale",
        ),
        (
            vec!["--headless", "--frames", "1", "--render-scale", "1"],
            "--render-scale",
        ),
        (vec!["--headless", "--frames", "1", "--step", "2"], "--step"),
    ] {
        let out = crate::cli::rollphase(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(
            err.contains(flag) && err.contains("--headless"),
            "{args:?}: {err}"
        );
    }
}
