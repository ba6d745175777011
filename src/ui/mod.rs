//! The app's egui side: the panels (menu, controls, status, plots), the keyboard and mouse
//! bindings, and [`Painter`](painter::Painter), which draws the 3D scene and the panels into any
//! wgpu target. Nothing here knows winit: `app.rs` feeds input in and carries [`UiAction`]s out,
//! and the windowless tests and `rollphase bench app` drive the same code.
//!
//! The UI never steps physics: it edits a [`Scene`] or sends a [`SimCommand`] to the simulation
//! thread, and reads the latest [`SimStatus`].
//!
//! Keys (as in MuJoCo's viewer): Space pause/play, → one step, R reset, + / − speed ×2 / ÷2,
//! F follow camera, C class mode (large fonts, full screen), H hide the controls, P plots,
//! Esc leaves class mode. Mouse on the 3D view: drag to orbit, wheel to zoom, double-click to
//! reset the camera.

pub mod painter;
pub mod plots;
pub mod workbench;

use std::path::{Path, PathBuf};

use egui::{Color32, Key, RichText};

use crate::geometry::Body;
use crate::integrate::{Method, Preset};
use crate::scene::{BodySpec, PRESETS, RandomBody, Scene, SceneSetup, ViewsSpec, load_scene_file};
use crate::sim::{SimCommand, SimStatus};
use crate::view::{CurvatureScale, ViewOptions};
use plots::{CurvatureMap, PlotHistory, plots_ui};

/// Largest α the slider offers (the models need α < π/2).
const ALPHA_MAX: f64 = 1.5;
/// m/m0 range of the logarithmic slider.
const MASS_RANGE: (f64, f64) = (1e-3, 1e3);
/// Playback speeds offered, simulation time per wall second.
const SPEED_RANGE: (f64, f64) = (0.05, 1000.0);

/// What the UI asks the app to do besides commanding the simulation.
#[derive(Debug, Clone)]
pub enum UiAction {
    /// A command for the simulation thread.
    Sim(SimCommand),
    /// Save the whole window (3D view and controls) as a PNG.
    Screenshot(PathBuf),
    /// Save the next `frames` frames of the 3D view as PNGs in `dir`.
    Record {
        /// Output folder.
        dir: PathBuf,
        /// How many frames.
        frames: u32,
    },
    /// Enter or leave full screen.
    Fullscreen(bool),
}

/// Progress of a recording, shown in the status panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RecordProgress {
    /// Frames written.
    pub done: u32,
    /// Frames asked for.
    pub total: u32,
}

/// The UI's state: what the controls show, the camera, the plots' history.
pub struct AppUi {
    /// Camera and overlay settings of the 3D view.
    pub view_options: ViewOptions,
    /// Which 3D views are on.
    pub views: ViewsSpec,
    /// Plots panel shown.
    pub show_plots: bool,
    /// Controls panel shown.
    pub show_controls: bool,
    /// Class mode: large fonts, full screen.
    pub class_mode: bool,
    /// Where the 3D view is, in points (set by [`Self::show`]).
    pub scene_rect: Option<egui::Rect>,
    /// A recording in progress (set by the app).
    pub recording: Option<RecordProgress>,
    /// The Poincaré field's state, when it is not simply shown (set by the painter).
    pub field_note: Option<String>,
    /// Measured frames per second of the window (set by the app).
    pub fps: Option<f64>,
    alpha: f64,
    inertial: bool,
    mass_ratio: f64,
    speed: f64,
    random: RandomBody,
    scene_path: String,
    shape_path: String,
    screenshot_path: String,
    record_dir: String,
    record_frames: u32,
    notice: Option<(String, bool)>,
    history: PlotHistory,
    map: Option<(u64, Option<CurvatureMap>)>,
    seen_run: Option<(u64, u64)>,
    seen_message: Option<String>,
    scene: Scene,
    base: Option<PathBuf>,
}

