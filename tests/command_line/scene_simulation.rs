//! What the renderer is given is physically right: the drawn contact point lies on the ramp
//! under the drawn body; perfect bodies roll with the exact period 2π/sin α; the SO(3) path
//! never draws a chord through the ball; the same scene gives the same snapshot on every run.

use std::f64::consts::TAU;

use glam::DVec3;
use rollphase::live::LiveRun;
use rollphase::scene::Scene;

fn sim(toml: &str) -> LiveRun {
    LiveRun::new(Scene::from_toml(toml).unwrap().setup(None).unwrap())
}

fn preset(name: &str) -> LiveRun {
    LiveRun::new(Scene::preset(name).unwrap().setup(None).unwrap())
}

/// Contact = centre + R · (contact in the body frame), on the plane z = 0.
fn check_contact(s: &LiveRun, tol: f64) {
    let snap = s.snapshot();
    let drawn = snap.pose.centre + snap.pose.rotation * snap.contact_in_body;
    assert!(
        (drawn - snap.contact_on_ramp).length() < tol,
        "{}: drawn contact {drawn:?} vs {:?} at t = {}",
        s.setup().scene.name,
        snap.contact_on_ramp,
        snap.t
    );
    assert_eq!(snap.contact_on_ramp.z, 0.0);
}

#[test]
fn the_drawn_contact_point_is_under_the_drawn_body() {
    for name in [
        "sphere-cruising",
        "sphere-doubling",
        "cylinder-near-critical",
        "cylinder-hysteresis",
    ] {
        let mut s = preset(name);
        for t in [0.0, 3.3, 17.0, 41.5] {
            s.advance_to(t).unwrap();
            check_contact(&s, 1e-9);
        }
    }
}

#[test]
fn perfect_bodies_roll_with_period_two_pi_over_sin_alpha() {
    // Sphere: ω = r × F = sin α about a fixed axis, so q_w = 0 every 2π/sin α.
    // Disk: one full turn of θ every 2π/sin α.
    for body in ["sphere", "disk"] {
        let views = if body == "sphere" {
            "[views]\nball = true\n"
        } else {
            ""
        };
        let toml = format!(
            "name = \"p\"\n[body]\nperfect = \"{body}\"\n[model]\nalpha_rad = 0.4\n[integrator]\npreset = \"precise\"\n{views}"
        );
        let mut s = sim(&toml);
        let exact = TAU / 0.4f64.sin();
        s.advance_to(3.5 * exact).unwrap();
        let t = s.snapshot().period.expect("period measured");
        assert!(
            (t - exact).abs() < 1e-8 * exact,
            "{body}: T = {t}, exact {exact}"
        );
        check_contact(&s, 1e-9);
    }
}

#[test]
fn the_ball_path_breaks_at_antipodal_jumps_instead_of_crossing_the_ball() {
    let mut s = preset("sphere-cruising");
    s.advance_to(120.0).unwrap();
    let snap = s.snapshot();
    assert!(
        snap.ball_trail.len() >= 2,
        "the 60-unit trail crosses ∂Ω at least once"
    );
    for piece in &snap.ball_trail {
        for w in piece.windows(2) {
            assert!((w[0] - w[1]).length() < 0.2, "a chord through the ball");
        }
        assert!(piece.iter().all(|p| p.length() <= 1.0 + 1e-12));
    }
    let q = snap.pose.rotation;
    let point = snap.ball_point.unwrap();
    let expected = if q.w < 0.0 {
        -DVec3::new(q.x, q.y, q.z)
    } else {
        DVec3::new(q.x, q.y, q.z)
    };
    assert!((point - expected).length() < 1e-12);
}

#[test]
fn a_scene_computes_only_what_its_views_show() {
    let mut s = preset("cylinder-near-critical");
    s.advance_to(10.0).unwrap();
    assert!(s.snapshot().ball_trail.is_empty() && s.snapshot().ball_point.is_none());
    let toml = "name = \"p\"\n[body]\nperfect = \"sphere\"\n[model]\nalpha_rad = 0.4\n[views]\nball = false\n";
    let mut s = sim(toml);
    s.advance_to(10.0).unwrap();
    assert!(s.snapshot().ball_trail.is_empty());
}

#[test]
fn the_same_scene_gives_the_same_snapshot() {
    let run = || {
        let mut s = preset("sphere-doubling");
        for k in 0..40 {
            s.advance_to(s.setup().frame_time(k)).unwrap();
        }
        s.snapshot()
    };
    assert_eq!(run(), run());
}

