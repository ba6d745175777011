//! The plots against time of every body the view shows: each body's rate (θ̇ or |ω|), its
//! numerical health and the ramp's contact force on it. Alone, the scene's own body's health
//! quantities and its N/F and μ needed are drawn one by one; with the other bodies shown, each
//! body is one colour (the 3D view's, the overlay's), so the health plot draws each body's worst
//! quantity and the force plot each body's N/F solid and μ needed dashed.

use egui::Color32;
use egui_plot::{Line, LineStyle, Plot, PlotPoints};

use crate::live::Snapshot;
use crate::live::history::{PlotHistory, Sample, health_quantities};

use super::{Key, SERIES_COLORS, Swatch, instrument, keyed};

/// A body whose series a plot draws: its name, its colour, its samples and what its model's
/// health measures.
struct ShownBody<'a> {
    label: &'a str,
    colour: Color32,
    history: &'a PlotHistory,
    measured: crate::live::Measured,
}

fn body_colour(n: usize) -> Color32 {
    let [r, g, b] = crate::colormap::body_colour(n);
    Color32::from_rgb(r, g, b)
}

/// The scene's own body, then each other body while the view shows them.
fn shown_bodies<'a>(history: &'a PlotHistory, snap: &'a Snapshot) -> Vec<ShownBody<'a>> {
    let mut bodies = vec![ShownBody {
        label: snap.label.as_str(),
        colour: body_colour(0),
        history,
        measured: snap.health.measured,
    }];
    if snap.views.lanes {
        for (n, lane) in snap.lanes.iter().enumerate() {
            if let Some(h) = history.lane(n + 1) {
                bodies.push(ShownBody {
                    label: lane.label.as_str(),
                    colour: body_colour(n + 1),
                    history: h,
                    measured: lane.health.measured,
                });
            }
        }
    }
    bodies
}

/// Each body's key: its name in its colour.
fn body_keys<'a>(bodies: &[ShownBody<'a>]) -> Vec<Key<'a>> {
    bodies
        .iter()
        .map(|b| (b.label, b.colour, Swatch::Line))
        .collect()
}

/// Every body on the ramp (the scene's own and its `[[bodies]]`) against time, each in its
/// colour: a cylinder's θ̇, a sphere's |ω|, from each body's own run.
pub(super) fn bodies_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    snap: &Snapshot,
    width: f32,
    height: f32,
) {
    let bodies = shown_bodies(history, snap);
    let keys = body_keys(&bodies);
    let axis = if snap.theta.is_some() {
        "dθ/dt"
    } else {
        "|ω|"
    };
    keyed(ui, width, height, &keys, |ui, plot_height| {
        instrument(Plot::new("bodies_rate"), "t", axis)
            .width(width)
            .height(plot_height)
            .x_axis_label("t")
            .y_axis_label(axis)
            .include_y(0.0)
            .show(ui, |p| {
                for b in &bodies {
                    let points: PlotPoints = b.history.plotted().map(|s| [s.t, s.rate]).collect();
                    p.line(Line::new(b.label, points).color(b.colour));
                }
            });
    });
}

/// The contact force against time: N/F and the friction rolling needs, with the scene's μ
/// (when it has one) and N = 0 as the lines the model must stay within.
pub(super) fn force_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    snap: &Snapshot,
    width: f32,
    height: f32,
) {
    let bodies = shown_bodies(history, snap);
    let friction = snap.contact.friction;
    let red = Color32::from_rgb(230, 60, 50);
    let normal =
        |h: &PlotHistory| -> PlotPoints { h.plotted().map(|s| [s.t, s.normal_force]).collect() };
    // Where N ≤ 0 no friction holds the body: drawn as a gap, not a line off to infinity.
    let needed = |h: &PlotHistory| -> PlotPoints {
        h.plotted()
            .map(|s| [s.t, s.friction_needed])
            .filter(|p| p[1].is_finite())
            .collect()
    };
    // Alone: N orange, μ needed blue, apart from the surface's red line. With other bodies:
    // each body's colour, N/F solid and μ needed dashed.
    let (orange, blue) = (SERIES_COLORS[1], SERIES_COLORS[0]);
    let mut keys: Vec<Key<'_>> = if bodies.len() == 1 {
        vec![
            ("N/F", orange, Swatch::Line),
            ("μ needed", blue, Swatch::Line),
        ]
    } else {
        let mut keys = body_keys(&bodies);
        keys.push(("dashed: μ needed", Color32::LIGHT_GRAY, Swatch::Line));
        keys
    };
    keys.push(("N = 0", Color32::GRAY, Swatch::Line));
    if friction.is_some() {
        keys.push(("surface μ", red, Swatch::Line));
    }
    keyed(ui, width, height, &keys, |ui, plot_height| {
        instrument(Plot::new("contact_force"), "t", "force / F")
            .width(width)
            .height(plot_height)
            .x_axis_label("t")
            .y_axis_label("N/F, μ")
            .include_y(0.0)
            .show(ui, |p| {
                if let [only] = bodies.as_slice() {
                    p.line(Line::new("N/F", normal(only.history)).color(orange));
                    p.line(Line::new("μ needed", needed(only.history)).color(blue));
                } else {
                    for b in &bodies {
                        p.line(
                            Line::new(format!("{}: N/F", b.label), normal(b.history))
                                .color(b.colour),
                        );
                        p.line(
                            Line::new(format!("{}: μ needed", b.label), needed(b.history))
                                .color(b.colour)
                                .style(LineStyle::dashed_dense()),
                        );
                    }
                }
                p.hline(egui_plot::HLine::new("N = 0", 0.0).color(Color32::GRAY));
                if let Some(mu) = friction {
                    p.hline(egui_plot::HLine::new("surface μ", mu).color(red));
                }
            });
    });
}

