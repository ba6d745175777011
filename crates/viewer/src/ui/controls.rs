//! The menu bar and the control panels: playback, α and m/m0, the integrator, the body, the
//! views.

use egui::{Color32, RichText};

use crate::geometry::Body;
use crate::integrate::{Method, Preset};
use crate::live::{SimCommand, SimStatus};
use crate::scene::{BodySpec, PRESETS, Scene};

use super::fields::{FieldOutcome, FineAlpha, NumberLimits, number_field};
use super::measuring_sweep::SweepTarget;
use super::{ALPHA_MAX, ALPHA_MIN, AppUi, MASS_RANGE, SPEED_RANGE, UiAction};

/// The α field's id (tests focus it through egui's memory).
pub const ALPHA_FIELD: &str = "alpha-field";
/// The m/m0 field's id.
pub const MASS_FIELD: &str = "mass-field";

/// The α and m/m0 rails' width in points.
const SLIDER_WIDTH: f32 = 260.0;
const ERROR: Color32 = Color32::from_rgb(230, 90, 80);
const GOOD: Color32 = Color32::from_rgb(120, 200, 120);

impl AppUi {
    pub(super) fn menu_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        egui::MenuBar::new().ui(ui, |ui| {
            self.file_menu_ui(ui, status, actions);
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
                let mut present = self.presenting;
                if ui.checkbox(&mut present, "Presentation (F5)").changed() {
                    let ctx = ui.ctx().clone();
                    self.set_presentation(&ctx, present, actions);
                }
                ui.checkbox(&mut self.show_keys, "Keys (?)");
                let mut class = self.class_mode;
                if ui.checkbox(&mut class, "Class mode (C)").changed() {
                    let ctx = ui.ctx().clone();
                    self.set_class_mode(&ctx, class, actions);
                }
                ui.checkbox(&mut self.full_resolution, "3D at full resolution")
                    .on_hover_text(
                        "On a CPU renderer the 3D view is drawn at a lower resolution when \
                         frames would take longer than 1/30 s (never below half; the status bar \
                         says \"3D at 70 %\"). Tick to always draw it in full.",
                    );
                if ui.button("Reset camera").clicked() {
                    self.reset_camera();
                }
            });
            ui.separator();
            ui.label(RichText::new(&self.scene.name).strong());
            // One line, elided with its whole text on hover: a lesson's description is longer
            // than the bar.
            ui.add(egui::Label::new(RichText::new(&self.scene.description).weak()).truncate());
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
        // Typed values are not clamped: one outside the range is refused with a word, as α and
        // m/m0 are (1e9 became 1000 and −5 became 0.05 without one).
        let speed = egui::Slider::new(&mut self.speed, SPEED_RANGE.0..=SPEED_RANGE.1)
            .logarithmic(true)
            .clamping(egui::SliderClamping::Never)
            .text("speed (t per s)");
        if ui
            .add(speed)
            .on_hover_text("+ / − double or halve")
            .changed()
        {
            if let Some(refused) = speed_refusal(self.speed) {
                self.notice = Some((refused, true));
                self.speed = status.speed;
            } else {
                actions.push(UiAction::Sim(SimCommand::SetSpeed(self.speed)));
            }
        }
        self.status_ui(ui, status);

