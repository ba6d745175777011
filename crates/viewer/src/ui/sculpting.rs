//! Sculpting in the app (the Body panel's "Sculpt" section): with "sculpt with the mouse" on, a
//! click on the body presses a dent and a right click pulls a bump, of the width and depth set
//! there, and a left-button drag from the body pulls the surface out (up) or presses it in (down) live, the
//! run restarting on the body at every move and the readout following, until the release keeps
//! it as one stroke (one undo); a drag past the edge of convexity stops at the edge and says
//! why. The mode amplitudes can be edited too. Each change is the core's stroke
//! ([`crate::geometry::sculpt`]) through a [`Sculptor`] (undo, redo; a stroke that would make
//! the body non-convex is refused with why) and restarts the run on the new body from the same
//! contact, at rest. Beside it: α*, the convexity, the smallest radius of curvature at the print
//! scale, and for a 3D body which way its orbits drift (`predict` on a worker thread, 8 starts).
//! The body saves as a shape file or an STL through the output layer.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use egui::RichText;

use super::{AppUi, UiAction};
use crate::analysis::design::DEFAULT_SCALE_MM;
use crate::analysis::experiment::prediction::{PredictOptions, Prediction, predict_until};
use crate::geometry::Body;
use crate::geometry::sculpt::{
    MAX_STROKE_HEIGHT, MAX_STROKE_WIDTH, MIN_STROKE_WIDTH, Stroke, StrokePoint,
};
use crate::live::{SimCommand, SimStatus};
use crate::scene::InitialSpec;
use crate::scene::sculpt::{SculptReadout, Sculptor, sculpted_scene};
use crate::view::pick::{PickView, body_point_at};

mod drag;

pub use drag::DRAG_HEIGHT_PER_POINT;
use drag::DragStroke;

/// What a stroke's notice adds when the body was a print's section, which any stroke drops.
const PRINT_DROPPED: &str = " (the print's section is dropped: the body is now its smooth modes)";

/// Starts of the drift measurement: enough to see the orbits a ball settles on, few enough to
/// answer in seconds.
const DRIFT_STARTS: usize = 8;

/// The sculpting section's settings and session.
pub struct SculptPanel {
    /// A click on the body sculpts it (left: dent, right: bump); off, the mouse turns the
    /// camera as before.
    pub on: bool,
    /// The stroke's width (rad).
    pub width: f64,
    /// The stroke's depth (⟨r⟩): how far the surface moves at the point.
    pub depth: f64,
    /// The print scale, mm per ⟨r⟩, of the radius of curvature and the STL.
    pub scale_mm: f64,
    /// Where the shape file and the STL are saved.
    pub shape_path: String,
    /// The body's view as last painted (set by the workbench).
    pub pick_view: Option<PickView>,
    session: Option<Sculptor>,
    readout: Option<(Body, SculptReadout)>,
    drift: Option<DriftJob>,
    /// The mode panel's values while they are edited, for the body they started from.
    draft: Option<(Body, Vec<ModeRow>)>,
    /// How long the last stroke took from the click to the restarted run's setup (ms).
    pub last_stroke_ms: Option<f64>,
    /// The scene the session follows (a new scene that is not the session's body starts a new
    /// session; frames before a stroke's scene arrives still show the old one).
    seen_scene: Option<u64>,
    /// The α and m/m0 the drift waits to see held still before it is measured.
    drift_wait: Option<((f64, f64), std::time::Instant)>,
    /// The stroke being dragged, from the press on the body to the release.
    dragging: Option<DragStroke>,
    /// The bodies a drag has sent to the simulation whose runs may not have arrived yet: a frame
    /// that shows one of them is the drag's, not a new body to start a session on.
    in_flight: Vec<crate::geometry::shape_file::ShapeFile>,
}

impl Default for SculptPanel {
    fn default() -> Self {
        Self {
            on: false,
            width: 0.3,
            depth: 0.02,
            scale_mm: 20.0,
            shape_path: "sculpted.json".into(),
            pick_view: None,
            session: None,
            readout: None,
            drift: None,
            draft: None,
            last_stroke_ms: None,
            seen_scene: None,
            drift_wait: None,
            dragging: None,
            in_flight: Vec::new(),
        }
    }
}

