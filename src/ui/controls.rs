//! The menu bar and the control panels: playback, α and m/m0, the integrator, the body, the
//! views.

use egui::{Color32, RichText};

use crate::geometry::Body;
use crate::integrate::{Method, Preset};
use crate::scene::{BodySpec, PRESETS, Scene};
use crate::sim::{SimCommand, SimStatus};

use super::{ALPHA_MAX, AppUi, MASS_RANGE, SPEED_RANGE, UiAction};

impl AppUi {
    pub(super) fn menu_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<UiAction>) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("Presets", |ui| {
                // Scenes first, then the lessons (scenes with a [[timeline]]) under a heading.
                let scenes: Vec<(&str, Scene)> = PRESETS
                    .iter()
                    .filter_map(|(name, text)| Some((*name, Scene::from_toml(text).ok()?)))
                    .collect();
                for lessons in [false, true] {
                    if lessons {
                        ui.separator();
                        ui.label(RichText::new("Lessons (N / B: next / previous step)").weak());
                    }
                    for (name, scene) in scenes
                        .iter()
                        .filter(|(_, s)| s.timeline.is_empty() != lessons)
                    {
                        if ui.button(*name).on_hover_text(&scene.description).clicked() {
                            self.load_preset(name, actions);
                            ui.close();
                        }
                    }
                }
            });
            ui.menu_button("View", |ui| {
                ui.checkbox(&mut self.show_controls, "Controls (H)");
                ui.checkbox(&mut self.show_plots, "Plots (P)");
                ui.checkbox(&mut self.view_options.follow, "Follow the body (F)");
                let mut class = self.class_mode;
                if ui.checkbox(&mut class, "Class mode (C)").changed() {
                    let ctx = ui.ctx().clone();
                    self.set_class_mode(&ctx, class, actions);
                }
                if ui.button("Reset camera").clicked() {
                    self.reset_camera();
                }
            });
            ui.separator();
            ui.label(RichText::new(&self.scene.name).strong());
            ui.label(RichText::new(&self.scene.description).weak());
        });
    }

    pub(super) fn controls_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let snap = &status.snapshot;
        if snap.lesson.is_some() {
            self.lesson_ui(ui, status, actions);
            ui.separator();
        }
        ui.heading("Playback");
        ui.horizontal(|ui| {
            let label = if status.paused { "Play" } else { "Pause" };
            if ui.button(label).on_hover_text("Space").clicked() {
                actions.push(UiAction::Sim(if status.paused {
                    SimCommand::Play
                } else {
                    SimCommand::Pause
                }));
            }
            if ui.button("Step").on_hover_text("→").clicked() {
                actions.push(UiAction::Sim(SimCommand::Step));
            }
            if ui.button("Reset").on_hover_text("R").clicked() {
                actions.push(UiAction::Sim(SimCommand::Reset));
            }
        });
        let speed = egui::Slider::new(&mut self.speed, SPEED_RANGE.0..=SPEED_RANGE.1)
            .logarithmic(true)
            .text("speed (t per s)");
        if ui
            .add(speed)
            .on_hover_text("+ / − double or halve")
            .changed()
        {
            actions.push(UiAction::Sim(SimCommand::SetSpeed(self.speed)));
        }
        self.status_ui(ui, status);

        ui.separator();
        ui.heading("Ramp");
        ui.label(format!(
            "α = {:.4} rad = {:.2}°   (α* = {:.4} rad = {:.2}°)",
            self.alpha,
            self.alpha.to_degrees(),
            snap.alpha_star,
            snap.alpha_star.to_degrees()
        ));
        let response = ui.add(
            egui::Slider::new(&mut self.alpha, 0.001..=ALPHA_MAX)
                .show_value(false)
                .step_by(0.0),
        );
        mark_on_slider(ui, &response, snap.alpha_star, 0.001..=ALPHA_MAX, "α*");
        if response.changed() {
            actions.push(UiAction::Sim(SimCommand::SetAlpha(self.alpha)));
        }
        ui.horizontal(|ui| {
            for (label, factor) in [
                ("0.9 α*", 0.9),
                ("α*", 1.0),
                ("1.05 α*", 1.05),
                ("2 α*", 2.0),
            ] {
                if ui.small_button(label).clicked() && snap.alpha_star > 0.0 {
                    self.alpha = (factor * snap.alpha_star).clamp(0.001, ALPHA_MAX);
                    actions.push(UiAction::Sim(SimCommand::SetAlpha(self.alpha)));
                }
            }
        });
        let was = self.inertial;
        ui.checkbox(&mut self.inertial, "inertia (m/m0 > 0; off: viscous model)");
        let mass = ui.add_enabled(
            self.inertial,
            egui::Slider::new(&mut self.mass_ratio, MASS_RANGE.0..=MASS_RANGE.1)
                .logarithmic(true)
                .text("m/m0"),
        );
        if was != self.inertial || (self.inertial && mass.changed()) {
            let m = if self.inertial { self.mass_ratio } else { 0.0 };
            actions.push(UiAction::Sim(SimCommand::SetMassRatio(m)));
        }
        ui.label(format!("model: {}", snap.model));

        ui.separator();
        ui.heading("Integrator");
        self.integrator_ui(ui, status, actions);

        ui.separator();
        ui.heading("Body");
        self.body_ui(ui, status, actions);

        ui.separator();
        ui.heading("Views");
        self.views_ui(ui, status, actions);

        ui.separator();
        ui.heading("Files");
        self.files_ui(ui, status, actions);
        if let Some((text, error)) = &self.notice {
            let color = if *error {
                Color32::from_rgb(230, 90, 80)
            } else {
                Color32::from_rgb(120, 200, 120)
            };
            ui.label(RichText::new(text).color(color));
        }
    }

    /// The lesson's place, its caption, and buttons for the previous and next step.
    fn lesson_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let snap = &status.snapshot;
        let Some(lesson) = snap.lesson else {
            return;
        };
        ui.heading("Lesson");
        let next = match lesson.next_at {
            Some(at) => format!("next at t = {at}"),
            None => "last step".into(),
        };
        ui.label(format!("step {} of {} ({next})", lesson.done, lesson.steps));
        if let Some(caption) = &snap.caption {
            ui.label(RichText::new(caption).strong());
        }
        ui.horizontal(|ui| {
            if ui
                .button("Previous step")
                .on_hover_text("B or Page Up")
                .clicked()
            {
                actions.push(UiAction::Sim(SimCommand::PreviousStep));
            }
            if ui
                .add_enabled(lesson.next_at.is_some(), egui::Button::new("Next step"))
                .on_hover_text("N or Page Down")
                .clicked()
            {
                actions.push(UiAction::Sim(SimCommand::NextStep));
            }
        });
    }

    pub(super) fn status_ui(&self, ui: &mut egui::Ui, status: &SimStatus) {
        let snap = &status.snapshot;
        let state = if status.paused { "paused" } else { "playing" };
        ui.label(format!("t = {:.2}   {state}", snap.t));
        let order = if snap.halted {
            "halted: 1/T = 0".to_string()
        } else {
            match snap.period {
                Some(p) => format!(
                    "T = {p:.4}, 1/T = {:.4}{}",
                    1.0 / p,
                    crate::view::multiplicity_text(snap.period_multiplicity)
                ),
                None => "T: measuring…".into(),
            }
        };
        ui.label(order);
        if let Some(d) = status.delivered_speed {
            ui.label(format!(
                "delivering {d:.2} of {:.2} t per s (tick {:.1} ms)",
                status.speed,
                status.tick_seconds * 1e3
            ));
        }
        if status.lagging {
            ui.label(
                RichText::new(
                    "⚠ the simulation cannot keep up with this speed at this integrator \
                     setting: lower the speed or pick a faster preset",
                )
                .color(Color32::from_rgb(240, 170, 40)),
            );
        }
        if let Some(fps) = self.fps {
            ui.label(format!("window: {fps:.0} frames/s"));
        }
        if let Some(r) = self.recording {
            ui.label(format!("recording frame {} of {}", r.done, r.total));
        }
        if let Some(m) = &status.message {
            ui.label(RichText::new(m).color(Color32::from_rgb(230, 90, 80)));
        }
    }

    pub(super) fn integrator_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let current = Preset::ALL
            .into_iter()
            .find(|p| p.method() == status.method);
        ui.horizontal(|ui| {
            for preset in Preset::ALL {
                let name = format!("{preset:?}").to_lowercase();
                if ui.selectable_label(current == Some(preset), name).clicked() {
                    actions.push(UiAction::Sim(SimCommand::SetMethod(preset.method())));
                }
            }
        });
        match current {
            Some(p) => {
                ui.label(format!(
                    "{}: expected error at t = 100: state {:.0e}, period {:.0e} (relative)",
                    status.method,
                    p.expected_state_error(),
                    p.expected_period_error()
                ))
                .on_hover_text(
                    "measured over the four models on the bundled bodies (rollphase bench accuracy)",
                );
            }
            None => {
                ui.label(format!(
                    "{}: a custom setting; `rollphase bench accuracy` measures its error",
                    status.method
                ));
            }
        }
        let h = &status.snapshot.health;
        ui.label(format!(
            "health: ||q|−1| {:.1e}, normal {:.1e}, energy {:.1e}; {} RHS evaluations",
            h.quat_norm_error, h.contact_normal_error, h.energy_drift, h.rhs_evals
        ));
    }

    pub(super) fn body_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let body = &status.setup.body;
        ui.label(format!(
            "{}, α* = {:.4} rad ({:.2}°)",
            match body {
                Body::Disk(_) => "cylinder (2D)",
                Body::Sphere(_) => "sphere (3D)",
            },
            status.setup.alpha_star,
            status.setup.alpha_star.to_degrees()
        ));
        // What the body is, so the generator's settings below are not read as the body's.
        ui.label(describe_body(&status.setup.scene.body));
        ui.separator();
        ui.label("a new random body:");
        ui.horizontal(|ui| {
            ui.radio_value(&mut self.random.dimension, 2, "2D cylinder");
            ui.radio_value(&mut self.random.dimension, 3, "3D sphere");
        });
        let max_modes = if self.random.dimension == 2 {
            crate::geometry::MAX_DISK_L
        } else {
            crate::geometry::MAX_SPHERE_L
        };
        ui.add(egui::Slider::new(&mut self.random.seed, 0..=9999).text("seed"));
        ui.add(egui::Slider::new(&mut self.random.sigma, 0.0..=1.0).text("σ"));
        self.random.modes = self.random.modes.clamp(2, max_modes);
        ui.add(egui::Slider::new(&mut self.random.modes, 2..=max_modes).text("modes l ≤"));
        if ui
            .button("Generate body")
            .on_hover_text("a seeded random body at the current α and m/m0")
            .clicked()
        {
            let mut scene = self.current_scene(status);
            scene.body = BodySpec {
                random: Some(self.random),
                ..BodySpec::default()
            };
            scene.initial = crate::scene::InitialSpec::default();
            scene.name = format!(
                "random {}D seed {} σ {}",
                self.random.dimension, self.random.seed, self.random.sigma
            );
            scene.description = "generated in the app".into();
            if self.random.dimension == 2 {
                scene.views.ball = false;
                scene.views.poincare = false;
            }
            self.load_scene(scene, self.base.clone(), actions);
        }
    }

    pub(super) fn views_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let is_disk = matches!(status.setup.body, Body::Disk(_));
        let before = self.views.clone();
        ui.checkbox(&mut self.views.body, "body on the ramp");
        ui.add_enabled(
            !is_disk,
            egui::Checkbox::new(&mut self.views.ball, "SO(3) ball"),
        )
        .on_disabled_hover_text("3D bodies only");
        ui.add_enabled(
            !is_disk,
            egui::Checkbox::new(&mut self.views.poincare, "Poincaré field on ∂Ω"),
        )
        .on_disabled_hover_text("3D bodies only");
        ui.checkbox(&mut self.views.overlay, "text overlay");
        ui.checkbox(&mut self.show_plots, "plots");
        if !(self.views.body || self.views.ball || self.views.poincare) {
            self.views.body = true;
        }
        if let Some(note) = &self.field_note
            && self.views.poincare
        {
            ui.label(RichText::new(note).weak());
        }
        if self.views != before {
            actions.push(UiAction::Sim(SimCommand::SetViews(self.views.clone())));
        }
    }
}

