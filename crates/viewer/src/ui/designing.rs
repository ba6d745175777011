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
            modes: 4,
            generations: DEFAULT_GENERATIONS,
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
    progress: Arc<Mutex<Option<DesignProgress>>>,
    result: Arc<Mutex<Option<Result<Design, String>>>>,
    stop: Arc<AtomicBool>,
}

impl Drop for DesignJob {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

impl DesignPanel {
    /// The design options the panel asks for on a body of `dimension`, or why they are refused
    /// (the same words as the command line's, with the panel's names).
    ///
    /// # Errors
    /// No target, a value out of range, or a target of the other dimension.
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
            seed: 1,
            max_generations: self.generations,
            band: Band::default(),
        };
        options.validate().map_err(|e| e.to_string())?;
        Ok(options)
    }

    /// Starts the search of `options` (replacing any running).
    pub fn start(&mut self, options: DesignOptions) {
        let progress = Arc::new(Mutex::new(None));
        let result = Arc::new(Mutex::new(None));
        let stop = Arc::new(AtomicBool::new(false));
        let (p, r, s) = (progress.clone(), result.clone(), stop.clone());
        let space = options.space;
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
        if let Err(e) = spawned {
            self.report = Some(Err(format!("no worker thread for the design: {e}")));
            return;
        }
        self.report = None;
        self.shown = None;
        self.job = Some(DesignJob {
            space,
            progress,
            result,
            stop,
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

    /// The latest progress of the running search.
    pub fn progress(&self) -> Option<DesignProgress> {
        self.job.as_ref()?.progress.lock().ok()?.clone()
    }
}

/// The report of a design in lines: holds or not, each target's value and margin, why not.
pub fn report_lines(d: &Design) -> Vec<String> {
    let mut lines = vec![format!(
        "{}: α* = {:.5} rad, {} generations, ended {:?}",
        if d.holds() { "holds" } else { "does not hold" },
        d.alpha_star,
        d.generations,
        d.ended
    )];
    for (a, c) in d.achieved.iter().zip(&d.check.targets) {
        lines.push(format!(
            "{}: {:.4} ({}); margin over the band {:+.4} {}",
            a.target.describe(),
            a.precise,
            if a.met { "met" } else { "not met" },
            c.margin,
            c.margin_unit
        ));
    }
    lines.extend(d.why_not(&|s| s.to_string()));
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
                ui.horizontal(|ui| {
                    ui.add(egui::Slider::new(&mut d.modes, 2..=8).text("modes l ≤"));
                });
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
                    if ui.button("Cancel (keep the best so far)").clicked() {
                        d.cancel();
                    }
                } else if ui.button("Design").clicked() {
                    match d.options(dimension) {
                        Ok(options) => d.start(options),
                        Err(why) => self.notice = Some((why, true)),
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
    /// best body so far on the ramp as it improves.
    pub(super) fn poll_design(&mut self, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let finished = self
            .design
            .job
            .as_ref()
            .and_then(|j| j.result.lock().ok()?.take());
        if let Some(found) = finished {
            self.design.job = None;
            self.design.report = Some(found.as_ref().map(report_lines).map_err(Clone::clone));
            match found {
                Ok(design) => self.run_designed(&design.body, "designed", status, actions),
                Err(why) => self.notice = Some((format!("design: {why}"), true)),
            }
            return;
        }
        let space = self.design.job.as_ref().map(|j| j.space);
        if let (Some(p), Some(space)) = (self.design.progress(), space) {
            let due = self.design.shown.as_ref().is_none_or(|(v, at)| {
                *v != p.best_vector && at.elapsed().as_secs_f64() >= SHOW_EVERY_S
            });
            if due {
                let body = space.body(&p.best_vector);
                self.design.shown = Some((p.best_vector.clone(), Instant::now()));
                if body.check_convex().is_ok() {
                    self.run_designed(&body, "the best so far", status, actions);
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

    /// Runs `body` on the ramp (the current α, m/m0, integrator and speed), from rest.
    fn run_designed(
        &mut self,
        body: &Body,
        what: &str,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let mut scene = self.current_scene(status);
        scene.name = format!("design: {what}");
        scene.description = "designed in the app".into();
        let scale = (self.base.as_deref(), Some(self.design.scale_mm));
        match sculpted_scene(&scene, body, InitialSpec::default(), scale) {
            Ok((_, setup)) => actions.push(UiAction::Sim(crate::live::SimCommand::Load(Box::new(
                setup,
            )))),
            Err(e) => self.notice = Some((format!("{what}: {e}"), true)),
        }
    }
}
