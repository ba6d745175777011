//! The app's egui side: the panels (menu, controls, status, plots), the keyboard and mouse
//! bindings, and [`Painter`](painter::Painter), which draws the 3D scene and the panels into any
//! wgpu target. Nothing here knows winit: `app.rs` feeds input in and carries [`UiAction`]s out,
//! and the windowless tests and `rollphase bench app` drive the same code.
//!
//! The UI never steps physics: it edits a [`Scene`] or sends a [`SimCommand`] to the simulation
//! thread, and reads the latest [`SimStatus`].
//!
//! Keys (as in MuJoCo's viewer): Space pause/play, → one step, R reset, + / − speed ×2 / ÷2,
//! F follow camera or hold it, F5 presentation mode (the 3D view alone), C class mode (large
//! fonts and caption, full screen), H hide the controls, P plots, ? the keys, Esc leaves
//! presentation or class mode; in a lesson, N or Page Down the next step, B or Page Up the
//! previous one (a presenter's clicker sends Page Down / Page Up). Mouse on the 3D view: drag to orbit, wheel to zoom, double-click to
//! reset the camera.
//!
//! | file | owns |
//! |---|---|
//! | `mod` | [`AppUi`]: the state, [`AppUi::show`] laying out the panels, [`UiAction`] |
//! | `controls` | the menu bar and the control panels (playback, α and m/m0, integrator, body, views) |
//! | `fields` | the typed number fields (α, m/m0) and the α rail's scale, finest at α* |
//! | `files` | the files panel: scenes, shapes, CSV and PNG out, presets |
//! | `dialog` | native Open / Save dialogs (rfd) on their own thread, or why there are none |
//! | `keys` | the keyboard bindings and class mode |
//! | `picking` | starts picked in the views: the curvature map, the SO(3) ball, the Poincaré field |
//! | `plot_axes` | the plots' axes: numbers on a 1-2-5 ladder, far enough apart to read |
//! | `plots`, `painter`, `workbench` | the plots, the wgpu painter, the windowless app core |
//! | `render_scale` | how finely the 3D view is drawn: full, or on a CPU renderer as 30 frames/s allow |
//! | `measuring_sweep` | the measuring sweep of α or m/m0 (hold each value until measured, then step) |
//! | `fonts` | egui's fonts with the bundled DejaVu Sans as the fallback |

pub mod dialog;
pub mod fonts;
pub mod measuring_sweep;
pub mod painter;
mod plot_axes;
pub mod plots;
pub mod render_scale;
pub mod workbench;

mod controls;
pub mod designing;
mod fields;
mod files;
mod keys;
mod picking;
mod sculpting;

pub use controls::{ALPHA_FIELD, MASS_FIELD};
pub use sculpting::DRAG_HEIGHT_PER_POINT;

use std::path::PathBuf;

use crate::dynamics::ModelKind;
use crate::geometry::Body;
use crate::live::history::PlotHistory;
use crate::live::{SimCommand, SimStatus};
use crate::scene::{RandomBody, Scene, SceneSetup, ViewsSpec};
use crate::view::{CurvatureScale, ViewOptions};
use plots::{CurvatureMap, plots_ui};

