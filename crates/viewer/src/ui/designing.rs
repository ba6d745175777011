//! Designing a body from the app (the Body panel's "Design" section): the `design` command's
//! targets (α*, hysteresis for a cylinder; orbits, drift, doubling for a sphere at a ramp angle
//! and m/m0), turned into targets by the one place every surface uses
//! ([`TargetRequest::targets`]) and searched by the core's [`design_until`] on a worker thread.
//! While it runs the panel shows the generation and the best objective, and the best body so far
//! rolls on the ramp (reloaded at most every [`SHOW_EVERY_S`] seconds, as it improves). Cancel
//! stops the search between generations: the best body so far is then checked as any design is
//! (ended "stopped"). The report is the design's own: each target's value and whether it is met,
//! the check's margins over the band, holds or not, and why not.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use egui::RichText;

use super::{AppUi, UiAction};
use crate::analysis::design::{
    Band, DEFAULT_GENERATIONS, DEFAULT_MAX_AMPLITUDE, DEFAULT_MIN_RADIUS_MM, Design, DesignOptions,
    DesignProgress, DesignSpace, Spelling, TargetRequest, design_until,
};
use crate::geometry::Body;
use crate::live::SimStatus;
use crate::scene::InitialSpec;
use crate::scene::sculpt::sculpted_scene;

/// The least time between two reloads of the best body so far: long enough to see it roll.
pub const SHOW_EVERY_S: f64 = 3.0;

/// The Design section's targets, settings and the search running.
pub struct DesignPanel {
    /// α* wanted (rad), if asked.
    pub alpha_star: Option<f64>,
    /// A cylinder's hysteresis: (m/m0, the fraction of α* it keeps rolling down to).
    pub hysteresis: Option<(f64, f64)>,
    /// A sphere's number of stable orbits.
    pub orbits: Option<usize>,
    /// A sphere's drift across per down.
    pub drift: Option<f64>,
    /// A sphere's m/m0 of period doubling.
    pub doubling: Option<f64>,
    /// The ramp angle (rad) and m/m0 of the orbits and drift targets (the doubling's angle).
    pub ramp: (f64, f64),
    /// The highest mode searched.
    pub modes: u32,
    /// Most generations.
    pub generations: usize,
    /// The seed of the search's start and steps (`rollphase design --seed`): the same seed and
    /// settings give the same body.
    pub seed: u64,
    /// mm per mean radius of the print.
    pub scale_mm: f64,
    job: Option<DesignJob>,
    /// The last design's report, or why there is none.
    pub report: Option<Result<Vec<String>, String>>,
    shown: Option<(Vec<f64>, Instant)>,
}

impl Default for DesignPanel {
    fn default() -> Self {
        Self {
            alpha_star: Some(0.15),
            hysteresis: None,
            orbits: None,
            drift: None,
            doubling: None,
            ramp: (0.15, 0.0),
            modes: crate::analysis::design::DEFAULT_MODES,
            generations: DEFAULT_GENERATIONS,
            seed: crate::analysis::design::DEFAULT_SEED,
            scale_mm: crate::analysis::design::DEFAULT_SCALE_MM,
            job: None,
            report: None,
            shown: None,
        }
    }
}

/// A search on a worker thread; dropped, it is told to stop.
struct DesignJob {
    space: DesignSpace,
    /// The print scale the search checks at (the body is saved with it).
    scale_mm: f64,
    /// Where the designed bodies run: the ramp angle relative to α*, or absolute, and m/m0.
    run_at: RunAt,
    /// The scene the search was started on; its bodies are loaded only while the app shows
    /// that scene or one of the search's own.
    scene: u64,
    progress: Arc<Mutex<Option<DesignProgress>>>,
    result: Arc<Mutex<Option<Result<Design, String>>>>,
    stop: Arc<AtomicBool>,
    worker: std::thread::JoinHandle<()>,
}

/// The ramp a designed body is shown on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunAt {
    /// At this multiple of the body's own α* (a target of α* or hysteresis: just above it, so
    /// the body rolls), and this m/m0.
    AboveAlphaStar(f64, f64),
    /// At the target's ramp angle and m/m0 (orbits, drift, doubling).
    Ramp(f64, f64),
}

