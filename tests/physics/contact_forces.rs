//! The contact force (issue 34): exact against perfect bodies and the viscous limit, against the
//! force differenced from the sampled centre of mass (the hand method), the paper
//! sphere's table of lift-off and slip, and the command line's flags and refusals.

use std::path::PathBuf;

use crate::cli::rollphase;

use rollphase::dynamics::ContactForce;
use rollphase::geometry::{Body, Disk, Sphere};
use rollphase::glam::DVec3;
use rollphase::simulate::{
    ContactLimits, InitialState, Model, OnViolation, RunError, Simulation, Trajectory, Violation,
    simulate,
};

/// f = m a − F from the sampled centre by second differences, with N and |f_t|/N.
fn differenced(tr: &Trajectory, mass: f64, alpha: f64) -> Vec<(f64, f64, f64)> {
    let (t, com): (Vec<f64>, Vec<DVec3>) = match tr {
        Trajectory::Sphere(s) => (s.t.clone(), s.com.clone()),
        Trajectory::Disk(d) => (
            d.t.clone(),
            d.x.iter()
                .zip(&d.y)
                .map(|(x, y)| DVec3::new(*x, 0.0, *y))
                .collect(),
        ),
    };
    let h = t[1] - t[0];
    let gravity = DVec3::new(alpha.sin(), 0.0, -alpha.cos());
    (1..t.len() - 1)
        .map(|i| {
            let a = (com[i + 1] - 2.0 * com[i] + com[i - 1]) / (h * h);
            let f = mass * a - gravity;
            (t[i], f.z, f.x.hypot(f.y) / f.z)
        })
        .collect()
}

fn extremes(v: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    (
        v.clone().fold(f64::INFINITY, f64::min),
        v.fold(f64::NEG_INFINITY, f64::max),
    )
}

/// The table, on the paper sphere from the default start, t ≤ 100: the exact forces
/// agree with the differenced ones (to the differencing's own error, far below the 1e-3 asked),
/// and the summary's refined extremes and lift-off times are the table's.
#[test]
fn the_paper_sphere_table_matches_the_differenced_forces() {
    let body = Body::paper_sphere(219, 0.25, 5).unwrap();
    // α, m/m0, the min N, max N, max μ (when it stays on), lift-off time.
    let table = [
        (0.15, 1.0, 0.981, 1.017, Some(0.219), None),
        (0.15, 10.0, 0.941, 1.127, Some(0.211), None),
        (0.5, 10.0, 0.338, 2.314, Some(1.374), None),
        (0.5, 100.0, -0.127, 3.268, None, Some(75.0)),
        (1.0, 10.0, -1.267, 4.09, None, Some(20.2)),
    ];
    for (alpha, mass, n_min, n_max, mu, lift) in table {
        let sim = Simulation::new(alpha, 100.0)
            .model(Model::Inertial { mass_ratio: mass })
            .samples(50_001);
        let (tr, summary) = simulate(&body, &sim).unwrap();
        let c = summary
            .contact
            .expect("every run reports its contact force");
        let d = differenced(&tr, mass, alpha);
        // Sample by sample, exact against differenced (h = 0.002: error O(h²) a few 1e-5).
        for (x, f) in d.iter().zip(&tr.forces()[1..]) {
            assert!(
                (x.1 - f.normal).abs() < 1e-3,
                "{alpha} {mass} at t = {}",
                x.0
            );
        }
        let (dmin, dmax) = extremes(d.iter().map(|x| x.1));
        assert!(
            (c.min_normal_force - dmin).abs() < 1e-3,
            "{alpha} {mass}: {c:?}"
        );
        assert!(
            (c.max_normal_force - dmax).abs() < 1e-3,
            "{alpha} {mass}: {c:?}"
        );
        assert!(
            (c.min_normal_force - n_min).abs() < 1.5e-3,
            "{alpha} {mass}: {c:?}"
        );
        assert!(
            (c.max_normal_force - n_max).abs() < 1.5e-3,
            "{alpha} {mass}: {c:?}"
        );
        match (mu, lift) {
            (Some(mu), None) => {
                let (_, dmu) = extremes(d.iter().map(|x| x.2));
                assert!((c.max_friction_needed - dmu).abs() < 1e-3, "{c:?}");
                assert!((c.max_friction_needed - mu).abs() < 1.5e-3, "{c:?}");
                assert_eq!(c.lift_off_t, None);
            }
            (_, Some(t)) => {
                let t_diff = d.iter().find(|x| x.1 <= 0.0).unwrap().0;
                let found = c.lift_off_t.expect("lift-off");
                assert!((found - t_diff).abs() < 0.01, "{found} vs {t_diff}");
                assert!((found - t).abs() < 0.05, "{found} vs the issue's {t}");
                assert!(c.max_friction_needed.is_infinite());
                assert!(summary.validity_warnings()[0].contains("leaves the ramp"));
            }
            _ => unreachable!(),
        }
    }
}