/// Whether any body the plots show has a health quantity to draw (a constraint or a conserved
/// quantity its model can drift from).
pub(super) fn health_measures(history: &PlotHistory, snap: &Snapshot) -> bool {
    shown_bodies(history, snap)
        .iter()
        .any(|b| !health_quantities(b.measured).is_empty())
}

/// The numerical health against time, on a log scale: alone, each quantity the running model
/// has; with other bodies, each body's worst quantity in its colour (its own model's).
pub(super) fn health_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    snap: &Snapshot,
    width: f32,
    height: f32,
) {
    let log = |v: f64| v.max(1e-17).log10();
    let bodies = shown_bodies(history, snap);
    // Only what the running model has (flat lines at the floor said nothing).
    let measuring: Vec<&ShownBody<'_>> = bodies
        .iter()
        .filter(|b| !health_quantities(b.measured).is_empty())
        .collect();
    if measuring.is_empty() {
        ui.allocate_ui(egui::vec2(width, height), |ui| {
            ui.vertical_centered(|ui| {
                ui.add_space(height * 0.35);
                ui.label("health: this model has no constraint or conserved quantity to drift");
                ui.label(egui::RichText::new("(θ is integrated directly)").weak());
            });
        });
        return;
    }
    let quantities = health_quantities(snap.health.measured);
    let keys: Vec<Key<'_>> = if bodies.len() == 1 {
        quantities
            .iter()
            .zip(SERIES_COLORS.iter().cycle())
            .map(|(q, &c)| (q.label, c, Swatch::Line))
            .collect()
    } else {
        let mut keys: Vec<Key<'_>> = measuring
            .iter()
            .map(|b| (b.label, b.colour, Swatch::Line))
            .collect();
        keys.push((
            "each body's worst quantity",
            Color32::LIGHT_GRAY,
            Swatch::Line,
        ));
        keys
    };
    keyed(ui, width, height, &keys, |ui, plot_height| {
        instrument(Plot::new("health"), "t", "log₁₀ error")
            .width(width)
            .height(plot_height)
            .x_axis_label("t")
            .y_axis_label("log₁₀ error")
            .include_y(-16.0)
            .show(ui, |p| {
                if bodies.len() == 1 {
                    for (q, &(label, color, _)) in quantities.iter().zip(&keys) {
                        let points: PlotPoints = history
                            .plotted()
                            .map(|s| [s.t, log((q.value)(s))])
                            .collect();
                        p.line(Line::new(label, points).color(color));
                    }
                    return;
                }
                for b in &measuring {
                    let own = health_quantities(b.measured);
                    let worst = |s: &Sample| own.iter().map(|q| (q.value)(s)).fold(0.0, f64::max);
                    let points: PlotPoints =
                        b.history.plotted().map(|s| [s.t, log(worst(s))]).collect();
                    p.line(Line::new(b.label, points).color(b.colour));
                }
            });
    });
}

#[cfg(test)]
mod tests {
    use crate::live::LiveRun;
    use crate::live::history::PlotHistory;
    use crate::scene::Scene;
    use crate::ui::workbench::offscreen_input;

    /// The words the plots row draws for `preset` run to t = `until` in a panel `width` points
    /// wide (the keys' labels, the axes, the health plot's note).
    fn plot_words(scene: Scene, until: f64, width: f32) -> Vec<String> {
        plot_words_changing(scene, until, width, |_, _| {})
    }

