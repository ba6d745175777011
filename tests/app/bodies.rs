//! Several bodies on one ramp (`[[bodies]]`): Save state writes every body's state and the file
//! loads each to the bit; Save scene pins each body's own model, so a hand's m/m0 stays the
//! scene's own body's; a headless clip draws both bodies, in their colours, and its plot data
//! hold both bodies' series.
#![cfg(feature = "app")]

use rollphase::live::{LiveRun, SimCommand};
use rollphase::scene::Scene;

use crate::app_ui::{app, frames_until};
use crate::cli::{rollphase, scratch};

#[test]
fn save_state_of_two_bodies_loads_every_body_to_the_bit() {
    let (gpu, target, mut bench) = app("which-one-stops");
    bench.sim.send(SimCommand::SetSpeed(60.0));
    frames_until(&mut bench, &gpu, &target, vec![], |s| s.snapshot.t > 5.0);
    bench.sim.send(SimCommand::SetMassRatio(2.0));
    // Past the smooth cylinder's first two turns (T = 2π/sin α = 40.2): its 1/T point is
    // measured. Its period is waited for, not a time: under load a frame spans many t0.
    frames_until(&mut bench, &gpu, &target, vec![], |s| {
        s.snapshot.mass_ratio == 2.0 && s.snapshot.t > 100.0 && s.snapshot.lanes[0].period.is_some()
    });
    bench.sim.send(SimCommand::Pause);
    let s = frames_until(&mut bench, &gpu, &target, vec![], |s| s.paused);
    assert_eq!(s.snapshot.lanes.len(), 1);
    assert_eq!(
        s.snapshot.lanes[0].mass_ratio, 0.0,
        "a hand's m/m0 is the own body's"
    );
    let dir = scratch("bodies-state");
    let (state_path, scene_path) = (dir.join("state.toml"), dir.join("scene.toml"));
    bench.ui.set_state_path(&state_path);
    bench.ui.set_scene_path(&scene_path);
    bench.ui.save_state(&s);
    let (notice, error) = bench.ui.notice().cloned().unwrap();
    assert!(!error, "{notice}");
    bench.ui.save_scene(&s);
    let (notice, error) = bench.ui.notice().cloned().unwrap();
    assert!(!error, "{notice}");
    // `rollphase replay` replays the scene's own body to the bit and says the other's state is
    // loaded as saved.
    let replay = rollphase(["replay", state_path.to_str().unwrap()]);
    let said = String::from_utf8_lossy(&replay.stdout).to_string();
    assert!(
        replay.status.success(),
        "{said}{}",
        String::from_utf8_lossy(&replay.stderr)
    );
    assert!(said.contains("the saved state to the bit"), "{said}");
    assert!(
        said.contains("other body ([[bodies]]): saved states loaded as written, not replayed"),
        "{said}"
    );
    let saved = Scene::from_toml(&std::fs::read_to_string(&state_path).unwrap()).unwrap();
    let scene = Scene::from_toml(&std::fs::read_to_string(&scene_path).unwrap()).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    // The other body's state, at the run's time, exactly.
    let resume = saved.bodies[0].resume.clone().expect("[bodies.resume]");
    assert_eq!(resume.t, s.snapshot.t);
    assert_eq!(resume.state, s.snapshot.lanes[0].state);
    // Loaded, every body goes on from its saved state, to the bit.
    let loaded = LiveRun::new(saved.setup(None).unwrap()).snapshot();
    assert_eq!(loaded.t, s.snapshot.t);
    assert_eq!(loaded.state, s.snapshot.state);
    assert_eq!(loaded.lanes[0].state, s.snapshot.lanes[0].state);
    assert_eq!(loaded.lanes[0].label, "smooth");
    // And every body's plot points come back as they were: the other body's 1/T point too.
    let lane_points = bench.ui.history().lane(1).unwrap().alpha_sweep_points();
    assert_eq!(lane_points.len(), 1, "{lane_points:?}");
    assert_eq!(resume.alpha_sweep, lane_points);
    let plots = rollphase::live::history::PlotHistory::of_setup(&saved.setup(None).unwrap());
    assert_eq!(plots.lane(1).unwrap().alpha_sweep_points(), lane_points);
    assert_eq!(
        plots.alpha_sweep_points(),
        bench.ui.history().alpha_sweep_points()
    );
    // Save scene: the own body at the hand's m/m0, the other at its own, its body inline.
    assert_eq!(scene.model.mass_ratio, 2.0);
    let other = scene.setup(None).unwrap();
    assert_eq!(other.lanes[0].ramp.mass_ratio, 0.0);
    assert_eq!(
        other.lanes[0].alpha_star, 0.0,
        "the smooth cylinder, inline"
    );
    assert!(scene.bodies[0].body.as_ref().unwrap().inline.is_some());
}