#[test]
fn the_heavy_cylinder_keeps_rolling_below_alpha_star_and_a_light_one_halts() {
    let mut heavy = preset("cylinder-hysteresis");
    heavy.advance_to(400.0).unwrap();
    let snap = heavy.snapshot();
    assert!(snap.alpha_rad < snap.alpha_star);
    assert!(
        !snap.halted && snap.period.is_some(),
        "the heavy disk rolls on"
    );
    let toml = Scene::preset("cylinder-hysteresis")
        .unwrap()
        .to_toml()
        .unwrap()
        .replace("mass_ratio = 10.0", "mass_ratio = 0.0");
    let mut light = sim(&toml);
    light.advance_to(400.0).unwrap();
    assert!(light.snapshot().halted, "the viscous disk halts below α*");
}

#[test]
fn changing_alpha_live_keeps_the_pose() {
    let mut s = preset("sphere-cruising");
    s.advance_to(5.0).unwrap();
    let before = s.snapshot();
    let ramp = rollphase::dynamics::Ramp::new(0.5, 0.0).unwrap();
    s.set_parameters(ramp, s.method()).unwrap();
    let after = s.snapshot();
    assert_eq!(before.pose, after.pose);
    assert_eq!(after.alpha_rad, 0.5);
    s.advance_to(6.0).unwrap();
    check_contact(&s, 1e-9);
}

#[test]
fn the_doubling_preset_shows_period_two_and_its_trail_covers_both_loops() {
    // The paper's body at α = 0.15, m/m0 = 6: by the preset's first frame the ∂Ω crossings
    // alternate between two points (period 2), and the trail kept on the body spans more than one
    // whole doubled cycle (two crossings of ∂Ω).
    let mut s = preset("sphere-doubling");
    let start = s.setup().scene.playback.start_time;
    s.advance_to(start).unwrap();
    let snap = s.snapshot();
    assert_eq!(snap.period_multiplicity, Some(2), "at t = {start}");
    let turn = snap.period.expect("crossings measured");
    assert!(
        s.setup().scene.playback.trail_time > 2.0 * turn,
        "turn {turn}"
    );
    assert_eq!(
        snap.cycle_crossings.len(),
        5,
        "a doubled cycle is decided by 2k + 1 crossings"
    );
    // Its T is the whole cycle, two crossings (44.19 + 45.15), whichever crossing came last: a
    // helper found "T = 44.188" at one frame count and "T = 45.143" at another.
    let cycle = snap.cycle_period.unwrap();
    assert!((cycle - 89.33).abs() < 0.01, "{cycle}");
    let crossing = snap.cycle_crossings[4].0 - snap.cycle_crossings[3].0;
    s.advance_to(start + crossing * 0.5 + 25.0).unwrap();
    let later = s.snapshot();
    assert_ne!(later.period, snap.period, "the last crossing alternates");
    assert_eq!(later.fate(), format!("periodic: period 2, T = {cycle:.3}"));
    assert_eq!(snap.fate(), later.fate());
}

#[test]
fn one_snapshot_of_a_doubled_cycle_puts_both_branches_in_the_crossings_plot() {
    // A headless render of a few frames feeds the plot one snapshot per frame, several
    // crossings apart: the plot must show both of the cycle's points, as the verdict says.
    let mut s = preset("sphere-doubling");
    let start = s.setup().scene.playback.start_time;
    s.advance_to(start).unwrap();
    let snap = s.snapshot();
    assert_eq!(snap.period_multiplicity, Some(2));
    let mut history = rollphase::live::history::PlotHistory::default();
    history.push(&snap);
    let regime = rollphase::live::history::Regime::of(&snap);
    let mut branches = history.checkpoint().crossings_at(&regime);
    branches.sort_by(f64::total_cmp);
    assert_eq!(branches.len(), 2, "{branches:?}");
    assert!(branches[1] - branches[0] > 0.05, "{branches:?}");
    // The same snapshot again adds nothing.
    history.push(&snap);
    assert_eq!(history.checkpoint().crossings_at(&regime).len(), 2);
}

#[test]
fn the_flip_preset_starts_below_the_flip_with_period_one() {
    // m/m0 = 2.5 lies below both flips (3.15 and 3.99, `figure sphere-bifurcation`).
    let mut s = preset("sphere-flip");
    s.advance_to(s.setup().scene.playback.start_time).unwrap();
    assert_eq!(s.snapshot().period_multiplicity, Some(1));
}

