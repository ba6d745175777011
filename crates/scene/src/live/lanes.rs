//! The scene's other bodies on the ramp (`[[bodies]]`, `scene::lanes`): each is a [`LiveRun`]
//! of its own, from a setup validated as any scene's, advanced on the scene's clock to the same
//! times as the scene's own body, so each is the run `simulate` makes of it alone. They share
//! the ramp: a change of α or of the integrator (a lesson's step or a hand) reaches them all;
//! m/m0 and the drag law are each body's own, and a hand changes only the scene's own body's.
//!
//! Each body's fate is said in the verdict's words ([`Snapshot::fate`]): periodic (with its
//! period), halted, left the model, or undecided while no period is measured.

use crate::dynamics::Ramp;
use crate::integrate::Method;

use super::history::Sample;
use super::{LiveRun, PeriodSpan, Snapshot};

impl LiveRun {
    /// Advances the other bodies to `t` (where the scene's own body is). A body whose run
    /// fails stops there with its reason on its line, as the scene's own would; the others go
    /// on.
    pub(super) fn lanes_to(&mut self, t: f64) {
        for lane in self.lanes.iter_mut().filter(|l| !l.is_stopped()) {
            // The failure is kept on the lane (`stopped`) and shown on its line.
            let _ = lane.advance_to(t);
        }
    }

    /// The ramp's new α and integrator, for the other bodies too (each keeps its m/m0 and drag
    /// law). A body whose model refuses them (a fixed step too coarse for it) stops with why.
    /// A body whose ramp and integrator stay as they were (a hand's m/m0, which is the own
    /// body's) goes on undisturbed: a change would end its run in progress and forget its
    /// crossings, and its period would be measured afresh for nothing.
    pub(super) fn lanes_follow(&mut self, alpha_rad: f64, method: Method) {
        for lane in &mut self.lanes {
            let ramp = Ramp {
                alpha_rad,
                ..lane.ramp()
            };
            if ramp == lane.ramp() && method == lane.method() {
                continue;
            }
            if let Err(e) = lane.change_parameters(ramp, method) {
                lane.stop_with(e.to_string());
            }
        }
    }

    /// The other bodies' plot samples taken since the last call, each tagged with its body.
    pub(super) fn take_lane_samples(&mut self, samples: &mut Vec<Sample>) {
        for (i, lane) in self.lanes.iter_mut().enumerate() {
            samples.extend(
                lane.take_plot_samples()
                    .into_iter()
                    .map(|s| Sample { body: i + 1, ..s }),
            );
        }
    }
}

