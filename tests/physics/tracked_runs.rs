//! `rollphase track`: the authors' tracked sphere gives their hand-picked period and advance
//! without hand-picking, against the model's prediction for the printed body; synthetic tracks
//! with a known period come back with it through noise, gaps, jumps and missing values; and a
//! track with no period, too few frames or the wrong columns is an error that writes nothing.

use std::path::Path;

use crate::cli::{data, rollphase, rollphase_ok, scratch};
use serde_json::Value;

fn summary(dir: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn the_authors_run_gives_their_period_and_advance_without_hand_picking() {
    let dir = scratch("authors");
    let body = dir.join("printed-sphere.json");
    rollphase_ok([
        "shape",
        "--from-mesh",
        data("printed-sphere.stl").to_str().unwrap(),
        "-o",
        body.to_str().unwrap(),
    ]);
    let out = dir.join("run");
    let alpha = 0.2f64.asin().to_string();
    let printed = rollphase_ok([
        "track",
        data("sphere-track-viscous.csv").to_str().unwrap(),
        "--markers",
        data("sphere-markers-viscous.csv").to_str().unwrap(),
        "--fps",
        "30",
        "--scale",
        "0.0404,0.0361",
        "--body",
        body.to_str().unwrap(),
        "--alpha",
        &alpha,
        "--out",
        out.to_str().unwrap(),
    ]);
    let s = summary(&out);
    eprintln!("{}", String::from_utf8_lossy(&printed));
    // The authors' one hand-picked period: 152.24 frames (5.07 s), 6.33 cm down, −0.42 cm
    // across. Measured here over every steady period (2026-11-26): 155.34 ± 1.5 frames,
    // 6.40 cm, −0.47 cm; the authors' period lies within the cycles' spread (4.6 frames).
    let period = s["period_frames"].as_f64().unwrap();
    let error = s["period_error_s"].as_f64().unwrap() * 30.0;
    let spread = s["period_spread_s"].as_f64().unwrap() * 30.0;
    // Its turns' times vary (blocks of the track scatter far beyond their errors), so the
    // period is the cycles' mean with their spread, not one frequency's fit.
    assert_eq!(s["period_error_from"], "cycles");
    assert_eq!(s["block_check"]["turns_vary"], true, "{}", s["block_check"]);
    // The centre leaves 5.8 times what its pixel noise explains unrepeated (a chaotic motion
    // can leave as much), and the markers show the orientation repeating every period.
    assert_eq!(
        s["repeat_shown"]["shown"], "by_markers",
        "{}",
        s["repeat_shown"]
    );
    assert!(
        (period - 152.24).abs() < spread,
        "{period} ± {error} (spread {spread})"
    );
    assert!(error > 0.1 && error < 3.0, "standard error {error} frames");
    // Each cycle's period spans two turns, so the mean's error is √2 × spread / √(cycles).
    let cycles = s["cycle_periods_s"].as_array().unwrap().len() as f64;
    assert!(
        (error - (2.0f64 / cycles).sqrt() * spread).abs() < 1e-9 * error,
        "{error} against {spread} over {cycles} cycles"
    );
    assert!((s["period_s"].as_f64().unwrap() - period / 30.0).abs() < 1e-12);
    let down = s["advance_down_cm"].as_f64().unwrap();
    let across = s["advance_across_cm"].as_f64().unwrap();
    assert!((down - 6.33).abs() < 0.1, "advance down {down} cm");
    assert!((across + 0.42).abs() < 0.15, "advance across {across} cm");
    assert!(s["periods_seen"].as_u64().unwrap() >= 9);
    // The release and the end of the ramp are left out, and said.
    let used = s["frames_used"].as_array().unwrap();
    assert!(used[0].as_f64().unwrap() > 170.0 && used[1].as_f64().unwrap() < 1919.0);
    assert!(s["warnings"].to_string().contains("end of the ramp"));
    assert!(s["markers"].as_u64().unwrap() > 500);
    // The markers (Fig. 5e's reading): a viscous run repeats after one period. Measured
    // 2026-11-26: 0.121 cm one period on, 0.177 cm two on, 0.584 cm at unrelated phases.
    let m = &s["marker_reading"];
    assert_eq!(m["verdict"], "every_period", "{m}");
    let (d1, floor) = (
        m["mismatch_one_cm"].as_f64().unwrap(),
        m["chance_floor_cm"].as_f64().unwrap(),
    );
    assert!(d1 < 0.3 * floor, "{m}");
    assert!(m["score"].as_f64().unwrap() < m["shuffled_score_max"].as_f64().unwrap());
    assert!(
        String::from_utf8_lossy(&printed).contains("markers: the markers repeat after one period")
    );
    // The model, parameter-free: the printed body's two viscous orbits advance 6.18 and 6.19
    // cm per period; measured 3.4 % more. m/m0 and t0 solved together from the period
    // (m/m0 = ⟨r⟩/(g t0²)) are deep in the viscous regime, and so is the SI's speed estimate
    // v²/(g⟨r⟩ sin²α) (the paper's ≈ 0.025 for v ≈ 1 cm/s).
    let m = &s["model"];
    let predicted = m["predicted_advance_down_cm"].as_f64().unwrap();
    assert!((predicted - 6.187).abs() < 0.01, "{predicted}");
    assert!((m["advance_down_difference"].as_f64().unwrap()).abs() < 0.05);
    assert_eq!(m["mass_ratio_model"], 0.0);
    assert_eq!(m["mass_ratio_from"], "period");
    let solved = m["mass_ratio"].as_f64().unwrap();
    let from_speed = m["mass_ratio_from_speed"].as_f64().unwrap();
    assert!(solved > 0.02 && solved < 0.1, "{solved}");
    assert!(from_speed > 0.02 && from_speed < 0.1, "{from_speed}");
    let t0 = m["t0_s"].as_f64().unwrap();
    let radius_m = m["scale_mm"].as_f64().unwrap() / 1000.0;
    assert!((solved - radius_m / (9.81 * t0 * t0)).abs() < 1e-9 * solved);
    let period_s = s["period_s"].as_f64().unwrap();
    assert!((t0 * m["predicted_period_t0"].as_f64().unwrap() - period_s).abs() < 1e-9);
    assert!(m["period_difference"].as_f64().unwrap().abs() < 1e-9);
    // The speed estimate's own t0 and the period it implies are reported beside it.
    let t0_speed = m["t0_from_speed_s"].as_f64().unwrap();
    assert!((from_speed - radius_m / (9.81 * t0_speed * t0_speed)).abs() < 1e-9 * from_speed);
    assert!(m["period_from_speed_s"].as_f64().unwrap() > period_s);
    // The evidence: the surrogates' floor and the track's dip.
    let sig = &s["significance"];
    assert_eq!(sig["surrogates"], 19);
    assert!(
        sig["normalised_dip"].as_f64().unwrap() < 0.5 * sig["surrogate_floor"].as_f64().unwrap()
    );
    // data.csv: every centre and marker point, folded.
    let csv = std::fs::read_to_string(out.join("data.csv")).unwrap();
    assert!(csv.starts_with("kind,frame,t_s,down_cm,across_cm,period,t_local_s"));
    assert!(csv.lines().filter(|l| l.starts_with("marker,")).count() > 500);
    let png = std::fs::read(out.join("figure.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // One marker row in 40 is too sparse to tell: said so, not guessed.
    let all = std::fs::read_to_string(data("sphere-markers-viscous.csv")).unwrap();
    let mut lines = all.lines();
    let mut sparse: String = lines.next().unwrap().to_string() + "\n";
    for l in lines.step_by(40) {
        sparse += l;
        sparse += "\n";
    }
    let sparse_file = dir.join("sparse-markers.csv");
    std::fs::write(&sparse_file, sparse).unwrap();
    let out = dir.join("sparse");
    rollphase_ok([
        "track",
        data("sphere-track-viscous.csv").to_str().unwrap(),
        "--markers",
        sparse_file.to_str().unwrap(),
        "--fps",
        "30",
        "--scale",
        "0.0404,0.0361",
        "--out",
        out.to_str().unwrap(),
    ]);
    let s = summary(&out);
    assert_eq!(
        s["marker_reading"]["verdict"], "too_sparse",
        "{}",
        s["marker_reading"]
    );
    // Markers too sparse to tell leave the centre's rough repeat as the only evidence.
    assert_eq!(
        s["repeat_shown"]["shown"], "roughly",
        "{}",
        s["repeat_shown"]
    );
}

/// Markers that are all NaN, or that never meet the track's frames, are no reading at all: an
/// error that says which, and nothing written (once "too sparse to tell: 0 detections in 0
/// cycles", exit 0).
#[test]
fn markers_that_never_meet_the_track_are_an_error_not_a_reading() {
    let dir = scratch("no-markers");
    for (name, rows, why) in [
        (
            "nan",
            "208,nan,nan,nan,nan\n209,nan,nan,nan,nan\n",
            "2 have a value that is not a finite",
        ),
        (
            "elsewhere",
            "1,5,5,0,0\n2,5,6,0,0\n",
            "the other 2 lie outside the track's frames",
        ),
    ] {
        let file = dir.join(format!("{name}-markers.csv"));
        std::fs::write(&file, format!("frame,x,y,xn,yn\n{rows}")).unwrap();
        let out = dir.join(name);
        let r = rollphase([
            "track",
            data("sphere-track-viscous.csv").to_str().unwrap(),
            "--markers",
            file.to_str().unwrap(),
            "--fps",
            "30",
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{name}: {err}");
        assert!(
            err.contains("none of its 2 rows is a marker") && err.contains(why),
            "{err}"
        );
        assert!(
            !out.join("summary.json").exists(),
            "{name}: nothing written"
        );
    }
}

/// A synthetic track: period `period` frames, advancing `advance` units a period, with a wobble
/// across and pseudo-random noise of `noise` units.
fn synthetic(frames: usize, period: f64, advance: f64, noise: f64) -> Vec<(f64, f64, f64)> {
    let w = std::f64::consts::TAU / period;
    let mut state = 12345u64;
    let mut rand = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    (0..frames)
        .map(|i| {
            let f = i as f64;
            let down = advance * f / period + 20.0 * (w * f).sin() + 8.0 * (2.0 * w * f).cos();
            let across = 30.0 * (w * f + 1.0).sin() - 0.02 * f;
            (f + 100.0, across + noise * rand(), down + noise * rand())
        })
        .collect()
}

fn write_track(path: &Path, rows: &[(f64, f64, f64)], skip: &[usize]) {
    let mut text = String::from("frame,xn,yn\n");
    for (i, (f, x, y)) in rows.iter().enumerate() {
        if skip.contains(&i) {
            continue;
        }
        text += &format!("{f},{x},{y}\n");
    }
    std::fs::write(path, text).unwrap();
}

fn track(file: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "track".to_string(),
        file.display().to_string(),
        "--out".into(),
        out.display().to_string(),
    ];
    // The synthetic tracks' scale, unless the test gives its own (clap refuses a flag twice,
    // which a test of --scale's own message must not mistake for it).
    if !extra.contains(&"--scale") {
        args.extend(["--scale".to_string(), "0.04,0.04".to_string()]);
    }
    args.extend(extra.iter().map(|s| s.to_string()));
    rollphase(&args)
}

#[test]
fn a_known_period_comes_back_through_noise_gaps_jumps_and_missing_values() {
    let dir = scratch("synthetic");
    let rows = synthetic(1500, 123.4, 160.0, 2.0);
    let clean = dir.join("clean.csv");
    write_track(&clean, &rows, &[]);
    let out = dir.join("clean");
    let o = track(&clean, &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    let period = s["period_frames"].as_f64().unwrap();
    let error = s["period_error_s"].as_f64().unwrap() * 30.0;
    assert!((period - 123.4).abs() < 0.2, "{period} ± {error}");
    assert!((period - 123.4).abs() < 4.0 * error.max(0.02));
    assert!((s["advance_down_cm"].as_f64().unwrap() - 160.0 * 0.04).abs() < 0.01);
    assert!((s["advance_across_cm"].as_f64().unwrap() + 0.02 * 123.4 * 0.04).abs() < 0.01);
    assert_eq!(s["warnings"].as_array().unwrap().len(), 0);

    // The same track, damaged: a gap of 6 frames, a NaN, an empty cell, a tracker jump.
    let mut text = String::from("frame,xn,yn\n");
    for (i, (f, x, y)) in rows.iter().enumerate() {
        match i {
            300..=305 => continue,
            400 => text += &format!("{f},nan,{y}\n"),
            401 => text += &format!("{f},,{y}\n"),
            700 => text += &format!("{f},{x},{}\n", y + 900.0),
            _ => text += &format!("{f},{x},{y}\n"),
        }
    }
    let damaged = dir.join("damaged.csv");
    std::fs::write(&damaged, text).unwrap();
    let out = dir.join("damaged");
    let o = track(&damaged, &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    assert!((s["period_frames"].as_f64().unwrap() - 123.4).abs() < 0.3);
    let warnings = s["warnings"].to_string();
    for said in ["non-finite", "bridged", "jump"] {
        assert!(warnings.contains(said), "{said}: {warnings}");
    }
    // A negative factor flips its axis, written as the parser reads numbers (not as a flag);
    // a track that then runs uphill says so, naming the factor.
    let out = dir.join("flipped");
    let o = track(&clean, &out, &["--scale", "-0.04,-0.04"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    assert!((s["advance_down_cm"].as_f64().unwrap() + 160.0 * 0.04).abs() < 0.01);
    assert!(
        s["warnings"].to_string().contains("up the ramp"),
        "{}",
        s["warnings"]
    );
    // The frame rate only changes the seconds.
    let out = dir.join("fps");
    assert!(track(&clean, &out, &["--fps", "60"]).status.success());
    let s = summary(&out);
    assert!(
        (s["period_s"].as_f64().unwrap() - s["period_frames"].as_f64().unwrap() / 60.0).abs()
            < 1e-12
    );
}

/// What classroom trackers write reads as the same track: Tracker's export (title line, tabs,
/// decimal commas, t in seconds at 29.97 frames/s, x down the ramp, metres) and trackpy's linked
/// table (an unnamed index column, the body among other particles, pixels) give the plain CSV's
/// period and advance. Each needs its scale; trackpy's needs the particle named; a frame rate
/// the times do not fall on is refused, naming it.
#[test]
fn trackers_and_trackpys_tables_give_the_plain_tables_answer() {
    let dir = scratch("trackers");
    let rows = synthetic(1500, 123.4, 160.0, 2.0);
    let plain = dir.join("plain.csv");
    write_track(&plain, &rows, &[]);
    let out = dir.join("plain");
    assert!(track(&plain, &out, &[]).status.success());
    let want = summary(&out);
    // Tracker: t = (frame − 100)/29.97 s, x (down) and y (across) in m (0.04 cm a unit).
    let mut text = String::from("mass A\nt\tx\ty\n");
    for (f, across, down) in &rows {
        let t = (f - 100.0) / 29.97;
        let cell = |v: f64| format!("{v:.9E}").replace('.', ",");
        text += &format!(
            "{}\t{}\t{}\n",
            cell(t),
            cell(down * 0.0004),
            cell(across * 0.0004)
        );
    }
    let tracker = dir.join("tracker.txt");
    std::fs::write(&tracker, text).unwrap();
    let none = dir.join("refused");
    let o = rollphase([
        "track",
        tracker.to_str().unwrap(),
        "--out",
        dir.join("no-scale").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("give --scale"));
    refused(&tracker, &none, &["--fps", "25"], "not a whole frame");
    let out = dir.join("tracker");
    let o = track(&tracker, &out, &["--scale", "100,100"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let got = summary(&out);
    assert_eq!(got["table"]["format"], "tracker");
    assert_eq!(got["fps"], 29.97);
    let close = |key: &str, tol: f64| {
        let (a, b) = (got[key].as_f64().unwrap(), want[key].as_f64().unwrap());
        assert!((a - b).abs() <= tol * b.abs(), "{key}: {a} against {b}");
    };
    close("period_frames", 1e-6);
    close("advance_down_cm", 1e-6);
    close("advance_across_cm", 1e-6);
    // trackpy: the body is particle 4 among a second particle that wanders; frame-major order.
    let mut text = String::from(",y,x,mass,frame,particle\n");
    for (i, (f, across, down)) in rows.iter().enumerate() {
        text += &format!("{},{across},{down},90,{f},4\n", 2 * i);
        text += &format!(
            "{},{},{},10,{f},9\n",
            2 * i + 1,
            (i % 7) as f64,
            (i % 5) as f64
        );
    }
    let trackpy = dir.join("linked.csv");
    std::fs::write(&trackpy, text).unwrap();
    refused(
        &trackpy,
        &none,
        &[],
        "pick the body's centre with --particle",
    );
    refused(&trackpy, &none, &["--particle", "5"], "has no particle 5");
    refused(&trackpy, &none, &["--particle", "4.5"], "whole number");
    let out = dir.join("trackpy");
    let o = track(&trackpy, &out, &["--particle", "4"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let got = summary(&out);
    assert_eq!(got["table"]["format"], "trackpy");
    assert_eq!(got["period_frames"], want["period_frames"]);
    assert_eq!(got["advance_down_cm"], want["advance_down_cm"]);
}

/// The printed sphere as the authors' generator makes it (seed 6, σ 0.25, l ≤ 4), without a
/// scale, written to `path`.
fn printed_sphere_shape(path: &Path) {
    rollphase_ok([
        "shape",
        "--dim",
        "3",
        "--paper-seed",
        "6",
        "--sigma",
        "0.25",
        "--modes",
        "4",
        "-o",
        path.to_str().unwrap(),
    ]);
}

fn refused(file: &Path, out: &Path, extra: &[&str], needle: &str) {
    let o = track(file, out, extra);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!o.status.success(), "{file:?} {extra:?} was accepted");
    assert!(err.contains(needle), "{extra:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        !out.join("summary.json").exists(),
        "a refused track wrote files"
    );
}

#[test]
fn tracks_without_a_period_or_with_bad_input_are_refused() {
    let dir = scratch("bad");
    let out = dir.join("out");
    // A random walk down the ramp repeats nothing.
    let mut state = 99u64;
    let mut walk = (0.0, 0.0);
    let rows: Vec<(f64, f64, f64)> = (0..1200)
        .map(|i| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
            let r1 = ((state >> 20) % 1000) as f64 / 1000.0 - 0.5;
            let r2 = ((state >> 40) % 1000) as f64 / 1000.0 - 0.5;
            walk = (walk.0 + 3.0 * r1, walk.1 + 1.0 + 3.0 * r2);
            (i as f64, walk.0, walk.1)
        })
        .collect();
    let p = dir.join("walk.csv");
    write_track(&p, &rows, &[]);
    refused(&p, &out, &[], "no period can be found with confidence");
    // It shows why: refused.png (the track and its mismatch at every shift), and nothing that
    // could pass for a run's results.
    let png = std::fs::read(out.join("refused.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    assert!(!out.join("figure.png").exists() && !out.join("data.csv").exists());
    let o = track(&p, &out, &[]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("refused.png"));
    std::fs::remove_file(out.join("refused.png")).unwrap();
    // A straight line at constant speed.
    let line: Vec<(f64, f64, f64)> = (0..600).map(|i| (i as f64, 0.0, i as f64)).collect();
    let p = dir.join("line.csv");
    write_track(&p, &line, &[]);
    refused(&p, &out, &[], "nothing repeats");
    // Too short for two periods of a 123-frame motion.
    let p = dir.join("short.csv");
    write_track(&p, &synthetic(200, 123.4, 160.0, 0.5), &[]);
    refused(&p, &out, &[], "period");
    // Frames out of order, named by row.
    let p = dir.join("order.csv");
    std::fs::write(&p, "frame,xn,yn\n1,0,0\n2,0,1\n2,0,2\n3,0,3\n").unwrap();
    refused(&p, &out, &[], "row 3");
    // Wrong columns: the ones there are listed.
    let p = dir.join("columns.csv");
    std::fs::write(&p, "t,x,y\n1,0,0\n").unwrap();
    refused(&p, &out, &[], "\"t\", \"x\", \"y\"");
    // Text in a number's place.
    let p = dir.join("text.csv");
    std::fs::write(&p, "frame,xn,yn\n1,0,zero\n").unwrap();
    refused(&p, &out, &[], "row 1, column \"yn\"");
    // Mostly missing.
    let p = dir.join("missing.csv");
    let rows = synthetic(600, 100.0, 100.0, 0.0);
    let mut text = String::from("frame,xn,yn\n");
    for (i, (f, x, y)) in rows.iter().enumerate() {
        if i % 3 == 0 {
            text += &format!("{f},nan,nan\n");
        } else {
            text += &format!("{f},{x},{y}\n");
        }
    }
    std::fs::write(&p, text).unwrap();
    refused(&p, &out, &[], "more than a fifth");
    // Devices, folders and bad flags, before any reading.
    let good = dir.join("good.csv");
    write_track(&good, &synthetic(1500, 123.4, 160.0, 1.0), &[]);
    refused(Path::new("/dev/zero"), &out, &[], "not a regular file");
    refused(&dir, &out, &[], "not a regular file");
    refused(&good, &out, &["--fps", "0"], "--fps");
    refused(&good, &out, &["--fps", "nan"], "--fps");
    refused(&good, &out, &["--scale", "1"], "--scale expects 2");
    refused(
        &good,
        &out,
        &["--scale", "0,1"],
        "--scale 0,1 is not allowed",
    );
    // The output folder is the input file: refused, the input untouched.
    let before = std::fs::read(&good).unwrap();
    let o = track(&good, &good, &[]);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&good).unwrap(), before);
    // A body without a scale cannot be compared in cm.
    let body = dir.join("body.json");
    printed_sphere_shape(&body);
    refused(
        &good,
        &out,
        &["--body", body.to_str().unwrap(), "--alpha", "0.2"],
        "scale_mm",
    );
}

/// The inertial regime end to end: the printed sphere's model run at m/m0 = 2.5 (the paper's
/// uncoated print), sin α = 0.2, ⟨r⟩ = 1 cm, filmed at 30 frames/s (t0 = √(⟨r⟩/(g·m/m0)), so
/// ≈ 20.5 frames a period, which the old search reported at twice the period or refused) with
/// 0.1 mm of noise, through `track --body`: the period comes back, and m/m0 and t0 solved
/// together from it give back 2.5 and its t0. The SI's speed estimate is reported beside them
/// (the main text's sin α form would be 5 times smaller).
#[test]
fn an_inertial_model_run_gives_back_its_mass_ratio_and_time_unit() {
    let dir = scratch("inertial");
    let alpha = 0.2f64.asin();
    let mass = 2.5;
    let t0 = (0.01f64 / (9.81 * mass)).sqrt();
    let film = crate::track_periods::filmed_orbit(mass, 60, 0.01, 5, 0..0);
    // Columns in the authors' units: xn across (0.0404 cm), yn down (0.0361 cm).
    let mut text = String::from("frame,xn,yn\n");
    for (i, down, across) in &film.rows {
        text += &format!("{i},{},{}\n", across / 0.0404, down / 0.0361);
    }
    let file = dir.join("inertial.csv");
    std::fs::write(&file, text).unwrap();
    let shape = dir.join("printed.json");
    printed_sphere_shape(&shape);
    let mut json: Value = serde_json::from_slice(&std::fs::read(&shape).unwrap()).unwrap();
    json["scale_mm"] = 10.0.into();
    std::fs::write(&shape, json.to_string()).unwrap();
    let out = dir.join("run");
    let alpha_text = alpha.to_string();
    let printed = rollphase_ok([
        "track",
        file.to_str().unwrap(),
        "--body",
        shape.to_str().unwrap(),
        "--alpha",
        &alpha_text,
        "--out",
        out.to_str().unwrap(),
    ]);
    eprintln!("{}", String::from_utf8_lossy(&printed));
    let s = summary(&out);
    let true_frames = film.true_frames;
    let period = s["period_frames"].as_f64().unwrap();
    assert!(
        (period - true_frames).abs() < 0.003 * true_frames,
        "{period} against {true_frames}"
    );
    let m = &s["model"];
    let solved = m["mass_ratio"].as_f64().unwrap();
    assert!((solved - mass).abs() < 0.02 * mass, "m/m0 {solved}");
    // Its stated error, the period's carried through the solve, holds the truth.
    let error = m["mass_ratio_error"].as_f64().unwrap();
    assert!(
        error > 0.0 && (solved - mass).abs() < 5.0 * error,
        "m/m0 {solved} ± {error}"
    );
    assert!((m["t0_s"].as_f64().unwrap() - t0).abs() < 0.01 * t0);
    // The model ran at the last iterate, within the solve's tolerance of the answer.
    assert!((m["mass_ratio_model"].as_f64().unwrap() - solved).abs() < 1e-3 * solved);
    assert!(m["advance_down_difference"].as_f64().unwrap().abs() < 0.01);
    assert!(m["speed_difference"].as_f64().unwrap().abs() < 0.01);
    // The SI's estimate: the right order (the body's shape aside), and sin²α, not sin α.
    let from_speed = m["mass_ratio_from_speed"].as_f64().unwrap();
    let speed_m_s = s["speed_cm_s"].as_f64().unwrap() / 100.0;
    assert!((from_speed - speed_m_s.powi(2) / (9.81 * 0.01 * 0.04)).abs() < 1e-9 * from_speed);
    assert!(from_speed > 0.5 && from_speed < 12.0, "{from_speed}");
}

/// The errors of m/m0 and t0 are the period's carried through the joint solve: its
/// sensitivity d ln(m/m0)/d ln T_s, read from the solve's own last steps, matches the finite
/// difference of whole solves at T_s(1 ± 1 %), viscous (−2 exactly) and inertial (the period
/// of the paper's sphere shortens with inertia, so the solve is not −2 there).
#[test]
fn the_mass_ratio_error_is_the_periods_carried_through_the_solve() {
    use rollphase::analysis::experiment::prediction::{PredictOptions, predict};
    use rollphase::analysis::experiment::tracking::model::{
        MassSource, Measured, compare_with_model,
    };
    use rollphase::geometry::Body;
    let body = Body::paper_sphere(219, 0.25, 5).unwrap();
    let options = PredictOptions {
        starts: 4,
        ..PredictOptions::default()
    };
    let orbit = predict(&body, 0.15, 0.0, &options).unwrap().orbits[0].clone();
    // t0 = 0.2 s gives m/m0 = 0.026 (viscous); t0 = 0.025 s gives about 1.6 (inertial).
    for t0 in [0.2, 0.025] {
        let solve = |factor: f64| {
            let measured = Measured {
                period_s: orbit.period * t0 * factor,
                advance_down_cm: orbit.advance_down,
                advance_across_cm: orbit.advance_across,
            };
            compare_with_model(&body, 10.0, 0.15, &measured, None, &options)
                .unwrap()
                .with_period_error(measured.period_s, 0.01 * measured.period_s)
        };
        let (centre, up, down) = (solve(1.0), solve(1.01), solve(1.0 / 1.01));
        let finite = (up.mass_ratio / down.mass_ratio).ln() / (1.01f64 * 1.01).ln();
        let stated = centre.period_sensitivity.unwrap();
        eprintln!(
            "t0 {t0}: m/m0 {} ± {:?} (model at {}), sensitivity {stated} against {finite}",
            centre.mass_ratio, centre.mass_ratio_error, centre.mass_ratio_model
        );
        assert!(
            (stated - finite).abs() < 0.03 * finite.abs(),
            "t0 {t0}: stated {stated}, whole solves {finite}"
        );
        let error = centre.mass_ratio_error.unwrap();
        assert!((error - 0.01 * stated.abs() * centre.mass_ratio).abs() < 1e-12 * error);
        assert!(
            (centre.t0_error_s.unwrap() - 0.5 * error / centre.mass_ratio * centre.t0_s).abs()
                < 1e-12
        );
    }
    // m/m0 = 0 asks for the viscous model: m/m0 is then the period's, not the user's (the JSON
    // said "given" for it), with the viscous model's exact sensitivity −2.
    let measured = Measured {
        period_s: orbit.period * 0.2,
        advance_down_cm: orbit.advance_down,
        advance_across_cm: orbit.advance_across,
    };
    let viscous = compare_with_model(&body, 10.0, 0.15, &measured, Some(0.0), &options).unwrap();
    assert_eq!(viscous.mass_ratio_from, MassSource::ViscousPeriod);
    assert_eq!(viscous.period_sensitivity, Some(-2.0));
    assert!((viscous.t0_s - 0.2).abs() < 1e-9, "t0 {}", viscous.t0_s);
    let given = compare_with_model(&body, 10.0, 0.15, &measured, Some(2.5), &options).unwrap();
    assert_eq!(
        (given.mass_ratio_from, given.mass_ratio),
        (MassSource::Given, 2.5)
    );
}