    /// [`plot_words`] with `change` called on the run before each whole time unit `k`.
    fn plot_words_changing(
        scene: Scene,
        until: f64,
        width: f32,
        change: impl Fn(&mut LiveRun, u32),
    ) -> Vec<String> {
        let mut run = LiveRun::new(scene.setup(None).unwrap());
        let mut history = PlotHistory::default();
        for k in 1..=until as u32 {
            change(&mut run, k);
            run.advance_to(f64::from(k)).unwrap();
            history.push(&run.snapshot());
            history.push_samples(run.take_plot_samples());
        }
        let snap = run.snapshot();
        let ctx = egui::Context::default();
        let mut words = Vec::new();
        for frame in 0..2 {
            let input = offscreen_input((width as u32, 400), f64::from(frame) / 60.0, Vec::new());
            let mut output = ctx.run_ui(input, |ui| {
                egui::CentralPanel::default().show(ui, |ui| {
                    super::super::plots_ui(ui, &history, &snap, None, snap.alpha_star, 220.0);
                });
            });
            output.textures_delta.clear();
            words = output
                .shapes
                .iter()
                .filter_map(|c| match &c.shape {
                    egui::Shape::Text(t) => Some(t.galley.text().to_string()),
                    _ => None,
                })
                .collect();
        }
        words
    }

    fn preset(name: &str) -> Scene {
        Scene::preset(name).unwrap()
    }

    /// The crossings plot draws the points measured under another drag law as a series of their
    /// own, named by the law: at one m/m0 they are another orbit, not a branch of this one.
    #[test]
    fn crossings_under_another_drag_law_are_a_series_of_their_own() {
        let words = plot_words_changing(preset("sphere-cruising"), 1000.0, 1900.0, |run, k| {
            if k == 500 {
                let law = crate::dynamics::DragLaw::LINEAR
                    .with("drag_exponent", 2.0)
                    .unwrap();
                let ramp = run.ramp().with_drag_law(law);
                run.set_parameters(ramp, run.method()).unwrap();
            }
        });
        let has = |s: &str| words.iter().any(|t| t == s);
        assert!(
            has("∂Ω crossings, settled") && has("linear drag"),
            "{words:?}"
        );
    }

    /// With the other bodies shown, each body is in the force plot in its colour, and a health
    /// plot with nothing to measure (viscous cylinders) gives the force plot its place.
    #[test]
    fn every_shown_body_is_in_the_force_plot() {
        let wide = plot_words(preset("which-one-stops"), 30.0, 1900.0);
        let has = |w: &[String], s: &str| w.iter().any(|t| t.contains(s));
        for word in ["dashed: μ needed", "smooth", "N = 0", "N/F, μ"] {
            assert!(has(&wide, word), "{word:?} not in {wide:?}");
        }
        assert!(
            !has(&wide, "no constraint or conserved quantity"),
            "{wide:?}"
        );
        // At 1,060 points (the app's 1600×900 window beside its controls) there is room for
        // five plots: the force plot is the fifth, in the health plot's place.
        let narrow = plot_words(preset("which-one-stops"), 30.0, 1060.0);
        assert!(has(&narrow, "dashed: μ needed"), "{narrow:?}");
        // Alone, a body's force plot names N/F and μ needed, as before.
        let alone = plot_words(preset("cylinder-near-critical"), 30.0, 1900.0);
        assert!(
            has(&alone, "μ needed") && !has(&alone, "dashed: μ needed"),
            "{alone:?}"
        );
    }

    /// With the other bodies shown, the health plot draws each body's worst quantity, named by
    /// the body (the doubling lesson's last step: three inertial spheres).
    #[test]
    fn every_shown_body_is_in_the_health_plot() {
        let mut scene = preset("lesson-period-doubling");
        scene.views.lanes = true;
        scene.timeline.clear();
        let words = plot_words(scene.clone(), 20.0, 1900.0);
        let has = |s: &str| words.iter().any(|t| t.contains(s));
        for word in [
            "each body's worst quantity",
            "this one",
            "m/m0 = 2",
            "m/m0 = 4.5",
        ] {
            assert!(has(word), "{word:?} not in {words:?}");
        }
        // The body's own quantities are not named one by one then; and the contact map, of the
        // body the three share, names each body's path instead of one "contact path".
        assert!(!has("||q|−1|") && !has("contact path"), "{words:?}");
        assert!(has("colour: curvature K"), "{words:?}");
        scene.bodies.clear();
        let alone = plot_words(scene, 20.0, 1900.0);
        assert!(alone.iter().any(|t| t.contains("||q|−1|")), "{alone:?}");
        assert!(
            alone.iter().any(|t| t.contains("contact path")),
            "{alone:?}"
        );
    }
}