#[test]
fn a_headless_clip_of_two_bodies_draws_both_and_writes_both_series() {
    use image::AnimationDecoder;
    let dir = scratch("bodies-clip");
    let gif = dir.join("which.gif");
    let data = dir.join("data");
    let o = rollphase([
        "--headless",
        "--preset",
        "which-one-stops",
        "--frames",
        "90",
        "--size",
        "320x180",
        "--gif",
        gif.to_str().unwrap(),
        "--plot-data",
        data.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = std::io::BufReader::new(std::fs::File::open(&gif).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(file)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap();
    assert_eq!(frames.len(), 90);
    // The smooth body is drawn in its sky blue (86, 180, 233), shaded: pixels near that hue.
    let last = frames.last().unwrap().buffer();
    let blue = last
        .pixels()
        .filter(|p| {
            let [r, g, b, _] = p.0.map(i32::from);
            b > 150 && b > r + 60 && g > r + 30
        })
        .count();
    assert!(blue > 200, "{blue} sky-blue pixels");
    let series = std::fs::read_to_string(data.join("series.csv")).unwrap();
    let other = std::fs::read_to_string(data.join("series-body-2.csv")).unwrap();
    let json = std::fs::read_to_string(data.join("plot-data.json")).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    // 90 frames at 4.5 t0 per second and 30 frames/s: t = 0 … 13.35, a sample every 0.1.
    assert_eq!(series.lines().count(), other.lines().count());
    assert_eq!(other.lines().next(), Some("t,theta,theta_dot"));
    assert!(other.lines().count() > 100);
    let meta: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(meta["bodies"][0]["label"], "smooth");
    assert_eq!(meta["bodies"][0]["model"], "disk-viscous");
}

/// A plot-data folder holding an earlier run's body files (more bodies than this run's) is
/// refused: they would read as this run's.
#[test]
#[expect(
    clippy::disallowed_methods,
    reason = "the fixture: an earlier run's file"
)]
fn an_earlier_runs_body_files_are_not_left_beside_this_ones() {
    let setup = Scene::preset("which-one-stops")
        .unwrap()
        .setup(None)
        .unwrap();
    let run = LiveRun::new(setup.clone());
    let history = rollphase::live::history::PlotHistory::default();
    let meta = rollphase::live::history::PlotMeta::of(&run.snapshot(), &setup, run.method());
    let dir = scratch("bodies-stale");
    std::fs::write(dir.join("series-body-3.csv"), "t,theta,theta_dot\n").unwrap();
    let err = history
        .write_csv_files(
            &dir,
            rollphase::live::Measured::default(),
            &meta,
            &rollphase::output::Inputs::none(),
        )
        .unwrap_err()
        .to_string();
    // The headless renderer refuses it before rendering anything, not after the clip.
    let gif = scratch("bodies-stale-gif").join("which.gif");
    let o = rollphase([
        "--headless",
        "--preset",
        "which-one-stops",
        "--frames",
        "30",
        "--size",
        "160x90",
        "--gif",
        gif.to_str().unwrap(),
        "--plot-data",
        dir.to_str().unwrap(),
    ]);
    let said = String::from_utf8_lossy(&o.stderr).to_string();
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        err.contains("series-body-3.csv is there from an earlier run"),
        "{err}"
    );
    assert_eq!(left.len(), 1, "nothing written: {left:?}");
    assert!(
        !o.status.success() && said.contains("series-body-3.csv is there from an earlier run"),
        "{said}"
    );
    assert!(!gif.exists(), "no clip rendered before the refusal");
}