/// Largest α the slider offers (the models need α < π/2).
const ALPHA_MAX: f64 = 1.5;
/// The α slider's smallest value.
const ALPHA_MIN: f64 = 0.001;
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
    /// Sculpting the body by hand.
    pub sculpt: sculpting::SculptPanel,
    /// Designing a body for targets.
    pub design: designing::DesignPanel,
    /// Which 3D views are on.
    pub views: ViewsSpec,
    /// Plots panel shown.
    pub show_plots: bool,
    /// Controls panel shown.
    pub show_controls: bool,
    /// Class mode: large fonts, full screen.
    pub class_mode: bool,
    /// Presentation mode (F5, `--present`): only the 3D view, large text, full screen.
    pub presenting: bool,
    /// The controls and plots as they were before presentation mode hid them.
    panels_before: (bool, bool),
    /// The `?` legend of the keys is showing.
    pub show_keys: bool,
    /// Presentation mode asked for before the first frame (`--present`).
    present_on_start: bool,
    /// Class mode asked for before the first frame (`--class`).
    class_on_start: bool,
    /// Where the 3D view is, in points (set by [`Self::show`]).
    pub scene_rect: Option<egui::Rect>,
    /// Where the lesson's plot is drawn large (presentation and class modes), in points, and
    /// its text size in pixels (set by [`Self::show`]; `None` when it is not shown).
    pub lesson_plot_rect: Option<(egui::Rect, f32)>,
    /// The controls' scroll area as the last frame laid it out: the rectangle it shows, in
    /// points, and the height of what it holds (more than the rectangle's where the controls
    /// run past the window, and then its scroll bar is drawn); `None` with the controls hidden.
    pub controls_scroll: Option<(egui::Rect, f32)>,
    /// A recording in progress (set by the app).
    pub recording: Option<RecordProgress>,
    /// The Poincaré field's state, when it is not simply shown (set by the painter).
    pub field_note: Option<String>,
    /// Measured frames per second of the window (set by the app).
    pub fps: Option<f64>,
    /// "3D at 70 %" while the 3D view is drawn below full resolution (the status bar's).
    pub render_scale_note: Option<String>,
    /// The View menu's "3D at full resolution": the automatic render scale is not used.
    pub full_resolution: bool,
    alpha: f64,
    inertial: bool,
    mass_ratio: f64,
    speed: f64,
    random: RandomBody,
    scene_path: String,
    /// Where Save state writes: a file of its own, so a later Save of the scene never replaces
    /// a saved run.
    state_path: String,
    shape_path: String,
    screenshot_path: String,
    record_dir: String,
    record_frames: u32,
    plot_data_dir: String,
    /// The automatic sweep running, if any.
    measuring_sweep: Option<measuring_sweep::MeasuringSweep>,
    /// The sweep the controls offer (kept while it is off).
    sweep_choice: measuring_sweep::MeasuringSweep,
    /// The value the sweep holds until it is measured.
    sweep_hold: measuring_sweep::SweepHold,
    /// The notice shown as a toast over the 3D view, and when it appeared (egui's clock).
    toast: Option<((String, bool), f64)>,
    notice: Option<(String, bool)>,
    history: PlotHistory,
    map: Option<(u64, Option<CurvatureMap>)>,
    seen_run: Option<(u64, u64)>,
    seen_message: Option<String>,
    scene: Scene,
    base: Option<PathBuf>,
    /// Files opened this session, newest first (at most [`RECENT_FILES`]).
    recent: Vec<PathBuf>,
    /// Where the contact map was drawn last frame.
    map_transform: Option<egui_plot::PlotTransform>,
    /// The screen's pixels per point, as of the last frame.
    pixels_per_point: f32,
    /// The turn about the ramp normal of a shift-drag in progress (radians).
    turn: f32,
    /// The lesson steps done as of the last status (the controls follow a step's changes).
    seen_step: Option<usize>,
    /// A speed asked for before the simulation has it (`--speed`): the control shows it, not
    /// the first statuses' older speed.
    asked_speed: Option<f64>,
    /// The sweep and crossing plots as each lesson step began (steps done → plots): B and R
    /// go back to a step, and its plots come back with it (stale points of later steps, in
    /// the other direction's colour, changed the lesson's final fit).
    step_plots: std::collections::BTreeMap<usize, crate::live::history::PlotCheckpoint>,
    /// The lesson's evidence, measured ahead on a worker thread for the setup now running.
    evidence: Option<crate::live::evidence::LessonEvidence>,
    /// The lesson step whose evidence the plots took in last (`None`: none since the run began).
    evidence_shown: Option<usize>,
    /// The pointer has not moved since presentation or class mode began (then at egui time
    /// `.1`): the large plot shows no values under it until it does.
    pointer_resting: bool,
    mode_entered_at: f64,
    /// Native Open / Save dialogs.
    pub dialogs: dialog::FileDialogs,
    /// A dropped mesh being fitted.
    mesh_fit: Option<files::PendingFit>,
    /// The α field's text while it has focus (applied on Enter or focus loss).
    alpha_edit: Option<String>,
    /// The m/m0 field's text while it has focus.
    mass_edit: Option<String>,
}

/// Files kept in the recent list.
pub const RECENT_FILES: usize = 8;