/// A drift measurement on a worker thread, for one body at one α and m/m0.
struct DriftJob {
    key: (Body, f64, f64),
    result: Arc<Mutex<Option<Result<String, String>>>>,
    stop: Arc<AtomicBool>,
}

impl Drop for DriftJob {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

impl DriftJob {
    fn start(body: Body, alpha: f64, mass: f64) -> Self {
        let result = Arc::new(Mutex::new(None));
        let stop = Arc::new(AtomicBool::new(false));
        let (b, r, s) = (body.clone(), result.clone(), stop.clone());
        let spawned = std::thread::Builder::new()
            .name("sculpt-drift".into())
            .spawn(move || {
                let options = PredictOptions {
                    starts: DRIFT_STARTS,
                    ..PredictOptions::default()
                };
                let said = match predict_until(&b, alpha, mass, &options, &s) {
                    Ok(p) => Ok(describe_drift(&p)),
                    Err(e) => Err(e.to_string()),
                };
                if !s.load(Ordering::Relaxed)
                    && let Ok(mut slot) = r.lock()
                {
                    *slot = Some(said);
                }
            });
        if let Err(e) = spawned
            && let Ok(mut slot) = result.lock()
        {
            *slot = Some(Err(format!("no worker thread: {e}")));
        }
        Self {
            key: (body, alpha, mass),
            result,
            stop,
        }
    }

    fn said(&self) -> Option<Result<String, String>> {
        self.result.lock().ok()?.clone()
    }
}

/// The drift in words, with the evidence it rests on: each stable orbit rolling down, with
/// its drift across per distance down and how many starts settled on it, and how many starts
/// ended elsewhere (at rest, on an unstable orbit, off the model, undecided).
fn describe_drift(p: &Prediction) -> String {
    let mut rolling: Vec<_> = p
        .orbits
        .iter()
        .filter(|o| o.stable && o.advance_down > 0.0)
        .collect();
    rolling.sort_by_key(|o| std::cmp::Reverse(o.starts));
    let on: usize = rolling.iter().map(|o| o.starts).sum();
    let elsewhere = p.starts.saturating_sub(on);
    if rolling.is_empty() {
        return format!(
            "drift: no stable orbit rolls down (0 of {} starts)",
            p.starts
        );
    }
    let orbits: Vec<String> = rolling
        .iter()
        .map(|o| {
            format!(
                "{:+.3} ({} start{})",
                o.advance_across / o.advance_down,
                o.starts,
                if o.starts == 1 { "" } else { "s" }
            )
        })
        .collect();
    format!(
        "drift across per down, stable orbits: {}; {elsewhere} of {} starts elsewhere",
        orbits.join(", "),
        p.starts
    )
}

impl AppUi {
    /// Follows the running body: when a new scene arrives, the session goes on if it runs the
    /// session's body (a stroke's restart), and starts afresh on any other body, at that body's
    /// print scale.
    pub(super) fn follow_sculpt(&mut self, status: &SimStatus) {
        let running = &status.setup.body;
        let same = |b: &Body| b.to_shape() == running.to_shape();
        if self.sculpt.seen_scene != Some(status.scene_id) {
            self.sculpt.seen_scene = Some(status.scene_id);
            // The simulation loads in the order sent: a drag's body shown means the ones sent
            // before it are done.
            let shown = running.to_shape();
            let drags = self.sculpt.in_flight.iter().position(|s| *s == shown);
            if let Some(i) = drags {
                self.sculpt.in_flight.drain(..=i);
            } else if !self.sculpt.session.as_ref().is_some_and(|s| same(s.body())) {
                self.sculpt.in_flight.clear();
                self.sculpt.dragging = None;
                self.sculpt.session = Some(Sculptor::new(running.clone()));
                self.sculpt.scale_mm = self.body_scale_mm(status).unwrap_or(DEFAULT_SCALE_MM);
            }
        }
        let stale = self.sculpt.on
            && self
                .sculpt
                .readout
                .as_ref()
                .is_none_or(|(b, r)| !same(b) || r.scale_mm != self.sculpt.scale_mm);
        if stale {
            let readout = SculptReadout::of(running, self.sculpt.scale_mm);
            self.sculpt.readout = Some((running.clone(), readout));
        }
    }

