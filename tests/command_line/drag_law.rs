//! The drag law on every surface (issue 44): each registered parameter is a flag of
//! `simulate`, `period` and `predict` with its `--help` line and range check, a field of their
//! JSON, and a `[model]` key of a scene, all from the core's registry.

use std::process::Output;

use rollphase::dynamics::drag::REGISTERED;
use rollphase::scene::Scene;

fn rollphase(args: &[&str]) -> Output {
    std::process::Command::new(crate::cli::binary())
        .args(args)
        .output()
        .expect("the binary runs")
}

fn folder(name: &str) -> std::path::PathBuf {
    let d = crate::cli::scratch(&format!("drag-law-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

const PERFECT_DISK: &str = r#"{"kind":"disk","modes":[]}"#;
const PERFECT_SPHERE: &str = r#"{"kind":"sphere","coeffs":[]}"#;

#[test]
fn every_registered_parameter_is_a_flag_with_its_help() {
    assert!(!REGISTERED.is_empty());
    for command in ["simulate", "period", "predict"] {
        let out = rollphase(&[command, "--help"]);
        let help = String::from_utf8_lossy(&out.stdout);
        for p in REGISTERED {
            assert!(
                help.contains(&format!("--{}", p.flag)),
                "{command} --help lacks --{}:\n{help}",
                p.flag
            );
        }
        assert!(help.contains("−γ |ω|^(n−1) ω"), "{command} --help:\n{help}");
    }
}

#[test]
fn a_value_out_of_range_is_refused_naming_the_flag_and_the_range() {
    let d = folder("range");
    let disk = d.join("disk.json");
    std::fs::write(&disk, PERFECT_DISK).unwrap();
    let disk = disk.to_str().unwrap();
    for bad in ["0.1", "5", "NaN", "inf", "-1"] {
        for args in [
            vec![
                "simulate", disk, "--alpha", "0.3", "--t-end", "1", "-o", "-",
            ],
            vec!["period", disk, "--alpha", "0.3"],
            vec!["predict", disk, "--alpha", "0.3", "--starts", "1"],
        ] {
            let mut args = args.clone();
            args.extend(["--drag-exponent", bad]);
            let out = rollphase(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
            assert!(
                err.contains("--drag-exponent") && err.contains("0.25 ≤ drag_exponent ≤ 4"),
                "{args:?}: {err}"
            );
        }
    }
}

#[test]
fn the_perfect_disk_rolls_at_the_power_laws_rate_on_every_command() {
    let d = folder("rate");
    let disk = d.join("disk.json");
    std::fs::write(&disk, PERFECT_DISK).unwrap();
    let disk = disk.to_str().unwrap();
    let summary = d.join("summary.json");
    let alpha: f64 = 0.3;
    let n = 0.5;
    let expected = alpha.sin().powf(1.0 / n);
    // simulate: the last row's θ̇, and the summary names the law.
    let out = rollphase(&[
        "simulate",
        disk,
        "--alpha",
        "0.3",
        "--t-end",
        "10",
        "--samples",
        "3",
        "-o",
        "-",
        "--drag-exponent",
        "0.5",
        "--summary",
        summary.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = String::from_utf8_lossy(&out.stdout);
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert!((last[2] / expected - 1.0).abs() < 1e-12, "θ̇ = {}", last[2]);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    assert_eq!(s["drag_exponent"], 0.5);
    // period: 2π/T by quadrature.
    let out = rollphase(&[
        "period",
        disk,
        "--alpha",
        "0.3",
        "--drag-exponent",
        "0.5",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let p: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let speed = p["mean_angular_speed"].as_f64().unwrap();
    assert!((speed / expected - 1.0).abs() < 1e-10, "2π/T = {speed}");
    assert_eq!(p["drag_exponent"], 0.5);
    // Without the flag: the paper's linear drag, said so.
    let out = rollphase(&["period", disk, "--alpha", "0.3", "--json"]);
    let p: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(p["drag_exponent"], 1.0);
    assert!((p["mean_angular_speed"].as_f64().unwrap() - alpha.sin()).abs() < 1e-12);
}

#[test]
fn predict_rolls_the_perfect_sphere_at_the_power_laws_speed() {
    let d = folder("predict");
    let ball = d.join("ball.json");
    std::fs::write(&ball, PERFECT_SPHERE).unwrap();
    let out = rollphase(&[
        "predict",
        ball.to_str().unwrap(),
        "--alpha",
        "0.3",
        "--starts",
        "2",
        "--t-cap",
        "2000",
        "--drag-exponent",
        "2",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let p: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(p["drag_exponent"], 2.0);
    let speed = p["orbits"][0]["speed"].as_f64().unwrap();
    let expected = 0.3f64.sin().sqrt();
    assert!(
        (speed / expected - 1.0).abs() < 1e-6,
        "speed {speed} against {expected}"
    );
    assert_eq!(p["orbits"][0]["stability"], "neutral");
}

#[test]
fn a_scene_takes_every_registered_parameter_by_its_key() {
    let base = "name = \"x\"\n[body]\nperfect = \"sphere\"\n[model]\nalpha_rad = 0.3\n";
    for p in REGISTERED {
        let text = format!("{base}{} = {}\n", p.key, p.max);
        let setup = Scene::from_toml(&text).unwrap().setup(None).unwrap();
        assert_eq!(setup.ramp.drag_law.get(p.key), Some(p.max));
        // Saved and read back, the value stays.
        let saved = toml::to_string(&setup.scene).unwrap();
        assert!(saved.contains(p.key), "{saved}");
        let again = Scene::from_toml(&saved).unwrap().setup(None).unwrap();
        assert_eq!(again.ramp.drag_law, setup.ramp.drag_law);
        let bad = format!("{base}{} = {}\n", p.key, p.max * 10.0);
        let err = Scene::from_toml(&bad)
            .and_then(|s| s.setup(None))
            .unwrap_err();
        assert!(
            err.to_string().contains(&format!("model.{} =", p.key)),
            "{err}"
        );
    }
    let misspelt = format!("{base}drag_exponant = 2\n");
    let err = Scene::from_toml(&misspelt).unwrap_err().to_string();
    assert!(
        err.contains("unknown field `drag_exponant`") && err.contains("drag-law parameter"),
        "{err}"
    );
    let unset = Scene::from_toml(base).unwrap().setup(None).unwrap();
    assert!(unset.ramp.drag_law.is_linear());
}