impl Drop for DesignJob {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

impl DesignPanel {
    /// The design options the panel asks for on a body of `dimension`, or why they are refused
    /// (the core's words, which name the command line's flags). Targets of the other dimension
    /// are not shown for this dimension and are left out.
    ///
    /// # Errors
    /// No target, or a value out of range.
    pub fn options(&self, dimension: u32) -> Result<DesignOptions, String> {
        let three_d = dimension == 3;
        let request = TargetRequest {
            alpha_star: self.alpha_star,
            hysteresis: self.hysteresis.filter(|_| !three_d),
            orbits: self.orbits.filter(|_| three_d),
            drift: self.drift.filter(|_| three_d),
            doubling: self.doubling.filter(|_| three_d),
            share: None,
            mass: (three_d && (self.orbits.is_some() || self.drift.is_some()))
                .then_some(self.ramp.1),
            alpha: (three_d
                && (self.orbits.is_some() || self.drift.is_some() || self.doubling.is_some()))
            .then_some(self.ramp.0),
        };
        let spell = Spelling {
            alpha: "the ramp angle",
            mass: "m/m0",
            share: "the share",
            targets: "α*, hysteresis (2D), orbits, drift or doubling (3D)",
        };
        let targets = request.targets(&spell).map_err(|e| e.to_string())?;
        let options = DesignOptions {
            space: DesignSpace {
                dimension,
                modes: self.modes,
            },
            targets,
            scale_mm: self.scale_mm,
            min_radius_mm: DEFAULT_MIN_RADIUS_MM,
            max_amplitude: DEFAULT_MAX_AMPLITUDE,
            start: None,
            seed: self.seed,
            max_generations: self.generations,
            band: Band::default(),
        };
        options.validate().map_err(|e| e.to_string())?;
        Ok(options)
    }

    /// Where the bodies of a search with these targets are shown: at the target's ramp (orbits,
    /// drift, doubling), else just above the body's own α* at the hysteresis target's m/m0 or
    /// `mass_now`.
    pub fn run_at(&self, dimension: u32, mass_now: f64) -> RunAt {
        let three_d = dimension == 3;
        match (
            three_d,
            self.orbits.is_some() || self.drift.is_some(),
            self.doubling,
        ) {
            (true, true, _) => RunAt::Ramp(self.ramp.0, self.ramp.1),
            (true, false, Some(mass)) => RunAt::Ramp(self.ramp.0, mass),
            _ => RunAt::AboveAlphaStar(
                1.05,
                self.hysteresis
                    .filter(|_| !three_d)
                    .map_or(mass_now, |h| h.0),
            ),
        }
    }

    /// Starts the search of `options` (replacing any running) for the scene `scene`, its
    /// bodies shown as `run_at` says.
    pub fn start(&mut self, options: DesignOptions, scene: u64, run_at: RunAt) {
        let progress = Arc::new(Mutex::new(None));
        let result = Arc::new(Mutex::new(None));
        let stop = Arc::new(AtomicBool::new(false));
        let (p, r, s) = (progress.clone(), result.clone(), stop.clone());
        let (space, scale_mm) = (options.space, options.scale_mm);
        let spawned = std::thread::Builder::new()
            .name("app-design".into())
            .spawn(move || {
                let tell = |d: DesignProgress| {
                    if let Ok(mut slot) = p.lock() {
                        *slot = Some(d);
                    }
                };
                let found = design_until(&options, &s, &tell).map_err(|e| e.to_string());
                if let Ok(mut slot) = r.lock() {
                    *slot = Some(found);
                }
            });
        let worker = match spawned {
            Ok(w) => w,
            Err(e) => {
                self.report = Some(Err(format!("no worker thread for the design: {e}")));
                return;
            }
        };
        self.report = None;
        self.shown = None;
        self.job = Some(DesignJob {
            space,
            scale_mm,
            run_at,
            scene,
            progress,
            result,
            stop,
            worker,
        });
    }

    /// Whether a search is running.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// Asks the running search to stop after its generation (its best body is then checked).
    pub fn cancel(&self) {
        if let Some(job) = &self.job {
            job.stop.store(true, Ordering::Relaxed);
        }
    }

    /// Whether the running search was asked to stop (it is checking its best body so far).
    pub fn cancelled(&self) -> bool {
        self.job
            .as_ref()
            .is_some_and(|j| j.stop.load(Ordering::Relaxed))
    }