impl AppUi {
    /// A UI for `setup` (the scene the simulation starts with); `base` is its file's folder.
    pub fn new(setup: &SceneSetup, base: Option<PathBuf>) -> Self {
        let views = setup.scene.views.clone();
        let inertial = ModelKind::of(&setup.body, &setup.ramp).is_inertial();
        Self {
            view_options: ViewOptions::default(),
            sculpt: sculpting::SculptPanel::default(),
            design: designing::DesignPanel::default(),
            views,
            show_plots: true,
            show_controls: true,
            class_mode: false,
            presenting: false,
            panels_before: (true, true),
            show_keys: false,
            present_on_start: false,
            class_on_start: false,
            scene_rect: None,
            lesson_plot_rect: None,
            controls_scroll: None,
            recording: None,
            field_note: None,
            fps: None,
            render_scale_note: None,
            full_resolution: false,
            alpha: setup.ramp.alpha_rad,
            inertial,
            mass_ratio: if inertial { setup.ramp.mass_ratio } else { 1.0 },
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
            state_path: "state.toml".into(),
            shape_path: "body.json".into(),
            screenshot_path: "screenshot.png".into(),
            record_dir: "recording".into(),
            record_frames: 120,
            plot_data_dir: "plot-data".into(),
            measuring_sweep: None,
            sweep_choice: measuring_sweep::MeasuringSweep::default(),
            sweep_hold: measuring_sweep::SweepHold::default(),
            toast: None,
            notice: None,
            history: PlotHistory::default(),
            map: None,
            seen_run: None,
            seen_message: None,
            scene: setup.scene.clone(),
            base,
            recent: Vec::new(),
            map_transform: None,
            pixels_per_point: 1.0,
            turn: 0.0,
            seen_step: None,
            step_plots: std::collections::BTreeMap::new(),
            evidence: None,
            evidence_shown: None,
            pointer_resting: false,
            mode_entered_at: 0.0,
            asked_speed: None,
            dialogs: dialog::FileDialogs::detect(),
            mesh_fit: None,
            alpha_edit: None,
            mass_edit: None,
        }
    }

    /// Shows a one-line notice in the status bar (`error` in red).
    pub fn notify(&mut self, text: String, error: bool) {
        self.notice = Some((text, error));
    }

    /// Whether the large lesson plot shows values under the pointer: not in presentation or
    /// class mode until the pointer moves (see `plots::PlotLook::hover`).
    pub fn plot_hover_shown(&self) -> bool {
        !self.pointer_resting
    }

    /// The plots' history.
    pub fn history(&self) -> &PlotHistory {
        &self.history
    }

    /// The playback speed as the speed control shows it.
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// α as the slider shows it.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Takes in the latest status and the plots' samples taken since the last frame (with the
    /// run they belong to): follows a new scene or run, and collects them.
    pub fn follow_status(
        &mut self,
        status: &SimStatus,
        scale: Option<CurvatureScale>,
        samples: ((u64, u64), Vec<crate::live::history::Sample>),
    ) {
        let run = (status.scene_id, status.run_id);
        let step = status.snapshot.lesson.map(|l| l.done);
        if self.seen_run != Some(run) {
            if self.seen_run.map(|r| r.0) != Some(status.scene_id) {
                self.history = PlotHistory::of_setup(&status.setup);
                self.step_plots.clear();
                self.scene = status.setup.scene.clone();
                self.views = status.setup.scene.views.clone();
            } else {
                self.history.clear_run();
                // A lesson run again from its start (R) or from an earlier step (B): the plots
                // as that step began.
                if let Some(done) = step
                    && let Some(checkpoint) = self.step_plots.get(&done)
                {
                    self.history.restore(checkpoint);
                    self.step_plots.retain(|&k, _| k <= done);
                }
            }
            self.follow_values(status);
            self.seen_run = Some(run);
            self.evidence_shown = None;
        }
        self.take_in_evidence(status, step);
        self.follow_sculpt(status);
        let evidence = self
            .evidence
            .as_ref()
            .filter(|e| !status.snapshot.off_script && e.is_for(&status.setup));
        self.view_options.lesson_ahead = match (step, evidence) {
            (Some(done), Some(e)) => crate::view::MeasuredAhead {
                period: e.period_shown(done),
                rate: e.rate_shown(done),
            },
            _ => crate::view::MeasuredAhead::default(),
        };
        if let Some(done) = step {
            self.step_plots
                .entry(done)
                .or_insert_with(|| self.history.checkpoint());
        }
        // A lesson step changed α, m/m0, the speed or the views: the controls show it. (Only
        // then: following every status would pull a slider back while it is being dragged.)
        if step != self.seen_step {
            self.follow_values(status);
            self.seen_step = step;
        }
        if self.map.as_ref().map(|m| m.0) != Some(status.scene_id)
            && let Some(scale) = scale
        {
            self.map = Some((
                status.scene_id,
                CurvatureMap::new(&status.setup.body, scale, 72, 36),
            ));
        }
        if let Some(asked) = self.asked_speed {
            self.speed = asked;
            if status.speed == asked {
                self.asked_speed = None;
            }
        }
        // A refused change: show the simulation's values again.
        if status.message.is_some() && status.message != self.seen_message {
            self.alpha = status.snapshot.alpha_rad;
            self.inertial = status.snapshot.model.is_inertial();
            self.speed = status.speed;
        }
        self.seen_message = status.message.clone();
        self.history.push(&status.snapshot);
        // Samples of an earlier run (taken before a reset this status already shows) are not
        // this run's.
        if samples.0 == run {
            self.history.push_samples(samples.1);
        }
    }