    /// The print scale the scene's body names: its inline shape's, or its shape file's.
    fn body_scale_mm(&self, status: &SimStatus) -> Option<f64> {
        let spec = &status.setup.scene.body;
        if let Some(inline) = &spec.inline {
            return inline.scale_mm();
        }
        let path = self.base.as_ref()?.join(spec.shape.as_ref()?);
        crate::geometry::shape_file::ShapeFile::load_scaled(&path)
            .ok()?
            .1
    }

    /// Where body-frame point `p` is drawn in the 3D view (screen points), if the body was
    /// painted and `p` is in front of the camera: for tests and scripted demos, which click
    /// there.
    pub fn body_point_position(&self, p: glam::DVec3) -> Option<egui::Pos2> {
        let rect = self.scene_rect?;
        let (x, y, _) = self.sculpt.pick_view?.project(p)?;
        let ppp = self.pixels_per_point;
        Some(rect.min + egui::vec2(x / ppp, y / ppp))
    }

    /// The body point under frame pixel (`x`, `y`) that a stroke may sculpt: `None` where the
    /// body is not under it; refused, with the notice saying why, without the body's view or on
    /// a body that is not strictly convex.
    pub(super) fn sculptable_point(
        &mut self,
        (x, y): (f32, f32),
        status: &SimStatus,
    ) -> Result<Option<StrokePoint>, ()> {
        let Some(view) = self.sculpt.pick_view else {
            self.notice = Some((
                "sculpting needs the body's view: turn it on under Views".into(),
                true,
            ));
            return Err(());
        };
        let Some(at) = body_point_at(&view, &status.setup.body, x, y) else {
            return Ok(None);
        };
        if let Err(e) = status.setup.body.check_convex() {
            self.notice = Some((
                format!(
                    "this body is not strictly convex ({e}): it rolls on its hull, and a stroke \
                     keeps it so; sculpt a convex body"
                ),
                true,
            ));
            return Err(());
        }
        Ok(Some(at))
    }

    /// A click at frame pixel (`x`, `y`) of the scene area while sculpting: a dent there (a bump
    /// with `pull`), if the body is under it. Returns whether the body was under it.
    pub(super) fn sculpt_click(
        &mut self,
        (x, y): (f32, f32),
        pull: bool,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) -> bool {
        let at = match self.sculptable_point((x, y), status) {
            Ok(Some(at)) => at,
            Ok(None) => return false,
            Err(()) => return true,
        };
        let stroke = Stroke {
            at,
            width: self.sculpt.width,
            height: if pull {
                self.sculpt.depth
            } else {
                -self.sculpt.depth
            },
        };
        let started = std::time::Instant::now();
        let Some(session) = self.sculpt.session.as_mut() else {
            return true;
        };
        match session.stroke(&stroke) {
            Ok(body) => {
                let body = body.clone();
                let what = if pull {
                    "pulled a bump"
                } else {
                    "pressed a dent"
                };
                self.run_sculpted(&body, what, status, actions);
                self.sculpt.last_stroke_ms = Some(started.elapsed().as_secs_f64() * 1e3);
            }
            Err(e) => self.notice = Some((e.to_string(), true)),
        }
        true
    }

    /// The scene and setup that run `body` (the session's body now) from `initial`, at rest,
    /// with the current α, m/m0, integrator and speed: the same checks as a file's.
    fn sculpted_setup(
        &self,
        body: &Body,
        initial: InitialSpec,
        status: &SimStatus,
    ) -> Result<crate::scene::SceneSetup, crate::scene::SceneError> {
        let mut scene = self.current_scene(status);
        let strokes = self.sculpt.session.as_ref().map_or(0, Sculptor::strokes);
        let name = scene
            .name
            .split(", sculpted")
            .next()
            .unwrap_or_default()
            .to_string();
        scene.name = format!("{name}, sculpted");
        scene.description = format!("sculpted in the app ({strokes} change(s) from the start)");
        let scale = (self.base.as_deref(), Some(self.sculpt.scale_mm));
        sculpted_scene(&scene, body, initial, scale).map(|(_, setup)| setup)
    }