impl AppUi {
    /// A UI for `setup` (the scene the simulation starts with); `base` is its file's folder.
    pub fn new(setup: &SceneSetup, base: Option<PathBuf>) -> Self {
        let views = setup.scene.views.clone();
        Self {
            view_options: ViewOptions::default(),
            views,
            show_plots: true,
            show_controls: true,
            class_mode: false,
            scene_rect: None,
            recording: None,
            field_note: None,
            fps: None,
            alpha: setup.ramp.alpha_rad,
            inertial: !setup.ramp.is_viscous(),
            mass_ratio: if setup.ramp.is_viscous() {
                1.0
            } else {
                setup.ramp.mass_ratio
            },
            speed: setup.scene.playback.speed,
            random: RandomBody {
                dimension: if matches!(setup.body, Body::Disk(_)) {
                    2
                } else {
                    3
                },
                seed: 1,
                sigma: 0.25,
                modes: 5,
            },
            scene_path: "scene.toml".into(),
            shape_path: "body.json".into(),
            screenshot_path: "screenshot.png".into(),
            record_dir: "recording".into(),
            record_frames: 120,
            notice: None,
            history: PlotHistory::default(),
            map: None,
            seen_run: None,
            seen_message: None,
            scene: setup.scene.clone(),
            base,
        }
    }

    /// Shows a one-line notice under the controls (`error` in red).
    pub fn notify(&mut self, text: String, error: bool) {
        self.notice = Some((text, error));
    }

    /// The plots' history.
    pub fn history(&self) -> &PlotHistory {
        &self.history
    }

    /// α as the slider shows it.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Takes in the latest status: follows a new scene or run, and collects plot samples.
    pub fn follow_status(&mut self, status: &SimStatus, scale: Option<CurvatureScale>) {
        let run = (status.scene_id, status.run_id);
        if self.seen_run != Some(run) {
            if self.seen_run.map(|r| r.0) != Some(status.scene_id) {
                self.history.clear_all();
                self.scene = status.setup.scene.clone();
                self.views = status.setup.scene.views.clone();
            } else {
                self.history.clear_run();
            }
            let snap = &status.snapshot;
            self.alpha = snap.alpha_rad;
            self.inertial = snap.mass_ratio > 0.0;
            if self.inertial {
                self.mass_ratio = snap.mass_ratio;
            }
            self.speed = status.speed;
            self.seen_run = Some(run);
        }
        if self.map.as_ref().map(|m| m.0) != Some(status.scene_id)
            && let Some(scale) = scale
        {
            self.map = Some((
                status.scene_id,
                CurvatureMap::new(&status.setup.body, scale, 72, 36),
            ));
        }
        // A refused change: show the simulation's values again.
        if status.message.is_some() && status.message != self.seen_message {
            self.alpha = status.snapshot.alpha_rad;
            self.inertial = status.snapshot.mass_ratio > 0.0;
            self.speed = status.speed;
        }
        self.seen_message = status.message.clone();
        self.history.push(&status.snapshot);
    }