    /// A lesson's evidence: measured ahead for each new setup with a timeline, and taken into
    /// the plots as each step opens (or as soon as it is measured), while the run plays the
    /// lesson as written. A run changed by hand is its own: its plots are what it collects.
    fn take_in_evidence(&mut self, status: &SimStatus, step: Option<usize>) {
        if self
            .evidence
            .as_ref()
            .is_none_or(|e| !e.is_for(&status.setup))
        {
            self.evidence = crate::live::evidence::LessonEvidence::start(status.setup.clone());
            self.evidence_shown = None;
        }
        if let (Some(done), Some(evidence)) = (step, &self.evidence)
            && !status.snapshot.off_script
            && self.evidence_shown != Some(done)
            && let Some(checkpoint) = evidence.step(done)
        {
            self.history.restore(&checkpoint);
            self.evidence_shown = Some(done);
        }
    }

    /// The line under a lesson's caption while the step's evidence is still being measured
    /// (`None` once it is shown, for a run changed by hand, or outside a lesson).
    pub fn evidence_note(&self, status: &SimStatus) -> Option<String> {
        let done = status.snapshot.lesson?.done;
        let evidence = self.evidence.as_ref()?;
        if status.snapshot.off_script || !evidence.is_for(&status.setup) {
            return None;
        }
        match evidence.progress(done) {
            // A no-break space: the number and its % never part at a line's end.
            (f, None) if f < 1.0 => Some(format!(
                "measuring this step's evidence ahead: {:.0}\u{a0}%",
                100.0 * f
            )),
            (_, Some(why)) => Some(format!("this step's evidence could not be measured: {why}")),
            // Measured: a claim the run does not bear out is said under it, never left standing.
            _ => match evidence.claim(done) {
                Some(Err(why)) => {
                    let claim = status.setup.timeline.get(done.checked_sub(1)?)?.claim?;
                    Some(crate::live::evidence::claim_not_shown(claim, &why))
                }
                _ => None,
            },
        }
    }

    /// Shows the simulation's α, m/m0, speed and views in the controls.
    fn follow_values(&mut self, status: &SimStatus) {
        let snap = &status.snapshot;
        self.alpha = snap.alpha_rad;
        self.inertial = snap.model.is_inertial();
        if self.inertial {
            self.mass_ratio = snap.mass_ratio;
        }
        self.speed = status.speed;
        self.views = snap.views.clone();
    }