    /// Restarts the run on `body` (the session's body now) from the contact the run has now, at
    /// rest; the notice says `what` was done. Refused, the session drops its newest body (the
    /// one this change pushed) and the notice says why.
    fn run_sculpted(
        &mut self,
        body: &Body,
        what: &str,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let printed = matches!(&status.setup.body, Body::Disk(d) if d.printed_section().is_some());
        match self.sculpted_setup(body, contact_now(status), status) {
            Ok(setup) => {
                self.notice = Some((
                    format!(
                        "{what}: α* {:.5} → {:.5} rad; restarted from the same contact{}",
                        status.setup.alpha_star,
                        setup.alpha_star,
                        if printed { PRINT_DROPPED } else { "" }
                    ),
                    false,
                ));
                actions.push(UiAction::Sim(SimCommand::Load(Box::new(setup))));
            }
            Err(e) => {
                // Not run: the session is as before this change.
                if let Some(session) = self.sculpt.session.as_mut() {
                    session.drop_newest();
                }
                self.notice = Some((e.to_string(), true));
            }
        }
    }

    /// The Body panel's sculpting: a tick turns the mouse to sculpting and shows the stroke's
    /// settings, undo and redo, the readout, the mode amplitudes and the save buttons.
    pub(super) fn sculpt_ui(
        &mut self,
        ui: &mut egui::Ui,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        ui.checkbox(&mut self.sculpt.on, "sculpt with the mouse")
            .on_hover_text(
                "a click on the body presses a dent, a right click pulls a bump; a left-button \
                 drag from the body pulls the surface out (up) or presses it in (down) as you \
                 move; the run restarts on the new body from the same contact (Ctrl+Z undoes)",
            );
        if !self.sculpt.on {
            return;
        }
        super::controls::named_slider(
            ui,
            "width (rad)",
            egui::Slider::new(&mut self.sculpt.width, MIN_STROKE_WIDTH..=MAX_STROKE_WIDTH),
        );
        super::controls::named_slider(
            ui,
            "depth (× mean r)",
            egui::Slider::new(&mut self.sculpt.depth, 0.001..=MAX_STROKE_HEIGHT).logarithmic(true),
        );
        ui.horizontal(|ui| {
            let (undo, redo) = self
                .sculpt
                .session
                .as_ref()
                .map_or((false, false), |s| (s.can_undo(), s.can_redo()));
            if ui.add_enabled(undo, egui::Button::new("Undo")).clicked() {
                self.step_history(true, status, actions);
            }
            if ui.add_enabled(redo, egui::Button::new("Redo")).clicked() {
                self.step_history(false, status, actions);
            }
        });
        self.readout_ui(ui, status);
        self.modes_ui(ui, status, actions);
        self.save_body_ui(ui, status);
    }

    /// What the drift measurement of the body running has said: `None` while it measures.
    pub fn sculpt_drift(&self) -> Option<Result<String, String>> {
        self.sculpt.drift.as_ref().and_then(DriftJob::said)
    }

    /// Undo (`back`) or redo, and run the body gone to (the buttons, Ctrl+Z and Ctrl+Y).
    pub(super) fn step_history(
        &mut self,
        back: bool,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        if self.sculpt.dragging.is_some() {
            // The drag is built on the body of its press: release it first.
            self.notice = Some((
                "release the drag first: it is one stroke, undone as one".into(),
                true,
            ));
            return;
        }
        let Some(session) = self.sculpt.session.as_mut() else {
            return;
        };
        let moved = if back { session.undo() } else { session.redo() };
        if moved {
            let body = session.body().clone();
            self.run_sculpted(
                &body,
                if back { "undone" } else { "redone" },
                status,
                actions,
            );
        }
    }