/// Draws a labelled tick below a value-less horizontal slider at `value`.
pub(super) fn mark_on_slider(
    ui: &egui::Ui,
    response: &egui::Response,
    value: f64,
    range: std::ops::RangeInclusive<f64>,
    label: &str,
) {
    let rect = response.rect;
    // egui's circular handle travels over the rail inset by its radius (height / 2.5).
    let inset = rect.height() / 2.5;
    let f = ((value - range.start()) / (range.end() - range.start())) as f32;
    if !(0.0..=1.0).contains(&f) {
        return;
    }
    let x = rect.left() + inset + f * (rect.width() - 2.0 * inset);
    let color = Color32::from_rgb(230, 70, 70);
    let painter = ui.painter();
    painter.line_segment(
        [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
        egui::Stroke::new(2.0, color),
    );
    painter.text(
        egui::pos2(x, rect.bottom()),
        egui::Align2::CENTER_TOP,
        label,
        egui::FontId::proportional(11.0),
        color,
    );
}

pub(super) fn method_spec(method: &Method) -> crate::scene::IntegratorSpec {
    use crate::scene::{IntegratorSpec, MethodName};
    if let Some(p) = Preset::ALL.into_iter().find(|p| p.method() == *method) {
        return IntegratorSpec {
            preset: Some(p),
            ..IntegratorSpec::default()
        };
    }
    match *method {
        Method::Dop853 { rtol, .. } => IntegratorSpec {
            method: Some(MethodName::Dop853),
            rtol: Some(rtol),
            ..IntegratorSpec::default()
        },
        Method::Rk4 { dt } => IntegratorSpec {
            method: Some(MethodName::Rk4),
            dt: Some(dt),
            ..IntegratorSpec::default()
        },
        Method::Cf4 { dt } => IntegratorSpec {
            method: Some(MethodName::Cf4),
            dt: Some(dt),
            ..IntegratorSpec::default()
        },
    }
}

/// Where a scene's body comes from, in words: the paper's own body, a file, an inline shape, a
/// seeded random body of ours, or a perfect one.
pub(super) fn describe_body(spec: &BodySpec) -> String {
    if let Some(path) = &spec.shape {
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        return if name == "paper-sphere.json" {
            "body: the paper's own (the authors' numpy seed 219, σ 0.25, l ≤ 5)".into()
        } else {
            format!("body: shape file {}", path.display())
        };
    }
    if spec.inline.is_some() {
        return "body: a shape given in the scene".into();
    }
    if let Some(r) = &spec.random {
        return format!(
            "body: random {}D, seed {}, σ {}, l ≤ {}",
            r.dimension, r.seed, r.sigma, r.modes
        );
    }
    if let Some(p) = &spec.perfect {
        return format!("body: perfect {p:?}").to_lowercase();
    }
    "body: none given".into()
}

#[cfg(test)]
mod body_tests {
    use super::describe_body;
    use crate::scene::Scene;

    #[test]
    fn the_body_line_names_the_real_body() {
        let doubling = Scene::preset("sphere-doubling").unwrap();
        assert!(
            describe_body(&doubling.body).contains("paper's own"),
            "{}",
            describe_body(&doubling.body)
        );
        let mut random = doubling.clone();
        random.body = crate::scene::BodySpec {
            random: Some(crate::scene::RandomBody {
                dimension: 3,
                seed: 7,
                sigma: 0.25,
                modes: 5,
            }),
            ..Default::default()
        };
        assert_eq!(
            describe_body(&random.body),
            "body: random 3D, seed 7, σ 0.25, l ≤ 5"
        );
    }
}
