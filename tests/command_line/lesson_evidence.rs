//! A lesson's evidence measured ahead (`live::evidence`): each step's plot points are there at
//! the step's end of the scene's own run, and what each caption claims is in them: the
//! period-doubling lesson's crossings of ∂Ω repeat once a turn at m/m0 = 0 and 2 and alternate
//! between two points at 4.5 and 6; the critical-angle lesson has its 1/T point at every α it
//! steps to, 0 below α*.

use std::sync::atomic::AtomicBool;

use rollphase::live::LiveRun;
use rollphase::live::evidence::{EvidenceState, measure_evidence, step_ends};
use rollphase::live::history::{Branch, PlotHistory};
use rollphase::scene::Scene;

fn evidence(name: &str) -> (rollphase::scene::SceneSetup, EvidenceState) {
    let setup = Scene::preset(name).unwrap().setup(None).unwrap();
    let mut last = None;
    measure_evidence(&setup, &AtomicBool::new(false), 1e9, |s| {
        last = Some(s.clone())
    });
    (setup, last.expect("the evidence run published its state"))
}

fn plots(state: &EvidenceState, done: usize) -> PlotHistory {
    let mut h = PlotHistory::default();
    h.restore(&state.steps[done]);
    h
}

/// The distinct crossing points (polar angle of ∂Ω's crossing, 1e-2 apart) at `mass`.
fn branches(h: &PlotHistory, mass: f64) -> Vec<f64> {
    let mut found: Vec<f64> = Vec::new();
    // The settled cycle: the last points at this mass (the first ones are its transient).
    let at: Vec<f64> = h
        .crossings_by_mass()
        .iter()
        .filter(|p| p[0] == mass)
        .map(|p| p[1])
        .collect();
    for &angle in at.iter().rev().take(6) {
        if found.iter().all(|&f| (f - angle).abs() > 1e-2) {
            found.push(angle);
        }
    }
    found
}

#[test]
fn the_doubling_lessons_evidence_shows_period_one_then_two() {
    let (setup, state) = evidence("lesson-period-doubling");
    assert!(state.failed.is_none(), "{:?}", state.failed);
    assert_eq!(state.steps.len(), setup.timeline.len() + 1);
    assert_eq!(state.t_done, *step_ends(&setup).last().unwrap());
    // Before the first step (t = 0) there is nothing yet.
    assert!(plots(&state, 0).crossings_by_mass().is_empty());
    for (done, mass, period) in [(1, 0.0, 1), (2, 2.0, 1), (3, 4.5, 2), (4, 6.0, 2)] {
        let h = plots(&state, done);
        let b = branches(&h, mass);
        assert_eq!(
            b.len(),
            period,
            "step {done} (m/m0 = {mass}) claims period {period}: crossings {b:?}"
        );
        // A step's evidence holds the steps before too, and no point of a later one.
        assert!(h.crossings_by_mass().iter().all(|p| p[0] <= mass));
    }
    // The two branches of period 2 are far apart on the plot (0.2–0.5 rad), not one smeared.
    let b = branches(&plots(&state, 3), 4.5);
    assert!((b[0] - b[1]).abs() > 0.1, "{b:?}");
}

#[test]
fn the_critical_angle_lessons_evidence_has_a_point_at_every_alpha() {
    let (setup, state) = evidence("lesson-critical-angle");
    assert!(state.failed.is_none(), "{:?}", state.failed);
    let star = setup.alpha_star;
    let last = plots(&state, setup.timeline.len());
    let points = last.sweep(Branch::Up);
    for step in &setup.timeline {
        let Some(alpha) = step.alpha_rad else {
            continue;
        };
        let point = points
            .iter()
            .find(|p| (p[0] / alpha - 1.0).abs() < 1e-9)
            .unwrap_or_else(|| panic!("no 1/T point at α = {} α*: {points:?}", alpha / star));
        // Below α* the cylinder halts (1/T = 0); above it rolls (1/T > 0).
        assert_eq!(
            point[1] > 0.0,
            alpha > star,
            "α = {} α*: {point:?}",
            alpha / star
        );
    }
    // The first step's own α (0.9 α*, from the scene) has its 0 too.
    let first = plots(&state, 1).sweep(Branch::Up);
    assert!(
        first.iter().any(|p| p[1] == 0.0),
        "step 1 claims a halt: {first:?}"
    );
}

#[test]
fn a_run_changed_by_hand_is_off_script_and_a_timeline_step_is_not() {
    let setup = Scene::preset("lesson-critical-angle")
        .unwrap()
        .setup(None)
        .unwrap();
    let mut run = LiveRun::new(setup);
    run.advance_to(250.0).unwrap();
    assert!(run.steps_done() >= 2 && !run.snapshot().off_script);
    let ramp = run.ramp();
    run.set_parameters(ramp, run.method()).unwrap();
    assert!(run.snapshot().off_script);
    assert!(!run.restarted().snapshot().off_script);
}