    fn readout_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus) {
        let Some((_, r)) = &self.sculpt.readout else {
            return;
        };
        ui.label(format!(
            "α* = {:.5} rad ({:.3}°)",
            r.alpha_star,
            r.alpha_star.to_degrees()
        ));
        let convex = if r.print.convex {
            format!("convex: smallest curvature {:.4}", r.print.convexity_min)
        } else {
            format!(
                "NOT convex: smallest curvature {:.4} (≤ 0)",
                r.print.convexity_min
            )
        };
        ui.label(convex);
        ui.horizontal(|ui| {
            ui.label(format!(
                "smallest radius of curvature {:.2} mm at",
                r.print.smallest_radius_mm
            ));
            ui.add(
                egui::DragValue::new(&mut self.sculpt.scale_mm)
                    .range(1.0..=1000.0)
                    .suffix(" mm per mean r"),
            );
        });
        if let Body::Sphere(_) = &status.setup.body {
            let key = (
                status.setup.body.clone(),
                status.snapshot.alpha_rad,
                status.snapshot.mass_ratio,
            );
            let fresh = self.sculpt.drift.as_ref().is_some_and(|j| {
                j.key.0.to_shape() == key.0.to_shape() && j.key.1 == key.1 && j.key.2 == key.2
            });
            // Measured once α and m/m0 have been still for a second: a slider being dragged,
            // a sweep or a lesson step would otherwise start a measurement every frame.
            let ramp = (key.1, key.2);
            match self.sculpt.drift_wait {
                _ if fresh => self.sculpt.drift_wait = None,
                Some((held, since)) if held == ramp => {
                    // A drag's bodies change every move: measured when it is released.
                    if since.elapsed().as_secs_f64() >= 1.0 && self.sculpt.dragging.is_none() {
                        self.sculpt.drift = Some(DriftJob::start(key.0, key.1, key.2));
                        self.sculpt.drift_wait = None;
                    }
                }
                _ => {
                    self.sculpt.drift = None;
                    self.sculpt.drift_wait = Some((ramp, std::time::Instant::now()));
                }
            }
            let said = self.sculpt.drift.as_ref().and_then(DriftJob::said);
            match said {
                None if self.sculpt.dragging.is_some() => {
                    ui.label(RichText::new("drift: measured when the drag is released").weak())
                }
                None => ui.label(RichText::new("drift: measuring (8 starts)…").weak()),
                Some(Ok(text)) => ui.add(egui::Label::new(text).wrap()),
                Some(Err(e)) => ui.label(RichText::new(format!("drift: {e}")).weak()),
            };
        }
        if let Some(ms) = self.sculpt.last_stroke_ms {
            ui.label(RichText::new(format!("last stroke: computed and sent in {ms:.0} ms")).weak());
        }
    }
}

/// The contact a restart starts from: the run's now (θ₀ for a cylinder, the orientation for a
/// 3D body), at rest.
pub(super) fn contact_now(status: &SimStatus) -> InitialSpec {
    let snap = &status.snapshot;
    let q = snap.pose.rotation;
    match snap.theta {
        Some(theta) => InitialSpec {
            theta0: theta,
            ..InitialSpec::default()
        },
        None => InitialSpec {
            q0: Some([q.w, q.x, q.y, q.z]),
            ..InitialSpec::default()
        },
    }
}

/// One row of the mode panel: a cylinder's (l, A_l, θ_l) or a 3D body's (l, m, Re A_lm,
/// Im A_lm).
#[derive(Debug, Clone, Copy, PartialEq)]
struct ModeRow {
    l: u32,
    m: i32,
    x: f64,
    y: f64,
}

