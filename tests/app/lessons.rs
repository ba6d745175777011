//! Lessons: a scene's `[[timeline]]` steps apply when the simulation reaches their times, in
//! the simulation (shared by the app and headless mode) and in the app's controller, whose
//! wall-clock ticks must land on the same instants as the headless frames. The three bundled
//! lessons show what their captions claim: periods equal to the quadrature's at each α, the
//! √ law, the two hysteresis branches, and period 1 → period 2 across the flip.

use rollphase::analysis::fit::sqrt_law;
use rollphase::analysis::orbits::disk_period::viscous_disk_period;
use rollphase::dynamics::Ramp;
use rollphase::geometry::Body;
use rollphase::live::{Controller, LiveRun, SimCommand, Snapshot};
use rollphase::scene::{Scene, SceneSetup};

fn lesson(name: &str) -> SceneSetup {
    Scene::preset(name).unwrap().setup(None).unwrap()
}

/// The α, m/m0, caption and step count a run shows at time `t`.
fn state_at(sim: &mut LiveRun, t: f64) -> (f64, f64, Option<String>, usize) {
    sim.advance_to(t).unwrap();
    let s = sim.snapshot();
    (s.alpha_rad, s.mass_ratio, s.caption, s.lesson.unwrap().done)
}

/// The run's snapshot just before each next step, and at the lesson's end after the last. The
/// run advances one time unit at a time, as the app's ticks and the clips' frames do: crossing
/// times located on the dense output of one 300-unit advance (steps of tens of units) are off by
/// up to 1e-5 of the period, which the quadrature comparison would see.
fn at_end_of_each_step(setup: &SceneSetup) -> Vec<Snapshot> {
    let end = setup.scene.playback.end_time.unwrap();
    let mut sim = LiveRun::new(setup.clone());
    (0..setup.timeline.len())
        .map(|i| {
            let until = setup.timeline.get(i + 1).map_or(end, |s| s.at) - 1e-6;
            while sim.time() + 1.0 < until {
                sim.advance_to(sim.time() + 1.0).unwrap();
            }
            sim.advance_to(until).unwrap();
            sim.snapshot()
        })
        .collect()
}

#[test]
fn a_lessons_steps_apply_at_their_times_and_nowhere_else() {
    for name in [
        "lesson-critical-angle",
        "lesson-inertia-hysteresis",
        "lesson-period-doubling",
    ] {
        let setup = lesson(name);
        let steps = setup.timeline.clone();
        assert!(steps.len() >= 4, "{name}");
        let mut sim = LiveRun::new(setup.clone());
        // A step at t = 0 holds from the first frame.
        assert_eq!(steps[0].at, 0.0);
        assert_eq!(sim.snapshot().caption, steps[0].caption, "{name}");
        let mut alpha = setup.ramp.alpha_rad;
        let mut mass = setup.ramp.mass_ratio;
        let mut caption = steps[0].caption.clone();
        for (i, step) in steps.iter().enumerate().skip(1) {
            // Just before the step: the previous values.
            let before = state_at(&mut sim, step.at - 1e-6);
            assert_eq!(before, (alpha, mass, caption.clone(), i), "{name} step {i}");
            let contact = sim.snapshot().contact_in_body;
            // At its time: the new values, from the same state of the body.
            alpha = step.alpha_rad.unwrap_or(alpha);
            mass = step.mass_ratio.unwrap_or(mass);
            if let Some(c) = &step.caption {
                caption = (!c.is_empty()).then(|| c.clone());
            }
            let at = state_at(&mut sim, step.at);
            assert_eq!(at, (alpha, mass, caption.clone(), i + 1), "{name} step {i}");
            assert_eq!(sim.time(), step.at);
            let moved = (sim.snapshot().contact_in_body - contact).length();
            assert!(moved < 1e-4, "{name} step {i}: the body jumped by {moved}");
        }
        assert_eq!(sim.snapshot().lesson.unwrap().next_at, None);
    }
}

#[test]
fn the_controllers_ticks_land_where_the_headless_frames_do() {
    // Speed steps split ticks: after V seconds of wall time the app is where frame V·fps of
    // the headless clip is, whatever the tick lengths.
    let setup = lesson("lesson-critical-angle");
    for tick in [1.0 / 60.0, 0.1, 0.37] {
        let mut c = Controller::new(setup.clone());
        let mut wall = 0.0;
        while wall < 40.0 {
            c.tick(tick, u64::MAX);
            wall += tick;
            let expected = setup.time_after_video(wall);
            let got = c.simulation().time();
            assert!(
                (got - expected).abs() < 1e-9 * expected.max(1.0),
                "tick {tick}: after {wall} s the app is at t = {got}, the clip at {expected}"
            );
            assert_eq!(c.speed(), setup.speed_at(got), "tick {tick} at t = {got}");
        }
        assert!(c.simulation().steps_done() >= 4);
    }
    // Frame k of the clip is video time k/fps.
    let fps = setup.scene.playback.fps;
    assert_eq!(setup.frame_time(90), setup.time_after_video(90.0 / fps));
}

