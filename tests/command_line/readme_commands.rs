//! The README's commands work on a fresh clone: the quick start's headless render writes the 60
//! frames it promises at 1280×720, and the `simulate` example's outputs are what the README says
//! (header, row count, summary keys, a body that rolled downhill).

use std::process::Command;

#[cfg(feature = "render")]
#[test]
fn readme_quick_start_renders_sixty_frames() {
    let readme = include_str!("../../README.md");
    let command = "cargo run -- --headless --frames 60 --out frames";
    assert!(
        readme.contains(command),
        "the README's quick start changed; update this test"
    );
    let dir = crate::cli::scratch("quick");
    let out = Command::new(crate::cli::binary())
        .args(["--headless", "--frames", "60", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for k in [0, 59] {
        let img = image::open(dir.join(format!("frame_{k:05}.png"))).unwrap();
        assert_eq!((img.width(), img.height()), (1280, 720));
    }
    assert!(!dir.join("frame_00060.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn readme_simulate_example_runs_on_the_bundled_sphere() {
    let dir = crate::cli::scratch("readme");
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("traj.csv");
    let summary = dir.join("summary.json");
    let shape = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/sphere.json");
    let out = Command::new(crate::cli::binary())
        .args(["simulate", shape, "--alpha", "0.3", "--t-end", "100", "-o"])
        .arg(&csv)
        .arg("--summary")
        .arg(&summary)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,qw,qx,qy,qz,ux,uy,uz,wx,wy,wz,x,y,z"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 1001);
    assert!(rows.iter().all(|r| r.iter().all(|v| v.is_finite())));
    assert!(rows.last().unwrap()[11] > 10.0, "the body rolled downhill");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    for key in [
        "rhs_evals",
        "steps",
        "max_quat_norm_error",
        "max_contact_normal_error",
        "energy_drift",
        "wall_seconds",
    ] {
        assert!(s.get(key).is_some(), "summary lacks {key}");
    }
    assert!(s["max_contact_normal_error"].as_f64().unwrap() < 1e-12);
}

/// The README's first command (60 frames of the default preset) shows a whole orbit: by its last
/// frame the body has crossed ∂Ω at least twice (so the period is measured) and the frames span
/// at least two of those periods.
#[cfg(feature = "render")]
#[test]
fn the_default_sixty_frames_show_a_whole_orbit() {
    use rollphase::live::LiveRun;
    use rollphase::scene::{DEFAULT_PRESET, Scene};
    let setup = Scene::preset(DEFAULT_PRESET).unwrap().setup(None).unwrap();
    let t_last = setup.frame_time(59);
    let mut sim = LiveRun::new(setup);
    sim.advance_to(t_last).unwrap();
    let snap = sim.snapshot();
    let period = snap
        .period
        .expect("a period is measured within the first 60 frames");
    assert!(
        t_last >= 2.0 * period,
        "60 frames reach t = {t_last}, but two crossings of ∂Ω take {}",
        2.0 * period
    );
}