/// Every mode of `body`'s family up to its degree (or the paper's l ≤ 5 for a round body), with
/// the body's values (0 where it has none).
fn mode_rows(body: &Body) -> Vec<ModeRow> {
    use crate::geometry::sculpt::ROUND_BODY_DEGREE;
    match body {
        Body::Disk(d) => {
            let top = d.modes().iter().map(|m| m.l).max().unwrap_or(0);
            (2..=top.max(ROUND_BODY_DEGREE))
                .map(|l| {
                    let m = d.modes().iter().find(|m| m.l == l);
                    ModeRow {
                        l,
                        m: 0,
                        x: m.map_or(0.0, |m| m.a),
                        y: m.map_or(0.0, |m| m.phase),
                    }
                })
                .collect()
        }
        Body::Sphere(s) => {
            let top = s.max_degree().max(ROUND_BODY_DEGREE);
            (2..=top)
                .flat_map(|l| (-(l as i32)..=l as i32).map(move |m| (l, m)))
                .map(|(l, m)| {
                    let c = s.coeffs().iter().find(|c| c.l == l && c.m == m);
                    ModeRow {
                        l,
                        m,
                        x: c.map_or(0.0, |c| c.re),
                        y: c.map_or(0.0, |c| c.im),
                    }
                })
                .collect()
        }
    }
}

/// The body the mode panel's rows describe (modes at 0 left out).
fn body_of_rows(like: &Body, rows: &[ModeRow]) -> Body {
    use crate::geometry::{Disk, DiskMode, Sphere, SphereCoeff};
    match like {
        Body::Disk(_) => Body::Disk(Disk::new(
            rows.iter()
                .filter(|r| r.x != 0.0)
                .map(|r| DiskMode {
                    l: r.l,
                    a: r.x,
                    phase: r.y,
                })
                .collect(),
        )),
        Body::Sphere(_) => Body::Sphere(Sphere::new(
            rows.iter()
                .filter(|r| r.x != 0.0 || r.y != 0.0)
                .map(|r| SphereCoeff {
                    l: r.l,
                    m: r.m,
                    re: r.x,
                    im: r.y,
                })
                .collect(),
        )),
    }
}

