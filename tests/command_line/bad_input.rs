//! Bad input is a clear error, never a panic: the binary exits with status 1 (2 for clap's usage
//! errors) and one message naming the value, why it is wrong and what is allowed.

use std::os::unix::fs::FileTypeExt;
use std::path::PathBuf;
use std::process::{Command, Output};

fn rollphase(args: &[&str]) -> Output {
    Command::new(crate::cli::binary())
        .args(args)
        .output()
        .expect("the binary runs")
}

fn temp_dir(name: &str) -> PathBuf {
    let d = crate::cli::scratch(&format!("bad-input-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

/// Asserts a clean failure whose message contains every `needle`.
fn fails_with(out: &Output, code: i32, needles: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    for n in needles {
        assert!(err.contains(n), "expected {n:?} in: {err}");
    }
}

const DISK: &str =
    r#"{"kind":"disk","modes":[{"l":2,"a":0.05,"phase":1.2},{"l":3,"a":-0.04,"phase":0.3}]}"#;
const SPHERE: &str = r#"{"kind":"sphere","coeffs":[{"l":2,"m":-2,"re":0.1,"im":0.0},{"l":3,"m":1,"re":0.05,"im":0.02}]}"#;

#[test]
fn alpha_outside_the_open_quarter_turn_is_rejected() {
    let d = temp_dir("alpha");
    let disk = write(&d, "disk.json", DISK);
    for alpha in ["0", "-0.1", "1e-16", "1.5708", "2", "NaN", "inf"] {
        let out = rollphase(&["period", &disk, "--alpha", alpha]);
        fails_with(&out, 1, &["alpha", "1e-9 ≤ alpha < π/2"]);
    }
}

#[test]
fn negative_or_nan_mass_is_rejected() {
    let d = temp_dir("mass");
    let sphere = write(&d, "s.json", SPHERE);
    for m in ["-1", "NaN"] {
        let out = rollphase(&[
            "simulate", &sphere, "--alpha", "0.3", "--mass", m, "--t-end", "1", "-o", "-",
        ]);
        fails_with(&out, 1, &["m/m0", "≥ 0"]);
    }
}

/// `figure --list`'s lines: one a figure.
const FIGURES_LISTED: usize = 12;

#[test]
fn non_convex_shape_names_the_worst_point() {
    let d = temp_dir("convex");
    // A strong l = 8 mode: r'' ~ a dominates r and the outline dents inward.
    let bad = write(
        &d,
        "bad.json",
        r#"{"kind":"disk","modes":[{"l":8,"a":3.0,"phase":0.0}]}"#,
    );
    // `simulate` rolls a dented cylinder on its convex hull (tests/physics/dented_bodies.rs); a command
    // that needs a convex body refuses it, naming the place and where it would run.
    let out = rollphase(&[
        "simulate", &bad, "--alpha", "0.3", "--t-end", "1", "-o", "-",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // `period` gives its viscous period on the hull too; with inertia it names `simulate`.
    let out = rollphase(&["period", &bad, "--alpha", "0.3"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = rollphase(&["period", &bad, "--alpha", "0.3", "--mass", "1"]);
    fails_with(&out, 1, &["convex hull", "simulate --mass"]);
    let dir = d.join("figure");
    let out = rollphase(&[
        "figure",
        "disk-transition",
        "--shape",
        &bad,
        "--out",
        dir.to_str().unwrap(),
    ]);
    fails_with(
        &out,
        1,
        &[
            "not convex",
            "curvature",
            "θ =",
            "needs > 0",
            "on its convex hull",
        ],
    );
    // inspect reports it without failing
    let out = rollphase(&["inspect", &bad, "--json"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["convex"], false);
    assert!(v["curvature_min"].as_f64().unwrap() < 0.0);
    let bad3 = write(
        &d,
        "bad3.json",
        r#"{"kind":"sphere","coeffs":[{"l":5,"m":3,"re":6.0,"im":0.0}]}"#,
    );
    let out = rollphase(&[
        "simulate", &bad3, "--alpha", "0.3", "--t-end", "1", "-o", "-",
    ]);
    fails_with(&out, 1, &["not convex", "principal curvature", "φ ="]);
}

#[test]
fn malformed_shape_files_give_line_and_field() {
    let d = temp_dir("malformed");
    let cases = [
        (
            "trunc.json",
            "{\"kind\":\"disk\",\n\"modes\":[{\"l\":2,",
            "line 2",
        ),
        (
            "kind.json",
            r#"{"kind":"torus","modes":[]}"#,
            "unknown variant `torus`",
        ),
        (
            "field.json",
            r#"{"kind":"disk","modes":[{"l":2,"a":0.1,"phase":0.0,"amp":1}]}"#,
            "unknown field `amp`",
        ),
        (
            "missing.json",
            r#"{"kind":"sphere","coeffs":[{"l":2,"m":0,"re":0.1}]}"#,
            "missing field `im`",
        ),
        (
            "type.json",
            r#"{"kind":"disk","modes":[{"l":"two","a":0.1,"phase":0.0}]}"#,
            "invalid type",
        ),
        ("empty.json", "", "EOF"),
    ];
    for (name, text, needle) in cases {
        let p = write(&d, name, text);
        let out = rollphase(&["inspect", &p]);
        fails_with(&out, 1, &[needle, "not a valid shape file"]);
    }
}

#[test]
fn out_of_range_modes_are_rejected() {
    let d = temp_dir("range");
    let cases = [
        (
            r#"{"kind":"disk","modes":[{"l":1,"a":0.1,"phase":0.0}]}"#,
            "l = 1",
        ),
        (
            r#"{"kind":"sphere","coeffs":[{"l":2,"m":3,"re":0.1,"im":0.0}]}"#,
            "−l ≤ m ≤ l",
        ),
        (
            r#"{"kind":"sphere","coeffs":[{"l":13,"m":0,"re":0.1,"im":0.0}]}"#,
            "l ≤ 12",
        ),
        (
            r#"{"kind":"disk","modes":[{"l":2,"a":0.1,"phase":0.0},{"l":2,"a":0.2,"phase":1.0}]}"#,
            "twice",
        ),
    ];
    for (i, (text, needle)) in cases.iter().enumerate() {
        let p = write(&d, &format!("r{i}.json"), text);
        let out = rollphase(&["inspect", &p]);
        fails_with(&out, 1, &[needle]);
    }
}

#[test]
fn missing_file_and_wrong_initial_state_are_explained() {
    let d = temp_dir("state");
    let disk = write(&d, "disk.json", DISK);
    let sphere = write(&d, "s.json", SPHERE);
    fails_with(
        &rollphase(&["inspect", "/nonexistent/body.json"]),
        1,
        &["cannot read shape file"],
    );
    fails_with(
        &rollphase(&[
            "simulate", &disk, "--alpha", "0.3", "--t-end", "1", "-o", "-", "--q0", "1,0,0,0",
        ]),
        1,
        &["2D disk", "--theta0"],
    );
    fails_with(
        &rollphase(&[
            "simulate", &sphere, "--alpha", "0.3", "--t-end", "1", "-o", "-", "--q0", "1,0,0",
        ]),
        1,
        &["--q0 expects 4"],
    );
    fails_with(
        &rollphase(&[
            "simulate", &sphere, "--alpha", "0.3", "--t-end", "1", "-o", "-", "--q0", "0,0,0,0",
        ]),
        1,
        &["zero length"],
    );
    fails_with(
        &rollphase(&[
            "simulate", &sphere, "--alpha", "0.3", "--t-end", "NaN", "-o", "-",
        ]),
        1,
        &["t_end"],
    );
    fails_with(
        &rollphase(&[
            "simulate",
            &sphere,
            "--alpha",
            "0.3",
            "--t-end",
            "1",
            "-o",
            "-",
            "--integrator",
            "rk4",
            "--dt",
            "0",
        ]),
        1,
        &["dt", "> 0"],
    );
    fails_with(
        &rollphase(&["period", &sphere, "--alpha", "0.3"]),
        1,
        &["3D sphere", "disks"],
    );
    fails_with(
        &rollphase(&["shape", "--dim", "4", "--seed", "1"]),
        2,
        &["dim"],
    );
    fails_with(
        &rollphase(&["shape", "--dim", "2", "--seed", "1", "--sigma", "-1"]),
        1,
        &["sigma"],
    );
}

#[test]
fn a_failed_run_leaves_no_partial_csv() {
    let d = temp_dir("partial");
    let sphere = write(&d, "s.json", SPHERE);
    let csv = d.join("traj.csv");
    // The step budget runs out mid-run: the error says where, and no file remains.
    let out = rollphase(&[
        "simulate",
        &sphere,
        "--alpha",
        "0.3",
        "--t-end",
        "1000",
        "--max-steps",
        "20",
        "-o",
        csv.to_str().unwrap(),
    ]);
    fails_with(
        &out,
        1,
        &[
            "integration stopped at t = ",
            "more than 20 steps",
            "no CSV was written",
        ],
    );
    assert!(!csv.exists());
    assert!(!d.join("traj.csv.partial").exists());
}

#[test]
fn an_unstable_fixed_step_is_refused_before_running() {
    let d = temp_dir("unstable");
    let sphere = write(&d, "s.json", SPHERE);
    let out = rollphase(&[
        "simulate",
        &sphere,
        "--alpha",
        "0.3",
        "--mass",
        "0.001",
        "--t-end",
        "10",
        "--integrator",
        "rk4",
        "--dt",
        "0.01",
        "-o",
        "-",
    ]);
    fails_with(
        &out,
        1,
        &[
            "unstable for m/m0 = 0.001",
            "relaxation time",
            "dt must be ≤",
            // The library's message names no flag; the command line adds the flags it ran with.
            "rk4 --dt 0.01",
        ],
    );
}

#[test]
fn figure_body_and_alpha_options_that_do_not_apply_are_refused() {
    let dir = temp_dir("figure-options");
    let disk = write(&dir, "disk.json", DISK);
    let sphere = write(&dir, "sphere.json", SPHERE);
    let out = dir.to_string_lossy().into_owned();
    // A 2D body for a 3D figure, and the reverse.
    let r = rollphase(&["figure", "sphere-doubling", "--shape", &disk, "--out", &out]);
    fails_with(&r, 1, &["sphere-doubling needs a 3D body", "disk"]);
    let r = rollphase(&["figure", "disk-flow", "--shape", &sphere, "--out", &out]);
    fails_with(&r, 1, &["disk-flow needs a 2D body", "sphere"]);
    // --alpha for a figure that sweeps α; --shape for the perfect sphere's figure.
    let r = rollphase(&["figure", "sphere-cruising", "--alpha", "0.2", "--out", &out]);
    fails_with(
        &r,
        1,
        &["sphere-cruising sweeps", "--alpha 0.2 does not apply"],
    );
    let r = rollphase(&["figure", "sphere-tube", "--shape", &sphere, "--out", &out]);
    fails_with(&r, 1, &["sphere-tube", "perfect sphere", "does not apply"]);
    // An α below the body's α* where no start rolls on a period-1 orbit (in 3D α* is where
    // every orientation rolls, so below it the figure runs and says what it found), and one
    // out of range. At --quick: the same refusal from 4 runs instead of 8 (28 CPU-s → 3).
    let r = rollphase(&[
        "figure",
        "sphere-bifurcation",
        "--alpha",
        "0.1",
        "--quick",
        "--out",
        &out,
    ]);
    fails_with(
        &r,
        1,
        &[
            "below this body's α* = 0.1394",
            "came to rest",
            "give a larger --alpha",
        ],
    );
    let r = rollphase(&["figure", "sphere-poincare", "--alpha", "2", "--out", &out]);
    fails_with(&r, 1, &["--alpha 2 is not allowed", "1e-9 ≤ α < π/2"]);
    // Unknown figure names list every figure.
    let r = rollphase(&["figure", "sphere-nope", "--out", &out]);
    fails_with(
        &r,
        1,
        &["unknown figure", "sphere-bifurcation", "disk-transition"],
    );
}

#[test]
fn figure_list_shows_every_figure() {
    let r = rollphase(&["figure", "--list"]);
    assert!(r.status.success());
    let text = String::from_utf8_lossy(&r.stdout);
    for f in rollphase::figures::FIGURES {
        let line = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(f.name))
            .unwrap_or_else(|| panic!("{} missing from --list", f.name));
        // The shardable ones are marked, from the one registry `--shard` and `merge` read.
        assert_eq!(line.ends_with("[--shard]"), f.sharded(), "{line}");
    }
    assert_eq!(text.lines().count(), FIGURES_LISTED, "{text}");
    assert_eq!(
        text.matches("[--shard]").count(),
        rollphase::figures::FIGURES
            .iter()
            .filter(|f| f.sharded())
            .count(),
        "{text}"
    );
}

#[test]
fn paper_seed_and_seed_are_exclusive_and_one_is_needed() {
    let r = rollphase(&["shape", "--dim", "3", "--seed", "1", "--paper-seed", "219"]);
    fails_with(&r, 2, &["--paper-seed"]);
    let r = rollphase(&["shape", "--dim", "3"]);
    fails_with(&r, 2, &["--seed"]);
    let r = rollphase(&["shape", "--dim", "3", "--paper-seed", "4294967296"]);
    fails_with(&r, 2, &["4294967296"]);
    let ok = rollphase(&["shape", "--dim", "3", "--paper-seed", "219"]);
    assert!(ok.status.success());
    let bundled = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/shapes/paper-sphere.json"
    ))
    .unwrap();
    assert_eq!(String::from_utf8_lossy(&ok.stdout), bundled);
}

/// A short 3D run written to `out`.
fn simulate_to(dir: &std::path::Path, out: &str) -> Output {
    let sphere = write(dir, "body.json", SPHERE);
    rollphase(&[
        "simulate",
        &sphere,
        "--alpha",
        "0.4",
        "--t-end",
        "1",
        "--samples",
        "3",
        "-o",
        out,
    ])
}

#[test]
fn simulate_output_keeps_symlinks_and_hard_links() {
    let dir = temp_dir("links");
    let target = write(&dir, "target.csv", "old\n");
    let link = dir.join("link.csv");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let r = simulate_to(&dir, &link.to_string_lossy());
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink(),
        "still a link"
    );
    assert!(
        std::fs::read_to_string(&target)
            .unwrap()
            .starts_with("t,qw"),
        "target rewritten"
    );

    let second = dir.join("second-name.csv");
    std::fs::hard_link(&target, &second).unwrap();
    let r = simulate_to(&dir, &target);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    use std::os::unix::fs::MetadataExt;
    assert_eq!(
        std::fs::metadata(&target).unwrap().ino(),
        std::fs::metadata(&second).unwrap().ino()
    );
    assert_eq!(
        std::fs::read(&target).unwrap(),
        std::fs::read(&second).unwrap()
    );
    // Nothing is left behind beside them.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.contains("partial")), "{names:?}");
}

#[test]
fn simulate_output_to_a_fifo_is_written_through_not_replaced() {
    let dir = temp_dir("fifo");
    let fifo = dir.join("pipe");
    let status = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(status.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let r = simulate_to(&dir, &fifo.to_string_lossy());
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = reader.join().unwrap();
    assert!(
        text.starts_with("t,qw") && text.lines().count() == 4,
        "{text}"
    );
    assert!(
        std::fs::metadata(&fifo).unwrap().file_type().is_fifo(),
        "still a FIFO"
    );
}

#[test]
fn an_input_is_never_overwritten_by_the_output() {
    let dir = temp_dir("same-file");
    let sphere = write(&dir, "body.json", SPHERE);
    let r = rollphase(&["export-stl", &sphere, "-o", &sphere]);
    fails_with(&r, 1, &["is also an input", "refusing to overwrite"]);
    assert_eq!(std::fs::read_to_string(&sphere).unwrap(), SPHERE);
    let r = rollphase(&[
        "simulate", &sphere, "--alpha", "0.4", "--t-end", "1", "-o", &sphere,
    ]);
    fails_with(&r, 1, &["is also an input"]);
    assert_eq!(std::fs::read_to_string(&sphere).unwrap(), SPHERE);
}

#[test]
fn a_closed_or_full_stdout_is_a_clean_exit() {
    use std::process::Stdio;
    // The reader goes away at once: quiet, status 0, no panic.
    let mut child = Command::new(crate::cli::binary())
        .args(["scenes"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    // A full disk behind standard output (Linux's /dev/full): one line, status 1.
    if let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") {
        let out = Command::new(crate::cli::binary())
            .args(["figure", "--list"])
            .stdout(full)
            .output()
            .unwrap();
        fails_with(&out, 1, &["cannot write to standard output"]);
    }
}

#[test]
fn counts_and_input_sizes_have_stated_limits() {
    let dir = temp_dir("limits");
    let sphere = write(&dir, "body.json", SPHERE);
    let csv = dir.join("out.csv").to_string_lossy().into_owned();
    let base = [
        "simulate", &sphere, "--alpha", "0.4", "--t-end", "10", "-o", &csv,
    ];
    // A fixed step whose step count exceeds the budget is refused before it starts: nothing
    // staged in the output folder (and a run of 1e301 steps that started would never return).
    let r = rollphase(&[&base[..], &["--integrator", "rk4", "--dt", "1e-300"]].concat());
    fails_with(&r, 1, &["dt = 1e-300", "max_steps = 100000000"]);
    assert_eq!(crate::cli::listing(&dir), ["body.json"], "nothing staged");
    let r = rollphase(&[&base[..], &["--samples", "1000000000"]].concat());
    fails_with(&r, 1, &["samples = 1000000000", "samples ≤ 10000000"]);
    assert!(!std::path::Path::new(&csv).exists());
    let data = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/data/cylinder_lag_times.csv"
    );
    let out = dir.to_string_lossy().into_owned();
    for n in ["0", "1000000000"] {
        let r = rollphase(&["fit-lag", data, "--bootstrap", n, "--out", &out]);
        fails_with(
            &r,
            1,
            &[&format!("--bootstrap {n}"), "10 ≤ resamples ≤ 100000"],
        );
    }
    let r = rollphase(&["figure", "disk-flow", "--threads", "10000", "--out", &out]);
    fails_with(&r, 1, &["--threads 10000", "threads ≤ 1024"]);
    let r = rollphase(&["--headless", "--frames", "0", "--out", &out]);
    fails_with(&r, 1, &["--frames 0", "frames ≤ 1000000"]);
    // An input far larger than any shape or scene file is refused after reading the limit.
    let big = write(&dir, "big.json", &" ".repeat((1 << 20) + 1));
    let r = rollphase(&["inspect", &big]);
    fails_with(
        &r,
        1,
        &["cannot read shape file", "larger than 1048576 bytes"],
    );
    let big_scene = write(&dir, "big.toml", &"#".repeat((1 << 20) + 1));
    let r = rollphase(&["--headless", "--scene", &big_scene, "--out", &out]);
    fails_with(
        &r,
        1,
        &["cannot read scene file", "larger than 1048576 bytes"],
    );
}

#[test]
fn scene_file_errors_name_the_scene_file_once() {
    let dir = temp_dir("scene-msg");
    let missing = dir.join("missing.toml").to_string_lossy().into_owned();
    let r = rollphase(&[
        "--headless",
        "--scene",
        &missing,
        "--out",
        &dir.to_string_lossy(),
    ]);
    fails_with(&r, 1, &["cannot read scene file"]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!err.contains("shape file"), "{err}");
    assert_eq!(
        err.matches("os error").count(),
        1,
        "the OS error once: {err}"
    );
    let bad = write(&dir, "bad.toml", "name = 3\n");
    let r = rollphase(&[
        "--headless",
        "--scene",
        &bad,
        "--out",
        &dir.to_string_lossy(),
    ]);
    fails_with(&r, 1, &["TOML parse error"]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(
        err.matches("TOML parse error").count(),
        1,
        "printed once: {err}"
    );
}

#[test]
fn period_never_prints_a_wrong_number_with_exit_zero() {
    let disk = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/disk.json");
    let json = |args: &[&str]| -> serde_json::Value {
        let r = rollphase(&[&["period", disk, "--json"][..], args].concat());
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let text = String::from_utf8_lossy(&r.stdout).into_owned();
        for bad in ["inf", "NaN", "-0.0"] {
            assert!(!text.contains(bad), "{bad} in {text}");
        }
        serde_json::from_str(&text).unwrap()
    };
    // So heavy that no turn is completed by --t-max: not a halt (no rest point exists at 20 α*),
    // not a period; the note says why.
    for mass in ["1e6", "1e300"] {
        let v = json(&["--alpha", "1.0", "--mass", mass]);
        assert_eq!(v["period"], serde_json::Value::Null, "{v}");
        assert_eq!(v["halts"], false, "{v}");
        assert!(v["note"].as_str().unwrap().contains("--t-max"), "{v}");
    }
    // The next double above α*: the integral cannot converge; it does not halt either.
    let a_star = json(&["--alpha", "0.1"])["alpha_star"].as_f64().unwrap();
    let next = f64::from_bits(a_star.to_bits() + 1);
    let v = json(&["--alpha", &format!("{next:e}")]);
    assert_eq!(v["period"], serde_json::Value::Null, "{v}");
    assert_eq!(v["halts"], false, "{v}");
    assert!(
        v["note"].as_str().unwrap().contains("too close to α*"),
        "{v}"
    );
    // At α* itself it halts, and says so without a note.
    let v = json(&["--alpha", &format!("{a_star:e}")]);
    assert_eq!(v["halts"], true, "{v}");
    assert_eq!(v["note"], serde_json::Value::Null, "{v}");
    assert_eq!(v["fate"], "halted", "{v}");
    // Every answer carries the verdict's words: a converged period is periodic; a heavy disk
    // whose turns still lengthen at --t-max is a transient, undecided, with no period (the old
    // output printed the second half's mean as "rolls: T = …").
    let v = json(&["--alpha", "0.3", "--mass", "2"]);
    assert_eq!(
        (&v["fate"], &v["multiplicity"]),
        (&"periodic".into(), &1.into()),
        "{v}"
    );
    assert!(v["period"].as_f64().unwrap() > 0.0, "{v}");
    let v = json(&["--alpha", "0.3", "--mass", "50", "--t-max", "150"]);
    assert_eq!(v["fate"], "undecided", "{v}");
    assert_eq!(v["why"]["reason"], "no_repeat", "{v}");
    assert_eq!(v["period"], serde_json::Value::Null, "{v}");
    let v = json(&["--alpha", &format!("{next:e}")]);
    assert_eq!(v["why"]["reason"], "at_threshold", "{v}");
    // At a coarse --rtol the turns cannot agree to 1e-8: undecided, and the note says which
    // setting decides it (the default does: periodic).
    let v = json(&["--alpha", "0.3", "--mass", "2", "--rtol", "1e-6"]);
    assert_eq!(v["fate"], "undecided", "{v}");
    assert!(v["note"].as_str().unwrap().contains("--rtol 1e-10"), "{v}");
    let text = rollphase(&[
        "period", disk, "--alpha", "0.3", "--mass", "50", "--t-max", "150",
    ]);
    let out = String::from_utf8_lossy(&text.stdout);
    assert!(out.contains("undecided:") && !out.contains("T = "), "{out}");
}

#[test]
fn options_that_do_not_apply_are_errors_not_ignored() {
    let dir = temp_dir("not-applying");
    let disk = write(&dir, "disk.json", DISK);
    let sphere = write(&dir, "sphere.json", SPHERE);
    let csv = dir.join("o.csv").to_string_lossy().into_owned();
    let sim = |body: &str, extra: &[&str]| {
        rollphase(
            &[
                &[
                    "simulate", body, "--alpha", "0.4", "--t-end", "1", "-o", &csv,
                ][..],
                extra,
            ]
            .concat(),
        )
    };
    fails_with(
        &sim(&sphere, &["--omega0", "1,0,0"]),
        1,
        &["--omega0 does not apply", "--mass 0"],
    );
    fails_with(
        &sim(&disk, &["--thetadot0", "1"]),
        1,
        &["--thetadot0 does not apply", "--mass 0"],
    );
    // A flag of the other kind of body, or one that the orientation already fixes, is refused,
    // never ignored.
    fails_with(
        &sim(&sphere, &["--mass", "1", "--thetadot0", "1"]),
        1,
        &["3D sphere", "not --thetadot0"],
    );
    fails_with(
        &sim(&disk, &["--mass", "1", "--spin", "1"]),
        1,
        &["2D disk", "not --spin"],
    );
    fails_with(
        &sim(&sphere, &["--q0", "1,0,0,0", "--spin", "1"]),
        1,
        &["--q0 is already the whole orientation"],
    );
    // `period` checks its start as `simulate` does.
    fails_with(
        &rollphase(&["period", &disk, "--alpha", "0.3", "--thetadot0", "0.5"]),
        1,
        &["--thetadot0 does not apply", "--mass 0"],
    );
    fails_with(
        &rollphase(&[
            "export-stl",
            &sphere,
            "-o",
            &dir.join("b.stl").to_string_lossy(),
            "--length-mm",
            "9",
        ]),
        1,
        &["--length-mm is for a 2D body"],
    );
    fails_with(
        &rollphase(&[
            "export-stl",
            &sphere,
            "-o",
            &dir.join("b.stl").to_string_lossy(),
            "--radius-mm",
            "1e-300",
        ]),
        1,
        &["--radius-mm 1e-300", "0.001 ≤ radius"],
    );
    // A huge angle is reduced modulo 2π with a warning, so θ still advances.
    let r = sim(
        &disk,
        &["--mass", "1", "--theta0", "1e17", "--samples", "3"],
    );
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(String::from_utf8_lossy(&r.stderr).contains("reduced modulo 2π"));
    let text = std::fs::read_to_string(&csv).unwrap();
    let thetas: Vec<f64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert!(
        thetas[0] < std::f64::consts::TAU && thetas[2] > thetas[0],
        "{thetas:?}"
    );
    // Scenes: 3D initial fields on a 2D body and the reverse.
    let scene = |body: &str, initial: &str| {
        let file = write(
            &dir,
            "s.toml",
            &format!(
                "name = \"s\"\n[body]\nperfect = \"{body}\"\n[model]\nalpha_rad = 0.3\n[initial]\n{initial}\n"
            ),
        );
        rollphase(&[
            "--headless",
            "--scene",
            &file,
            "--out",
            &dir.to_string_lossy(),
        ])
    };
    fails_with(
        &scene("disk", "contact = [1.0, 2.0]"),
        1,
        &["initial.contact", "2D disk"],
    );
    fails_with(
        &scene("sphere", "theta0 = 1.0"),
        1,
        &["initial.theta0", "3D sphere"],
    );
    fails_with(
        &scene("disk", "spin = 1.0"),
        1,
        &["2D disk", "not initial.spin"],
    );
    fails_with(
        &scene("sphere", "q0 = [1.0, 0.0, 0.0, 0.0]\nspin = 0.5"),
        1,
        &["initial.q0 is already the whole orientation"],
    );
    // An initial velocity kept in a viscous scene (as the app saves it with the mass slider at
    // 0) loads; the velocity is not used. (Through the library: rendering it needs the render
    // feature, which a --no-default-features build lacks.)
    let viscous = "name = \"s\"\n[body]\nperfect = \"sphere\"\n[model]\nalpha_rad = 0.3\n\
                   [initial]\nomega = [0.0, 0.1, 0.0]\n";
    let setup = rollphase::scene::Scene::from_toml(viscous)
        .and_then(|s| s.setup(None))
        .unwrap();
    assert!(matches!(
        setup.start,
        rollphase::simulate::Start::Sphere { omega0, .. } if omega0 == glam::DVec3::ZERO
    ));
}

#[test]
fn a_fixed_step_that_leaves_the_constraint_stops_with_dt_and_the_health_figures() {
    let dir = temp_dir("unhealthy");
    let sphere = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/sphere.json");
    let csv = dir.join("o.csv").to_string_lossy().into_owned();
    let rk4 = |dt: &str| {
        rollphase(&[
            "simulate",
            sphere,
            "--alpha",
            "0.3",
            "--t-end",
            "100",
            "--integrator",
            "rk4",
            "--dt",
            dt,
            "-o",
            &csv,
        ])
    };
    // dt = 1.5 passes the step-doubling check (estimate < 1e-3 per step) but its error adds
    // up: the health guard stops it. (dt ≥ 2 is refused by the check at the first step.)
    fails_with(
        &rk4("1.5"),
        1,
        &[
            "--dt 1.5",
            "fixed step dt = 1.5",
            "||q| − 1| =",
            "contact-normal error =",
            "1e-3",
        ],
    );
    assert!(
        !std::path::Path::new(&csv).exists(),
        "no CSV from a run that failed"
    );
    let r = rk4("0.2");
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

#[test]
fn under_determined_fits_and_out_of_range_scene_angles_are_refused() {
    let dir = temp_dir("fits");
    let one = write(
        &dir,
        "one.csv",
        "run_idx,alpha*,alpha,t_lag\n0,0.1,0.2,\"[1.0, 1.1]\"\n",
    );
    let r = rollphase(&["fit-lag", &one, "--out", &dir.to_string_lossy()]);
    fails_with(&r, 1, &["run 0 has 1 distinct angle", "at least 4 angles"]);
    // α/α* that would tilt the ramp past vertical names the factor, not a radian value.
    let scene = write(
        &dir,
        "s.toml",
        "name = \"s\"\n[body]\nrandom = { dimension = 3, seed = 1, sigma = 0.25, modes = 5 }\n\
         [model]\nalpha_over_critical = 100\n",
    );
    let r = rollphase(&[
        "--headless",
        "--scene",
        &scene,
        "--out",
        &dir.to_string_lossy(),
    ]);
    fails_with(
        &r,
        1,
        &["alpha_over_critical = 100", "steeper than a vertical wall"],
    );
    let r = rollphase(&["bench", "app", "--speed", "nan"]);
    if crate::cli::binary_has_app() {
        fails_with(&r, 1, &["--speed NaN is not allowed"]);
    } else {
        fails_with(&r, 1, &["bench app needs the `app` feature"]);
    }
}

/// `--step K` opens a lesson at a step it has; anything else is refused before a window opens.
#[test]
fn a_lesson_step_that_is_not_there_is_refused_by_name() {
    let r = rollphase(&["app", "--preset", "sphere-cruising", "--step", "2"]);
    fails_with(
        &r,
        1,
        &["--step 2 needs a lesson", "\"sphere-cruising\" has none"],
    );
    for k in ["0", "6"] {
        let r = rollphase(&["app", "--preset", "lesson-period-doubling", "--step", k]);
        fails_with(
            &r,
            1,
            &[
                &format!("--step {k} is not a step"),
                "it has 5: give 1 to 5",
            ],
        );
    }
    let r = rollphase(&["app", "--preset", "lesson-period-doubling", "--step", "-1"]);
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("--step"));
}

#[test]
fn ctrl_c_leaves_no_partial_output() {
    let dir = temp_dir("interrupt");
    let sphere = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/sphere.json");
    let csv = dir.join("long.csv");
    let child = Command::new(crate::cli::binary())
        .args([
            "simulate", sphere, "--alpha", "0.3", "--t-end", "1e7", "--rtol", "1e-12", "-o",
        ])
        .arg(&csv)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the run is under way (its staged file exists), then interrupt it. A run that
    // ends first (refused, or failed) is reported with its own message.
    let mut child = child;
    while std::fs::read_dir(&dir).unwrap().next().is_none() {
        if child.try_wait().unwrap().is_some() {
            let out = child.wait_with_output().unwrap();
            panic!(
                "the run ended before it staged its file: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

#[test]
fn a_fixed_step_that_would_be_silently_wrong_is_refused_with_dt_and_its_estimate() {
    let d = temp_dir("coarse-step");
    let sphere = write(&d, "sphere.json", rollphase::assets::SPHERE);
    let disk = write(&d, "disk.json", rollphase::assets::DISK);
    let csv = d.join("rows.csv");
    let run = |file: &str, integrator: &str, dt: &str| {
        rollphase(&[
            "simulate",
            file,
            "--alpha",
            "0.3",
            "--t-end",
            "100",
            "-o",
            csv.to_str().unwrap(),
            "--integrator",
            integrator,
            "--dt",
            dt,
        ])
    };
    for dt in ["5", "25", "100"] {
        for integrator in ["cf4", "rk4"] {
            let out = run(&sphere, integrator, dt);
            fails_with(
                &out,
                1,
                &["too coarse", &format!("dt = {dt}"), "use dt ≤", "no CSV"],
            );
            assert!(!csv.exists(), "no rows for a refused run");
        }
    }
    fails_with(&run(&disk, "rk4", "100"), 1, &["too coarse", "dt = 100"]);
    // Longer than the run: refused before it starts, with the number in exponent form.
    let out = run(&sphere, "cf4", "1e308");
    fails_with(&out, 1, &["longer than the whole run", "1e308"]);
    assert!(String::from_utf8_lossy(&out.stderr).len() < 400);
    // A step of the accuracy table runs.
    let out = run(&sphere, "cf4", "0.2");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn fit_lag_refuses_data_without_variance_and_flags_a_fit_at_its_bound() {
    let dir = temp_dir("fit-bounds");
    let out = dir.join("out");
    let flat = write(
        &dir,
        "flat.csv",
        "run_idx,alpha*,alpha,t_lag\n0,0.1,0.12,\"[5, 5]\"\n0,0.1,0.14,\"[5, 5]\"\n0,0.1,0.16,\"[5, 5]\"\n0,0.1,0.2,\"[5, 5]\"\n",
    );
    let r = rollphase(&["fit-lag", &flat, "--out", out.to_str().unwrap()]);
    fails_with(&r, 1, &["every lag time is 5 s", "cannot be fitted"]);
    assert!(!out.join("fit-lag").exists(), "nothing written");
    // A lag time that grows away from the smallest angle: no α* below it fits, and the search
    // ends at its bound, which the output says rather than reporting the bound as a fit.
    let odd = write(
        &dir,
        "odd.csv",
        "run_idx,alpha*,alpha,t_lag\n0,0.1,0.12,\"[1, 1.1]\"\n0,0.1,0.14,\"[2, 2.1]\"\n0,0.1,0.16,\"[3, 3.2]\"\n0,0.1,0.2,\"[5, 5.1]\"\n",
    );
    let args = [
        "fit-lag",
        &odd,
        "--out",
        out.to_str().unwrap(),
        "--bootstrap",
        "20",
    ];
    // A bound is not a fit: exit 1, the files written for a look, unless --allow-bound.
    let r = rollphase(&args);
    fails_with(&r, 1, &["a bound, not a fit", "--allow-bound"]);
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("fit-lag/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["at_bound"], true);
    let r = rollphase(&[&args[..], &["--allow-bound"]].concat());
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("warning:") && err.contains("a bound, not a fit"),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("fit-lag/summary.json")).unwrap()).unwrap();
    assert!(!summary["warnings"].as_array().unwrap().is_empty());
}

/// Lag times t = A (α − α*)^β for three runs at eight angles, two repeats each (±1 % apart).
fn lag_csv(beta: f64) -> String {
    let mut text = String::from("run_idx,alpha*,alpha,t_lag\n");
    for (run, star) in [(0, 0.15), (1, 0.17), (2, 0.2)] {
        for d in [0.005, 0.01, 0.02, 0.03, 0.05, 0.07, 0.1, 0.14] {
            let t = 0.2 * f64::powf(d, beta);
            text += &format!(
                "{run},{star},{},\"[{}, {}]\"\n",
                star + d,
                t * 1.01,
                t * 0.99
            );
        }
    }
    text
}

#[test]
fn fit_lag_searches_every_exponent_the_drag_laws_accept() {
    let dir = temp_dir("fit-range");
    // β = −3 is a drag exponent n = 1/(1/2 − β) = 2/7, inside the accepted 0.25 ≤ n ≤ 4: it was
    // once reported as the old range's edge −1.5 "± 0.0000", exit 0.
    for (beta, n) in [(-3.0, 2.0 / 7.0), (-0.5, 1.0), (0.1, 2.5)] {
        let data = write(&dir, &format!("beta{beta}.csv"), &lag_csv(beta));
        let out = dir.join(format!("out{beta}"));
        let r = rollphase(&[
            "fit-lag",
            &data,
            "--out",
            out.to_str().unwrap(),
            "--bootstrap",
            "20",
        ]);
        assert!(
            r.status.success(),
            "β = {beta}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
        let summary: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("fit-lag/summary.json")).unwrap())
                .unwrap();
        let fitted = summary["shared_exponent"].as_f64().unwrap();
        assert!((fitted - beta).abs() < 0.01, "β = {beta}: fitted {fitted}");
        assert_eq!(summary["at_bound"], false);
        let sd = summary["shared_exponent_stderr"].as_f64().unwrap();
        assert!(sd > 0.0, "β = {beta}: σ {sd}");
        let fitted_n = summary["drag_exponent"]["n"].as_f64().unwrap();
        assert!(
            (fitted_n - n).abs() < 0.03 * n,
            "β = {beta}: n {fitted_n}, not {n}"
        );
    }
    // Steeper than any accepted drag law: a bound, no σ, exit 1 naming the flag.
    let data = write(&dir, "beta-5.csv", &lag_csv(-5.0));
    let out = dir.join("out-5");
    let r = rollphase(&[
        "fit-lag",
        &data,
        "--out",
        out.to_str().unwrap(),
        "--bootstrap",
        "20",
    ]);
    fails_with(&r, 1, &["a bound", "--allow-bound"]);
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("fit-lag/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["shared_exponent_at_bound"], true);
    assert!(summary["shared_exponent_stderr"].is_null());
    assert!(summary["drag_exponent"].is_null());
}

#[test]
fn a_perfect_sphere_is_told_which_figures_do_not_apply_and_why() {
    let dir = temp_dir("perfect");
    let perfect = write(&dir, "perfect.json", r#"{"kind":"sphere","coeffs":[]}"#);
    let out = dir.join("out");
    for (figure, why) in [
        ("sphere-poincare", "no attractors to find"),
        ("sphere-halting", "no halting loops"),
    ] {
        // No --alpha given: the message is about the body, not about an α nobody chose.
        let r = rollphase(&[
            "figure",
            figure,
            "--quick",
            "--shape",
            &perfect,
            "--out",
            out.to_str().unwrap(),
        ]);
        fails_with(&r, 1, &[figure, "does not apply to a perfect sphere", why]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!err.contains("alpha = 0"), "{err}");
    }
}

#[test]
fn tolerances_and_spans_beyond_double_precision_name_the_real_cause() {
    let sphere = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/sphere.json");
    let disk = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/disk.json");
    // Not "stiff, try the viscous model": the tolerance itself is the problem.
    let r = rollphase(&[
        "simulate", sphere, "--alpha", "0.3", "--t-end", "10", "--atol", "1e-300", "-o", "-",
    ]);
    fails_with(
        &r,
        1,
        &["atol = 1e-300", "1e-20 ≤ atol", "double precision"],
    );
    assert!(!String::from_utf8_lossy(&r.stderr).contains("viscous model"));
    // Not "the step fell below double precision" at t = 0: the span is the problem.
    let r = rollphase(&[
        "period", disk, "--alpha", "0.3", "--mass", "1", "--t-max", "1e300",
    ]);
    fails_with(&r, 1, &["--t-max 1e300", "t_max ≤ 1e9"]);
    let r = rollphase(&[
        "simulate", sphere, "--alpha", "0.3", "--t-end", "1e300", "-o", "-",
    ]);
    fails_with(&r, 1, &["t_end = 1e300", "t_end ≤ 1e9"]);
    // Numbers far from 1 in exponent form: no message spells out 300 digits.
    assert!(String::from_utf8_lossy(&r.stderr).len() < 400);
}

#[test]
fn simulate_writes_rows_to_standard_output_by_default_but_not_two_streams_there() {
    let sphere = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/sphere.json");
    let r = rollphase(&[
        "simulate",
        sphere,
        "--alpha",
        "0.3",
        "--t-end",
        "1",
        "--samples",
        "3",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = String::from_utf8_lossy(&r.stdout);
    assert!(
        text.starts_with("t,qw") && text.lines().count() == 4,
        "{text}"
    );
    let r = rollphase(&[
        "simulate",
        sphere,
        "--alpha",
        "0.3",
        "--t-end",
        "1",
        "--summary",
        "-",
    ]);
    fails_with(
        &r,
        1,
        &["-o and --summary both name standard output", "its own file"],
    );
    assert!(r.stdout.is_empty());
}

/// Issue 33, case 4: an interrupt while a hard-linked file is rewritten in place leaves every
/// name with the old contents or the complete new ones, never a cut file, and no backup behind.
#[test]
fn an_interrupt_during_an_in_place_rewrite_leaves_every_name_whole() {
    let dir = temp_dir("interrupt-in-place");
    let body = write(&dir, "body.json", SPHERE);
    let run = |alpha: &str, out: &std::path::Path| {
        let mut c = Command::new(crate::cli::binary());
        c.args(["simulate", &body, "--alpha", alpha, "--t-end", "100"])
            .args(["--samples", "200000", "-o"])
            .arg(out)
            .stderr(std::process::Stdio::piped());
        c
    };
    let out = dir.join("out.csv");
    let link = dir.join("out-link.csv");
    assert!(run("0.30", &out).status().unwrap().success());
    std::fs::hard_link(&out, &link).unwrap();
    let old = std::fs::read(&out).unwrap();
    let new_path = dir.join("expected-new.csv");
    assert!(run("0.31", &new_path).status().unwrap().success());
    let new = std::fs::read(&new_path).unwrap();
    assert_ne!(old, new);
    let mut child = run("0.31", &out).spawn().unwrap();
    // Interrupt once the commit has begun (its backup of the old contents exists), or as soon
    // as the destination changes, whichever is seen first (or the run has ended).
    loop {
        let committing = std::fs::read_dir(&dir).unwrap().any(|e| {
            e.unwrap()
                .file_name()
                .to_string_lossy()
                .contains("previous")
        });
        let changed = std::fs::metadata(&out).map(|m| m.len()).ok() != Some(old.len() as u64);
        if committing || changed || child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let _ = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    let finished = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&finished.stderr);
    assert!(!err.contains("panicked"), "{err}");
    let after = std::fs::read(&out).unwrap();
    assert_eq!(after, std::fs::read(&link).unwrap(), "the two names differ");
    assert!(
        after == old || after == new,
        "a name holds neither the old nor the complete new file ({} bytes; old {}, new {}); {err}",
        after.len(),
        old.len(),
        new.len()
    );
    if finished.status.code() == Some(130) && after == new {
        assert!(err.contains("files written are complete"), "{err}");
    }
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

/// Issue 33, case 5: a path naming one of the process's descriptors is written through it (a log
/// the shell appends to keeps its lines), never replaced by a rename.
#[test]
fn an_output_naming_a_descriptor_writes_through_it() {
    let dir = temp_dir("descriptor");
    let body = write(&dir, "body.json", SPHERE);
    let log = dir.join("log.txt");
    std::fs::write(&log, "IMPORTANT\n").unwrap();
    let appending = std::fs::OpenOptions::new().append(true).open(&log).unwrap();
    let r = Command::new(crate::cli::binary())
        .args(["simulate", &body, "--alpha", "0.4", "--t-end", "1"])
        .args(["--samples", "3", "-o", "/proc/self/fd/1"])
        .stdout(appending)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(text.starts_with("IMPORTANT\nt,qw"), "{text}");
    assert_eq!(text.lines().count(), 5, "{text}");
    // The summary through standard error, appended to its log too.
    let err_log = dir.join("err.log");
    std::fs::write(&err_log, "EARLIER\n").unwrap();
    let appending = std::fs::OpenOptions::new()
        .append(true)
        .open(&err_log)
        .unwrap();
    let csv = dir.join("rows.csv");
    let r = Command::new(crate::cli::binary())
        .args(["simulate", &body, "--alpha", "0.4", "--t-end", "1"])
        .args(["--samples", "3", "--summary", "/dev/stderr", "-o"])
        .arg(&csv)
        .stderr(appending)
        .output()
        .unwrap();
    assert!(r.status.success());
    let text = std::fs::read_to_string(&err_log).unwrap();
    assert!(text.starts_with("EARLIER\n{"), "{text}");
    assert!(std::fs::read_to_string(&csv).unwrap().starts_with("t,qw"));
}

/// Issue 33, case 6: two outputs of one command naming one file are refused before any work,
/// saying so; the null device takes both.
#[test]
fn two_outputs_naming_one_file_are_refused_but_the_null_device_takes_both() {
    let dir = temp_dir("collide");
    let body = write(&dir, "body.json", SPHERE);
    let in_dir = |args: &[&str]| {
        Command::new(crate::cli::binary())
            .args([
                "simulate",
                &body,
                "--alpha",
                "0.4",
                "--t-end",
                "1",
                "--samples",
                "3",
            ])
            .args(args)
            .current_dir(&dir)
            .output()
            .unwrap()
    };
    let r = in_dir(&["-o", "run.csv", "--summary", "./run.csv"]);
    fails_with(
        &r,
        1,
        &["-o and --summary both name ./run.csv", "its own file"],
    );
    assert!(!dir.join("run.csv").exists());
    // The same when the file exists: the message is the collision, not "is also an input".
    std::fs::write(dir.join("run.csv"), "keep").unwrap();
    let r = in_dir(&["-o", "run.csv", "--summary", "run.csv"]);
    fails_with(&r, 1, &["both name run.csv"]);
    assert!(!String::from_utf8_lossy(&r.stderr).contains("is also an input"));
    assert_eq!(
        std::fs::read_to_string(dir.join("run.csv")).unwrap(),
        "keep"
    );
    let r = in_dir(&["-o", "/dev/null", "--summary", "/dev/null"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

/// Issue 33, case 9: binary output on standard output is the data alone; the status line goes
/// to standard error.
#[test]
fn binary_output_on_standard_output_is_the_data_alone() {
    let dir = temp_dir("stl-stdout");
    let body = write(&dir, "body.json", SPHERE);
    for out in ["-", "/dev/stdout"] {
        let r = rollphase(&["export-stl", &body, "--detail", "1", "-o", out]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let stl = &r.stdout;
        assert!(stl.len() > 84);
        let triangles = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
        assert_eq!(stl.len(), 84 + 50 * triangles, "{out}: bytes after the STL");
        assert!(String::from_utf8_lossy(&r.stderr).contains("triangles, watertight"));
    }
}

/// Issue 33, case 10: the stiff corner. `period` takes the viscous limit at m/m0 ≤ rtol as
/// `simulate` does (it failed with "step size fell to 0e0" at 1e-300), saying so; a stiff run
/// that would take minutes is announced with an estimate before it starts.
#[test]
fn stiff_corners_take_the_viscous_limit_or_warn_with_an_estimate_before_running() {
    use std::io::BufRead;
    let dir = temp_dir("stiff");
    let disk = write(&dir, "disk.json", DISK);
    let r = rollphase(&[
        "period", &disk, "--alpha", "0.3", "--mass", "1e-300", "--json",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let report: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(report["model"], "disk-viscous");
    assert!(
        report["note"]
            .as_str()
            .unwrap()
            .contains("ran the viscous model")
    );
    let viscous = rollphase(&["period", &disk, "--alpha", "0.3", "--json"]);
    let viscous: serde_json::Value = serde_json::from_slice(&viscous.stdout).unwrap();
    assert_eq!(report["period"], viscous["period"]);

    let sphere = write(&dir, "sphere.json", SPHERE);
    for args in [
        vec![
            "simulate",
            &sphere,
            "--alpha",
            "0.3",
            "--mass",
            "1e-8",
            "--t-end",
            "0.5",
            "-o",
            "/dev/null",
        ],
        vec!["period", &disk, "--alpha", "0.3", "--mass", "1e-6"],
    ] {
        let mut child = Command::new(crate::cli::binary())
            .args(&args)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        std::io::BufReader::new(child.stderr.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        let _ = child.kill();
        let _ = child.wait();
        assert!(
            first.starts_with("warning: m/m0 =") && first.contains("right-hand-side evaluations"),
            "{args:?}: {first}"
        );
    }
}

/// Issue 33, case 11: messages that were false or unreadable. A quaternion of huge or tiny
/// components is a direction like any other; a negative --atol gets the tolerance's own
/// message, not clap's "unexpected argument"; a sweep spec's 400 kB line is not echoed whole;
/// `max_degree` is called `max_degree`; a stiff or singular step names no "tiny m/m0" it was
/// not given; angles print readably.
#[test]
fn messages_say_what_is_true_in_readable_numbers() {
    let dir = temp_dir("messages");
    let sphere = write(&dir, "sphere.json", SPHERE);
    let run = |extra: &[&str]| {
        let mut args = vec![
            "simulate",
            &sphere,
            "--alpha",
            "0.3",
            "--t-end",
            "1",
            "--samples",
            "2",
        ];
        args.extend_from_slice(extra);
        rollphase(&args)
    };
    let reference = run(&["--q0", "1,1,0,0"]);
    assert!(reference.status.success());
    for q0 in ["1e154,1e154,0,0", "1e-160,1e-160,0,0"] {
        let r = run(&["--q0", q0]);
        assert!(
            r.status.success(),
            "{q0}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
        assert_eq!(
            r.stdout, reference.stdout,
            "{q0} is the direction of 1,1,0,0"
        );
    }
    fails_with(
        &run(&["--q0", "0,0,0,0"]),
        1,
        &["--q0 0,0,0,0 has zero length"],
    );
    fails_with(&run(&["--atol", "-1"]), 1, &["atol = -1 is not allowed"]);
    let r = run(&["--drag", "1e-300"]);
    assert!(!String::from_utf8_lossy(&r.stderr).contains("tiny m/m0"));
    let r = rollphase(&["period", &write(&dir, "d.json", DISK), "--alpha", "1e-300"]);
    fails_with(&r, 1, &["alpha = 1e-300 rad", "round-off"]);
    let r = run(&["--mass=-1e-300"]);
    fails_with(&r, 1, &["m/m0 = -1e-300 is not allowed"]);
    let r = run(&["--drag=-1e-300"]);
    fails_with(&r, 1, &["gamma = -1e-300 is not allowed"]);

    let long = format!(
        "alpha = [{}x]\n[bodies]\npaper_seeds = [219]\n",
        "0.1,".repeat(100_000)
    );
    let spec = write(&dir, "long.toml", &long);
    let r = rollphase(&["sweep", &spec, "--out", dir.join("o").to_str().unwrap()]);
    fails_with(&r, 1, &["characters in all"]);
    assert!(r.stderr.len() < 2000, "{} bytes of message", r.stderr.len());
    let spec = write(
        &dir,
        "degree.toml",
        "alpha = [0.2]\n[bodies]\nseeds = [1]\nmax_degree = 20\n",
    );
    let r = rollphase(&["sweep", &spec, "--out", dir.join("o").to_str().unwrap()]);
    fails_with(&r, 1, &["bodies.max_degree = 20", "2 ≤ max_degree ≤ 12"]);
}

/// Issue 37: `--spin 0 --q0 …` passed because a zero spin counted as not given; given is given.
#[test]
fn a_zero_spin_is_still_a_spin() {
    let dir = temp_dir("zero-spin");
    let sphere = write(&dir, "sphere.json", SPHERE);
    let disk = write(&dir, "disk.json", DISK);
    let r = rollphase(&[
        "simulate", &sphere, "--alpha", "0.3", "--t-end", "1", "--spin", "0", "--q0", "1,0,0,0",
    ]);
    fails_with(&r, 1, &["--spin", "--q0 is already the whole orientation"]);
    let r = rollphase(&[
        "simulate", &disk, "--alpha", "0.3", "--t-end", "1", "--spin", "0",
    ]);
    fails_with(&r, 1, &["2D disk", "not --spin"]);
    // Without --spin, the default (no turn) applies as before.
    let r = rollphase(&[
        "simulate",
        &sphere,
        "--alpha",
        "0.3",
        "--t-end",
        "1",
        "--samples",
        "2",
        "--q0",
        "1,0,0,0",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

/// An integrator's name is read by one parser, with one message, wherever it is given: the
/// command line's --integrator, a scene's integrator.method and a sweep spec's integrators.
#[test]
fn a_bad_integrator_name_gets_the_same_message_everywhere() {
    let expected = "\"euler\" is not an integrator: one of dop853 (adaptive, rtol), rk4 or cf4";
    let dir = temp_dir("integrator-name");
    let shape = write(&dir, "disk.json", DISK);
    let cli = rollphase(&[
        "simulate",
        &shape,
        "--alpha",
        "0.1",
        "--integrator",
        "euler",
    ]);
    fails_with(&cli, 2, &[expected]);
    let scene = write(
        &dir,
        "scene.toml",
        &format!(
            "name = \"s\"\n[body]\nshape = \"{shape}\"\n[model]\nalpha_rad = 0.1\n\
             [integrator]\nmethod = \"euler\"\n"
        ),
    );
    let out = rollphase(&[
        "--headless",
        "--scene",
        &scene,
        "--out",
        dir.join("f").to_str().unwrap(),
    ]);
    fails_with(&out, 1, &[expected]);
    let spec = write(
        &dir,
        "spec.toml",
        "alpha = [0.1]\nintegrators = [\"euler:0.1\"]\n[bodies]\nseeds = [1]\n",
    );
    let out = rollphase(&["sweep", &spec, "--out", dir.join("s").to_str().unwrap()]);
    fails_with(&out, 1, &[expected]);
    // A spec string that is no kind with a setting lists the spec strings.
    let spec = write(
        &dir,
        "spec2.toml",
        "alpha = [0.1]\nintegrators = [\"euler\"]\n[bodies]\nseeds = [1]\n",
    );
    let out = rollphase(&["sweep", &spec, "--out", dir.join("s").to_str().unwrap()]);
    fails_with(
        &out,
        1,
        &["\"euler\" is not an integrator: one of fast, balanced, precise, dop853:RTOL"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `period --rtol` is checked whichever model runs: the viscous quadrature does not use it, and
/// `--rtol nan` or `-5` passed there while the inertial run refused them (a helper's, 2026-12-02).
#[test]
fn period_refuses_a_bad_rtol_in_the_viscous_model_too() {
    let disk = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/disk.json");
    for rtol in ["nan", "-5", "0", "1"] {
        for mass in ["0", "2"] {
            let rtol = format!("--rtol={rtol}");
            let r = rollphase(&["period", disk, "--alpha", "0.3", "--mass", mass, &rtol]);
            fails_with(&r, 1, &["rtol", "1e-15 ≤ rtol < 1"]);
        }
    }
}