#[test]
fn a_fixed_step_too_coarse_stops_the_run_with_a_red_overlay_line() {
    // CF4 keeps |q| = 1 exactly, so at dt = 5 every health number stays at round-off while the
    // orbit is wrong by radians; the step-doubling check stops it and says why.
    let mut s = sim(
        // (Played at 150 time units a second, so that a frame, 5 time units, holds the step.)
        "name = \"coarse\"\n[body]\nrandom = { dimension = 3, seed = 1, sigma = 0.25 }\n[model]\nalpha_rad = 0.3\n[integrator]\nmethod = \"cf4\"\ndt = 5.0\n[playback]\nspeed = 150.0\n",
    );
    let e = s.advance_to(100.0).unwrap_err().to_string();
    assert!(e.contains("too coarse") && e.contains("dt = 5"), "{e}");
    let stopped = s.snapshot().stopped.expect("the overlay says why");
    assert!(
        stopped.starts_with("STOPPED: CF4 dt 5 too coarse") && stopped.contains("use dt ≤"),
        "{stopped}"
    );
    // A step the accuracy table accepts runs and says nothing.
    let mut fine = sim(
        "name = \"fine\"\n[body]\nrandom = { dimension = 3, seed = 1, sigma = 0.25 }\n[model]\nalpha_rad = 0.3\n[integrator]\nmethod = \"cf4\"\ndt = 0.2\n[playback]\nspeed = 150.0\n",
    );
    fine.advance_to(100.0).unwrap();
    assert_eq!(fine.snapshot().stopped, None);
}

/// Which Poincaré field is wanted is decided by the simulation, once, for the app and the
/// headless frames: the field of the current viscous ramp when the view is on, none for a
/// cylinder or with the view off, and "needs the viscous model" with inertia.
#[test]
fn the_simulation_says_which_poincare_field_is_wanted() {
    use rollphase::dynamics::Ramp;
    use rollphase::live::FieldWanted;
    let mut s = preset("poincare-field");
    let ramp = s.ramp();
    assert_eq!(s.snapshot().poincare_field, FieldWanted::Ramp(ramp));
    // A new α makes the field drawn for the old one stale: the wanted ramp changes with it.
    let steeper = Ramp::with_drag(ramp.alpha_rad + 0.01, 0.0, ramp.drag).unwrap();
    s.set_parameters(steeper, s.method()).unwrap();
    assert_eq!(s.snapshot().poincare_field, FieldWanted::Ramp(steeper));
    let heavy = Ramp::with_drag(ramp.alpha_rad, 2.0, ramp.drag).unwrap();
    s.set_parameters(heavy, s.method()).unwrap();
    assert_eq!(s.snapshot().poincare_field, FieldWanted::NeedsViscous);
    let mut views = s.snapshot().views;
    views.poincare = false;
    s.set_views(&views);
    assert_eq!(s.snapshot().poincare_field, FieldWanted::Off);
    let mut cylinder = preset("cylinder-near-critical");
    let mut views = cylinder.snapshot().views;
    views.poincare = true;
    cylinder.set_views(&views);
    assert_eq!(cylinder.snapshot().poincare_field, FieldWanted::Off);
}

/// The app's simulation follows the exact contact force: a heavy body on a steep ramp first
/// needs more friction than the scene's surface gives, then would leave the ramp; the overlay
/// line says so from that moment, and changing the parameters starts the check afresh.
#[test]
fn a_scene_says_when_its_motion_stops_being_rollable() {
    let toml = "name = \"steep\"\n[body]\nshape = \"../shapes/paper-sphere.json\"\n\
                [model]\nalpha_rad = 1.0\nmass_ratio = 10.0\nfriction = 1.0\n";
    let scene = Scene::from_toml(toml).unwrap();
    let base = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let mut s = LiveRun::new(scene.setup(Some(&base)).unwrap());
    s.advance_to(2.0).unwrap();
    assert_eq!(s.snapshot().validity, None, "rolls at first");
    s.advance_to(25.0).unwrap();
    let snap = s.snapshot();
    let line = snap.validity.expect("flagged");
    // It slips first (t ≈ 8.0); the friction needed then grows without bound towards the
    // lift-off, so the line names the surface's μ rather than a number.
    assert!(
        line.starts_with("slips at t = 8.0") && line.contains("μ = 1"),
        "{line}"
    );
    assert!((snap.contact.lift_off_t.unwrap() - 20.207).abs() < 0.01);
    // The same motion as `simulate`: the first lift-off at t ≈ 20.2 (issue 34's table).
    assert!(snap.contact.min_normal_force < 0.0);
    // Changing the parameters is a new regime: checked afresh from there.
    let ramp = rollphase::dynamics::Ramp::new(0.15, 1.0).unwrap();
    s.set_parameters(ramp, s.method()).unwrap();
    assert_eq!(s.snapshot().validity, None);
    // A bad μ is refused with the field's name.
    let bad = toml.replace("friction = 1.0", "friction = -0.5");
    let e = Scene::from_toml(&bad)
        .unwrap()
        .setup(Some(&base))
        .unwrap_err();
    assert!(e.to_string().contains("model.friction"), "{e}");
}