impl Snapshot {
    /// The body's fate so far, in the verdict's words (`analysis::verdict::Fate`): "left the
    /// model: …", "halted", "periodic: period k, T = …" (a cylinder's T one full turn, a
    /// sphere's the whole cycle, its k crossings of ∂Ω: a doubled cycle's two crossings take
    /// 44.19 and 45.15 on the paper's body at m/m0 = 6, and T = 89.33 is neither alone), or
    /// "undecided: …" with what would decide it; a stopped run says why.
    pub fn fate(&self) -> String {
        if let Some(stopped) = &self.stopped {
            return format!("stopped: {stopped}");
        }
        if let Some(validity) = &self.validity {
            return format!("left the model: the body {validity}");
        }
        if self.halted {
            return "halted".to_string();
        }
        // The T stated beside the fate is the one every surface states ([`Self::stated_period`]):
        // a sphere whose cycle is not decided has a first look at T, not a period.
        match self.stated_period() {
            Some((t, PeriodSpan::FullTurn)) => format!("periodic: T = {t:.3}"),
            Some((t, PeriodSpan::Cycle { crossings })) => {
                format!("periodic: period {crossings}, T = {t:.3}")
            }
            _ => "undecided: no period yet (needs more turns)".to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::history::{PlotData, PlotHistory, PlotMeta};
    use super::super::{LiveRun, Measured};
    use crate::scene::Scene;

    fn which_one_stops() -> crate::scene::SceneSetup {
        Scene::preset("which-one-stops")
            .unwrap()
            .setup(None)
            .unwrap()
    }

    /// A body on a lane is the run of its own scene alone, to the bit, whatever the frames: the
    /// same trust as a body loaded from a file.
    #[test]
    fn a_body_beside_another_runs_as_it_would_alone() {
        let setup = which_one_stops();
        let mut together = LiveRun::new(setup.clone());
        let mut t = 0.0;
        for k in 0..200 {
            t += 0.05 + 0.3 * f64::from(k % 7) / 7.0;
            together.advance_to(t).unwrap();
        }
        for (lane_setup, lane) in setup.lanes.iter().zip(&together.snapshot().lanes) {
            let mut alone = LiveRun::new(lane_setup.clone());
            alone.advance_to(t).unwrap();
            let alone = alone.snapshot();
            assert_eq!(lane.t, alone.t);
            assert_eq!(lane.state, alone.state, "the body beside is its run alone");
        }
        // And the scene's own body is unchanged by the other's company.
        let mut own = setup.clone();
        own.lanes.clear();
        let mut alone = LiveRun::new(own);
        alone.advance_to(t).unwrap();
        assert_eq!(together.snapshot().state, alone.snapshot().state);
    }

    /// Which one stops: the designed cylinder halts on the 9° ramp, the smooth one rolls with
    /// the perfect disk's exact period 2π/sin α; each says so in the verdict's words.
    #[test]
    fn each_body_states_its_own_fate() {
        let setup = which_one_stops();
        let alpha = setup.ramp.alpha_rad;
        let mut run = LiveRun::new(setup);
        let mut history = PlotHistory::default();
        for k in 1..=90 {
            run.advance_to(f64::from(k)).unwrap();
            history.push(&run.snapshot());
        }
        let snap = run.snapshot();
        assert_eq!(snap.fate(), "halted");
        // The 1/T plot shows each: the designed cylinder at rest (1/T = 0), the smooth one
        // turning at sin α / 2π.
        let up = |h: &PlotHistory| h.sweep(super::super::history::Branch::Up);
        assert_eq!(up(&history), [[alpha, 0.0]]);
        let smooth_points = up(history.lane(1).expect("the smooth body's history"));
        assert_eq!(smooth_points.len(), 1);
        let rate = smooth_points[0][1];
        assert!(
            (rate - alpha.sin() / std::f64::consts::TAU).abs() < 1e-6 * rate,
            "{rate}"
        );
        let smooth = &snap.lanes[0];
        let period = smooth.period.expect("two turns measured");
        let exact = std::f64::consts::TAU / alpha.sin();
        assert!((period - exact).abs() < 1e-6 * exact, "{period} vs {exact}");
        assert!(
            smooth.fate().starts_with("periodic: T = 40.16"),
            "{}",
            smooth.fate()
        );
        assert_eq!(smooth.label, "smooth");
        assert_eq!(snap.label, "α* = 10°");
    }

    /// The ramp is one: α set by hand reaches every body; m/m0 set by hand is the scene's own
    /// body's alone.
    #[test]
    fn alpha_by_hand_moves_every_body_and_mass_only_the_own() {
        let mut run = LiveRun::new(which_one_stops());
        run.advance_to(5.0).unwrap();
        let ramp = crate::dynamics::Ramp::with_drag(0.2, 3.0, 1.0).unwrap();
        run.set_parameters(ramp, run.method()).unwrap();
        run.advance_to(6.0).unwrap();
        let snap = run.snapshot();
        assert_eq!(snap.alpha_rad, 0.2);
        assert_eq!(snap.mass_ratio, 3.0);
        assert_eq!(snap.lanes[0].alpha_rad, 0.2);
        assert_eq!(
            snap.lanes[0].mass_ratio, 0.0,
            "the smooth one keeps its m/m0"
        );
        assert_eq!(snap.lanes[0].t, 6.0);
    }

    /// A hand's m/m0 is the own body's alone: the other body's run goes on as if nothing
    /// happened, its crossings (and so its period) kept, its trajectory the one it has alone.
    #[test]
    fn mass_by_hand_leaves_the_other_bodys_run_untouched() {
        let setup = which_one_stops();
        let mut alone = LiveRun::new(setup.lanes[0].clone());
        alone.advance_to(100.0).unwrap();
        let mut run = LiveRun::new(setup);
        run.advance_to(60.0).unwrap();
        let before = run.snapshot().lanes[0].last_crossing_t;
        assert!(before.is_some(), "a crossing before the change");
        let ramp = crate::dynamics::Ramp::with_drag(run.ramp().alpha_rad, 2.0, 1.0).unwrap();
        run.set_parameters(ramp, run.method()).unwrap();
        assert_eq!(run.snapshot().lanes[0].last_crossing_t, before);
        run.advance_to(100.0).unwrap();
        let (lane, lone) = (&run.snapshot().lanes[0], alone.snapshot());
        assert!(lane.period.is_some(), "two crossings by t = 100");
        assert_eq!(lane.period, lone.period);
        assert_eq!(lane.state, lone.state);
    }

    /// The plot data hold every body's series, each in files of its own, named in
    /// plot-data.json with its fate.
    #[test]
    fn the_plot_data_hold_both_bodies_series() {
        let setup = which_one_stops();
        let mut run = LiveRun::new(setup.clone());
        let mut history = PlotHistory::default();
        for k in 1..=40 {
            run.advance_to(f64::from(k)).unwrap();
            history.push(&run.snapshot());
            history.push_samples(run.take_plot_samples());
        }
        assert_eq!(history.lanes(), 1);
        assert_eq!(history.samples().count(), 401);
        assert_eq!(history.lane(1).unwrap().samples().count(), 401);
        let snap = run.snapshot();
        let meta = PlotMeta::of(&snap, &setup, run.method());
        let dir = std::env::temp_dir().join(format!("rollphase-lanes-{}", std::process::id()));
        let inputs = crate::output::Inputs::none();
        let written = history
            .write_csv_files(&dir, Measured::default(), &meta, &inputs)
            .unwrap();
        assert_eq!(written.len(), 6 + 4);
        let series = std::fs::read_to_string(dir.join("series-body-2.csv")).unwrap();
        let json = std::fs::read_to_string(dir.join("plot-data.json")).unwrap();
        std::fs::remove_dir_all(&dir).ok();
        assert_eq!(
            series,
            history
                .lane(1)
                .unwrap()
                .csv(PlotData::Series, Measured::default())
        );
        let rows: Vec<&str> = series.lines().collect();
        assert_eq!(rows[0], "t,theta,theta_dot");
        assert_eq!(rows.len(), 402);
        // The smooth disk turns at sin α exactly: its θ̇ column is the run's.
        let rate: f64 = rows[200].split(',').nth(2).unwrap().parse().unwrap();
        assert!((rate - setup.ramp.alpha_rad.sin()).abs() < 1e-9, "{rate}");
        let meta: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(meta["bodies"][0]["label"], "smooth");
        assert_eq!(meta["bodies"][0]["files"][0], "series-body-2.csv");
        // Each body's shape, start and drag law, as the scene's own body's are given.
        assert_eq!(meta["bodies"][0]["shape"]["perfect"], "disk");
        assert_eq!(meta["bodies"][0]["initial"], meta["initial"]);
        assert_eq!(meta["bodies"][0]["drag_exponent"], 1.0);
        assert_eq!(meta["bodies"][0]["drag_gamma"], 1.0);
        assert_eq!(meta["drag_gamma"], 1.0);
        assert!(meta["friction"].is_null() && meta["bodies"][0]["friction"].is_null());
        assert!(meta["body"]["shape"].is_string(), "{}", meta["body"]);
        assert_eq!(meta["fate"], snap.fate());
        assert_eq!(meta["bodies"][0]["fate"], snap.lanes[0].fate());
    }

    /// The period-doubling lesson's comparison step says the body at m/m0 = 2 is on period 1
    /// and the one at 4.5 on period 2: their own runs say so by the step's end.
    #[test]
    fn the_doubling_comparison_shows_period_1_beside_period_2() {
        let setup = Scene::preset("lesson-period-doubling")
            .unwrap()
            .setup(None)
            .unwrap();
        let end = setup.scene.playback.end_time.unwrap();
        let mut run = LiveRun::new(setup);
        let mut history = PlotHistory::default();
        for k in 1..=end.ceil() as u32 {
            run.advance_to(f64::from(k).min(end)).unwrap();
            history.push(&run.snapshot());
        }
        let snap = run.snapshot();
        assert!(snap.views.lanes, "the last step shows them");
        let k: Vec<Option<usize>> = snap.lanes.iter().map(|l| l.period_multiplicity).collect();
        assert_eq!(k, [Some(1), Some(2)], "m/m0 = 2 and 4.5");
        assert!(
            snap.lanes
                .iter()
                .all(|l| l.fate().starts_with("periodic: period"))
        );
        // The crossings plot shows it too: each body's settled crossings at its own m/m0, the
        // last of them on one branch at 2 and on two at 4.5.
        for (body, mass, branches) in [(1, 2.0, 1), (2, 4.5, 2)] {
            let points = history.crossings_of_body(body);
            assert!(points.len() >= branches, "body {body}: {points:?}");
            assert!(
                points.iter().all(|p| p[0] == mass),
                "body {body}: {points:?}"
            );
            let mut last: Vec<f64> = points.iter().rev().take(6).map(|p| p[1]).collect();
            last.sort_by(f64::total_cmp);
            let gaps = last.windows(2).filter(|w| w[1] - w[0] > 0.02).count();
            assert_eq!(gaps + 1, branches, "body {body}: {last:?}");
        }
    }

    /// A body whose entry takes the scene's body shares its contact map; one of another shape
    /// does not.
    #[test]
    fn a_body_shares_the_contact_map_only_when_it_is_the_same_body() {
        let mut scene = Scene::preset("lesson-period-doubling").unwrap();
        scene.bodies[1].body = Some(crate::scene::BodySpec {
            perfect: Some(crate::scene::PerfectBody::Sphere),
            ..Default::default()
        });
        let snap = LiveRun::new(scene.setup(None).unwrap()).snapshot();
        assert!(snap.shares_body);
        let shares: Vec<bool> = snap.lanes.iter().map(|l| l.shares_body).collect();
        assert_eq!(shares, [true, false]);
    }

    /// With the scene's SO(3) ball shown, each other body's orientation is followed too, for
    /// the ball to draw its path in its colour; with the ball off, none is.
    #[test]
    fn each_bodys_path_is_followed_in_the_ball_while_it_is_shown() {
        let setup = Scene::preset("lesson-period-doubling")
            .unwrap()
            .setup(None)
            .unwrap();
        assert!(setup.scene.views.ball);
        let mut views = setup.scene.views.clone();
        let mut run = LiveRun::new(setup);
        run.advance_to(60.0).unwrap();
        let snap = run.snapshot();
        for lane in &snap.lanes {
            assert!(lane.ball_point.is_some(), "{}", lane.label);
            assert!(lane.ball_trail.iter().map(Vec::len).sum::<usize>() > 10);
        }
        views.ball = false;
        run.set_views(&views);
        run.advance_to(61.0).unwrap();
        assert!(run.snapshot().lanes.iter().all(|l| l.ball_point.is_none()));
    }

    /// A change of α, by a lesson's step or by hand, reaches every body's plotted samples from
    /// its time on: none is left from the old ramp by a step that had reached beyond it.
    #[test]
    fn samples_after_a_change_of_alpha_are_of_the_new_ramp() {
        let text = "name = \"two\"\n[body]\nperfect = \"disk\"\n[model]\nalpha_rad = 0.2\n\
                    [[timeline]]\nat = 0.5\nalpha_rad = 0.4\n[[bodies]]\nlabel = \"b\"\n";
        let setup = Scene::from_toml(text).unwrap().setup(None).unwrap();
        let mut run = LiveRun::new(setup);
        let mut samples = Vec::new();
        let mut t = 0.0;
        for k in 1..=60 {
            t = f64::from(k) * 0.13;
            run.advance_to(t).unwrap();
            samples.extend(run.take_plot_samples());
            if k == 30 {
                // By hand, mid-run: from the time shown on.
                let ramp = crate::dynamics::Ramp::with_drag(0.3, 0.0, 1.0).unwrap();
                run.set_parameters(ramp, run.method()).unwrap();
            }
        }
        let hand = 30.0 * 0.13;
        for body in [0, 1] {
            let series: Vec<_> = samples.iter().filter(|s| s.body == body).collect();
            assert_eq!(series.len(), 1 + (t / 0.1).floor() as usize, "body {body}");
            for s in series {
                let alpha = if s.t <= 0.5 {
                    0.2
                } else if s.t <= hand {
                    0.4
                } else {
                    0.3
                };
                // A perfect disk's viscous θ̇ is sin α exactly.
                assert!(
                    (s.rate - f64::sin(alpha)).abs() < 1e-9,
                    "body {body} at t = {}: θ̇ = {} on the ramp at {alpha}",
                    s.t,
                    s.rate
                );
            }
        }
    }
}