#[test]
fn next_and_previous_jump_between_steps_and_reset_restarts_the_lesson() {
    let setup = lesson("lesson-period-doubling");
    let at: Vec<f64> = setup.timeline.iter().map(|s| s.at).collect();
    let mut c = Controller::new(setup.clone());
    assert_eq!(c.simulation().steps_done(), 1);
    c.apply(SimCommand::NextStep);
    assert_eq!(c.message(), None);
    assert_eq!(c.simulation().time(), at[1]);
    assert_eq!(c.simulation().steps_done(), 2);
    assert_eq!(c.simulation().ramp().mass_ratio, 2.0);
    c.apply(SimCommand::NextStep);
    assert_eq!(c.simulation().time(), at[2]);
    assert_eq!(c.speed(), 50.0, "step 3 sets the speed");
    // Back: to the start of the step before the current one, from a fresh run.
    c.apply(SimCommand::PreviousStep);
    assert_eq!(c.simulation().time(), at[1]);
    assert_eq!(c.simulation().steps_done(), 2);
    assert_eq!(c.simulation().ramp().mass_ratio, 2.0);
    assert_eq!(c.speed(), 30.0, "the speed in force there");
    c.apply(SimCommand::PreviousStep);
    assert_eq!(c.simulation().time(), 0.0);
    assert_eq!(c.simulation().ramp().mass_ratio, 0.0);
    // The whole way to the end, then no further.
    for _ in 1..at.len() {
        c.apply(SimCommand::NextStep);
    }
    assert_eq!(c.simulation().ramp().mass_ratio, 6.0);
    c.apply(SimCommand::NextStep);
    // Information, not a failure (it showed in the error colour).
    assert_eq!(c.info(), Some("the lesson has no next step"));
    assert!(c.message().is_none());
    // Reset: the lesson from its start, views as it started.
    let mut views = setup.scene.views.clone();
    views.ball = false;
    c.apply(SimCommand::SetViews(views));
    c.apply(SimCommand::Reset);
    assert_eq!(c.simulation().time(), 0.0);
    assert_eq!(c.simulation().ramp().mass_ratio, 0.0);
    assert!(c.simulation().snapshot().views.ball);
    // A scene without a timeline says so.
    let mut plain = Controller::new(
        Scene::preset("sphere-cruising")
            .unwrap()
            .setup(None)
            .unwrap(),
    );
    plain.apply(SimCommand::NextStep);
    assert!(plain.info().unwrap().contains("no lesson timeline"));
}

#[test]
fn a_timeline_step_can_turn_views_on_and_change_the_integrator() {
    let text = Scene::preset("sphere-cruising").unwrap().to_toml().unwrap()
        + "\n[[timeline]]\nat = 5.0\nviews = { ball = true }\nintegrator = \"precise\"\n";
    let mut scene = Scene::from_toml(&text).unwrap();
    scene.views.ball = false;
    let mut sim = LiveRun::new(scene.setup(None).unwrap());
    sim.advance_to(4.0).unwrap();
    assert!(!sim.snapshot().views.ball);
    assert!(sim.snapshot().ball_trail.is_empty());
    assert_eq!(sim.snapshot().integrator, "dop853");
    sim.advance_to(10.0).unwrap();
    let s = sim.snapshot();
    assert!(s.views.ball);
    assert!(
        !s.ball_trail.is_empty(),
        "the SO(3) trail records from the step on"
    );
    assert_eq!(sim.method(), rollphase::integrate::Preset::Precise.method());
}