    /// Draws the whole UI for one frame into the root `ui` and returns what it asks for.
    pub fn show(&mut self, ui: &mut egui::Ui, status: &SimStatus) -> Vec<UiAction> {
        let mut actions = Vec::new();
        self.keyboard(ui.ctx(), status, &mut actions);
        egui::Panel::top("menu").show(ui, |ui| self.menu_ui(ui, &mut actions));
        if self.show_controls {
            egui::Panel::left("controls")
                .resizable(true)
                .default_size(300.0)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        self.controls_ui(ui, status, &mut actions);
                    });
                });
        }
        if self.show_plots {
            let height = if self.class_mode { 260.0 } else { 180.0 };
            egui::Panel::bottom("plots")
                .resizable(false)
                .show(ui, |ui| {
                    let map = self.map.as_ref().and_then(|m| m.1.as_ref());
                    plots_ui(
                        ui,
                        &self.history,
                        &status.snapshot,
                        map,
                        status.snapshot.alpha_star,
                        height,
                    );
                });
        }
        egui::CentralPanel::no_frame().show(ui, |ui| self.scene_ui(ui));
        actions
    }

    fn keyboard(&mut self, ctx: &egui::Context, status: &SimStatus, actions: &mut Vec<UiAction>) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let pressed = |k: Key| ctx.input(|i| i.key_pressed(k));
        if pressed(Key::Space) {
            actions.push(UiAction::Sim(if status.paused {
                SimCommand::Play
            } else {
                SimCommand::Pause
            }));
        }
        if pressed(Key::ArrowRight) {
            actions.push(UiAction::Sim(SimCommand::Step));
        }
        if pressed(Key::R) {
            actions.push(UiAction::Sim(SimCommand::Reset));
        }
        let faster = pressed(Key::Plus) || pressed(Key::Equals);
        let slower = pressed(Key::Minus);
        if faster || slower {
            let factor = if faster { 2.0 } else { 0.5 };
            self.speed = (status.speed * factor).clamp(SPEED_RANGE.0, SPEED_RANGE.1);
            actions.push(UiAction::Sim(SimCommand::SetSpeed(self.speed)));
        }
        if pressed(Key::F) {
            self.view_options.follow = !self.view_options.follow;
        }
        if pressed(Key::C) {
            self.set_class_mode(ctx, !self.class_mode, actions);
        }
        if pressed(Key::Escape) && self.class_mode {
            self.set_class_mode(ctx, false, actions);
        }
        if pressed(Key::H) {
            self.show_controls = !self.show_controls;
        }
        if pressed(Key::P) {
            self.show_plots = !self.show_plots;
        }
    }

    fn set_class_mode(&mut self, ctx: &egui::Context, on: bool, actions: &mut Vec<UiAction>) {
        self.class_mode = on;
        ctx.set_zoom_factor(if on { 1.6 } else { 1.0 });
        self.view_options.text_scale = if on { 1.8 } else { 1.0 };
        actions.push(UiAction::Fullscreen(on));
    }

    fn menu_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<UiAction>) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("Presets", |ui| {
                for (name, text) in PRESETS {
                    let description = Scene::from_toml(text)
                        .map(|s| s.description)
                        .unwrap_or_default();
                    if ui.button(*name).on_hover_text(description).clicked() {
                        self.load_preset(name, actions);
                        ui.close();
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

    fn reset_camera(&mut self) {
        self.view_options = ViewOptions {
            text_scale: self.view_options.text_scale,
            follow: self.view_options.follow,
            ..ViewOptions::default()
        };
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let snap = &status.snapshot;
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

    fn status_ui(&self, ui: &mut egui::Ui, status: &SimStatus) {
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

    fn integrator_ui(
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
                    describe_method(&status.method),
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
                    describe_method(&status.method)
                ));
            }
        }
        let h = &status.snapshot.health;
        ui.label(format!(
            "health: ||q|−1| {:.1e}, normal {:.1e}, energy {:.1e}; {} RHS evaluations",
            h.quat_norm_error, h.contact_normal_error, h.energy_drift, h.rhs_evals
        ));
    }

    fn body_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus, actions: &mut Vec<UiAction>) {
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

    fn views_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus, actions: &mut Vec<UiAction>) {
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

    fn files_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus, actions: &mut Vec<UiAction>) {
        egui::Grid::new("files").num_columns(3).show(ui, |ui| {
            ui.label("scene");
            ui.add(egui::TextEdit::singleline(&mut self.scene_path).desired_width(130.0));
            ui.horizontal(|ui| {
                if ui.button("Load").clicked() {
                    let path = PathBuf::from(&self.scene_path);
                    match load_scene_file(&path) {
                        Ok(setup) => {
                            self.notice = Some((format!("loaded {}", path.display()), false));
                            self.base = path.parent().map(Path::to_path_buf);
                            actions.push(UiAction::Sim(SimCommand::Load(Box::new(setup))));
                        }
                        Err(e) => {
                            self.notice = Some((format!("{}: {e}", path.display()), true));
                        }
                    }
                }
                if ui.button("Save").clicked() {
                    let mut scene = self.current_scene(status);
                    // A saved scene carries its body inline, so it loads from anywhere.
                    scene.body = BodySpec {
                        inline: Some(status.setup.body.to_file()),
                        ..BodySpec::default()
                    };
                    self.notice = Some(write_file(&self.scene_path, &scene.to_toml()));
                }
            });
            ui.end_row();
            ui.label("shape");
            ui.add(egui::TextEdit::singleline(&mut self.shape_path).desired_width(130.0));
            ui.horizontal(|ui| {
                if ui.button("Load").clicked() {
                    self.load_shape(status, actions);
                }
                if ui.button("Save").clicked() {
                    let json = status.setup.body.to_file().to_json();
                    self.notice = Some(write_file(&self.shape_path, &json));
                }
            });
            ui.end_row();
            ui.label("screenshot");
            ui.add(egui::TextEdit::singleline(&mut self.screenshot_path).desired_width(130.0));
            if ui.button("Save PNG").clicked() {
                actions.push(UiAction::Screenshot(PathBuf::from(&self.screenshot_path)));
            }
            ui.end_row();
            ui.label("record");
            ui.add(egui::TextEdit::singleline(&mut self.record_dir).desired_width(130.0));
            ui.horizontal(|ui| {
                ui.add(egui::DragValue::new(&mut self.record_frames).range(1..=100_000));
                let busy = self.recording.is_some();
                if ui
                    .add_enabled(!busy, egui::Button::new("Record"))
                    .on_hover_text("the next N frames of the 3D view, as shown, as PNGs")
                    .clicked()
                {
                    actions.push(UiAction::Record {
                        dir: PathBuf::from(&self.record_dir),
                        frames: self.record_frames,
                    });
                }
            });
            ui.end_row();
        });
    }

    fn load_shape(&mut self, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let path = PathBuf::from(&self.shape_path);
        match crate::geometry::ShapeFile::load(&path) {
            Ok(body) => {
                let mut scene = self.current_scene(status);
                scene.body = BodySpec {
                    inline: Some(body.to_file()),
                    ..BodySpec::default()
                };
                // A contact point or angle names a place on the old body; start the new one afresh.
                scene.initial = crate::scene::InitialSpec::default();
                scene.name = path
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "shape".into());
                if matches!(body, Body::Disk(_)) {
                    scene.views.ball = false;
                    scene.views.poincare = false;
                }
                self.load_scene(scene, None, actions);
            }
            Err(e) => self.notice = Some((format!("{e:#}"), true)),
        }
    }

    /// The scene as it runs now: the loaded one with the live α, m/m0, integrator, speed and
    /// views.
    fn current_scene(&self, status: &SimStatus) -> Scene {
        let mut scene = self.scene.clone();
        let snap = &status.snapshot;
        scene.model.alpha_rad = Some(snap.alpha_rad);
        scene.model.alpha_over_critical = None;
        scene.model.mass_ratio = snap.mass_ratio;
        scene.integrator = method_spec(&status.method);
        scene.playback.speed = status.speed;
        scene.views = self.views.clone();
        scene
    }

    fn load_preset(&mut self, name: &str, actions: &mut Vec<UiAction>) {
        match Scene::preset(name) {
            Ok(scene) => self.load_scene(scene, None, actions),
            Err(e) => self.notice = Some((e.to_string(), true)),
        }
    }

    fn load_scene(&mut self, scene: Scene, base: Option<PathBuf>, actions: &mut Vec<UiAction>) {
        match scene.setup(base.as_deref()) {
            Ok(setup) => {
                self.notice = setup.model_note.clone().map(|n| (n, false));
                actions.push(UiAction::Sim(SimCommand::Load(Box::new(setup))));
            }
            Err(e) => self.notice = Some((e.to_string(), true)),
        }
    }

    fn scene_ui(&mut self, ui: &mut egui::Ui) {
        let rect = ui.max_rect();
        self.scene_rect = Some(rect);
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        if response.dragged() {
            let d = response.drag_delta();
            self.view_options.yaw -= d.x * 0.01;
            self.view_options.pitch = (self.view_options.pitch + d.y * 0.01).clamp(-1.2, 1.2);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta().y);
            if scroll != 0.0 {
                self.view_options.zoom =
                    (self.view_options.zoom * (-scroll * 0.002).exp()).clamp(0.2, 5.0);
            }
        }
        if response.double_clicked() {
            self.reset_camera();
        }
    }
}

/// Draws a labelled tick below a value-less horizontal slider at `value`.
fn mark_on_slider(
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

/// "DOP853 rtol 1e-8" and the like.
pub fn describe_method(method: &Method) -> String {
    match *method {
        Method::Dop853 { rtol, .. } => format!("DOP853 rtol {rtol:.0e}"),
        Method::Rk4 { dt } => format!("RK4 dt {dt}"),
        Method::Cf4 { dt } => format!("CF4 dt {dt}"),
    }
}

fn method_spec(method: &Method) -> crate::scene::IntegratorSpec {
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

/// Writes `text` to `path`; the notice says what happened.
fn write_file(path: &str, text: &str) -> (String, bool) {
    match std::fs::write(path, text) {
        Ok(()) => (format!("saved {path}"), false),
        Err(e) => (format!("cannot write {path}: {e}"), true),
    }
}
