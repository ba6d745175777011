//! The real window as a user meets it. With no display, `rollphase` exits non-zero with one
//! line suggesting `--headless`. Under Xvfb (CI installs it), the window opens on llvmpipe, runs
//! for a few seconds, and its screenshot shows the curvature-coloured body and the controls
//! panel; on exit it prints its frame-time summary.
#![cfg(feature = "app")]

use std::path::PathBuf;
use std::process::{Command, Output};

mod common;

fn rollphase_without_display(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rollphase"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap()
}

#[test]
fn no_display_is_one_line_suggesting_headless() {
    for args in [&[][..], &["app", "--preset", "perfect-sphere"][..]] {
        let o = rollphase_without_display(args);
        assert!(!o.status.success(), "{args:?} succeeded without a display");
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(e.trim().lines().count(), 1, "{args:?}: {e:?}");
        assert!(e.contains("no display"), "{e:?}");
        assert!(e.contains("--headless"), "{e:?}");
    }
}

#[test]
fn bad_window_flags_name_the_value() {
    let cases: &[(&[&str], &str)] = &[
        (&["app", "--exit-after", "inf"], "--exit-after inf"),
        (&["app", "--screenshot-after", "soon", "x.png"], "\"soon\""),
        (&["app", "--preset", "nope"], "no preset named \"nope\""),
        (&["--headless", "--exit-after", "2"], "are for the window"),
    ];
    for (args, needle) in cases {
        let o = rollphase_without_display(args);
        assert!(!o.status.success(), "{args:?} succeeded");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains(needle), "{args:?}: {e:?} lacks {needle:?}");
    }
}

#[test]
fn window_under_xvfb_shows_the_body_and_the_controls() {
    let has_xvfb = Command::new("xvfb-run")
        .arg("--help")
        .output()
        .is_ok_and(|o| o.status.success() || !o.stdout.is_empty() || !o.stderr.is_empty());
    if !has_xvfb {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must run the window smoke test: install xvfb (apt-get install xvfb xauth)"
        );
        eprintln!("skipped: xvfb-run is not installed (apt-get install xvfb xauth)");
        return;
    }
    let shot: PathBuf =
        std::env::temp_dir().join(format!("rollphase-window-{}.png", std::process::id()));
    let _ = std::fs::remove_file(&shot);
    let o = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_rollphase"))
        .args(["--preset", "sphere-cruising", "--screenshot-after", "3"])
        .arg(&shot)
        .args(["--exit-after", "4"])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "the window run failed: {e}");
    assert!(e.contains("frame time mean"), "no frame-time summary: {e}");
    let img = image::open(&shot).unwrap().to_rgba8();
    let (w, h) = img.dimensions();
    assert!(w >= 640 && h >= 400, "screenshot is {w}x{h}");
    // The controls panel on the left: egui's dark panel with light text on it.
    let panel_w = 200;
    let (dark, light) = common::frames::panel_pixels(&img, panel_w, 40..h - 40);
    let area = (panel_w * (h - 80)) as usize;
    assert!(dark > area / 2, "no controls panel: {dark} dark of {area}");
    assert!(
        light > 500,
        "no text in the controls panel: {light} light pixels"
    );
    // The body in the 3D view, right of the panel: the curvature colours.
    let body = common::frames::curvature_coloured_pixels(&img, 300..w);
    assert!(body > 2000, "no curvature-coloured body: {body} pixels");
    let _ = std::fs::remove_file(&shot);
}
