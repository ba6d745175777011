//! The files panel: load and save scenes and shapes, fit a body to a dropped mesh, write the
//! trajectory CSV and screenshots, switch presets.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError};

use crate::geometry::mesh_fit::{FitOptions, FitReport, MeshFit, fit_mesh};
use crate::geometry::mesh_read::MeshSource;
use crate::geometry::{Body, ShapeFile};
use crate::live::{SimCommand, SimStatus};
use crate::scene::{BodySpec, Scene, load_scene_file};

use super::controls::method_spec;

/// What Save state does, for its button and menu entry.
pub(super) const SAVE_STATE_HINT: &str = "the scene as it runs now, at its time, pose and \
    velocity, with the sweep plots' points, to the state path (a file of its own, so saving the \
    scene never replaces it): opening it goes on from there (Save scene writes the scene from \
    its start)";
use super::dialog::{DialogPurpose, FileDialogs};
use super::{AppUi, UiAction};
use crate::scene::description::{
    SAVED_PREFIX, STARTED_AS, STATE_END, STATE_PREFIX, original_description,
};

impl AppUi {
    pub(super) fn files_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let hint = match self.dialogs.availability() {
            Ok(()) => "Open… and Save as… show the desktop's file dialog; or type a path, or drop \
                       a .toml scene, a .json shape or an .stl/.obj/.ply mesh on the window."
                .to_string(),
            Err(why) => format!(
                "{why}: type a path, or drop a .toml scene, a .json shape or an .stl/.obj/.ply \
                 mesh on the window."
            ),
        };
        ui.label(egui::RichText::new(hint).small().weak());
        // Each path gets the panel's whole width on a row of its own, its buttons on the row
        // under it: beside the buttons a field had room for four characters.
        path_field(ui, "scene", &mut self.scene_path);
        buttons_row(ui, |ui| {
            if ui.button("Load").clicked() {
                let path = PathBuf::from(&self.scene_path);
                self.open_scene(&path, actions);
            }
            if ui.button("Save").clicked() {
                self.save_scene(status);
            }
            let current = Path::new(&self.scene_path);
            dialog_buttons(
                &mut self.dialogs,
                ui,
                [DialogPurpose::OpenScene, DialogPurpose::SaveScene],
                current,
            );
        });
        path_field(ui, "state", &mut self.state_path);
        buttons_row(ui, |ui| {
            if ui
                .button("Save state")
                .on_hover_text(SAVE_STATE_HINT)
                .clicked()
            {
                self.save_state(status);
            }
            if ui
                .button("Resume")
                .on_hover_text("open the saved state: the run goes on from where it was saved")
                .clicked()
            {
                let path = PathBuf::from(&self.state_path);
                self.open_scene(&path, actions);
            }
        });
        path_field(ui, "shape", &mut self.shape_path);
        buttons_row(ui, |ui| {
            if ui.button("Load").clicked() {
                self.load_shape(status, actions);
            }
            if ui.button("Save").clicked() {
                self.save_shape(status);
            }
            let current = Path::new(&self.shape_path);
            dialog_buttons(
                &mut self.dialogs,
                ui,
                [DialogPurpose::OpenShape, DialogPurpose::SaveShape],
                current,
            );
        });
        path_field(ui, "screenshot", &mut self.screenshot_path);
        buttons_row(ui, |ui| {
            if ui.button("Save PNG").clicked() {
                actions.push(UiAction::Screenshot(PathBuf::from(&self.screenshot_path)));
            }
        });
        path_field(ui, "record", &mut self.record_dir);
        buttons_row(ui, |ui| {
            ui.add(egui::DragValue::new(&mut self.record_frames).range(1..=100_000));
            let busy = self.recording.is_some();
            if ui
                .add_enabled(!busy, egui::Button::new("Record"))
                .on_hover_text(
                    "the next N frames of the 3D view, as shown: PNGs into a folder, or one \
                     clip at the scene's fps when the path ends in .gif (or .mp4, with ffmpeg)",
                )
                .clicked()
            {
                actions.push(UiAction::Record {
                    dir: PathBuf::from(&self.record_dir),
                    frames: self.record_frames,
                });
            }
        });
        path_field(ui, "plot data", &mut self.plot_data_dir);
        buttons_row(ui, |ui| {
            if ui
                .button("Export CSV")
                .on_hover_text(
                    "the plotted data into this folder: sweep-alpha.csv (1/T against α), \
                     sweep-mass.csv (∂Ω crossings against m/m0), health.csv, contact-force.csv",
                )
                .clicked()
            {
                self.export_plot_data(status);
            }
        });
        if !self.recent.is_empty() {
            ui.label("recent");
            let mut reopen = None;
            for path in &self.recent {
                let name = path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                if ui
                    .small_button(name)
                    .on_hover_text(path.display().to_string())
                    .clicked()
                {
                    reopen = Some(path.clone());
                }
            }
            if let Some(path) = reopen {
                self.open_file(&path, status, actions);
            }
        }
    }

    /// Opens a scene (.toml) or shape (.json) file, or fits a body to a mesh (.stl, .obj, .ply)
    /// and rolls it, as a drop on the window or the recent list does; a bad file leaves the
    /// running scene as it is and says why in the notice, with the command line's message.
    pub fn open_file(&mut self, path: &Path, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("toml") => {
                self.scene_path = path.display().to_string();
                self.open_scene(path, actions);
            }
            Some("json") => {
                self.shape_path = path.display().to_string();
                self.load_shape(status, actions);
            }
            Some(e) if MESH_EXTENSIONS.contains(&e) => self.start_mesh_fit(path),
            _ => {
                self.notice = Some((
                    format!(
                        "{}: rollphase opens scene files (.toml), shape files (.json) and \
                         meshes to fit a body to (.stl, .obj, .ply)",
                        path.display()
                    ),
                    true,
                ));
            }
        }
    }

    /// Starts fitting a body to the mesh at `path` on a thread of its own, as `rollphase shape
    /// --from-mesh` fits it (a mesh of millions of triangles takes seconds, which would freeze
    /// the window); [`Self::poll_mesh_fit`] rolls the body when the fit is done. A new drop
    /// replaces a fit still running (its answer is dropped).
    fn start_mesh_fit(&mut self, path: &Path) {
        let (send, answer) = std::sync::mpsc::channel();
        let done = Arc::new((AtomicUsize::new(0), AtomicUsize::new(0)));
        let file = path.to_path_buf();
        let progress = Arc::clone(&done);
        let spawned = std::thread::Builder::new()
            .name("mesh fit".into())
            .spawn(move || {
                let fit = MeshSource::open(&file).and_then(|source| {
                    fit_mesh(&source, &FitOptions::default(), &|_, i, total| {
                        progress.0.store(i, Ordering::Relaxed);
                        progress.1.store(total, Ordering::Relaxed);
                    })
                });
                // The receiver is gone only when another drop replaced this fit.
                let _ = send.send(fit.map_err(|e| e.to_string()));
            });
        match spawned {
            Ok(_) => {
                self.notice = Some((format!("fitting a body to {}…", path.display()), false));
                self.mesh_fit = Some(PendingFit {
                    path: path.to_path_buf(),
                    answer,
                    done,
                });
            }
            Err(e) => {
                self.notice = Some((
                    format!("{}: could not start the fit: {e}", path.display()),
                    true,
                ));
            }
        }
    }

    /// Collects a mesh fit that has finished: its body rolls from rest (as a loaded shape file
    /// does) and the notice gives the fit's residual; a mesh that cannot be fitted leaves the
    /// running scene and says why. While the fit runs the notice counts its triangles.
    pub(super) fn poll_mesh_fit(
        &mut self,
        ctx: &egui::Context,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let Some(pending) = &self.mesh_fit else {
            return;
        };
        let answer = match pending.answer.try_recv() {
            Err(TryRecvError::Empty) => {
                let (i, total) = (
                    pending.done.0.load(Ordering::Relaxed),
                    pending.done.1.load(Ordering::Relaxed),
                );
                if total > 0 {
                    self.notice = Some((
                        format!(
                            "fitting a body to {}: {i} of {total} triangles…",
                            pending.path.display()
                        ),
                        false,
                    ));
                }
                ctx.request_repaint_after(std::time::Duration::from_millis(100));
                return;
            }
            Err(TryRecvError::Disconnected) => Err(format!(
                "{}: the fit stopped without an answer",
                pending.path.display()
            )),
            Ok(answer) => answer,
        };
        let Some(PendingFit { path, .. }) = self.mesh_fit.take() else {
            return;
        };
        match answer {
            Ok(MeshFit {
                body,
                shape,
                report,
            }) => {
                self.remember(&path);
                self.roll_shape(shape, matches!(body, Body::Disk(_)), &path, status, actions);
                if !self.notice.as_ref().is_some_and(|(_, error)| *error) {
                    let note = self.notice.take().map(|(n, _)| format!("; {n}"));
                    self.notice = Some((
                        format!("{}{}", fit_summary(&report), note.unwrap_or_default()),
                        false,
                    ));
                }
            }
            Err(e) => self.notice = Some((e, true)),
        }
    }

    /// Writes the scene to the path field's file. A saved scene carries its body inline, so it
    /// loads from anywhere.
    pub fn save_scene(&mut self, status: &SimStatus) {
        let scene = self.scene_to_save(status);
        self.write_scene(&scene);
    }

    /// The scene as it runs now ([`Self::current_scene`]) with its body inline, so the file
    /// loads from anywhere.
    fn scene_to_save(&self, status: &SimStatus) -> Scene {
        let mut scene = self.current_scene(status);
        scene.body = BodySpec {
            inline: Some(status.setup.body.to_shape()),
            ..BodySpec::default()
        };
        for (entry, lane) in scene.bodies.iter_mut().zip(&status.setup.lanes) {
            entry.body = Some(BodySpec {
                inline: Some(lane.body.to_shape()),
                ..BodySpec::default()
            });
        }
        scene
    }

    /// Writes `scene` to the scene path; the notice says where, or why not.
    fn write_scene(&mut self, scene: &Scene) {
        let path = self.scene_path.clone();
        self.write_toml(scene, &path, "the scene");
    }

    /// Writes `scene` to `path`; the notice says what was saved where, or why not.
    fn write_toml(&mut self, scene: &Scene, path: &str, what: &str) {
        self.notice = Some(match scene.to_toml() {
            Ok(text) => match write_file(path, &text) {
                (_, false) => (format!("saved {what} to {path}"), false),
                failed => failed,
            },
            Err(e) => (e.to_string(), true),
        });
    }

    /// The File menu: what the files panel does, reachable without scrolling the controls
    /// (Export sat at the bottom of a scrolling panel). The paths are the panel's fields.
    pub(super) fn file_menu_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        ui.menu_button("File", |ui| {
            let dialogs = self.dialogs.availability().is_ok() && !self.dialogs.is_open();
            // Why the dialog entries are greyed out, and what to do instead.
            let no_dialog = match self.dialogs.availability() {
                Err(why) => format!(
                    "{why}: type the path into the Files panel's fields (a mesh into the shape \
                     field), or drop the file on the window"
                ),
                Ok(()) => "a file dialog is already open".to_string(),
            };
            if ui
                .add_enabled(dialogs, egui::Button::new("Open scene…"))
                .on_disabled_hover_text(&no_dialog)
                .clicked()
            {
                let current = PathBuf::from(&self.scene_path);
                self.dialogs.open(DialogPurpose::OpenScene, &current);
                ui.close();
            }
            if ui
                .add_enabled(dialogs, egui::Button::new("Open shape or mesh…"))
                .on_disabled_hover_text(&no_dialog)
                .clicked()
            {
                let current = PathBuf::from(&self.shape_path);
                self.dialogs.open(DialogPurpose::OpenShape, &current);
                ui.close();
            }
            ui.separator();
            let scene_path = self.scene_path.clone();
            if ui
                .button(format!("Save scene to {scene_path}"))
                .on_hover_text("the scene with the current α, m/m0 and views, from its start")
                .clicked()
            {
                self.save_scene(status);
                ui.close();
            }
            let state_path = self.state_path.clone();
            if ui
                .button(format!("Save state to {state_path}"))
                .on_hover_text(SAVE_STATE_HINT)
                .clicked()
            {
                self.save_state(status);
                ui.close();
            }
            if ui
                .add_enabled(dialogs, egui::Button::new("Save scene as…"))
                .on_disabled_hover_text(&no_dialog)
                .clicked()
            {
                let current = PathBuf::from(&self.scene_path);
                self.dialogs.open(DialogPurpose::SaveScene, &current);
                ui.close();
            }
            ui.separator();
            let plot_dir = self.plot_data_dir.clone();
            if ui
                .button(format!("Export plot data to {plot_dir}/"))
                .on_hover_text(
                    "every plotted series as CSV with plot-data.json (scene, body, model, α, \
                     α*, m/m0, integrator, t)",
                )
                .clicked()
            {
                self.export_plot_data(status);
                ui.close();
            }
            let shot = self.screenshot_path.clone();
            if ui.button(format!("Screenshot to {shot}")).clicked() {
                actions.push(UiAction::Screenshot(PathBuf::from(shot)));
                ui.close();
            }
            ui.label(
                egui::RichText::new("paths: the Files panel's fields")
                    .small()
                    .weak(),
            );
        });
    }

    /// Writes the run as it is now to the state path: the scene ([`Self::save_scene`]) with a
    /// `[resume]` of the time, the model's whole state and the sweep plots' points, so that
    /// opening it goes on where the run was.
    pub fn save_state(&mut self, status: &SimStatus) {
        let mut scene = self.scene_to_save(status);
        let snap = &status.snapshot;
        if let Some((n, lane)) = snap.lanes.iter().enumerate().find(|(_, l)| l.t != snap.t) {
            self.notice = Some((
                format!(
                    "cannot save the state: body {} ({}) stopped at t = {:.2}, not at the run's                      t = {:.2} (the bodies are saved together, at one time); save the scene, or                      reset",
                    n + 2,
                    lane.label,
                    lane.t,
                    snap.t
                ),
                true,
            ));
            return;
        }
        scene.description = format!(
            "{STATE_PREFIX}{:.2} (α = {:.5} rad, m/m0 = {}, {}); {STATE_END}{}",
            snap.t,
            snap.alpha_rad,
            crate::view::short_number(snap.mass_ratio),
            snap.drag_law.label(),
            original_description(&scene.description)
        );
        scene.resume = Some(self.history.saved(snap.t, snap.state.clone()));
        // How the run got here: replayed from the scene's start, it reaches this state to the
        // bit (`LiveRun::replayed`).
        scene.replay = snap.replay.clone();
        // Each other body with its own plots' points, so they load back as they were.
        for (n, (entry, lane)) in scene.bodies.iter_mut().zip(&snap.lanes).enumerate() {
            let saved = match self.history.lane(n + 1) {
                Some(plots) => plots.saved(lane.t, lane.state.clone()),
                None => {
                    crate::live::history::PlotHistory::default().saved(lane.t, lane.state.clone())
                }
            };
            entry.resume = Some(saved.into());
        }
        let path = self.state_path.clone();
        self.write_toml(&scene, &path, "the run's state");
    }

    /// Sets the scene path (as typed into its field).
    pub fn set_scene_path(&mut self, path: &Path) {
        self.scene_path = path.display().to_string();
    }

    /// Sets the shape path (as typed into its field).
    pub fn set_shape_path(&mut self, path: &Path) {
        self.shape_path = path.display().to_string();
    }

    /// Sets the state path (as typed into its field).
    pub fn set_state_path(&mut self, path: &Path) {
        self.state_path = path.display().to_string();
    }

    /// Sets the plot data folder (as typed into its field).
    pub fn set_plot_data_dir(&mut self, dir: &Path) {
        self.plot_data_dir = dir.display().to_string();
    }

    /// Writes the plotted data (the α sweep, the mass sweep, the health history) into the plot
    /// data folder; the notice says where, or why not.
    pub fn export_plot_data(&mut self, status: &SimStatus) {
        let dir = PathBuf::from(&self.plot_data_dir);
        let meta =
            crate::live::history::PlotMeta::of(&status.snapshot, &status.setup, status.method);
        self.notice = Some(
            match self.history.write_csv_files(
                &dir,
                status.snapshot.health.measured,
                &meta,
                &crate::output::Inputs::none(),
            ) {
                Ok(files) => (
                    format!(
                        "exported {} CSV files and {} to {}",
                        files.len() - 1,
                        crate::live::history::PLOT_META_FILE,
                        // Where it is, not where a relative path would be from somewhere.
                        std::fs::canonicalize(&dir).unwrap_or(dir).display()
                    ),
                    false,
                ),
                Err(e) => (e.to_string(), true),
            },
        );
    }

    /// Writes the body's shape file to the path field's file.
    fn save_shape(&mut self, status: &SimStatus) {
        self.notice = Some(match status.setup.body.to_shape().to_json() {
            Ok(json) => write_file(&self.shape_path, &json),
            Err(e) => (format!("cannot write the shape file: {e}"), true),
        });
    }

    /// Acts on a file dialog's answer: open the file, or save to it (the path field takes the
    /// chosen path, so Save writes there again).
    pub(super) fn dialog_answered(
        &mut self,
        purpose: DialogPurpose,
        chosen: Option<PathBuf>,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let Some(path) = chosen else {
            self.notice = Some((
                "no file chosen (if no dialog appeared, this desktop offers no file chooser: \
                 type a path instead)"
                    .into(),
                false,
            ));
            return;
        };
        match purpose {
            DialogPurpose::OpenScene | DialogPurpose::OpenShape => {
                self.open_file(&path, status, actions);
            }
            DialogPurpose::SaveScene => {
                self.scene_path = path.display().to_string();
                self.save_scene(status);
            }
            DialogPurpose::SaveShape => {
                self.shape_path = path.display().to_string();
                self.save_shape(status);
            }
        }
    }

    fn open_scene(&mut self, path: &Path, actions: &mut Vec<UiAction>) {
        match load_scene_file(path) {
            Ok(setup) => {
                self.notice = Some((format!("loaded {}", path.display()), false));
                self.base = path.parent().map(Path::to_path_buf);
                self.remember(path);
                actions.push(UiAction::Sim(SimCommand::Load(Box::new(setup))));
            }
            Err(e @ crate::scene::SceneError::SceneIo { .. }) => {
                self.notice = Some((e.to_string(), true));
            }
            Err(e) => {
                self.notice = Some((format!("bad scene file {}: {e}", path.display()), true));
            }
        }
    }

    /// Puts `path` first in the recent list.
    fn remember(&mut self, path: &Path) {
        let path = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        self.recent.retain(|p| *p != path);
        self.recent.insert(0, path);
        self.recent.truncate(super::RECENT_FILES);
    }

    /// Files opened this session, newest first.
    pub fn recent_files(&self) -> &[PathBuf] {
        &self.recent
    }

    /// The message under the controls: (text, is an error).
    pub fn notice(&self) -> Option<&(String, bool)> {
        self.notice.as_ref()
    }

    /// Loads the shape field's file: a shape file (JSON), rolled at once, or a mesh, fitted on
    /// a thread of its own and rolled when done (as a dropped one is).
    pub fn load_shape(&mut self, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let path = PathBuf::from(&self.shape_path);
        // A mesh typed into the field is fitted as a dropped one is: where no file dialog
        // exists, this is the way to load one (Load read JSON only: "stream did not contain
        // valid UTF-8").
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if extension.is_some_and(|e| MESH_EXTENSIONS.contains(&e.as_str())) {
            self.start_mesh_fit(&path);
            return;
        }
        match ShapeFile::load(&path) {
            Ok(body) => {
                self.remember(&path);
                let disk = matches!(body, Body::Disk(_));
                self.roll_shape(body.to_shape(), disk, &path, status, actions);
            }
            Err(e) => self.notice = Some((format!("{e:#}"), true)),
        }
    }

    /// Runs `shape` (from the file `path`) in the current scene's ramp, α, m/m0 and integrator,
    /// from rest.
    fn roll_shape(
        &mut self,
        shape: ShapeFile,
        disk: bool,
        path: &Path,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let mut scene = self.current_scene(status);
        scene.body = BodySpec {
            inline: Some(shape),
            ..BodySpec::default()
        };
        // A contact point or angle names a place on the old body; start the new one afresh.
        scene.initial = crate::scene::InitialSpec::default();
        scene.name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "shape".into());
        // The old description names the old body.
        scene.description = format!(
            "The body of {}, rolled from rest on the ramp that was running (α, m/m0 and the \
             integrator kept).",
            path.file_name()
                .unwrap_or(path.as_os_str())
                .to_string_lossy()
        );
        if disk {
            scene.views.ball = false;
            scene.views.poincare = false;
        }
        self.load_scene(scene, None, actions);
    }

    /// The scene as it runs now: the loaded one with the live α, m/m0, integrator, speed and
    /// views.
    /// The scene as it runs now: the running setup's scene (so a start clicked on the map or the
    /// Poincaré sphere, or turned by a shift-drag, is the saved start), with the current α, m/m0,
    /// integrator, speed and views, and, when α or m/m0 were changed, a description that says
    /// so rather than the original one (which may name another α).
    pub(super) fn current_scene(&self, status: &SimStatus) -> Scene {
        let mut scene = status.setup.scene.clone();
        let snap = &status.snapshot;
        let ramp = &status.setup.ramp;
        if snap.alpha_rad != ramp.alpha_rad
            || snap.mass_ratio != ramp.mass_ratio
            || snap.drag_law != ramp.drag_law
        {
            let first = original_description(&scene.description);
            scene.description = format!(
                "{SAVED_PREFIX}{:.4} rad ({:.3} α*), m/m0 = {}, {}{}",
                snap.alpha_rad,
                snap.alpha_rad / status.setup.alpha_star,
                crate::view::short_number(snap.mass_ratio),
                snap.drag_law.label(),
                if first.is_empty() {
                    String::new()
                } else {
                    format!("{STARTED_AS}{first}")
                }
            );
        }
        scene.model.alpha_rad = Some(snap.alpha_rad);
        scene.model.alpha_over_critical = None;
        scene.model.mass_ratio = snap.mass_ratio;
        // A scene that named its model names the one the saved m/m0 asks for, so that the
        // file loads again after inertia was turned on or off.
        if scene.model.kind.is_some() {
            let now = crate::dynamics::Ramp {
                mass_ratio: snap.mass_ratio,
                ..*ramp
            };
            let kind =
                crate::dynamics::ModelKind::for_dimension(status.setup.body.dimension(), &now);
            scene.model.kind = Some(kind.name().to_string());
        }
        scene.model.drag_law = crate::scene::DragLawFields::from(&snap.drag_law);
        scene.integrator = method_spec(&status.method);
        // A scene from its start has no history to replay (Save state adds the run's).
        scene.replay.clear();
        scene.playback.speed = status.speed;
        scene.views = self.views.clone();
        // Each other body as it runs: its own body, start and model written out (a hand
        // changes only the scene's own m/m0, which an entry without a model would take).
        for (entry, lane) in scene.bodies.iter_mut().zip(&status.setup.lanes) {
            let mut model = lane.scene.model.clone();
            model.alpha_rad = None;
            model.alpha_over_critical = None;
            entry.model = Some(crate::scene::LaneModel::whole(&model));
            entry.body = Some(lane.scene.body.clone());
            entry.initial = Some(lane.scene.initial.clone());
        }
        scene
    }

    pub(super) fn load_preset(&mut self, name: &str, actions: &mut Vec<UiAction>) {
        match Scene::preset(name) {
            Ok(scene) => self.load_scene(scene, None, actions),
            Err(e) => self.notice = Some((e.to_string(), true)),
        }
    }

    pub(super) fn load_scene(
        &mut self,
        scene: Scene,
        base: Option<PathBuf>,
        actions: &mut Vec<UiAction>,
    ) {
        match scene.setup(base.as_deref()) {
            Ok(setup) => {
                self.notice = setup.model_note.clone().map(|n| (n, false));
                actions.push(UiAction::Sim(SimCommand::Load(Box::new(setup))));
            }
            Err(e) => self.notice = Some((e.to_string(), true)),
        }
    }

    pub(super) fn scene_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let rect = ui.max_rect();
        self.scene_rect = Some(rect);
        self.pixels_per_point = ui.ctx().pixels_per_point();
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        // Shift-drag turns a 3D body about the ramp normal; the run restarts from the turned
        // orientation when the drag ends.
        let disk = status.snapshot.theta.is_some();
        let turning = ui.input(|i| i.modifiers.shift) && !disk && !self.sculpt_dragging();
        if response.dragged() && turning {
            self.turn += response.drag_delta().x * 0.01;
            self.notice = Some((
                format!(
                    "turning the body by {:.0}° about the ramp normal (release to restart)",
                    self.turn.to_degrees()
                ),
                false,
            ));
        }
        if response.drag_stopped() && self.turn != 0.0 {
            let angle = std::mem::take(&mut self.turn) as f64;
            self.restart_turned(angle, status, actions);
        }
        // Sculpting: a drag from the body pulls or presses its surface as the pointer moves
        // (a drag from elsewhere turns the camera).
        if self.sculpt.on
            && !turning
            && response.drag_started_by(egui::PointerButton::Primary)
            && let Some(origin) = ui.input(|i| i.pointer.press_origin())
            && self.poincare_pick(rect, origin, status).is_none()
            && !self.in_ball_inset(rect, origin, status)
        {
            self.sculpt_drag_start(
                (
                    (origin.x - rect.min.x) * self.pixels_per_point,
                    (origin.y - rect.min.y) * self.pixels_per_point,
                ),
                origin.y,
                status,
            );
        }
        if self.sculpt_dragging() {
            if let Some(pos) = response.interact_pointer_pos() {
                self.sculpt_drag_move(pos.y, status, actions);
            }
            if response.drag_stopped() || !ui.input(|i| i.pointer.primary_down()) {
                self.sculpt_drag_end();
            }
        }
        // Sculpting: a click on the body presses a dent, a right click pulls a bump (the
        // insets keep their own clicks).
        let sculpted = self.sculpt.on
            && (response.clicked() || response.secondary_clicked())
            && response.interact_pointer_pos().is_some_and(|pos| {
                self.poincare_pick(rect, pos, status).is_none()
                    && !self.in_ball_inset(rect, pos, status)
                    && self.sculpt_click(
                        (
                            (pos.x - rect.min.x) * self.pixels_per_point,
                            (pos.y - rect.min.y) * self.pixels_per_point,
                        ),
                        response.secondary_clicked(),
                        status,
                        actions,
                    )
            });
        // A click on the Poincaré sphere starts from that orientation on ∂Ω.
        if !sculpted
            && response.clicked()
            && let Some(pos) = response.interact_pointer_pos()
        {
            if let Some(p) = self.poincare_pick(rect, pos, status) {
                self.restart_from_boundary(p, status, actions);
            } else if self.in_ball_inset(rect, pos, status) {
                // The ball shows where the orientation has been; it is not a place to start
                // from (a point inside it is no rotation by π). Say where to click instead.
                self.notice = Some((
                    "the SO(3) ball shows the path of the orientation; to start from an \
                     orientation, click the Poincaré sphere (Views: Poincaré field on ∂Ω), or a \
                     body point on the curvature map"
                        .into(),
                    false,
                ));
            }
        }
        if response.dragged() && !turning && !self.sculpt_dragging() {
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

/// "Open…" and "Save as…" beside a path field whose file is `current`, where a dialog can
/// appear; `purposes` are the field's open and save purposes.
fn dialog_buttons(
    dialogs: &mut FileDialogs,
    ui: &mut egui::Ui,
    purposes: [DialogPurpose; 2],
    current: &Path,
) {
    if dialogs.availability().is_err() {
        return;
    }
    let idle = !dialogs.is_open();
    for (label, purpose) in ["Open…", "Save as…"].into_iter().zip(purposes) {
        if ui.add_enabled(idle, egui::Button::new(label)).clicked() {
            dialogs.open(purpose, current);
        }
    }
}

/// Width of the labels in front of the path fields, so the fields line up.
const PATH_LABEL_WIDTH: f32 = 70.0;

/// A labelled path field as wide as the panel; hovering shows the whole path.
fn path_field(ui: &mut egui::Ui, label: &str, path: &mut String) -> egui::Response {
    ui.horizontal(|ui| {
        let text = ui.label(label);
        ui.add_space((PATH_LABEL_WIDTH - text.rect.width()).max(0.0));
        let hover = path.clone();
        ui.add(egui::TextEdit::singleline(path).desired_width(ui.available_width()))
            .on_hover_text(hover)
    })
    .inner
}

/// The buttons under a path field, from the panel's left edge so four of them fit its width.
fn buttons_row(ui: &mut egui::Ui, add: impl FnOnce(&mut egui::Ui)) {
    ui.horizontal(add);
    ui.add_space(ui.spacing().item_spacing.y);
}

/// Writes `text` to `path` through the output layer; the notice says what happened.
pub(super) fn write_file(path: &str, text: &str) -> (String, bool) {
    let inputs = crate::output::Inputs::none();
    match crate::output::write_bytes(std::path::Path::new(path), text.as_bytes(), &inputs) {
        Ok(()) => (format!("saved {path}"), false),
        Err(e) => (e.to_string(), true),
    }
}

/// The meshes a dropped or opened file may be (any case), as `shape --from-mesh` reads them.
const MESH_EXTENSIONS: [&str; 3] = ["stl", "obj", "ply"];

/// A mesh fit running on its own thread.
pub(super) struct PendingFit {
    path: PathBuf,
    answer: Receiver<Result<MeshFit, String>>,
    /// Triangles done and in all, as the fit reports them.
    done: Arc<(AtomicUsize, AtomicUsize)>,
}

/// The notice after a mesh fit: what was fitted and how well, in mm where the mesh was.
fn fit_summary(r: &FitReport) -> String {
    let degree = if r.dimension == 3 {
        format!("3D, degree L = {}", r.modes)
    } else {
        format!("2D (cylinder), modes up to M = {}", r.modes)
    };
    let warnings = match r.warnings.as_slice() {
        [] => String::new(),
        [one] => format!("; warning: {one}"),
        [first, rest @ ..] => format!("; warning: {first} (and {} more)", rest.len()),
    };
    format!(
        "fitted {} ({degree}, uniform density): rms residual {:.3} % of ⟨r⟩ ({:.4} mm), max \
         {:.3} %; ⟨r⟩ = {:.3} mm, α* = {:.4}{warnings}",
        Path::new(&r.file)
            .file_name()
            .map_or(r.file.clone(), |n| n.to_string_lossy().into_owned()),
        100.0 * r.rms_residual,
        r.rms_residual_mm,
        100.0 * r.max_residual,
        r.scale_mm,
        r.alpha_star
    )
}

#[cfg(test)]
mod tests {
    use super::{PATH_LABEL_WIDTH, path_field};
    use crate::ui::workbench::offscreen_input;

    #[test]
    fn a_path_field_takes_the_panels_width_after_its_label() {
        // In the controls panel's default 300-point width the field showed four characters
        // while it shared its row with four buttons; on a row of its own it gets the rest.
        let ctx = egui::Context::default();
        let mut field = egui::Rect::NOTHING;
        let mut panel = egui::Rect::NOTHING;
        for frame in 0..2 {
            let input = offscreen_input((1600, 900), frame as f64 / 60.0, Vec::new());
            let mut output = ctx.run_ui(input, |ui| {
                egui::Panel::left("controls")
                    .default_size(300.0)
                    .show(ui, |ui| {
                        let mut path = "assets/scenes/sphere-cruising.toml".to_string();
                        field = path_field(ui, "scene", &mut path).rect;
                        panel = ui.max_rect();
                    });
            });
            // Nothing is painted, so the font atlas's updates are dropped on purpose.
            output.textures_delta.clear();
        }
        assert!(
            field.width() >= panel.width() - PATH_LABEL_WIDTH - 20.0,
            "field {field:?} in panel {panel:?}"
        );
        assert!(field.width() >= 180.0, "field {field:?}");
        assert!(
            field.right() <= panel.right() + 0.5,
            "field {field:?} past {panel:?}"
        );
    }
}