impl AppUi {
    /// The mode amplitudes, editable: a value is taken when its drag ends or its typing is
    /// done, and the body is checked and run as a stroke's would be.
    fn modes_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let Some(session) = &self.sculpt.session else {
            return;
        };
        let body = session.body().clone();
        if self
            .sculpt
            .draft
            .as_ref()
            .is_none_or(|(b, _)| b.to_shape() != body.to_shape())
        {
            self.sculpt.draft = Some((body.clone(), mode_rows(&body)));
        }
        let disk = matches!(body, Body::Disk(_));
        let mut committed = false;
        egui::CollapsingHeader::new("Mode amplitudes")
            .id_salt("sculpt-modes")
            .show(ui, |ui| {
                let Some((_, rows)) = self.sculpt.draft.as_mut() else {
                    return;
                };
                egui::ScrollArea::vertical()
                    .max_height(220.0)
                    .show(ui, |ui| {
                        egui::Grid::new("sculpt-mode-grid").show(ui, |ui| {
                            if disk {
                                ui.label("l");
                                ui.label("A_l");
                                ui.label("θ_l (rad)");
                            } else {
                                ui.label("l, m");
                                ui.label("Re A_lm");
                                ui.label("Im A_lm");
                            }
                            ui.end_row();
                            for row in rows.iter_mut() {
                                ui.label(if disk {
                                    row.l.to_string()
                                } else {
                                    format!("{}, {}", row.l, row.m)
                                });
                                for v in [&mut row.x, &mut row.y] {
                                    // Taken when typing is done, not at each key.
                                    let r = ui.add(
                                        egui::DragValue::new(v)
                                            .speed(0.002)
                                            .max_decimals(4)
                                            .update_while_editing(false),
                                    );
                                    committed |= r.drag_stopped() || (r.changed() && !r.dragged());
                                }
                                ui.end_row();
                            }
                        });
                    });
            });
        if !committed {
            return;
        }
        let Some((_, rows)) = &self.sculpt.draft else {
            return;
        };
        let edited = body_of_rows(&body, rows);
        let Some(session) = self.sculpt.session.as_mut() else {
            return;
        };
        match session.set_body(edited) {
            Ok(b) => {
                let b = b.clone();
                self.run_sculpted(&b, "modes edited", status, actions);
            }
            Err(e) => {
                self.notice = Some((e.to_string(), true));
                self.sculpt.draft = None;
            }
        }
    }

    /// Save the body as a shape file (with the print scale) or as an STL at that scale, through
    /// the output layer (never over an input, never half-written).
    fn save_body_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus) {
        ui.horizontal(|ui| {
            ui.label("save to");
            ui.add(egui::TextEdit::singleline(&mut self.sculpt.shape_path).desired_width(160.0));
        });
        ui.horizontal(|ui| {
            if ui.button("Save shape file").clicked() {
                self.save_sculpted(status, false);
            }
            if ui.button("Save STL").clicked() {
                self.save_sculpted(status, true);
            }
        });
    }

    /// Saves the body running to the sculpt panel's path: its shape file (with the print
    /// scale), or with `stl` its print mesh in mm (a `.json` path's `.stl` twin, any other path
    /// as given); never over the shape file the scene read. The notice says where, or why not.
    pub fn save_sculpted(&mut self, status: &SimStatus, stl: bool) {
        let path = std::path::PathBuf::from(self.sculpt.shape_path.trim());
        let stl_named = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("stl"));
        if path.as_os_str() == "-" || (!stl && stl_named) {
            self.notice = Some((
                format!(
                    "{} is not a place for the body's {}: give a file path{}",
                    path.display(),
                    if stl { "STL" } else { "shape file" },
                    if stl { "" } else { " ending in .json" }
                ),
                true,
            ));
            return;
        }
        let scale = self.sculpt.scale_mm;
        let body = &status.setup.body;
        // The shape file the scene read (a preset's is bundled, not on disk) is never written.
        let read = match (&status.setup.scene.body.shape, &self.base) {
            (Some(shape), Some(base)) => vec![base.join(shape)],
            _ => Vec::new(),
        };
        let inputs = crate::output::Inputs::of(read);
        // Either file is made in memory and written by the output layer in one call
        // (staged, all or nothing, never over an input).
        let (path, bytes) = if stl {
            // A shape file's name gives its STL's (body.json: body.stl); any other path is
            // taken as given (a device, a name without an extension), never changed silently.
            let json = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("json"));
            let path = if json {
                path.with_extension("stl")
            } else {
                path
            };
            (path, stl_bytes(body, scale))
        } else {
            let json = body.to_shape().with_scale_mm(Some(scale)).to_json();
            (
                path,
                json.map(String::into_bytes).map_err(anyhow::Error::from),
            )
        };
        let result = bytes.and_then(|b| {
            crate::output::write_bytes(&path, &b, &inputs).map_err(anyhow::Error::from)
        });
        self.notice = Some(match result {
            Ok(()) => (
                format!(
                    "saved the body to {} ({scale} mm per mean radius)",
                    path.display()
                ),
                false,
            ),
            Err(e) => (format!("{e:#}"), true),
        });
    }
}

/// The body's print mesh as a binary STL in mm, `scale_mm` per ⟨r⟩ (a cylinder 2 ⟨r⟩ long), in
/// memory: the same mesh `export-stl` and `design --stl` write.
fn stl_bytes(body: &Body, scale_mm: f64) -> anyhow::Result<Vec<u8>> {
    let mesh = crate::geometry::mesh::print_mesh(body, 6, 2.0);
    let name = match body {
        Body::Disk(_) => format!("sculpted {}", crate::geometry::mesh::DISK_AXIS_TAG),
        Body::Sphere(_) => "sculpted".to_string(),
    };
    let mut bytes = Vec::new();
    mesh.write_stl(&mut bytes, scale_mm, &name)?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drift_is_said_with_its_evidence() {
        let body = Body::paper_sphere(219, 0.25, 5).unwrap();
        let options = PredictOptions {
            starts: 4,
            ..PredictOptions::default()
        };
        let p =
            crate::analysis::experiment::prediction::predict(&body, 0.15, 0.0, &options).unwrap();
        let said = describe_drift(&p);
        assert!(said.contains("of 4 starts elsewhere"), "{said}");
        let mut none = p.clone();
        none.orbits.clear();
        assert_eq!(
            describe_drift(&none),
            "drift: no stable orbit rolls down (0 of 4 starts)"
        );
    }
}