/// The disk's force comes from different formulas (the θ-derivatives of the centre); it is
/// checked the same way.
#[test]
fn the_disk_force_matches_the_differenced_force() {
    let body = Body::paper_disk(219, 0.25, 5).unwrap();
    for (alpha, mass) in [(0.3, 2.0), (0.8, 20.0)] {
        let sim = Simulation::new(alpha, 60.0)
            .model(Model::Inertial { mass_ratio: mass })
            .samples(30_001);
        let (tr, summary) = simulate(&body, &sim).unwrap();
        let d = differenced(&tr, mass, alpha);
        let worst = d
            .iter()
            .zip(&tr.forces()[1..])
            .map(|(x, f)| (x.1 - f.normal).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-4, "{alpha} {mass}: {worst}");
        let (dmin, _) = extremes(d.iter().map(|x| x.1));
        let c = summary.contact.unwrap();
        assert!((c.min_normal_force - dmin).abs() < 1e-3, "{c:?} vs {dmin}");
        assert!(c.max_normal_force > c.min_normal_force);
    }
}

/// Exact results: a uniform disk or ball rolling freely (no drag) from rest is held back by
/// F sin α/3 or 2F sin α/7 and pressed by F cos α at every instant; with drag, at its terminal
/// speed, the ramp holds back the whole pull F sin α; the viscous models need tan α throughout.
#[test]
fn perfect_bodies_and_the_viscous_limit_have_exact_forces() {
    let alpha: f64 = 0.4;
    for (body, share) in [
        (Body::Disk(Disk::perfect()), 1.0 / 3.0),
        (Body::Sphere(Sphere::perfect()), 2.0 / 7.0),
    ] {
        let free = Simulation::new(alpha, 20.0)
            .model(Model::Inertial { mass_ratio: 3.0 })
            .drag(0.0)
            .samples(21);
        let (tr, s) = simulate(&body, &free).unwrap();
        for f in tr.forces() {
            assert!((f.normal - alpha.cos()).abs() < 1e-12, "{f:?}");
            assert!((f.friction[0] + share * alpha.sin()).abs() < 1e-12, "{f:?}");
            assert!(f.friction[1].abs() < 1e-12);
        }
        let c = s.contact.unwrap();
        assert!((c.max_friction_needed - share * alpha.tan()).abs() < 1e-12);
        // With drag: from rest it speeds up to terminal, where f = −F.
        let dragged = Simulation::new(alpha, 80.0)
            .model(Model::Inertial { mass_ratio: 3.0 })
            .samples(2);
        let (tr, _) = simulate(&body, &dragged).unwrap();
        let last = tr.forces()[1];
        assert!((last.friction[0] + alpha.sin()).abs() < 1e-8, "{last:?}");
        assert!((last.friction_needed() - alpha.tan()).abs() < 1e-8);
        // Viscous: −F exactly, at every sample.
        let (tr, s) = simulate(&body, &Simulation::new(alpha, 5.0).samples(6)).unwrap();
        assert!(
            tr.forces()
                .iter()
                .all(|f| *f == ContactForce::viscous(alpha))
        );
        assert_eq!(s.contact.unwrap().max_friction_needed, alpha.tan());
    }
}

/// `OnViolation::Stop` ends the run at the first violation with its time; `Warn` runs to the
/// end and reports both.
#[test]
fn stop_and_warn_policies() {
    let body = Body::paper_sphere(219, 0.25, 5).unwrap();
    let heavy = Simulation::new(1.0, 40.0).model(Model::Inertial { mass_ratio: 10.0 });
    let stop = ContactLimits {
        friction: None,
        on_violation: OnViolation::Stop,
    };
    match simulate(&body, &heavy.limits(stop)) {
        Err(RunError::LeftModel {
            violation: Violation::LiftOff { t },
            report,
        }) => {
            assert!((t - 20.207).abs() < 0.01, "{t}");
            assert!(report.min_normal_force <= 0.0);
        }
        other => panic!("{other:?}"),
    }
    // μ = 1 on the same run: it slips long before it leaves the ramp.
    let rough = ContactLimits {
        friction: Some(1.0),
        on_violation: OnViolation::Warn,
    };
    let (_, s) = simulate(&body, &heavy.limits(rough)).unwrap();
    let c = s.contact.unwrap();
    let slip = c.slip_t.expect("slips");
    assert!(slip < c.lift_off_t.unwrap());
    let w = s.validity_warnings();
    assert_eq!(w.len(), 2);
    assert!(w[0].starts_with("slips at t") && w[1].starts_with("leaves the ramp"));
    // A disk's start given away from rest: the check starts at t = 0.
    let disk = Body::paper_disk(219, 0.25, 5).unwrap();
    let spinning = Simulation::new(0.3, 5.0)
        .model(Model::Inertial { mass_ratio: 50.0 })
        .initial(InitialState::Disk {
            theta0: 0.0,
            theta_dot0: 3.0,
        });
    let (_, s) = simulate(&disk, &spinning).unwrap();
    assert!(s.contact.unwrap().min_normal_force.is_finite());
}