/// The doubling lesson's scene started at t = 4200, in its last step (three bodies shown).
fn doubling_lesson_from_4200() -> String {
    String::from_utf8(rollphase(["scenes", "--toml", "lesson-period-doubling"]).stdout)
        .unwrap()
        .replace(
            "trail_time = 120.0",
            "trail_time = 120.0\nstart_time = 4200.0",
        )
}

/// The SO(3) ball draws every shown body's path in its colour: the doubling lesson's last step
/// (three bodies) has the sky-blue and green paths of m/m0 = 2 and 4.5 in the inset, which the
/// same frame with the other bodies hidden does not.
#[test]
fn the_ball_draws_each_shown_bodys_path_in_its_colour() {
    let dir = scratch("bodies-ball");
    let lesson = doubling_lesson_from_4200();
    let frame = |name: &str, text: &str| {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, text).unwrap();
        let out = dir.join(name);
        let o = rollphase([
            "--headless",
            "--scene",
            scene.to_str().unwrap(),
            "--size",
            "960x540",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        image::open(out.join("frame_00000.png")).unwrap().to_rgb8()
    };
    // Pixels of the inset (the top right) that `near` picks.
    let in_inset = |img: &image::RgbImage, near: &dyn Fn([i32; 3]) -> bool| {
        let (w, h) = img.dimensions();
        img.enumerate_pixels()
            .filter(|(x, y, p)| *x > w * 3 / 4 && *y < h * 9 / 20 && near(p.0.map(i32::from)))
            .count()
    };
    let shown = frame("shown", &lesson);
    let hidden = frame(
        "hidden",
        &lesson.replace("views = { lanes = true }", "views = { lanes = false }"),
    );
    std::fs::remove_dir_all(&dir).ok();
    // Sky blue (86, 180, 233) and bluish green (0, 158, 115), drawn at up to 75 % opacity over
    // the ball's dim blue: the green reads about (50, 140, 130), apart from the y axis's light
    // green, whose green stands far above its blue.
    let sky_blue = |[r, g, b]: [i32; 3]| b > 150 && b > r + 60 && g > r + 30;
    let green = |[r, g, b]: [i32; 3]| g > 110 && g > r + 60 && (-5..=40).contains(&(g - b));
    for (name, near) in [
        ("sky blue", &sky_blue as &dyn Fn([i32; 3]) -> bool),
        ("green", &green),
    ] {
        let (with, without) = (in_inset(&shown, near), in_inset(&hidden, near));
        assert!(
            with > 2 * without + 50,
            "{name}: {with} pixels with the bodies shown, {without} hidden"
        );
    }
}

/// A lesson rendered from past its steps keeps the plots of the steps it skipped: the doubling
/// lesson from t = 4200 writes the crossings at m/m0 = 0, 2, 4.5 and 6 that its steps measured
/// (the simulation to the start collects them at every frame step, as frames from 0 would),
/// not only those at 6 (a helper found them lost).
#[test]
fn a_late_start_keeps_the_plots_of_the_steps_it_skipped() {
    let dir = scratch("bodies-late-start");
    let lesson = doubling_lesson_from_4200();
    let scene = dir.join("late.toml");
    std::fs::write(&scene, lesson).unwrap();
    let data = dir.join("data");
    let o = rollphase([
        "--headless",
        "--scene",
        scene.to_str().unwrap(),
        "--size",
        "64x36",
        "--out",
        dir.join("frames").to_str().unwrap(),
        "--plot-data",
        data.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let crossings = std::fs::read_to_string(data.join("sweep-mass.csv")).unwrap();
    let other = std::fs::read_to_string(data.join("sweep-mass-body-3.csv")).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let count = |text: &str, mass: &str| {
        text.lines()
            .filter(|l| l.split(',').next() == Some(mass))
            .count()
    };
    // Period 1 at 0 and 2, period 2 at 4.5 and 6: one branch, then two.
    let branches: Vec<usize> = ["0.0", "2.0", "4.5", "6.0"]
        .iter()
        .map(|m| count(&crossings, m))
        .collect();
    assert_eq!(branches, [1, 1, 2, 2], "{crossings}");
    // The body at m/m0 = 4.5, hidden until the last step, has its two branches too.
    assert_eq!(count(&other, "4.5"), 2, "{other}");
}