    /// The latest progress of the running search.
    pub fn progress(&self) -> Option<DesignProgress> {
        self.job.as_ref()?.progress.lock().ok()?.clone()
    }
}

/// The report of a design in lines: holds or not, each target's value (and its margin over the
/// band where the body could be checked: a body that is not convex is not), why not.
pub fn report_lines(d: &Design) -> Vec<String> {
    let mut lines = vec![format!(
        "{}: α* = {:.5} rad, {} generations, ended {:?}",
        if d.holds() { "holds" } else { "does not hold" },
        d.alpha_star,
        d.generations,
        d.ended
    )];
    for (k, a) in d.achieved.iter().enumerate() {
        let margin = d
            .check
            .targets
            .get(k)
            .filter(|c| c.target == a.target)
            .map_or(String::new(), |c| {
                format!("; margin over the band {:+.4} {}", c.margin, c.margin_unit)
            });
        lines.push(format!(
            "{}: {:.4} ({}){margin}",
            a.target.describe(),
            a.precise,
            if a.met { "met" } else { "not met" },
        ));
    }
    // The app has no time budget: a stopped search was cancelled.
    let setting = |s: &str| match s {
        "budget" => "BUDGET".to_string(),
        "seed" => "seed (rollphase design --seed)".to_string(),
        other => other.to_string(),
    };
    for why in d.why_not(&setting) {
        if why.contains("BUDGET") {
            lines.push(
                "cancelled: this is the best body so far, checked (Design again with more \
                 generations searches further)"
                    .to_string(),
            );
        } else {
            lines.push(why);
        }
    }
    lines.dedup();
    lines
}

impl AppUi {
    /// The Body panel's "Design" section.
    pub(super) fn design_ui(&mut self, ui: &mut egui::Ui, status: &SimStatus) {
        let dimension = status.setup.body.dimension();
        egui::CollapsingHeader::new("Design a body")
            .id_salt("design")
            .show(ui, |ui| {
                self.design_targets_ui(ui, dimension);
                let d = &mut self.design;
                super::controls::named_slider(
                    ui,
                    "modes l ≤",
                    egui::Slider::new(&mut d.modes, 2..=8),
                );
                ui.add(
                    egui::DragValue::new(&mut d.seed)
                        .range(0..=u64::from(u32::MAX))
                        .prefix("seed "),
                )
                .on_hover_text(
                    "the seed of the search's start and steps (rollphase design --seed): the \
                     same seed and settings give the same body",
                );
                ui.add(
                    egui::DragValue::new(&mut d.generations)
                        .range(1..=5000)
                        .prefix("at most ")
                        .suffix(" generations"),
                );
                ui.add(
                    egui::DragValue::new(&mut d.scale_mm)
                        .range(1.0..=1000.0)
                        .suffix(" mm per mean radius"),
                );
                if d.running() {
                    if d.cancelled() {
                        ui.label(RichText::new("cancelled: checking the best body so far…").weak());
                    } else if ui.button("Cancel (keep the best so far)").clicked() {
                        d.cancel();
                    }
                } else if ui.button("Design").clicked() {
                    if !status.setup.timeline.is_empty() {
                        self.notice = Some((
                            "a lesson is not a place to design: its captions are about its own \
                             body (load a scene first)"
                                .into(),
                            true,
                        ));
                    } else {
                        let run_at = d.run_at(dimension, status.snapshot.mass_ratio);
                        match d.options(dimension) {
                            Ok(options) => d.start(options, status.scene_id, run_at),
                            Err(why) => self.notice = Some((why, true)),
                        }
                    }
                }
                self.design_status_ui(ui);
            });
    }

    fn design_targets_ui(&mut self, ui: &mut egui::Ui, dimension: u32) {
        let d = &mut self.design;
        let toggle = |ui: &mut egui::Ui, on: bool, label: &str| {
            let mut on = on;
            ui.checkbox(&mut on, label);
            on
        };
        let on = toggle(ui, d.alpha_star.is_some(), "α* (rad)");
        d.alpha_star = on.then(|| d.alpha_star.unwrap_or(0.15));
        if let Some(a) = &mut d.alpha_star {
            ui.add(egui::DragValue::new(a).speed(0.001).range(0.001..=1.0));
        }
        if dimension == 2 {
            let on = toggle(
                ui,
                d.hysteresis.is_some(),
                "hysteresis: rolls down to F·α* at m/m0",
            );
            d.hysteresis = on.then(|| d.hysteresis.unwrap_or((2.0, 0.9)));
            if let Some((m, f)) = &mut d.hysteresis {
                ui.horizontal(|ui| {
                    ui.add(egui::DragValue::new(m).speed(0.1).prefix("m/m0 "));
                    ui.add(egui::DragValue::new(f).speed(0.01).prefix("F "));
                });
            }
            return;
        }
        let on = toggle(ui, d.orbits.is_some(), "stable orbits");
        d.orbits = on.then(|| d.orbits.unwrap_or(2));
        if let Some(k) = &mut d.orbits {
            ui.add(egui::DragValue::new(k).range(1..=6));
        }
        let on = toggle(ui, d.drift.is_some(), "drift across per down");
        d.drift = on.then(|| d.drift.unwrap_or(0.1));
        if let Some(x) = &mut d.drift {
            ui.add(egui::DragValue::new(x).speed(0.01));
        }
        let on = toggle(ui, d.doubling.is_some(), "period doubling at m/m0");
        d.doubling = on.then(|| d.doubling.unwrap_or(4.0));
        if let Some(m) = &mut d.doubling {
            ui.add(egui::DragValue::new(m).speed(0.1));
        }
        if d.orbits.is_some() || d.drift.is_some() || d.doubling.is_some() {
            ui.horizontal(|ui| {
                ui.add(
                    egui::DragValue::new(&mut d.ramp.0)
                        .speed(0.001)
                        .prefix("ramp α "),
                );
                ui.add(
                    egui::DragValue::new(&mut d.ramp.1)
                        .speed(0.1)
                        .prefix("m/m0 "),
                );
            });
        }
    }