        ui.separator();
        ui.heading("Ramp");
        // Rails as wide as the panel's default width allows (egui's are 100 px): a wider rail is
        // a finer one. A fixed width: one taken from the available width would widen the
        // resizable panel frame after frame.
        ui.spacing_mut().slider_width = SLIDER_WIDTH;
        self.alpha_field_ui(ui, snap.alpha_star, actions);
        // The rail is finest at α*, where the transition is: equal steps of the handle are
        // equal ratios of |α − α*| (FineAlpha), from 10⁻⁴ rad up to the ends.
        let scale = FineAlpha::new(snap.alpha_star);
        let mut position = scale.position(self.alpha);
        let response = ui
            .add(
                egui::Slider::new(&mut position, -1.0..=1.0)
                    .show_value(false)
                    .step_by(0.0),
            )
            .on_hover_text("finest near α*: each step is a fixed ratio of |α − α*|");
        mark_on_slider(ui, &response, 0.0, -1.0..=1.0, "α*");
        if response.changed() {
            self.alpha = scale.alpha(position);
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
                    self.alpha = (factor * snap.alpha_star).clamp(ALPHA_MIN, ALPHA_MAX);
                    actions.push(UiAction::Sim(SimCommand::SetAlpha(self.alpha)));
                }
            }
        });
        let was = self.inertial;
        ui.checkbox(&mut self.inertial, "inertia (m/m0 > 0; off: viscous model)");
        let mut mass_changed = false;
        ui.add_enabled_ui(self.inertial, |ui| {
            ui.horizontal(|ui| {
                ui.label("m/m0");
                let limits = NumberLimits {
                    name: "m/m0",
                    unit: "",
                    range: MASS_RANGE,
                };
                match number_field(
                    ui,
                    MASS_FIELD,
                    self.mass_ratio,
                    &mut self.mass_edit,
                    &limits,
                ) {
                    FieldOutcome::Committed(mass) => {
                        self.mass_ratio = mass;
                        mass_changed = true;
                    }
                    FieldOutcome::Refused(why) => self.notice = Some((why, true)),
                    FieldOutcome::Unchanged => {}
                }
            });
            mass_changed |= ui
                .add(
                    egui::Slider::new(&mut self.mass_ratio, MASS_RANGE.0..=MASS_RANGE.1)
                        .logarithmic(true)
                        .show_value(false),
                )
                .changed();
        });
        if was != self.inertial || (self.inertial && mass_changed) {
            let m = if self.inertial { self.mass_ratio } else { 0.0 };
            actions.push(UiAction::Sim(SimCommand::SetMassRatio(m)));
        }
        drag_law_ui(ui, &snap.drag_law, actions);
        ui.label(format!("model: {}", snap.model));
        self.measuring_sweep_ui(ui);

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
    }

    /// The bar along the window's bottom, always shown: the latest notice (saved, loaded, a bad
    /// file's reason, in red for an error) and the simulation's refusal, if any. Messages used to
    /// end the scrolling controls panel, often off-screen.
    pub(super) fn status_bar_ui(&self, ui: &mut egui::Ui, status: &SimStatus) {
        ui.horizontal_wrapped(|ui| {
            let snap = &status.snapshot;
            let state = if status.paused { "paused" } else { "playing" };
            ui.label(RichText::new(format!("t = {:>9.2}  {state}", snap.t)).monospace());
            ui.separator();
            if let Some(note) = &self.render_scale_note {
                ui.label(RichText::new(note).weak()).on_hover_text(
                    "the 3D view is drawn at this share of its width and height to keep 30 \
                     frames/s on this CPU renderer; View ▸ 3D at full resolution draws it in full",
                );
                ui.separator();
            }
            if let Some(r) = self.recording {
                ui.label(format!("recording frame {} of {}", r.done, r.total));
                ui.separator();
            }
            if let Some(sweep) = self.measuring_sweep {
                let line = sweep.describe(&self.sweep_hold);
                let line = if status.paused {
                    format!("{line} (paused)")
                } else {
                    line
                };
                ui.label(RichText::new(line).color(GOOD));
                ui.separator();
            }
            if status.lagging {
                ui.label(
                    RichText::new(
                        "⚠ the simulation cannot keep up with this speed at this integrator \
                         setting: lower the speed or pick a faster preset",
                    )
                    .color(Color32::from_rgb(240, 170, 40)),
                );
                ui.separator();
            }
            if let Some(m) = &status.message {
                ui.label(RichText::new(m).color(ERROR));
            } else if let Some(i) = &status.info {
                ui.label(RichText::new(i).color(GOOD));
            } else if let Some((text, error)) = &self.notice {
                ui.label(RichText::new(text).color(if *error { ERROR } else { GOOD }));
            } else {
                ui.label(RichText::new("ready").weak());
            }
        });
    }

    /// The α field (applied on Enter or focus loss) with α in degrees and α* beside it.
    fn alpha_field_ui(&mut self, ui: &mut egui::Ui, alpha_star: f64, actions: &mut Vec<UiAction>) {
        // Wrapped: class mode's large text leaves the degrees and α* no room beside the field.
        ui.horizontal_wrapped(|ui| {
            ui.label("α");
            let limits = NumberLimits {
                name: "α",
                unit: " rad",
                range: (ALPHA_MIN, ALPHA_MAX),
            };
            match number_field(ui, ALPHA_FIELD, self.alpha, &mut self.alpha_edit, &limits) {
                FieldOutcome::Committed(alpha) => {
                    self.alpha = alpha;
                    actions.push(UiAction::Sim(SimCommand::SetAlpha(alpha)));
                }
                FieldOutcome::Refused(why) => self.notice = Some((why, true)),
                FieldOutcome::Unchanged => {}
            }
            ui.label(format!(
                "rad = {:.3}°   α* = {:.5} rad = {:.3}°",
                self.alpha.to_degrees(),
                alpha_star,
                alpha_star.to_degrees()
            ));
        });
    }

    /// The measuring sweep of α or m/m0 (a live bifurcation diagram): which, and the step.
    fn measuring_sweep_ui(&mut self, ui: &mut egui::Ui) {
        // Wrapped: in class mode's third of the screen the row does not fit on one line.
        ui.horizontal_wrapped(|ui| {
            let mut on = self.measuring_sweep.is_some();
            if ui
                .checkbox(&mut on, "sweep")
                .on_hover_text(format!(
                    "holds α or m/m0 until the run there is measured (its period settled to \
                     1e-3, the body halted, or its cycle of ∂Ω crossings found; at most {} t), \
                     so the 1/T or crossing plot gets its point, then steps: the bifurcation \
                     diagram grows as the sweep runs",
                    super::measuring_sweep::HOLD_CAP
                ))
                .changed()
            {
                self.set_measuring_sweep(on.then_some(self.sweep_choice));
            }
            let mut choice = self.sweep_choice;
            egui::ComboBox::from_id_salt("sweep_what")
                .selected_text(choice.target.name())
                .show_ui(ui, |ui| {
                    for t in SweepTarget::ALL {
                        if ui
                            .selectable_value(&mut choice.target, t, t.name())
                            .changed()
                        {
                            choice.step = t.default_step();
                            choice.end = None;
                        }
                    }
                });
            let target = choice.target;
            ui.add(
                egui::DragValue::new(&mut choice.step)
                    .range(-1.0..=1.0)
                    .speed(1e-4)
                    .custom_formatter(move |step, _| target.shown_step(step))
                    .custom_parser(move |text| target.parse_step(text)),
            )
            .on_hover_text(choice.target.step_hint());
            ui.label("per point");
            // Where it stops: without an end a sweep ran on to the end of the slider's range
            // (m/m0 = 50) and then sat there.
            let (lo, hi) = choice.target.range();
            let mut bounded = choice.end.is_some();
            ui.checkbox(&mut bounded, "until").on_hover_text(
                "the last value the sweep takes; off: the end of the slider's range",
            );
            if bounded {
                let mut end = choice
                    .end
                    .unwrap_or(if choice.step < 0.0 { lo } else { hi });
                ui.add(
                    egui::DragValue::new(&mut end)
                        .range(lo..=hi)
                        .speed(1e-3)
                        .max_decimals(5),
                );
                choice.end = Some(end);
            } else {
                choice.end = None;
            }
            if choice != self.sweep_choice {
                let other_target = choice.target != self.sweep_choice.target;
                self.sweep_choice = choice;
                if self.measuring_sweep.is_some() {
                    if other_target {
                        self.set_measuring_sweep(Some(choice));
                    } else {
                        self.measuring_sweep = Some(choice);
                    }
                }
            }
        });
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

    /// The playback status: always the same four lines (paused or playing, measuring or not),
    /// so the controls below never jump; warnings go to the status bar.
    pub(super) fn status_ui(&self, ui: &mut egui::Ui, status: &SimStatus) {
        let snap = &status.snapshot;
        let state = if status.paused { "paused" } else { "playing" };
        ui.label(format!("t = {:.2}   {state}", snap.t));
        let left_at = snap.contact.violations().first().map(|v| v.t());
        let order = if let Some(t) = left_at {
            // The verdict's `left_model`: no period is the body's past it.
            format!("left the model at t = {t:.2}")
        } else if snap.halted {
            "halted: 1/T = 0".to_string()
        } else {
            match snap.stated_period() {
                // Before the cycle is decided the last crossings' spacing is no period of it
                // (half of it on a doubled orbit): said for what it is.
                Some((p, crate::live::PeriodSpan::LastCrossings)) => {
                    format!("∂Ω to ∂Ω: {p:.4} (no cycle yet)")
                }
                Some((p, _)) => format!(
                    "T = {p:.4}, 1/T = {:.4}{}",
                    1.0 / p,
                    crate::view::multiplicity_text(snap.period_multiplicity)
                ),
                None => "T: measuring…".into(),
            }
        };
        ui.label(order);
        ui.label(match status.delivered_speed {
            Some(d) => format!(
                "delivering {d:.2} of {:.2} t per s (tick {:.1} ms)",
                status.speed,
                status.tick_seconds * 1e3
            ),
            None => format!("delivering — of {:.2} t per s", status.speed),
        });
        ui.label(match self.fps {
            Some(fps) => format!("window: {fps:.0} frames/s"),
            None => "window: — frames/s".into(),
        });
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
        // Only the quantities the model has (a cylinder has no |q|, a viscous model no energy).
        let mut parts: Vec<String> = [
            (h.measured.quat_norm, "||q|−1|", h.quat_norm_error),
            (h.measured.contact_normal, "normal", h.contact_normal_error),
            (h.measured.energy, "energy", h.energy_drift),
        ]
        .into_iter()
        .filter(|q| q.0)
        .map(|(_, name, v)| format!("{name} {v:.1e}"))
        .collect();
        parts.push(format!("{} RHS evaluations", h.rhs_evals));
        ui.label(format!("health: {}", parts.join(", ")));
    }

    pub(super) fn body_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let body = &status.setup.body;
        ui.label(format!(
            "{}, α* = {:.5} rad ({:.3}°)",
            match body {
                Body::Disk(_) => "cylinder (2D)",
                Body::Sphere(_) => "sphere (3D)",
            },
            status.setup.alpha_star,
            status.setup.alpha_star.to_degrees()
        ));
        // What the body is, so the generator's settings below are not read as the body's.
        ui.label(describe_body(&status.setup.scene.body));
        self.sculpt_ui(ui, status, actions);
        self.design_ui(ui, status);
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
        named_slider(
            ui,
            "seed",
            egui::Slider::new(&mut self.random.seed, 0..=9999),
        );
        named_slider(
            ui,
            "σ",
            egui::Slider::new(&mut self.random.sigma, 0.0..=1.0),
        );
        self.random.modes = self.random.modes.clamp(2, max_modes);
        named_slider(
            ui,
            "modes l ≤",
            egui::Slider::new(&mut self.random.modes, 2..=max_modes),
        );
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
        if !status.setup.lanes.is_empty() {
            ui.checkbox(
                &mut self.views.lanes,
                match status.setup.lanes.len() {
                    1 => "the other body on the ramp".to_string(),
                    n => format!("the other {n} bodies on the ramp"),
                },
            )
            .on_hover_text(
                "the scene's [[bodies]]: they run whether shown or not; α and the integrator are                  the ramp's, each keeps its own m/m0",
            );
        }
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

/// Draws a labelled tick at `value` on a value-less horizontal slider, its label below it in
/// a line of its own (painted over the next row, it sat on a button in class mode's larger
/// layout), in the small text style, which scales with the modes' text.
pub(super) fn mark_on_slider(
    ui: &mut egui::Ui,
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
    let font = egui::TextStyle::Small.resolve(ui.style());
    let (line, _) = ui.allocate_exact_size(
        egui::vec2(rect.width(), ui.fonts_mut(|f| f.row_height(&font))),
        egui::Sense::hover(),
    );
    let painter = ui.painter();
    painter.line_segment(
        [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
        egui::Stroke::new(2.0, color),
    );
    painter.text(
        egui::pos2(x, line.top()),
        egui::Align2::CENTER_TOP,
        label,
        font,
        color,
    );
}

pub(super) fn method_spec(method: &Method) -> crate::scene::IntegratorSpec {
    crate::scene::IntegratorSpec::of(method)
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

/// Why a typed playback speed is refused, or `None` when it is allowed.
fn speed_refusal(speed: f64) -> Option<String> {
    let (lo, hi) = SPEED_RANGE;
    (!(lo..=hi).contains(&speed)).then(|| {
        format!(
            "speed {speed} t per s is not allowed: {lo} ≤ speed ≤ {hi} (the slider's range; \
             + and − double and halve it)"
        )
    })
}

#[cfg(test)]
mod speed_tests {
    use super::*;

    #[test]
    fn a_speed_outside_the_range_is_refused_with_the_range_named() {
        assert!(speed_refusal(1.0).is_none() && speed_refusal(SPEED_RANGE.1).is_none());
        for bad in [1e9, -5.0, 0.0, f64::NAN, f64::INFINITY] {
            let why = speed_refusal(bad).expect("refused");
            assert!(why.contains("0.05 ≤ speed ≤ 1000"), "{why}");
        }
    }
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

/// `slider` with its value box and its name (`label`) in the panel's width: where the name does
/// not fit beside them (class mode's large text in a third of the screen) it goes above, and the
/// slider narrows, so that neither the value nor the name is cut at the edge, and the row is
/// never wider than the panel (the random body's sliders at the rails' 260 points made the
/// controls 390 points wide in a 300-point panel, which pushed the scroll bar out of sight).
pub(super) fn named_slider(
    ui: &mut egui::Ui,
    label: &str,
    slider: egui::Slider<'_>,
) -> egui::Response {
    let spacing = ui.spacing().clone();
    let value_box = 2.0 * spacing.interact_size.x + spacing.item_spacing.x;
    let name_width =
        ui.fonts_mut(|f| {
            f.layout_no_wrap(
                label.to_string(),
                egui::TextStyle::Body.resolve(ui.style()),
                egui::Color32::WHITE,
            )
        })
        .size()
        .x + spacing.item_spacing.x;
    let room = ui.available_width() - value_box;
    let beside = room - name_width >= spacing.slider_width.min(80.0);
    if !beside {
        ui.label(label);
    }
    ui.scope(|ui| {
        let width = if beside { room - name_width } else { room };
        ui.spacing_mut().slider_width = width.clamp(40.0, spacing.slider_width);
        ui.add(if beside { slider.text(label) } else { slider })
    })
    .inner
}

/// One slider per parameter of the core's drag-law registry, showing the running value: a new
/// law appears here without code for it.
fn drag_law_ui(ui: &mut egui::Ui, law: &crate::dynamics::DragLaw, actions: &mut Vec<UiAction>) {
    for (parameter, value) in law.parameters() {
        let mut value = value;
        let label = parameter.key.replace('_', " ");
        let response = named_slider(
            ui,
            &label,
            egui::Slider::new(&mut value, parameter.min..=parameter.max).logarithmic(true),
        );
        if response.on_hover_text(parameter.help).changed() {
            actions.push(UiAction::Sim(SimCommand::SetDragParameter(
                parameter.key,
                value,
            )));
        }
    }
}