#[test]
fn the_critical_angle_lesson_measures_the_quadratures_periods_and_the_sqrt_law() {
    let setup = lesson("lesson-critical-angle");
    let Body::Disk(disk) = setup.body.clone() else {
        panic!("a cylinder lesson");
    };
    let alpha_star = setup.alpha_star;
    let mut points = Vec::new();
    for s in at_end_of_each_step(&setup) {
        let end = s.t;
        if s.alpha_rad < alpha_star {
            assert!(s.halted, "below α* the cylinder halts by t = {end}");
            continue;
        }
        // Each α is held long enough for a whole period to be measured, and it is the
        // period the quadrature gives (SI §1B), not a transient.
        let measured = s.period.unwrap_or_else(|| {
            panic!(
                "no period by t = {end} at α/α* = {}",
                s.alpha_rad / alpha_star
            )
        });
        let exact = viscous_disk_period(&disk, &Ramp::new(s.alpha_rad, 0.0).unwrap())
            .period
            .unwrap();
        assert!(
            (measured - exact).abs() < 1e-5 * exact,
            "α/α* = {}: lesson {measured}, quadrature {exact}",
            s.alpha_rad / alpha_star
        );
        points.push([s.alpha_rad, 1.0 / measured]);
    }
    assert!(points.len() >= 5);
    // The fit the 1/T plot draws: T = a/√(α − α*) + b through the points up to 1.05 α* holds
    // them to 1 % (0.4 % measured); further out the bottleneck no longer dominates and the law
    // overestimates T.
    let (a, b) = sqrt_law(&points, alpha_star).unwrap();
    for [alpha, rate] in &points {
        let t_fit = a / (alpha - alpha_star).sqrt() + b;
        let t = 1.0 / rate;
        if *alpha <= rollphase::analysis::fit::SQRT_LAW_REACH * alpha_star {
            assert!(
                (t_fit - t).abs() < 0.01 * t,
                "α = {alpha}: fit {t_fit}, measured {t}"
            );
        } else {
            assert!(t_fit > 1.05 * t, "α = {alpha}: fit {t_fit}, measured {t}");
        }
    }
    // Near α* the bottleneck term dominates: 1/T → 0 like √(α − α*).
    let nearest = points[0];
    let bottleneck = a / (nearest[0] - alpha_star).sqrt();
    assert!(
        bottleneck > 0.75 / nearest[1],
        "{bottleneck} of T = {}",
        1.0 / nearest[1]
    );
}

#[test]
fn the_hysteresis_lesson_rolls_below_the_critical_angle_only_on_the_way_down() {
    let setup = lesson("lesson-inertia-hysteresis");
    let alpha_star = setup.alpha_star;
    let seen: Vec<(f64, bool, f64)> = at_end_of_each_step(&setup)
        .iter()
        .map(|s| {
            let rolling = s.period.is_some() && !s.halted;
            (s.alpha_rad / alpha_star, rolling, s.angular_speed)
        })
        .collect();
    let at = |f: f64| {
        seen.iter()
            .find(|(r, _, _)| (r - f).abs() < 1e-9)
            .copied()
            .unwrap_or_else(|| panic!("no step at {f} α*: {seen:?}"))
    };
    // Up: at rest below α*, rolling above it.
    assert!(!at(0.9).1 && at(0.9).2 < 1e-6, "{seen:?}");
    assert!(at(1.05).1 && at(1.2).1, "{seen:?}");
    // Down: still rolling at 0.95, 0.8 and 0.6 α*, halted at 0.45 α*.
    assert!(at(0.95).1 && at(0.8).1 && at(0.6).1, "{seen:?}");
    let last_two = &seen[seen.len() - 2..];
    assert!(last_two[0].2 < 1e-6, "halted at 0.45 α*: {seen:?}");
    // Back at 0.9 α*: at rest, where it rolled on the way down.
    assert!(!last_two[1].1 && last_two[1].2 < 1e-3, "{seen:?}");
}

#[test]
fn the_period_doubling_lesson_goes_from_period_1_to_period_2() {
    let setup = lesson("lesson-period-doubling");
    let seen: Vec<_> = at_end_of_each_step(&setup)
        .iter()
        .map(|s| (s.mass_ratio, s.period_multiplicity))
        .collect();
    assert_eq!(
        seen,
        vec![
            (0.0, Some(1)),
            (2.0, Some(1)),
            (4.5, Some(2)),
            (6.0, Some(2)),
            // The comparison step: the lesson's body stays at 6 beside the others.
            (6.0, Some(2))
        ]
    );
}

#[test]
fn a_target_within_rounding_of_now_is_now() {
    // A tick can end a hair after a step time; integrating a few ulps must not fail.
    for name in ["lesson-critical-angle", "lesson-period-doubling"] {
        let mut sim = LiveRun::new(lesson(name));
        sim.advance_to(2449.999999).unwrap();
        let t = sim.time();
        for tiny in [1e-15, 1e-13, 4.6e-13, 1e-12] {
            sim.advance_to(t + tiny).unwrap();
        }
        sim.advance_to(t + 1e-6).unwrap();
        assert_eq!(sim.time(), t + 1e-6);
    }
}