    /// Moves the swept parameter by the time simulated since the last frame (a new run, or a
    /// pause, starts the count afresh).
    /// The measuring sweep: holds the value until the run there is measured (the plots then
    /// have its point), then steps ([`measuring_sweep`]).
    fn advance_sweep(&mut self, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let Some(sweep) = self.measuring_sweep else {
            self.sweep_hold = measuring_sweep::SweepHold::default();
            return;
        };
        let snap = &status.snapshot;
        if status.paused || status.message.is_some() {
            return;
        }
        let observed = measuring_sweep::HoldObservation {
            t: snap.t,
            value: sweep.value(snap.alpha_rad, snap.mass_ratio),
            last_crossing_t: snap.last_crossing_t,
            period: snap.period,
            multiplicity: snap.period_multiplicity,
            reports_cycles: snap.theta.is_none(),
            halted: snap.halted,
        };
        let starting_mass =
            sweep.target == measuring_sweep::SweepTarget::MassRatio && snap.mass_ratio <= 0.0;
        if !starting_mass {
            match self.sweep_hold.observe(&observed) {
                measuring_sweep::HoldVerdict::Waiting => return,
                measuring_sweep::HoldVerdict::Measured(_) => {}
                measuring_sweep::HoldVerdict::GaveUp => {
                    self.notice = Some((
                        format!(
                            "sweep: no settled period at {} = {:.5} within {} t; stepped on \
                             without a point",
                            sweep.target.name(),
                            observed.value,
                            measuring_sweep::HOLD_CAP
                        ),
                        false,
                    ));
                }
            }
        }
        match sweep.next(snap.alpha_rad, snap.mass_ratio, self.mass_ratio) {
            measuring_sweep::SweepStep::Alpha(alpha) => {
                self.alpha = alpha;
                self.sweep_hold = measuring_sweep::SweepHold::at(alpha);
                actions.push(UiAction::Sim(SimCommand::SetAlpha(alpha)));
            }
            measuring_sweep::SweepStep::MassRatio(m) => {
                self.mass_ratio = m;
                self.inertial = true;
                self.sweep_hold = measuring_sweep::SweepHold::at(m);
                actions.push(UiAction::Sim(SimCommand::SetMassRatio(m)));
            }
            measuring_sweep::SweepStep::Done => {
                self.measuring_sweep = None;
                self.notice = Some((
                    format!(
                        "the {} sweep reached the end of its range",
                        sweep.target.name()
                    ),
                    false,
                ));
            }
        }
    }