/// A dented cylinder in the app rolls on its hull as `simulate` rolls it: it tips across a flat
/// (the overlay counts the tip and its energy), the drawn contact stays under the drawn body
/// through the tip, and its θ matches the command line's run.
#[test]
fn a_dented_cylinder_tips_across_its_flats_in_the_app_as_in_simulate() {
    use rollphase::geometry::Body;
    use rollphase::simulate::{InitialState, Model, Simulation as Run, Trajectory, simulate};
    let dir = crate::cli::scratch("dented-scene");
    std::fs::create_dir_all(&dir).unwrap();
    let body = Body::paper_disk(219, 0.5, 9).unwrap();
    std::fs::write(dir.join("printed.json"), body.to_shape().to_json().unwrap()).unwrap();
    let toml = "name = \"dented\"\n[body]\nshape = \"printed.json\"\n[model]\nalpha_rad = 0.3\n\
                mass_ratio = 2.0\n[initial]\ntheta0 = 5.7\n[integrator]\npreset = \"precise\"\n";
    let mut s = LiveRun::new(Scene::from_toml(toml).unwrap().setup(Some(&dir)).unwrap());
    assert_eq!(s.snapshot().hull_tips, Some((0, 0.0)));
    for t in [1.0, 3.4, 3.55, 3.7, 6.0] {
        s.advance_to(t).unwrap();
        check_contact(&s, 1e-9);
    }
    let snap = s.snapshot();
    let (tips, lost) = snap.hull_tips.unwrap();
    assert_eq!(tips, 1);
    assert!(lost > 0.0);
    // The scene's run on the command line's side, to `t_end` in `samples` rows.
    let on_the_command_line = |t_end: f64, samples: usize| {
        let run = Run::new(0.3, t_end)
            .model(Model::Inertial { mass_ratio: 2.0 })
            .samples(samples)
            .initial(InitialState::Disk {
                theta0: 5.7,
                theta_dot0: 0.0,
            });
        let (tr, summary) = simulate(&body, &run).unwrap();
        let Trajectory::Disk(d) = tr else {
            unreachable!()
        };
        (d, summary)
    };
    let (d, summary) = on_the_command_line(6.0, 2);
    assert_eq!(summary.hull.unwrap().tips, 1);
    assert!(
        (snap.theta.unwrap() - d.theta[1]).abs() < 1e-7,
        "{:?} vs {}",
        snap.theta,
        d.theta[1]
    );
    // Its flat spans θ = 0 mod 2π, so every full turn is made by a tip across it: the period
    // (time between turns) is still measured, and is the time the command line's run takes
    // for θ to advance by 2π.
    s.advance_to(200.0).unwrap();
    let period = s
        .snapshot()
        .period
        .expect("turns are counted across the flat");
    let (d, _) = on_the_command_line(200.0, 200_001);
    let turn = |k: f64| {
        let target = 5.7 + k * std::f64::consts::TAU;
        d.t[d.theta.iter().position(|&th| th >= target).unwrap()]
    };
    let turns = ((d.theta[d.theta.len() - 1] - 5.7) / std::f64::consts::TAU).floor();
    let last = turn(turns) - turn(turns - 1.0);
    assert!(
        (period - last).abs() < 2e-3 * last,
        "app {period} vs simulate {last}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A saved state (`[resume]`) goes on where the run was: the same time and state vector, and
/// from there the same motion as the run that was never stopped (to the integrator's
/// tolerance: the resumed run starts its step-size control afresh).
#[test]
fn a_saved_state_goes_on_where_the_run_was() {
    for name in [
        "sphere-cruising",
        "sphere-doubling",
        "cylinder-near-critical",
        "cylinder-hysteresis",
    ] {
        let mut run = preset(name);
        run.advance_to(37.5).unwrap();
        let snap = run.snapshot();
        let mut scene = Scene::preset(name).unwrap();
        scene.resume = Some(rollphase::scene::ResumeSpec {
            t: snap.t,
            state: snap.state.clone(),
            ..Default::default()
        });
        let text = scene.to_toml().unwrap();
        let mut resumed = sim(&text);
        assert_eq!(resumed.time(), 37.5, "{name}");
        assert_eq!(resumed.state().vector(), run.state().vector(), "{name}");
        // A headless render of it starts there too (or at the scene's start_time, if later).
        let start_time = resumed.setup().scene.playback.start_time;
        assert_eq!(
            resumed.setup().frame_time(0),
            start_time.max(37.5),
            "{name}"
        );
        run.advance_to(60.0).unwrap();
        resumed.advance_to(60.0).unwrap();
        let (a, b) = (run.state().vector(), resumed.state().vector());
        let gap = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(gap < 1e-5, "{name}: {a:?} vs {b:?}");
        // Reset goes back to the saved state, not to the scene's own start.
        let again = resumed.restarted();
        assert_eq!(again.time(), 37.5, "{name}");
    }
}

/// A `[resume]` that does not fit the scene is refused with the key and the reason.
#[test]
fn a_bad_saved_state_is_refused_with_what_is_wrong() {
    let base = Scene::preset("sphere-cruising").unwrap().to_toml().unwrap();
    let unit = "[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]";
    for (resume, expected) in [
        ("t = 5.0\nstate = [1.0, 0.0]".to_string(), "resume.state"),
        (
            "t = 5.0\nstate = [1.0, 0.0, 0.0, 0.0, nan, 0.0]".to_string(),
            "not a finite number",
        ),
        (
            "t = 5.0\nstate = [2.0, 0.0, 0.0, 0.0, 0.0, 0.0]".to_string(),
            "has length 2",
        ),
        (format!("t = -1.0\nstate = {unit}"), "resume.t = -1"),
        (format!("t = inf\nstate = {unit}"), "resume.t = inf"),
        (
            format!("t = 1.0\nstate = {unit}\nalpha_sweep = [[0.2, 0.01, 0.0, 0.5]]"),
            "resume.alpha_sweep[0]",
        ),
        (
            format!("t = 1.0\nstate = {unit}\ncrossings = [[1.0, nan]]"),
            "resume.crossings[0]",
        ),
        // Points no run could have measured (a helper's, 2026-12-02: accepted, then written to
        // --plot-data): α past π/2, α = 1e300, m/m0 < 0, a polar angle past π.
        (
            format!("t = 1.0\nstate = {unit}\nalpha_sweep = [[2.0, 0.01, 0.0, 1.0]]"),
            "α in [1e-9, π/2)",
        ),
        (
            format!("t = 1.0\nstate = {unit}\nalpha_sweep = [[1e300, 1e300, 1e300, 1.0]]"),
            "resume.alpha_sweep[0]",
        ),
        (
            format!("t = 1.0\nstate = {unit}\ncrossings = [[1.0, 0.5], [-1.0, 1.17]]"),
            "resume.crossings[1]",
        ),
        (
            format!("t = 1.0\nstate = {unit}\ncrossings = [[1.0, 100.0]]"),
            "a polar angle from 0 to π",
        ),
        (
            format!("t = 1.0\nstate = {unit}\nspeed = 3.0"),
            "unknown field",
        ),
        // A number too many is refused, not cut off (a helper's, 2026-12-03).
        (
            format!("t = 1.0\nstate = {unit}\nalpha_sweep = [[0.25, 0.1, 0.0, 1.0, 5.0]]"),
            "point 0 has 5 numbers, not 4",
        ),
        (
            format!("t = 1.0\nstate = {unit}\ncrossings = [[4.5, 1.1], [4.5, 1.1, 7.0]]"),
            "point 1 has 3 numbers, not 2",
        ),
    ] {
        let text = format!("{base}\n[resume]\n{resume}\n");
        let err = match Scene::from_toml(&text) {
            Err(e) => e.to_string(),
            Ok(scene) => scene.setup(None).unwrap_err().to_string(),
        };
        assert!(err.contains(expected), "{resume}: {err}");
    }
    // More crossings than the plot keeps are refused, not silently cut to the newest 5000.
    let many = vec!["[1.0, 0.5]"; 5001].join(", ");
    let text = format!("{base}\n[resume]\nt = 1.0\nstate = {unit}\ncrossings = [{many}]\n");
    let err = Scene::from_toml(&text)
        .unwrap()
        .setup(None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("resume.crossings has 5001 points, but the crossings plot keeps at most 5000"),
        "{err}"
    );
    // A cylinder has no crossings of ∂Ω to keep.
    let cylinder = Scene::preset("cylinder-near-critical")
        .unwrap()
        .to_toml()
        .unwrap();
    let text =
        format!("{cylinder}\n[resume]\nt = 1.0\nstate = [0.0, 0.0]\ncrossings = [[0.0, 1.0]]\n");
    let err = Scene::from_toml(&text)
        .unwrap()
        .setup(None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("the body is a cylinder: crossings of ∂Ω are a sphere's"),
        "{err}"
    );
}

/// The model's CSV row (as `simulate` writes it, without the contact force) at the run's state.
struct RowOf(f64);

impl rollphase::dynamics::ModelVisitor for RowOf {
    type Output = Vec<f64>;

    fn visit<const N: usize, M: rollphase::dynamics::RollingModel<N>>(
        self,
        model: &M,
        y: &[f64; N],
    ) -> Vec<f64> {
        let mut row = Vec::new();
        model.row(self.0, y, &mut row);
        row
    }
}

/// The run you watch is the run you would compute (issue 62): a scene advanced frame by frame at
/// 60 and at 8 frames a second (with a pause of a few frames on the way), and the same scene run
/// by `simulate` (rows from its dense output at t = 100 and 400, its run going on to 500), give
/// the same rows to the bit, at the fast and the balanced settings. The live run once built a
/// new stepper every frame, whose steps ended where the frames fell: the two frame rates
/// differed by 3e-6 at the balanced setting.
#[test]
fn the_live_run_is_simulates_run_at_any_frame_rate() {
    use rollphase::integrate::Preset;
    use rollphase::simulate::{InitialState, RunSpec, Start, run};
    for name in ["sphere-cruising", "cylinder-hysteresis"] {
        for setting in [Preset::Fast, Preset::Balanced] {
            let mut scene = Scene::preset(name).unwrap();
            scene.integrator = rollphase::scene::IntegratorSpec {
                preset: Some(setting),
                ..Default::default()
            };
            let mut setup = scene.setup(None).unwrap();
            assert!(setup.timeline.is_empty(), "{name}: no lesson steps");
            let initial = match &setup.start {
                Start::Disk {
                    theta0, theta_dot0, ..
                } => InitialState::Disk {
                    theta0: *theta0,
                    theta_dot0: *theta_dot0,
                },
                Start::Sphere { q0, omega0, .. } => InitialState::Sphere {
                    q0: *q0,
                    omega0: *omega0,
                },
            };
            // The start as `simulate` makes it from those numbers (it normalises q₀ again).
            setup.start = Start::new(&setup.body, initial).unwrap();
            let spec = RunSpec {
                ramp: setup.ramp,
                initial,
                method: setup.method,
                t_end: 500.0,
                samples: 6,
                max_steps: 50_000_000,
                limits: setup.limits,
            };
            let mut rows: Vec<Vec<f64>> = Vec::new();
            run(&setup.body, &spec, |r| rows.push(r.to_vec())).unwrap();
            let speed = setup.scene.playback.speed;
            for fps in [60.0, 8.0] {
                let mut live = LiveRun::new(setup.clone());
                let tick = speed / fps;
                let mut frame = 0u64;
                let mut t = 0.0;
                for (k, target) in [(1, 100.0), (4, 400.0)] {
                    // Frames a tick apart, a few of them paused (asking for no new time), and
                    // one at the target itself.
                    while t + tick < target - 1e-6 {
                        frame += 1;
                        if !(50..55).contains(&frame) {
                            t += tick;
                        }
                        live.advance_to(t).unwrap();
                    }
                    t = target;
                    live.advance_to(t).unwrap();
                    assert_eq!(live.time(), target);
                    let shown = live.state().visit(&live.ramp(), RowOf(live.time()));
                    // The columns the integrator carries (t, θ, θ̇ …; t, q, x, y) to the bit. A
                    // sphere's contact columns (u, ω, z) are solved for at each row by Newton's
                    // method warm-started from the integrator's last contact, which a row taken
                    // aside does not have: they agree to rounding.
                    let carried: Vec<usize> = match shown.len() {
                        14 => vec![0, 1, 2, 3, 4, 11, 12],
                        n => (0..n).collect(),
                    };
                    for i in carried {
                        assert_eq!(
                            shown[i], rows[k][i],
                            "{name} at {setting:?}, {fps} frames/s: t = {target}, column {i}"
                        );
                    }
                    for (i, (a, b)) in shown.iter().zip(&rows[k]).enumerate() {
                        assert!(
                            (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                            "{name} at {setting:?}, {fps} frames/s: t = {target}, column {i}: \
                             {a} against {b}"
                        );
                    }
                }
            }
        }
    }
}

/// What the app's Save state writes (tests/app/app_ui.rs checks the app writes this): the
/// scene with the model as it runs now, the state, and how the run got there.
fn saved_state(setup: &rollphase::scene::SceneSetup, run: &LiveRun) -> Scene {
    let snap = run.snapshot();
    let mut scene = setup.scene.clone();
    scene.model.alpha_rad = Some(snap.alpha_rad);
    scene.model.alpha_over_critical = None;
    scene.model.mass_ratio = snap.mass_ratio;
    scene.model.drag_law = rollphase::scene::DragLawFields::from(&snap.drag_law);
    scene.integrator = rollphase::scene::IntegratorSpec::of(&run.method());
    scene.resume = Some(rollphase::scene::ResumeSpec {
        t: snap.t,
        state: snap.state.clone(),
        ..Default::default()
    });
    scene.replay = snap.replay.clone();
    // Through the file's TOML, as the app writes and reads it.
    Scene::from_toml(&scene.to_toml().unwrap()).unwrap()
}

/// Changes made by hand take effect at a simulation time, and the saved state records them:
/// replayed from the scene's start (its first model, each change at its time, the resumes),
/// the run reaches the saved state to the bit, whatever frames the live run was advanced
/// through. Here a viscous ball is given inertia, then a steeper ramp, then the fast setting,
/// between frames of uneven length; saved, resumed, changed again and saved again.
#[test]
fn a_saved_state_replays_from_the_start_to_the_bit() {
    let setup = Scene::preset("sphere-cruising")
        .unwrap()
        .setup(None)
        .unwrap();
    let mut run = LiveRun::new(setup.clone());
    let mut t = 0.0;
    for (k, dt) in [0.37, 1.13, 0.05, 2.9].iter().cycle().take(48).enumerate() {
        t += dt;
        run.advance_to(t).unwrap();
        let ramp = run.ramp();
        match k {
            12 => run
                .set_parameters(
                    rollphase::dynamics::Ramp {
                        mass_ratio: 2.0,
                        ..ramp
                    },
                    run.method(),
                )
                .unwrap(),
            24 => run
                .set_parameters(
                    rollphase::dynamics::Ramp {
                        alpha_rad: 0.35,
                        ..ramp
                    },
                    run.method(),
                )
                .unwrap(),
            36 => run
                .set_parameters(ramp, rollphase::integrate::Preset::Fast.method())
                .unwrap(),
            // A drag law's parameter, as the app's drag field sets it: saved states with one
            // could not be opened again (serde's flatten beside deny_unknown_fields).
            42 => run
                .set_parameters(
                    rollphase::dynamics::Ramp {
                        drag_law: rollphase::dynamics::DragLaw::LINEAR
                            .with("drag_exponent", 1.5)
                            .unwrap(),
                        ..ramp
                    },
                    run.method(),
                )
                .unwrap(),
            _ => {}
        }
    }
    let saved = saved_state(&setup, &run);
    assert_eq!(saved.replay.len(), 5, "{:?}", saved.replay);
    let saved_setup = saved.setup(None).unwrap();
    let replayed = LiveRun::replayed(&saved_setup).unwrap();
    assert_eq!(replayed.time(), run.time());
    assert_eq!(replayed.state().vector(), run.state().vector());
    // Its progress: a report about every hundredth of the way (at most 1.5 apart), in order,
    // up to the end; and the run reported on is the same to the bit.
    let mut reports: Vec<(f64, f64)> = Vec::new();
    LiveRun::replayed_reporting(&saved_setup, &mut |t, end| reports.push((t, end))).unwrap();
    assert!(reports.len() >= 100, "{} reports", reports.len());
    assert!(reports.windows(2).all(|w| w[0].0 <= w[1].0));
    assert!(
        reports
            .windows(2)
            .all(|w| w[1].0 - w[0].0 <= 1.5 * run.time() / 100.0 + 1e-9)
    );
    assert_eq!(reports.last().map(|r| r.0), Some(run.time()));
    let reported = LiveRun::replayed_reporting(&saved_setup, &mut |_, _| {}).unwrap();
    assert_eq!(reported.state().vector(), run.state().vector());

    // Resumed from the file, changed again and saved again: the replay goes through the
    // resume (the integrator started afresh there, as the resumed run's was).
    let mut resumed = LiveRun::new(saved_setup.clone());
    let t0 = resumed.time();
    resumed.advance_to(t0 + 3.3).unwrap();
    let ramp = resumed.ramp();
    resumed
        .set_parameters(
            rollphase::dynamics::Ramp {
                mass_ratio: 0.5,
                ..ramp
            },
            resumed.method(),
        )
        .unwrap();
    resumed.advance_to(t0 + 20.71).unwrap();
    let again = saved_state(&saved_setup, &resumed);
    assert_eq!(again.replay.len(), 7, "{:?}", again.replay);
    let replayed = LiveRun::replayed(&again.setup(None).unwrap()).unwrap();
    assert_eq!(replayed.state().vector(), resumed.state().vector());
    // Without the resume's restart the replay would not be exact: the check can fail.
    let mut skipped = again.clone();
    skipped.replay.remove(5);
    let off = LiveRun::replayed(&skipped.setup(None).unwrap()).unwrap();
    assert_ne!(off.state().vector(), resumed.state().vector());
}

#[test]
fn a_replay_that_cannot_lead_to_its_saved_state_is_refused_by_name() {
    let setup = Scene::preset("sphere-cruising")
        .unwrap()
        .setup(None)
        .unwrap();
    let mut run = LiveRun::new(setup.clone());
    run.advance_to(5.0).unwrap();
    let saved = saved_state(&setup, &run);
    let refused = |scene: &Scene| scene.setup(None).unwrap_err().to_string();
    let mut no_resume = saved.clone();
    no_resume.resume = None;
    assert!(refused(&no_resume).contains("without [resume]"));
    let mut late_start = saved.clone();
    late_start.replay[0].at = 1.0;
    assert!(refused(&late_start).contains("needs t = 0"));
    for bad in [f64::NAN, 6.0, -1.0] {
        let mut s = saved.clone();
        s.replay.push(rollphase::scene::ReplayEntry {
            at: bad,
            ..s.replay[0].clone()
        });
        assert!(
            refused(&s).contains("is not allowed"),
            "{bad}: {}",
            refused(&s)
        );
    }
    let mut steep = saved.clone();
    steep.replay[0].alpha_rad = 2.0;
    assert!(
        refused(&steep).contains("[[replay]] entry 1 (at t = 0)"),
        "{}",
        refused(&steep)
    );
    // A step the app would not have run: coarser than a frame.
    let mut coarse = saved.clone();
    coarse.replay[0].integrator = rollphase::integrate::Method::Rk4 { dt: 10.0 };
    assert!(refused(&coarse).contains("entry 1"), "{}", refused(&coarse));
    // A time past the saved one is named readably, not in 309 digits.
    let mut huge = saved.clone();
    huge.replay.push(rollphase::scene::ReplayEntry {
        at: 1e308,
        ..huge.replay[0].clone()
    });
    assert!(
        refused(&huge).contains("at t = 1e308"),
        "{}",
        refused(&huge)
    );
    // An unknown key in an entry is refused, naming the entry's own fields.
    let text = saved
        .to_toml()
        .unwrap()
        .replace("[[replay]]\n", "[[replay]]\nspeed = 2.0\n");
    let e = Scene::from_toml(&text).unwrap_err().to_string();
    assert!(
        e.contains("unknown field `speed`") && e.contains("`integrator`"),
        "{e}"
    );
    // A saved state without a replay resumes, but says why it cannot be replayed.
    let mut plain = saved.clone();
    plain.replay.clear();
    let e = LiveRun::replayed(&plain.setup(None).unwrap()).unwrap_err();
    assert!(e.to_string().contains("no [[replay]]"), "{e}");
}

/// `rollphase replay STATE` runs a saved state again and says whether it reaches it to the
/// bit; a state that its replay does not reach (edited by hand) exits 1 naming the difference,
/// and a plain scene or a state without a replay is refused with why.
#[test]
fn the_replay_command_checks_a_saved_state() {
    let setup = Scene::preset("sphere-cruising")
        .unwrap()
        .setup(None)
        .unwrap();
    let mut run = LiveRun::new(setup.clone());
    run.advance_to(3.3).unwrap();
    let ramp = run.ramp();
    run.set_parameters(
        rollphase::dynamics::Ramp {
            mass_ratio: 2.0,
            ..ramp
        },
        run.method(),
    )
    .unwrap();
    run.advance_to(11.7).unwrap();
    let saved = saved_state(&setup, &run);
    let dir = crate::cli::scratch("replay-command");
    // As a file of its own: the preset's bundled shape written inline, as `scenes --toml` does.
    let write = |name: &str, scene: &Scene| {
        let mut scene = scene.clone();
        if let Some(shape) = scene.body.shape.take() {
            let json = rollphase::scene::bundled_shape(&shape).unwrap();
            scene.body.inline = Some(rollphase::geometry::ShapeFile::from_json(json).unwrap());
        }
        let path = dir.join(name);
        std::fs::write(&path, scene.to_toml().unwrap()).unwrap();
        path.to_string_lossy().into_owned()
    };
    let text = |o: &std::process::Output| {
        format!(
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        )
    };
    let good = write("state.toml", &saved);
    let o = crate::cli::rollphase(["replay", good.as_str()]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("the saved state to the bit (10 numbers)"),
        "{}",
        text(&o)
    );
    // One number of the saved state moved by an ulp's worth: not reached, exit 1.
    let mut edited = saved.clone();
    let state = &mut edited.resume.as_mut().unwrap().state;
    state[7] += 1e-12;
    let bad = write("edited.toml", &edited);
    let o = crate::cli::rollphase(["replay", bad.as_str()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("differs from the saved state") && text(&o).contains("in 1 of 10"),
        "{}",
        text(&o)
    );
    // A scene is not a saved state; a state without [[replay]] cannot be replayed.
    let mut plain = saved.clone();
    plain.resume = None;
    plain.replay.clear();
    let o = crate::cli::rollphase(["replay", write("plain.toml", &plain).as_str()]);
    assert!(
        !o.status.success() && text(&o).contains("has no [resume]"),
        "{}",
        text(&o)
    );
    let mut old = saved.clone();
    old.replay.clear();
    let o = crate::cli::rollphase(["replay", write("old.toml", &old).as_str()]);
    assert!(
        !o.status.success() && text(&o).contains("no [[replay]]"),
        "{}",
        text(&o)
    );
}