    /// Every frame, shown or not: the search's end (its report, its body on the ramp) and the
    /// best body so far on the ramp as it improves. Bodies are loaded only while the app shows
    /// the scene the search started on or one of its own bodies; another scene cancels it.
    pub(super) fn poll_design(&mut self, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let Some(job) = &self.design.job else {
            return;
        };
        let ours = status.scene_id == job.scene || status.setup.scene.name.starts_with("design: ");
        if !ours && !job.stop.load(Ordering::Relaxed) {
            job.stop.store(true, Ordering::Relaxed);
            self.notice = Some((
                "design cancelled: another scene was loaded (its best body so far is checked \
                 and reported, not run)"
                    .into(),
                false,
            ));
        }
        let (run_at, scale_mm, space) = (job.run_at, job.scale_mm, job.space);
        let finished = job.result.lock().ok().and_then(|mut r| r.take());
        let died = finished.is_none() && job.worker.is_finished();
        if died {
            self.design.job = None;
            self.design.report = Some(Err(
                "the design search stopped without a result (a failure in the search)".into(),
            ));
            return;
        }
        if let Some(found) = finished {
            self.design.job = None;
            self.design.report = Some(found.as_ref().map(report_lines).map_err(Clone::clone));
            match found {
                Ok(design) if ours => {
                    if let Err(e) = design.body.check_convex() {
                        self.notice = Some((
                            format!("the design is not strictly convex ({e}): not run"),
                            true,
                        ));
                    } else {
                        let at = (run_at, scale_mm);
                        self.run_designed(&design.body, "designed", at, status, actions);
                    }
                }
                Ok(_) => {}
                Err(why) => self.notice = Some((format!("design: {why}"), true)),
            }
            return;
        }
        if let (Some(p), true) = (self.design.progress(), ours) {
            let due = self.design.shown.as_ref().is_none_or(|(v, at)| {
                *v != p.best_vector && at.elapsed().as_secs_f64() >= SHOW_EVERY_S
            });
            if due {
                let body = space.body(&p.best_vector);
                self.design.shown = Some((p.best_vector.clone(), Instant::now()));
                if body.check_convex().is_ok() {
                    let at = (run_at, scale_mm);
                    self.run_designed(&body, "the best so far", at, status, actions);
                }
            }
        }
    }

    /// The search's progress and the report.
    fn design_status_ui(&mut self, ui: &mut egui::Ui) {
        if let Some(p) = self.design.progress() {
            ui.label(format!(
                "generation {} of {}, best objective {:.4}",
                p.generation, p.max_generations, p.best
            ));
        } else if self.design.running() {
            ui.label(RichText::new("finding a start…").weak());
        }
        match &self.design.report {
            Some(Ok(lines)) => {
                for line in lines {
                    ui.add(egui::Label::new(line.as_str()).wrap());
                }
            }
            Some(Err(why)) => {
                ui.colored_label(egui::Color32::from_rgb(230, 90, 80), why);
            }
            None => {}
        }
    }

    /// Runs `body` where `run_at` says (at 1.05 of its own α*, or at a target's ramp), with
    /// the current integrator and speed, from rest; saved with the search's print scale.
    fn run_designed(
        &mut self,
        body: &Body,
        what: &str,
        (run_at, scale_mm): (RunAt, f64),
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let mut scene = self.current_scene(status);
        scene.name = format!("design: {what}");
        scene.description = "designed in the app".into();
        let (alpha, ratio, mass) = match run_at {
            RunAt::AboveAlphaStar(ratio, mass) => (None, Some(ratio), mass),
            RunAt::Ramp(alpha, mass) => (Some(alpha), None, mass),
        };
        scene.model.alpha_rad = alpha;
        scene.model.alpha_over_critical = ratio;
        scene.model.mass_ratio = mass;
        scene.model.kind = None;
        let at = (self.base.as_deref(), Some(scale_mm));
        match sculpted_scene(&scene, body, InitialSpec::default(), at) {
            Ok((_, setup)) => actions.push(UiAction::Sim(crate::live::SimCommand::Load(Box::new(
                setup,
            )))),
            Err(e) => self.notice = Some((format!("{what}: {e}"), true)),
        }
    }
}