    /// A new notice (saved, loaded, a refusal) also shows for a few seconds as a toast at the top
    /// of the 3D view, where the eye is; the status bar keeps it.
    fn toast_ui(&mut self, ctx: &egui::Context) {
        const SHOWN: f64 = 3.5;
        let now = ctx.input(|i| i.time);
        if let Some(notice) = &self.notice
            && self.toast.as_ref().map(|t| &t.0) != Some(notice)
        {
            self.toast = Some((notice.clone(), now));
        }
        let Some(((text, error), since)) = &self.toast else {
            return;
        };
        if now - since > SHOWN {
            return;
        }
        ctx.request_repaint_after(std::time::Duration::from_millis(250));
        let Some(rect) = self.scene_rect else {
            return;
        };
        egui::Area::new(egui::Id::unique("rollphase-toast"))
            .fixed_pos(egui::pos2(rect.center().x, rect.top() + 12.0))
            .pivot(egui::Align2::CENTER_TOP)
            .interactable(false)
            .show(ctx, |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    let color = if *error {
                        egui::Color32::from_rgb(230, 90, 80)
                    } else {
                        egui::Color32::from_rgb(120, 200, 120)
                    };
                    let mut words = egui::RichText::new(text).color(color);
                    // Read from the back of a room in presentation and class modes.
                    if self.presenting || self.class_mode {
                        words = words.size(crate::view::ROOM_TEXT_PX / ctx.pixels_per_point());
                    }
                    ui.label(words);
                });
            });
    }

    /// A paused run says so over the 3D view, where the room looks (in presentation mode the
    /// status bar and the Play button are hidden), in the overlay's size.
    fn paused_badge_ui(&self, ctx: &egui::Context, status: &SimStatus) {
        if !status.paused || status.message.is_some() {
            return;
        }
        let Some(rect) = self.scene_rect else {
            return;
        };
        let size = if self.class_mode { 26.0 } else { 18.0 };
        let insets = self.view_rects(rect.size(), status);
        let corner = paused_badge_corner(rect, &insets[1..], self.pixels_per_point, 2.4 * size);
        egui::Area::new(egui::Id::unique("rollphase-paused"))
            .fixed_pos(corner)
            .pivot(egui::Align2::RIGHT_BOTTOM)
            .interactable(false)
            .show(ctx, |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.label(
                        egui::RichText::new("❚❚ paused (Space plays)")
                            .size(size)
                            .color(egui::Color32::from_rgb(255, 214, 10)),
                    );
                });
            });
    }

    /// Opens in presentation mode (`--present`): applied on the first frame.
    pub fn present_on_start(&mut self) {
        self.present_on_start = true;
    }

    /// Plays at `speed` (`--speed`): the command to the simulation, and the speed control
    /// showing it (the control follows the simulation only on a new run or lesson step).
    pub fn set_speed(&mut self, speed: f64) -> SimCommand {
        self.speed = speed;
        self.asked_speed = Some(speed);
        SimCommand::SetSpeed(speed)
    }

    /// Opens in class mode (`--class`): applied on the first frame.
    pub fn class_on_start(&mut self) {
        self.class_on_start = true;
    }

    /// With the camera held (F), moves where it looks to the body when the body has rolled
    /// more than 6 ⟨r⟩ away, so the view re-frames the body instead of losing it.
    fn keep_body_in_view(&mut self, status: &SimStatus) {
        if self.view_options.follow {
            return;
        }
        let centre = status.snapshot.pose.centre;
        let far = self
            .view_options
            .fixed_target
            .is_none_or(|f| (f - centre).length() > 6.0);
        if far {
            self.view_options.fixed_target = Some(centre);
        }
    }

    /// Starts (or with `None` stops) a measuring sweep; it first measures the running value.
    pub fn set_measuring_sweep(&mut self, sweep: Option<measuring_sweep::MeasuringSweep>) {
        if let Some(s) = sweep {
            self.sweep_choice = s;
        }
        self.measuring_sweep = sweep;
        self.sweep_hold = measuring_sweep::SweepHold::default();
    }

    /// Draws the whole UI for one frame into the root `ui` and returns what it asks for.
    pub fn show(&mut self, ui: &mut egui::Ui, status: &SimStatus) -> Vec<UiAction> {
        let mut actions = Vec::new();
        // A file dropped on the window (winit's DroppedFile, through egui-winit) opens as if
        // typed into the files panel.
        let dropped: Vec<PathBuf> = ui.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .collect()
        });
        for path in dropped {
            self.open_file(&path, status, &mut actions);
        }
        if let Some((purpose, chosen)) = self.dialogs.poll() {
            self.dialog_answered(purpose, chosen, status, &mut actions);
        }
        let ctx = ui.ctx().clone();
        self.poll_mesh_fit(&ctx, status, &mut actions);
        if std::mem::take(&mut self.present_on_start) {
            let ctx = ui.ctx().clone();
            self.set_presentation(&ctx, true, &mut actions);
        }
        if std::mem::take(&mut self.class_on_start) {
            let ctx = ui.ctx().clone();
            self.set_class_mode(&ctx, true, &mut actions);
        }
        self.keyboard(ui.ctx(), status, &mut actions);
        self.keep_class_zoom(ui.ctx());
        self.advance_sweep(status, &mut actions);
        self.poll_design(status, &mut actions);
        self.keep_body_in_view(status);
        if !self.presenting {
            egui::Panel::top("menu").show(ui, |ui| self.menu_ui(ui, status, &mut actions));
            // Outermost at the bottom, so no panel or plot hides it.
            egui::Panel::bottom("status").show(ui, |ui| self.status_bar_ui(ui, status));
        }
        self.controls_scroll = None;
        if self.show_controls {
            // A floor on the width: after the window shrank (or a 4K detour) the panel comes back
            // to a usable width instead of staying as narrow as the small window forced it.
            // In class mode the room looks at the 3D view and the lesson's plot: the controls
            // take at most 30 % of the width (at 1280×720 they took 42 %, the view 35 %).
            let widest = if self.class_mode {
                (ui.ctx().content_rect().width() * 0.3).max(280.0)
            } else {
                f32::INFINITY
            };
            egui::Panel::left("controls")
                .resizable(true)
                .default_size(300.0)
                .min_size(280.0)
                .max_size(widest)
                .show(ui, |ui| {
                    ui.spacing_mut().scroll = controls_scroll_style();
                    // Its rows must fit the panel (`controls::named_slider`): a vertical scroll
                    // area is as wide as its widest row, and past the panel's edge its bar is
                    // drawn out of sight.
                    let shown = egui::ScrollArea::vertical().show(ui, |ui| {
                        // Every label wraps at the panel's edge rather than running past it
                        // (class mode's large text in a third of the screen cut them).
                        ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Wrap);
                        self.controls_ui(ui, status, &mut actions);
                    });
                    self.controls_scroll = Some((shown.inner_rect, shown.content_size.y));
                });
        }
        // The plot a lesson step talks about, large beside the 3D view, in presentation and
        // class modes (in presentation mode every other plot is hidden, and the lessons' words
        // "watch the 1/T plot" named a plot that was not on screen).
        // A moved pointer shows values again; the moves the mode change itself makes (the
        // window going full screen, the zoom) within its first seconds do not count.
        if self.pointer_resting
            && ui.input(|i| {
                i.time - self.mode_entered_at > POINTER_SETTLE_S
                    && i.events
                        .iter()
                        .any(|e| matches!(e, egui::Event::PointerMoved(_)))
            })
        {
            self.pointer_resting = false;
        }
        let lesson_plot = status.snapshot.views.plot;
        let large_plot = (self.presenting || self.class_mode) && !lesson_plot.is_none();
        self.lesson_plot_rect = None;
        if large_plot {
            // A share of what the controls leave (class mode keeps them), so the 3D view keeps
            // the larger part.
            let width = ui.available_width() * LESSON_PLOT_SHARE;
            egui::Panel::right("lesson-plot")
                .resizable(false)
                .exact_size(width)
                .show(ui, |ui| {
                    self.lesson_plot_rect = Some(lesson_plot_ui(
                        ui,
                        lesson_plot,
                        &self.history,
                        &status.snapshot,
                        width,
                        !self.pointer_resting,
                    ));
                });
        }
        // In class mode the large plot stands for the row of plots, which would take the
        // 3D view's height.
        if self.show_plots && !(large_plot && self.class_mode) {
            // Class mode's plots are taller, but never more than a third of the window: the
            // 3D view is what the room looks at.
            let height = if self.class_mode {
                (ui.ctx().content_rect().height() / 3.0).clamp(180.0, 260.0)
            } else {
                180.0
            };
            egui::Panel::bottom("plots")
                .resizable(false)
                .show(ui, |ui| {
                    let map = self.map.as_ref().and_then(|m| m.1.as_ref());
                    let input = plots_ui(
                        ui,
                        &self.history,
                        &status.snapshot,
                        map,
                        status.snapshot.alpha_star,
                        height,
                    );
                    self.map_transform = input.transform;
                    if let Some((theta, phi)) = input.clicked {
                        self.restart_from_contact(theta, phi, status, &mut actions);
                    }
                });
        }
        egui::CentralPanel::no_frame().show(ui, |ui| self.scene_ui(ui, status, &mut actions));
        self.toast_ui(ui.ctx());
        self.paused_badge_ui(ui.ctx(), status);
        self.keys_legend_ui(ui.ctx());
        actions
    }
}

