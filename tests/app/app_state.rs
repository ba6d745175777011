//! The simulation side of the app as a state machine, without a window or a clock: commands
//! change α and m/m0 on the running state, pause/step/reset/load behave as a user expects, a
//! refused command becomes a message that leaves the state alone, and a tick that exceeds its work
//! budget is reported as lagging behind the requested speed.

use rollphase::dynamics::ModelKind;
use rollphase::integrate::Method;
use rollphase::live::{Controller, SimCommand};
use rollphase::scene::Scene;

fn controller(preset: &str) -> Controller {
    Controller::new(Scene::preset(preset).unwrap().setup(None).unwrap())
}

#[test]
fn playing_advances_by_speed_times_wall_time_and_pause_stops_it() {
    let mut c = controller("sphere-cruising");
    let speed = c.speed();
    c.tick(0.5, u64::MAX);
    assert!((c.simulation().time() - 0.5 * speed).abs() < 1e-12);
    c.apply(SimCommand::Pause);
    c.tick(1.0, u64::MAX);
    assert!((c.simulation().time() - 0.5 * speed).abs() < 1e-12);
    c.apply(SimCommand::Play);
    c.apply(SimCommand::SetSpeed(10.0));
    c.tick(0.1, u64::MAX);
    assert!((c.simulation().time() - (0.5 * speed + 1.0)).abs() < 1e-12);
}

#[test]
fn step_advances_one_frame_and_pauses() {
    let mut c = controller("cylinder-hysteresis");
    c.apply(SimCommand::Step);
    assert!(c.is_paused());
    let fps = c.simulation().setup().scene.playback.fps;
    assert!((c.simulation().time() - c.speed() / fps).abs() < 1e-12);
}

#[test]
fn alpha_changes_apply_live_and_reset_restores_the_start() {
    let mut c = controller("sphere-cruising");
    let start = c.simulation().snapshot();
    c.tick(1.0, u64::MAX);
    let pose = c.simulation().snapshot().pose;
    c.apply(SimCommand::SetAlpha(0.5));
    assert_eq!(c.message(), None);
    assert_eq!(
        c.simulation().snapshot().pose,
        pose,
        "a live change keeps the pose"
    );
    assert_eq!(c.simulation().ramp().alpha_rad, 0.5);
    c.apply(SimCommand::SetMassRatio(2.0));
    assert_eq!(c.simulation().ramp().mass_ratio, 2.0);
    assert_eq!(c.simulation().state().kind(), ModelKind::SphereInertial);
    c.apply(SimCommand::Reset);
    let again = c.simulation().snapshot();
    assert_eq!(again.t, 0.0);
    assert_eq!(again.pose, start.pose);
}

#[test]
fn sweeping_alpha_down_shows_halting_as_zero_rate() {
    // A viscous sphere below its critical angle stops: the UI's 1/T reads 0.
    let mut c = controller("sphere-cruising");
    let alpha_star = c.simulation().setup().alpha_star;
    c.apply(SimCommand::SetAlpha(0.3 * alpha_star));
    c.apply(SimCommand::SetSpeed(100.0));
    c.tick(5.0, u64::MAX);
    assert!(c.simulation().snapshot().halted);
}

#[test]
fn refused_commands_leave_the_state_and_say_why() {
    let mut c = controller("sphere-cruising");
    c.tick(0.2, u64::MAX);
    let before = c.simulation().snapshot();
    c.apply(SimCommand::SetAlpha(2.0));
    assert!(c.message().unwrap().contains("alpha = 2"));
    c.apply(SimCommand::SetMassRatio(-1.0));
    assert!(c.message().unwrap().contains("m/m0 = -1"));
    c.apply(SimCommand::SetSpeed(0.0));
    assert!(c.message().unwrap().contains("speed 0"));
    c.apply(SimCommand::SetMethod(Method::Rk4 { dt: -1.0 }));
    assert!(c.message().is_some());
    assert_eq!(c.simulation().snapshot(), before);
}

#[test]
fn unstable_settings_are_refused_and_falling_behind_is_reported() {
    let mut c = controller("sphere-doubling");
    // A fixed step far beyond stability on the inertial model is refused up front...
    c.apply(SimCommand::SetMethod(Method::Rk4 { dt: 50.0 }));
    assert!(
        c.message().unwrap().contains("unstable"),
        "{:?}",
        c.message()
    );
    // ...and a step budget too small for the requested speed is reported as lagging.
    c.apply(SimCommand::SetSpeed(1000.0));
    c.tick(1.0, 10);
    assert!(c.is_lagging());
}

#[test]
fn loading_a_preset_replaces_the_scene() {
    let mut c = controller("sphere-cruising");
    c.tick(1.0, u64::MAX);
    let cyl = Scene::preset("cylinder-near-critical")
        .unwrap()
        .setup(None)
        .unwrap();
    c.apply(SimCommand::Load(Box::new(cyl)));
    assert_eq!(c.simulation().time(), 0.0);
    assert_eq!(c.simulation().state().kind(), ModelKind::DiskViscous);
    assert_eq!(c.speed(), 30.0);
}

#[test]
fn reset_restores_the_scenes_speed_too() {
    let mut c = controller("sphere-cruising");
    let scene_speed = c.speed();
    c.apply(SimCommand::SetSpeed(2.0 * scene_speed));
    c.tick(0.5, u64::MAX);
    c.apply(SimCommand::Reset);
    assert_eq!(c.speed(), scene_speed);
    assert_eq!(c.simulation().time(), 0.0);
}

#[test]
fn every_registered_drag_parameter_changes_live_and_a_bad_value_is_refused() {
    use rollphase::dynamics::drag::REGISTERED;
    for p in REGISTERED {
        let mut c = controller("perfect-sphere");
        c.tick(0.2, u64::MAX);
        c.apply(SimCommand::SetDragParameter(p.key, p.max));
        assert!(c.message().is_none(), "{:?}", c.message());
        assert_eq!(c.simulation().ramp().drag_law.get(p.key), Some(p.max));
        assert_eq!(c.simulation().snapshot().drag_law.get(p.key), Some(p.max));
        let before = c.simulation().snapshot();
        c.apply(SimCommand::SetDragParameter(p.key, p.max * 2.0));
        assert!(c.message().unwrap().contains(p.key), "{:?}", c.message());
        assert_eq!(c.simulation().snapshot(), before);
    }
    // The perfect (viscous) ball rolls at the power law's speed, (sin α)^(1/n) with n = 2:
    // its state is [q, x, y], x the distance rolled from the start.
    let mut c = controller("perfect-sphere");
    c.apply(SimCommand::SetDragParameter("drag_exponent", 2.0));
    c.tick(1.0, u64::MAX);
    let alpha = c.simulation().ramp().alpha_rad;
    let t = c.simulation().time();
    let x = c.simulation().snapshot().state[4];
    assert!(
        t > 0.0 && (x / t / alpha.sin().sqrt() - 1.0).abs() < 1e-9,
        "x = {x} at t = {t}"
    );
}