fn temp_dir(name: &str) -> PathBuf {
    let d = crate::cli::scratch(&format!("forces-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn simulate_reports_and_writes_the_forces() {
    let dir = temp_dir("cli");
    let shape = dir.join("sphere.json");
    let s = rollphase([
        "shape",
        "--dim",
        "3",
        "--paper-seed",
        "219",
        "-o",
        shape.to_str().unwrap(),
    ]);
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    let csv = dir.join("run.csv");
    let summary = dir.join("summary.json");
    let base = [
        "simulate",
        shape.to_str().unwrap(),
        "--alpha",
        "1.0",
        "--mass",
        "10",
        "--t-end",
        "30",
        "--samples",
        "301",
    ];
    // Warn (the default): exit 0, the CSV written, the warning on stderr and in the summary.
    let mut args = base.to_vec();
    args.extend([
        "--forces",
        "-o",
        csv.to_str().unwrap(),
        "--summary",
        summary.to_str().unwrap(),
    ]);
    let out = rollphase(&args);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("warning: the body leaves the ramp at t = 20.2"),
        "{err}"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let header = text.lines().next().unwrap();
    assert!(header.ends_with(",z,normal_force,friction_x,friction_y,friction_needed"));
    assert!(text.contains(",inf"), "friction_needed is inf once N ≤ 0");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    assert!((json["lift_off_t"].as_f64().unwrap() - 20.207).abs() < 0.01);
    assert!(json["min_normal_force"].as_f64().unwrap() < 0.0);
    // Without --forces the CSV keeps its model columns.
    let mut args = base.to_vec();
    args.extend(["-o", csv.to_str().unwrap()]);
    assert!(rollphase(&args).status.success());
    let header = std::fs::read_to_string(&csv).unwrap();
    assert!(header.lines().next().unwrap().ends_with(",x,y,z"));
    // Stop: exit 1 naming the time and the force; the CSV is left as it was.
    let before = std::fs::read(&csv).unwrap();
    let mut args = base.to_vec();
    args.extend(["--on-invalid", "stop", "-o", csv.to_str().unwrap()]);
    let out = rollphase(&args);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("leaves the ramp at t = 20.2"), "{err}");
    assert!(err.contains("N/F from"), "{err}");
    assert_eq!(std::fs::read(&csv).unwrap(), before);
    // A slip needs a μ: with one it is timed.
    let mut args = base.to_vec();
    args.extend(["--friction", "0.5", "--on-invalid", "stop", "-o", "-"]);
    let out = rollphase(&args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("slips at t = ") && err.contains("μ = 0.5"),
        "{err}"
    );
    // Bad μ: refused before the run, naming the flag.
    for bad in ["nan", "-0.1", "inf"] {
        let mut args = base.to_vec();
        let flag = format!("--friction={bad}");
        args.push(&flag);
        let out = rollphase(&args);
        assert_eq!(out.status.code(), Some(1), "{bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("--friction") && err.contains("mu ≥ 0"),
            "{err}"
        );
        assert!(out.stdout.is_empty());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Watching the force does not move the run: `settle_checked` (which watches) and
/// `settle_with` (which does not) give the same crossings, bit for bit, on an inertial run of
/// the paper's body. (The watch's contact look-ups leave the integrator's Newton warm start
/// alone; when they moved it, two of 216 fast sweep answers changed in their last bits.)
#[test]
fn watching_the_force_leaves_the_trajectory_bit_for_bit() {
    use rollphase::analysis::orbits::sphere_orbits::{Settle, settle_checked, settle_with};
    use rollphase::analysis::studies::sphere::random_orientation;
    use rollphase::dynamics::Ramp;
    use rollphase::integrate::Method;
    let Body::Sphere(sphere) = Body::paper_sphere(219, 0.25, 5).unwrap() else {
        unreachable!()
    };
    let ramp = Ramp::new(0.2, 1.0).unwrap();
    let settle = Settle {
        t_max: 600.0,
        ..Settle::default()
    };
    for o in 0..3 {
        let q0 = random_orientation(&sphere, 1, o);
        let method = Method::dop853(settle.rtol);
        let (fate, crossings, _) = settle_with(&sphere, &ramp, q0, &settle, method).unwrap();
        let watched = settle_checked(&sphere, &ramp, q0, &settle, method).unwrap();
        assert_eq!(watched.fate, fate);
        assert_eq!(watched.crossings, crossings);
        assert!(watched.contact.min_normal_force > 0.0);
    }
}

/// `simulate`'s summary says what became of the body in the verdict's words, and claims only
/// what the run shows: a lift-off first, a rest only where the body is still and unpushed, and
/// otherwise undecided (a fixed-time run does not look for a cycle).
#[test]
fn a_simulated_run_states_its_fate_from_its_evidence_alone() {
    use rollphase::analysis::verdict::{Fate, Undecided};
    let sphere = Body::paper_sphere(219, 0.25, 5).unwrap();
    // Below α* a viscous body creeps to rest, and is halted from a sampled time on.
    let (_, s) = simulate(&sphere, &Simulation::new(0.05, 400.0).samples(401)).unwrap();
    assert!(
        matches!(s.fate, Fate::Halted { t: Some(t) } if t > 0.0 && t <= 400.0),
        "{:?}",
        s.fate
    );
    // Above it, rolling at the end: undecided, with how far from rest it is.
    let (_, s) = simulate(&sphere, &Simulation::new(0.3, 100.0).samples(11)).unwrap();
    assert!(
        matches!(s.fate, Fate::Undecided { why: Undecided::NotSettled { t_end, from_rest } }
            if t_end == 100.0 && from_rest > 0.01),
        "{:?}",
        s.fate
    );
    // A body too heavy to have sped up yet is still at t = 0 and pushed: never halted.
    let heavy = Simulation::new(0.3, 5.0)
        .samples(6)
        .model(Model::Inertial { mass_ratio: 1e10 });
    let (_, s) = simulate(&sphere, &heavy).unwrap();
    assert_eq!(s.fate.name(), "undecided", "{:?}", s.fate);
    // Heavy on a steep ramp it bounces off: left_model, with the lift-off's time, whatever the
    // model does after it.
    let steep = Simulation::new(1.0, 40.0).model(Model::Inertial { mass_ratio: 10.0 });
    let (_, s) = simulate(&sphere, &steep).unwrap();
    match s.fate {
        Fate::LeftModel {
            violation: Violation::LiftOff { t },
        } => assert_eq!(Some(t), s.contact.unwrap().lift_off_t),
        other => panic!("{other:?}"),
    }
    // A perfect disk rolls forever: undecided, never halted.
    let disk = Body::Disk(Disk::perfect());
    let (_, s) = simulate(&disk, &Simulation::new(0.2, 50.0).samples(6)).unwrap();
    assert_eq!(s.fate.name(), "undecided");
}

/// The studies' lift-off-only watch (`ContactWatch::lift_off_only`, behind `decided_run`) times
/// a lift-off as the full watch of `simulate` does on the same steps, with fewer force
/// evaluations.
#[test]
fn the_lift_off_only_watch_times_the_lift_off_as_the_full_watch_does() {
    use rollphase::analysis::orbits::sphere_orbits::{Decide, decided_run};
    use rollphase::dynamics::Ramp;
    use rollphase::glam::DQuat;
    use rollphase::integrate::Method;
    let body = Body::paper_sphere(219, 0.25, 5).unwrap();
    let Body::Sphere(sphere) = &body else {
        unreachable!()
    };
    let mut lifted = 0;
    for (alpha, mass) in [(1.0, 10.0), (0.5, 300.0), (0.2014, 300.0), (0.15, 1.0)] {
        let rtol = 1e-10;
        let sim = Simulation::new(alpha, 300.0)
            .samples(2)
            .model(Model::Inertial { mass_ratio: mass })
            .initial(InitialState::Sphere {
                q0: DQuat::IDENTITY,
                omega0: DVec3::ZERO,
            })
            .method(Method::dop853(rtol));
        let (_, summary) = simulate(&body, &sim).unwrap();
        let full = summary.contact.unwrap().lift_off_t;
        let decide = Decide {
            t_min: 300.0,
            t_cap: 300.0,
            max_k: 0,
            tol: 0.0,
        };
        let ramp = Ramp::new(alpha, mass).unwrap();
        let run =
            decided_run(sphere, &ramp, DQuat::IDENTITY, &decide, (0.0, 0.0, 0), rtol).unwrap();
        let cheap = run.contact.unwrap().lift_off_t;
        match (full, cheap) {
            (Some(a), Some(b)) => assert!(
                (a - b).abs() < 1e-9,
                "α = {alpha}, m/m0 = {mass}: {a} vs {b}"
            ),
            (None, None) => {}
            other => panic!("α = {alpha}, m/m0 = {mass}: {other:?}"),
        }
        assert_eq!(run.left_model(), full.is_some());
        lifted += usize::from(full.is_some());
    }
    assert!(lifted >= 2, "{lifted} of the runs left the ramp");
}