/// The share of the width beside the controls that the lesson's large plot takes.
const LESSON_PLOT_SHARE: f32 = 0.4;

/// The smallest text of the lesson's large plot, in pixels: read from the back of a room, as
/// the 3D view's text in these modes.
pub const LESSON_PLOT_TEXT_PX: f32 = crate::view::ROOM_TEXT_PX;

/// The lesson's plot `plot`, as large as its panel allows, its text at least
/// [`LESSON_PLOT_TEXT_PX`] pixels (titles, ticks, axis names and keys). Returns where it went
/// and its text size in pixels.
fn lesson_plot_ui(
    ui: &mut egui::Ui,
    plot: crate::scene::LessonPlot,
    history: &PlotHistory,
    snap: &crate::live::Snapshot,
    width: f32,
    hover: bool,
) -> (egui::Rect, f32) {
    let ppp = ui.ctx().pixels_per_point();
    let points = LESSON_PLOT_TEXT_PX / ppp;
    let style = ui.style_mut();
    for text_style in [
        egui::TextStyle::Small,
        egui::TextStyle::Body,
        egui::TextStyle::Button,
        egui::TextStyle::Heading,
    ] {
        if let Some(font) = style.text_styles.get_mut(&text_style) {
            font.size = font.size.max(points);
        }
    }
    let title = ui.label(egui::RichText::new(plot.title()).strong());
    let height = (ui.available_height() - 8.0).max(120.0);
    // egui_plot draws the y axis's name a quarter of its line height left of the plot's own
    // rectangle: room for it here, or the panel's edge cut the room-size "1/T" to "1/I".
    let axis_name_room = (0.3 * points).ceil() + 1.0;
    let inner_width = (width - 16.0 - axis_name_room).max(120.0);
    let plot_rect = ui
        .horizontal(|ui| {
            ui.add_space(axis_name_room);
            ui.scope(|ui| {
                let look = plots::PlotLook::large(ppp, hover);
                plots::lesson_plot(ui, plot, history, snap, (inner_width, height), look)
            })
            .response
            .rect
        })
        .inner;
    (title.rect.union(plot_rect), points * ppp)
}

/// How long after entering presentation or class mode pointer moves are the mode change's own
/// (the window resized under a resting pointer), seconds.
/// Two seconds: under a loaded X server the full-screen resize's pointer event came after 0.5 s
/// and showed a label at the pointer's position × the zoom.
const POINTER_SETTLE_S: f64 = 2.0;

/// Where the paused badge's bottom-right corner goes (points): the scene's bottom-right corner,
/// moved left of any inset (`insets`: the SO(3) ball's and the Poincaré view's rectangles in
/// pixels from the scene's corner) that reaches down into the badge's band of `badge_height`,
/// so the badge never covers an inset (it covered the Poincaré view's bottom edge).
pub(crate) fn paused_badge_corner(
    scene: egui::Rect,
    insets: &[Option<[u32; 4]>],
    pixels_per_point: f32,
    badge_height: f32,
) -> egui::Pos2 {
    const MARGIN: f32 = 12.0;
    let band_top = scene.height() - MARGIN - badge_height;
    let right = insets
        .iter()
        .flatten()
        .filter(|r| (r[1] + r[3]) as f32 / pixels_per_point > band_top)
        .map(|r| r[0] as f32 / pixels_per_point - MARGIN)
        .fold(scene.width() - MARGIN, f32::min);
    scene.min + egui::vec2(right, scene.height() - MARGIN)
}

/// The controls' scroll bar: drawn whether or not the pointer is over the controls, and beside
/// them rather than over them. egui's own styles, `solid()` as well as `floating()`, draw a bar
/// only while the pointer is over its area (their dormant opacity is 0), so in class mode the
/// last rows were cut at the status bar with no sign of more below; a room sees this one, and a
/// teacher can grab it.
fn controls_scroll_style() -> egui::style::ScrollStyle {
    egui::style::ScrollStyle {
        bar_width: 10.0,
        dormant_background_opacity: 0.4,
        dormant_handle_opacity: 0.8,
        active_background_opacity: 0.5,
        active_handle_opacity: 0.9,
        ..egui::style::ScrollStyle::solid()
    }
}

#[cfg(test)]
mod tests {
    use super::paused_badge_corner;
    use crate::view::layout::layout_for;

    #[test]
    fn the_paused_badge_keeps_clear_of_the_insets() {
        // The badge (about 300 × 45 points) at its corner, at two window sizes and both
        // scales, with the ball and the Poincaré view stacked on the right.
        for (w, h, ppp) in [
            (1220.0, 880.0, 1.0),
            (900.0, 650.0, 2.0),
            (1540.0, 1040.0, 1.0),
        ] {
            let scene = egui::Rect::from_min_size(egui::pos2(380.0, 20.0), egui::vec2(w, h));
            let size = ((w * ppp) as u32, (h * ppp) as u32);
            let insets = layout_for(size, true, true, true);
            let corner = paused_badge_corner(scene, &insets[1..], ppp, 45.0);
            let badge = egui::Rect::from_min_max(corner - egui::vec2(300.0, 45.0), corner);
            assert!(scene.contains_rect(badge), "{badge:?} in {scene:?}");
            for r in insets[1..].iter().flatten() {
                let inset = egui::Rect::from_min_size(
                    scene.min + egui::vec2(r[0] as f32, r[1] as f32) / ppp,
                    egui::vec2(r[2] as f32, r[3] as f32) / ppp,
                );
                assert!(!inset.intersects(badge), "{badge:?} covers {inset:?}");
            }
            // With one inset at the top the corner stays where it was.
            let one = layout_for(size, true, true, false);
            let c = paused_badge_corner(scene, &one[1..], ppp, 45.0);
            assert_eq!(c, scene.max - egui::vec2(12.0, 12.0));
        }
    }
}
