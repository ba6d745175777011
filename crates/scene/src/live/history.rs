//! The plots' history: what the app's plots (and `--headless --plot-data`) show, accumulated
//! from a run: the time series θ(t) and θ̇(θ) or the contact's angles, the health and the
//! contact force, sampled every [`PLOT_SAMPLE_DT`](super::PLOT_SAMPLE_DT) by the simulation
//! itself ([`PlotHistory::push_samples`]); and from its snapshots 1/T against α collected
//! while α is swept (a halted body counts as 1/T = 0, separately for sweeps up and down, so
//! hysteresis shows as two branches), the settled crossings of ∂Ω against m/m0 collected while
//! the mass is swept, and the numerical health against time. Plain data, tested without a
//! window; [`PlotHistory::csv`] writes each series as CSV (the app's "Export CSV", and the
//! headless renderer's).

use std::collections::{BTreeMap, VecDeque};

use std::path::Path;

use crate::output::{self, Inputs, OutputSet};

use super::{Measured, Snapshot};

mod crossings;
mod csv_data;
mod plot_meta;

use crossings::Crossings;
pub use csv_data::PlotData;
use plot_meta::{BODY_DATA, body_files};
pub use plot_meta::{BodyMeta, PLOT_META_FILE, PlotMeta};

/// Samples kept per time series (older ones are dropped): the last 5000 time units.
pub const MAX_SAMPLES: usize = 50_000;

/// Points per plotted time series (see [`PlotHistory::plotted`]).
pub const PLOT_POINTS: usize = 1000;

/// Width of the α bins of the 1/T sweep in ln α: 0.1 % of α (a slider step is far finer than
/// a user can resolve; one point per bin and direction keeps the newest measurement). Relative,
/// so that steps of 1 % of α* near a small α* (0.05 rad) stay apart, as the critical-angle
/// lesson needs.
const SWEEP_BIN: f64 = 1e-3;

/// The α bin a 1/T point belongs to: points in one bin are the same α to the sweep.
fn sweep_bin(alpha: f64) -> i64 {
    (alpha.ln() / SWEEP_BIN).round() as i64
}

/// A cycle the live run settled on ([`PlotCheckpoint::cycle_at`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SettledCycle {
    /// Its crossings of ∂Ω, k (1: a closed orbit, 2: doubled).
    pub multiplicity: usize,
    /// The time it takes, all k crossings.
    pub period: f64,
    /// The last time the run was seen on it.
    pub seen_at: f64,
    /// Its k crossings' plotted angles (rad), as the crossings plot shows them.
    pub angles: Vec<f64>,
}

/// One sample of the time series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Simulation time.
    pub t: f64,
    /// 2D: θ (unwrapped); 3D: the contact's polar angle θ.
    pub theta: f64,
    /// 2D: θ̇; 3D: |ω|.
    pub rate: f64,
    /// 3D: the contact's azimuth φ; 2D: 0.
    pub phi: f64,
    /// Worst ||q| − 1| so far.
    pub quat_norm_error: f64,
    /// Worst contact-normal error so far.
    pub contact_normal_error: f64,
    /// Worst |E + W − E(0)| so far.
    pub energy_drift: f64,
    /// The ramp's normal force N/F.
    pub normal_force: f64,
    /// The friction rolling needs, |f_t|/N (infinite where N ≤ 0).
    pub friction_needed: f64,
    /// Whose: 0 the scene's own body, n its n-th `[[bodies]]` entry (body n + 1).
    pub body: usize,
}

/// The branch of the 1/T plot a point belongs to: the way α was last moved (hysteresis shows
/// as two branches).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Branch {
    /// α increased (or not moved yet).
    Up,
    /// α decreased.
    Down,
}

/// What the plots show, accumulated from snapshots.
#[derive(Debug, Clone, Default)]
pub struct PlotHistory {
    samples: VecDeque<Sample>,
    /// The other bodies' (`[[bodies]]`) histories, by entry: their samples, 1/T points and
    /// crossings, each taken from its own snapshots as the scene's own body's are.
    others: Vec<PlotHistory>,
    /// (direction, α bin) → (α, 1/T, m/m0).
    sweep: BTreeMap<(Branch, Regime, i64), (f64, f64)>,
    last_alpha: Option<f64>,
    direction: Option<Branch>,
    last_period: Option<f64>,
    /// The settled ∂Ω crossings.
    crossings: Crossings,
}

/// What a 1/T point was measured under: m/m0 and the drag law. Points of different regimes
/// are different series, never one: a point taken at drag exponent 2 once went unmarked into
/// a series collected at 1 (issue 60).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Regime {
    /// m/m0's bits (0 for the viscous model), so that the regime can order a map.
    mass_bits: u64,
    /// The drag law in words ([`crate::dynamics::DragLaw::label`]).
    drag: String,
}

impl Regime {
    /// m/m0 `mass_ratio` under the drag law `drag`.
    pub fn new(mass_ratio: f64, drag: &crate::dynamics::DragLaw) -> Self {
        Self {
            // −0 and +0 are one regime.
            mass_bits: (mass_ratio + 0.0).to_bits(),
            drag: drag.label(),
        }
    }

    /// The regime a snapshot runs under.
    pub fn of(snap: &Snapshot) -> Self {
        Self::new(snap.mass_ratio, &snap.drag_law)
    }

    /// m/m0 `mass_ratio` under the drag law its words `drag` name (a saved state's points).
    pub fn labelled(mass_ratio: f64, drag: &str) -> Self {
        Self {
            mass_bits: (mass_ratio + 0.0).to_bits(),
            drag: drag.to_string(),
        }
    }

    /// Its m/m0.
    pub fn mass_ratio(&self) -> f64 {
        f64::from_bits(self.mass_bits)
    }

    /// Its drag law in words.
    pub fn drag(&self) -> &str {
        &self.drag
    }

    /// As a plot's key names it: "m/m0 = 10, linear drag".
    pub fn label(&self) -> String {
        let m = format!("{:.4}", self.mass_ratio());
        let m = m.trim_end_matches('0').trim_end_matches('.');
        format!("m/m0 = {m}, {}", self.drag)
    }
}

/// What a [`PlotHistory`] has collected besides its time series: the α sweep's points and the
/// settled crossings, with what they are judged against (the last α, the sweep's direction).
/// The app keeps one as each lesson step begins, so that going back a step shows the plots
/// of the step returned to.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlotCheckpoint {
    sweep: BTreeMap<(Branch, Regime, i64), (f64, f64)>,
    last_alpha: Option<f64>,
    direction: Option<Branch>,
    crossings: Crossings,
    /// The other bodies' (`[[bodies]]`), by entry.
    others: Vec<PlotCheckpoint>,
}

impl PlotCheckpoint {
    /// The 1/T points in `alpha`'s bin (the sweep's own "same α", 0.1 % of α) measured under
    /// `regime` (m/m0 and drag law), with their branch.
    ///
    /// # Example
    /// ```
    /// use rollphase_scene::live::history::{PlotHistory, Regime};
    /// let linear = Regime::labelled(0.0, "linear drag");
    /// assert!(PlotHistory::default().checkpoint().rates_at(0.1, &linear).is_empty());
    /// ```
    pub fn rates_at(&self, alpha: f64, regime: &Regime) -> Vec<(Branch, f64)> {
        self.sweep
            .iter()
            .filter(|((_, r, bin), _)| *bin == sweep_bin(alpha) && r == regime)
            .map(|((branch, _, _), &(_, rate))| (*branch, rate))
            .collect()
    }

    /// Every 1/T point (α, 1/T) measured under `regime`, both branches, in α's order.
    ///
    /// ```
    /// use rollphase_scene::live::history::{PlotHistory, Regime};
    /// let linear = Regime::labelled(0.0, "linear drag");
    /// assert!(PlotHistory::default().checkpoint().points_at(&linear).is_empty());
    /// ```
    pub fn points_at(&self, regime: &Regime) -> Vec<[f64; 2]> {
        let mut points: Vec<[f64; 2]> = self
            .sweep
            .iter()
            .filter(|((_, r, _), _)| r == regime)
            .map(|(_, &(alpha, rate))| [alpha, rate])
            .collect();
        points.sort_by(|a, b| a[0].total_cmp(&b[0]));
        points
    }

    /// The direction the α sweep was last moving in, if it has moved.
    pub fn direction(&self) -> Option<Branch> {
        self.direction
    }

    /// The settled crossings of ∂Ω (polar angles) collected under `regime` (at its m/m0, under
    /// its drag law), oldest first.
    ///
    /// # Example
    /// ```
    /// use rollphase_scene::live::history::{PlotHistory, Regime};
    /// let at_2 = Regime::labelled(2.0, "linear drag");
    /// assert!(PlotHistory::default().checkpoint().crossings_at(&at_2).is_empty());
    /// ```
    pub fn crossings_at(&self, regime: &Regime) -> Vec<f64> {
        self.crossings
            .under(regime.drag())
            .into_iter()
            .filter(|p| p[0] == regime.mass_ratio())
            .map(|p| p[1])
            .collect()
    }

    /// The cycle the run last settled on at `alpha` (the sweep's own "same α", 0.1 %) under
    /// `regime` (the live run's verdict, `Snapshot::period_multiplicity`), if it settled there.
    ///
    /// # Example
    /// ```
    /// use rollphase_scene::live::history::{PlotHistory, Regime};
    /// let at_2 = Regime::labelled(2.0, "linear drag");
    /// assert_eq!(PlotHistory::default().checkpoint().cycle_at(0.15, &at_2), None);
    /// ```
    pub fn cycle_at(&self, alpha: f64, regime: &Regime) -> Option<&SettledCycle> {
        self.crossings
            .cycles
            .get(&(regime.clone(), sweep_bin(alpha)))
    }

    /// How the body first left the model (lift-off, slip; the verdict's `left_model` in words)
    /// at `alpha` under `regime`, if it did.
    ///
    /// # Example
    /// ```
    /// use rollphase_scene::live::history::{PlotHistory, Regime};
    /// let at_2 = Regime::labelled(2.0, "linear drag");
    /// assert_eq!(PlotHistory::default().checkpoint().left_model_at(0.15, &at_2), None);
    /// ```
    pub fn left_model_at(&self, alpha: f64, regime: &Regime) -> Option<&str> {
        self.crossings
            .left_model
            .get(&(regime.clone(), sweep_bin(alpha)))
            .map(String::as_str)
    }
}

impl PlotHistory {
    /// Clears the time series (a new run); the α sweep is kept, since it describes the body.
    pub fn clear_run(&mut self) {
        self.samples.clear();
        self.others.iter_mut().for_each(Self::clear_run);
        self.last_period = None;
    }

    /// Clears everything (a new body).
    pub fn clear_all(&mut self) {
        *self = Self::default();
    }

    /// What the sweep and crossing plots hold now.
    pub fn checkpoint(&self) -> PlotCheckpoint {
        PlotCheckpoint {
            sweep: self.sweep.clone(),
            last_alpha: self.last_alpha,
            direction: self.direction,
            crossings: self.crossings.clone(),
            others: self.others.iter().map(Self::checkpoint).collect(),
        }
    }

    /// Puts the sweep and crossing plots back as they were at `checkpoint` (the time series
    /// belong to the run and are left alone).
    pub fn restore(&mut self, checkpoint: &PlotCheckpoint) {
        let c = checkpoint.clone();
        self.sweep = c.sweep;
        self.last_alpha = c.last_alpha;
        self.direction = c.direction;
        self.crossings = c.crossings;
        self.last_period = None;
        self.others.truncate(c.others.len());
        for (n, other) in c.others.iter().enumerate() {
            self.other_mut(n + 1).restore(other);
        }
    }

    /// Takes in the simulation's samples ([`LiveRun::take_plot_samples`](super::LiveRun::take_plot_samples)),
    /// oldest first; one not after the last taken is left out.
    pub fn push_samples(&mut self, samples: impl IntoIterator<Item = Sample>) {
        for s in samples {
            let series = match s.body {
                0 => &mut self.samples,
                n => &mut self.other_mut(n).samples,
            };
            if series.back().is_some_and(|last| s.t <= last.t) {
                continue;
            }
            series.push_back(s);
            if series.len() > MAX_SAMPLES {
                series.pop_front();
            }
        }
    }

    /// Takes in one snapshot: a sweep point when a new period was measured or the body halted,
    /// and a settled crossing of ∂Ω.
    pub fn push(&mut self, snap: &Snapshot) {
        let alpha = snap.alpha_rad;
        // A sphere's whole cycle once decided, not its last crossing interval, which alternates
        // on a doubled cycle.
        let stated = snap.stated_period().map(|(t, _)| t);
        if let Some(prev) = self.last_alpha
            && alpha != prev
        {
            self.direction = Some(if alpha > prev {
                Branch::Up
            } else {
                Branch::Down
            });
            // Periods measured before the change belong to the old α.
            self.last_period = stated;
        }
        self.last_alpha = Some(alpha);
        let direction = self.direction.unwrap_or(Branch::Up);
        let bin = sweep_bin(alpha);
        // Past a lift-off or a slip the model's motion is not the body's: no point of it is
        // recorded (the verdict's `left_model`).
        let rollable = snap.validity.is_none();
        if rollable && snap.halted {
            self.sweep
                .insert((direction, Regime::of(snap), bin), (alpha, 0.0));
        } else if let Some(period) = stated
            && rollable
            && self.last_period != Some(period)
            && period > 0.0
        {
            self.sweep
                .insert((direction, Regime::of(snap), bin), (alpha, 1.0 / period));
        }
        self.last_period = stated;

        self.crossings.take(snap);
        for (n, lane) in snap.lanes.iter().enumerate() {
            self.other_mut(n + 1).push(lane);
        }
    }

    /// Body `n`'s history (n ≥ 1: the n-th `[[bodies]]` entry), made if it is not there yet.
    fn other_mut(&mut self, n: usize) -> &mut PlotHistory {
        if self.others.len() < n {
            self.others.resize_with(n, PlotHistory::default);
        }
        &mut self.others[n - 1]
    }

    /// The plots of a saved state (`[resume]`): its 1/T and crossing points, taken in as if
    /// collected, each 1/T point under its saved drag law (or the scene's, `drag`, where the
    /// file has none), and its last α as the one the next change is judged from.
    pub fn resumed(
        resume: &crate::scene::ResumeSpec,
        alpha_now: f64,
        drag: &crate::dynamics::DragLaw,
    ) -> Self {
        let mut history = Self::default();
        let labels = (resume.alpha_sweep_drag.len() == resume.alpha_sweep.len())
            .then_some(&resume.alpha_sweep_drag);
        for (i, &[alpha, rate, mass, dir]) in resume.alpha_sweep.iter().enumerate() {
            let direction = if dir < 0.0 { Branch::Down } else { Branch::Up };
            let bin = sweep_bin(alpha);
            let regime = match labels {
                Some(l) => Regime::labelled(mass, &l[i]),
                None => Regime::new(mass, drag),
            };
            history
                .sweep
                .insert((direction, regime, bin), (alpha, rate));
        }
        history.crossings =
            Crossings::from_points(&resume.crossings, &resume.crossings_drag, &drag.label());
        history.last_alpha = Some(alpha_now);
        history
    }

    /// The plots a scene starts with: its saved state's (`[resume]`), and each other body's
    /// from its own `[bodies.resume]`; empty for a scene that starts afresh.
    pub fn of_setup(setup: &crate::scene::SceneSetup) -> Self {
        let resumed = |s: &crate::scene::SceneSetup| match &s.scene.resume {
            Some(resume) => Self::resumed(resume, s.ramp.alpha_rad, &s.ramp.drag_law),
            None => Self::default(),
        };
        let mut history = resumed(setup);
        for (i, lane) in setup.lanes.iter().enumerate() {
            *history.other_mut(i + 1) = resumed(lane);
        }
        history
    }

    /// The saved state `[resume]` keeps of the run at `t` in `state`, with these plots' points.
    pub fn saved(&self, t: f64, state: Vec<f64>) -> crate::scene::ResumeSpec {
        crate::scene::ResumeSpec {
            t,
            state,
            alpha_sweep: self.alpha_sweep_points(),
            crossings: self.crossings_by_mass(),
            alpha_sweep_drag: self.alpha_sweep_drag(),
            crossings_drag: self.crossings_drag(),
        }
    }

    /// The 1/T points as `[resume]` keeps them: [α, 1/T, m/m0, +1 up or −1 down].
    pub fn alpha_sweep_points(&self) -> Vec<[f64; 4]> {
        self.sweep
            .iter()
            .map(|((direction, regime, _), &(alpha, rate))| {
                let dir = if *direction == Branch::Down {
                    -1.0
                } else {
                    1.0
                };
                [alpha, rate, regime.mass_ratio(), dir]
            })
            .collect()
    }

    /// The drag law of each 1/T point, in [`Self::alpha_sweep_points`]'s order (a saved
    /// state's `alpha_sweep_drag`).
    pub fn alpha_sweep_drag(&self) -> Vec<String> {
        self.sweep
            .keys()
            .map(|(_, regime, _)| regime.drag().to_string())
            .collect()
    }

    /// Whether any settled crossing of ∂Ω was collected (the mass sweep plot is shown then).
    pub fn has_crossings(&self) -> bool {
        !self.crossings.points.is_empty()
    }

    /// Whether any other body (`[[bodies]]`) has a settled crossing of ∂Ω.
    pub fn has_lane_crossings(&self) -> bool {
        self.others.iter().any(Self::has_crossings)
    }

    /// The settled crossing points of body `n` (0: the scene's own; n: its n-th `[[bodies]]`
    /// entry) as (m/m0, polar angle), oldest first.
    pub fn crossings_of_body(&self, n: usize) -> Vec<[f64; 2]> {
        let crossings = match n {
            0 => Some(&self.crossings),
            n => self.others.get(n - 1).map(|h| &h.crossings),
        };
        crossings.map_or_else(Vec::new, |c| c.points.iter().copied().collect())
    }

    /// The settled crossing points of ∂Ω as (m/m0, polar angle), oldest first.
    pub fn crossings_by_mass(&self) -> Vec<[f64; 2]> {
        self.crossings.points.iter().copied().collect()
    }

    /// The drag law of each crossing point, in [`Self::crossings_by_mass`]'s order (a saved
    /// state's `crossings_drag`).
    pub fn crossings_drag(&self) -> Vec<String> {
        self.crossings.laws.iter().cloned().collect()
    }

    /// The crossing points grouped by the drag law they were measured under, each law once, in
    /// the order of its first point: a law's points are an orbit diagram of their own.
    pub fn crossings_by_law(&self) -> Vec<(String, Vec<[f64; 2]>)> {
        let mut laws: Vec<&String> = Vec::new();
        for law in &self.crossings.laws {
            if !laws.contains(&law) {
                laws.push(law);
            }
        }
        laws.into_iter()
            .map(|law| (law.clone(), self.crossings.under(law)))
            .collect()
    }

    /// The samples, oldest first.
    pub fn samples(&self) -> impl Iterator<Item = &Sample> {
        self.samples.iter()
    }

    /// How many other bodies (`[[bodies]]`) have a history.
    pub fn lanes(&self) -> usize {
        self.others.len()
    }

    /// The history of the `n`-th other body (`[[bodies]]` entry n, from 1): its plots and CSV
    /// are the scene's own body's, for it. `None` for a body with none yet.
    pub fn lane(&self, n: usize) -> Option<&PlotHistory> {
        self.others.get(n.checked_sub(1)?)
    }

    /// At most about [`PLOT_POINTS`] evenly spaced samples, the newest always included: a
    /// plot a few hundred pixels wide shows no more, and every point drawn costs tessellation
    /// and fill time (on a CPU renderer the full series doubled the frame time).
    pub fn plotted(&self) -> impl Iterator<Item = &Sample> {
        let n = self.samples.len();
        let stride = n.div_ceil(PLOT_POINTS).max(1);
        // Count from the newest sample so it is always drawn.
        let offset = (n + stride - 1) % stride;
        self.samples.iter().skip(offset).step_by(stride)
    }

    /// The newest `n` samples at full resolution, oldest first: the phase curve, whose peaks a
    /// thinned series would cut.
    pub fn recent(&self, n: usize) -> impl Iterator<Item = &Sample> {
        self.samples
            .iter()
            .skip(self.samples.len().saturating_sub(n))
    }

    /// The sweep points (α, 1/T) of one direction, every regime's, by regime then α.
    pub fn sweep(&self, direction: Branch) -> Vec<[f64; 2]> {
        self.sweep
            .iter()
            .filter(|((d, _, _), _)| *d == direction)
            .map(|(_, &(a, f))| [a, f])
            .collect()
    }

    /// The sweep points (α, 1/T) of one direction, one series per regime (m/m0 and drag law),
    /// each by α: what the 1/T plot draws, never one series of several regimes.
    pub fn sweep_by_regime(&self, direction: Branch) -> BTreeMap<Regime, Vec<[f64; 2]>> {
        let mut series: BTreeMap<Regime, Vec<[f64; 2]>> = BTreeMap::new();
        for ((d, regime, _), &(a, f)) in &self.sweep {
            if *d == direction {
                series.entry(regime.clone()).or_default().push([a, f]);
            }
        }
        series
    }

    /// The sweep points (α, 1/T, m/m0) of one direction with the drag law each was measured
    /// under (a lesson may sweep α at several masses), by regime then α.
    pub fn sweep_with_regime(&self, direction: Branch) -> Vec<([f64; 3], &str)> {
        self.sweep
            .iter()
            .filter(|((d, _, _), _)| *d == direction)
            .map(|((_, r, _), &(a, f))| ([a, f, r.mass_ratio()], r.drag()))
            .collect()
    }
}

/// A health quantity of the plots: its label, its CSV column and its value in a sample.
#[derive(Debug, Clone, Copy)]
pub struct HealthQuantity {
    /// As the plot's legend names it.
    pub label: &'static str,
    /// As health.csv's header names it.
    pub column: &'static str,
    /// Its worst value so far in a sample.
    pub value: fn(&Sample) -> f64,
}

/// The health quantities the running model measures (`measured`), in plot order: a cylinder
/// has no quaternion or contact normal, the viscous models no energy balance.
pub fn health_quantities(measured: Measured) -> Vec<HealthQuantity> {
    [
        (
            measured.quat_norm,
            HealthQuantity {
                label: "||q|−1|",
                column: "quat_norm_error",
                value: |s| s.quat_norm_error,
            },
        ),
        (
            measured.contact_normal,
            HealthQuantity {
                label: "contact normal",
                column: "contact_normal_error",
                value: |s| s.contact_normal_error,
            },
        ),
        (
            measured.energy,
            HealthQuantity {
                label: "|E+W−E₀|",
                column: "energy_drift",
                value: |s| s.energy_drift,
            },
        ),
    ]
    .into_iter()
    .filter_map(|(has, q)| has.then_some(q))
    .collect()
}

impl PlotHistory {
    /// The files [`Self::write_csv_files`] writes into its folder for a ramp of `bodies`
    /// bodies.
    pub fn file_names(bodies: usize) -> Vec<String> {
        let mut names: Vec<String> = PlotData::ALL
            .iter()
            .map(|d| d.file_name().to_string())
            .collect();
        names.push(PLOT_META_FILE.to_string());
        names.extend((2..=bodies).flat_map(body_files));
        names
    }

    /// Checks, before any work, that the plot data of a ramp of `bodies` bodies can be written
    /// into `dir`: the folder's checks ([`output::check_folder`]: none of `inputs`, no device),
    /// and no body file of an earlier run with more bodies there (it would read as this run's;
    /// it is not this run's to remove).
    pub fn check_folder(dir: &Path, bodies: usize, inputs: &Inputs) -> output::Result<()> {
        let names = Self::file_names(bodies);
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        output::check_folder(dir, &names, inputs)?;
        for name in (bodies + 1..=crate::scene::MAX_BODIES).flat_map(body_files) {
            let path = dir.join(&name);
            if std::fs::symlink_metadata(&path).is_ok() {
                return Err(output::OutputError::Io {
                    path,
                    error: std::io::Error::new(
                        std::io::ErrorKind::AlreadyExists,
                        format!(
                            "{name} is there from an earlier run with more bodies, and this \
                             run has {bodies}: it would read as this run's (remove it, or write \
                             the plot data to another folder)"
                        ),
                    ),
                });
            }
        }
        Ok(())
    }

    /// Writes the data sets into the folder `dir` (created if missing) as
    /// [`PlotData::file_name`]s with `meta` as [`PLOT_META_FILE`], through the output layer: all
    /// or none, none of them one of `inputs`. Returns the files written.
    pub fn write_csv_files(
        &self,
        dir: &Path,
        measured: Measured,
        meta: &PlotMeta,
        inputs: &Inputs,
    ) -> output::Result<Vec<std::path::PathBuf>> {
        Self::check_folder(dir, 1 + meta.bodies.len(), inputs)?;
        output::create_folder(dir)?;
        let mut set = OutputSet::new();
        let mut written = Vec::new();
        for data in PlotData::ALL {
            let path = dir.join(data.file_name());
            set.write(&path, self.csv(data, measured).as_bytes(), inputs)?;
            written.push(path);
        }
        for body in &meta.bodies {
            let none = PlotHistory::default();
            let lane = self.lane(body.body - 1).unwrap_or(&none);
            for (data, name) in BODY_DATA.iter().zip(&body.files) {
                let path = dir.join(name);
                set.write(&path, lane.csv(*data, measured).as_bytes(), inputs)?;
                written.push(path);
            }
        }
        let path = dir.join(PLOT_META_FILE);
        // Serialising plain numbers and strings cannot fail.
        let json = serde_json::to_string_pretty(meta).expect("plot metadata as JSON") + "\n";
        set.write(&path, json.as_bytes(), inputs)?;
        written.push(path);
        set.commit()?;
        Ok(written)
    }
}

#[cfg(test)]
mod tests {
    use super::{Branch, PlotData, PlotHistory, Regime};
    use crate::live::{LiveRun, Measured};
    use crate::scene::Scene;

    /// An α sweep up and down on the near-critical cylinder: both directions in sweep-alpha.csv,
    /// a halted body as 1/T = 0, and the health columns of the model only.
    #[test]
    fn the_csv_holds_what_the_plots_show() {
        let setup = Scene::preset("cylinder-near-critical")
            .unwrap()
            .setup(None)
            .unwrap();
        let alpha_star = setup.alpha_star;
        let mut sim = LiveRun::new(setup);
        let mut history = PlotHistory::default();
        let mut t = 0.0;
        for alpha in [1.5, 2.0, 1.5, 0.9].map(|f| f * alpha_star) {
            let ramp = crate::dynamics::Ramp::with_drag(alpha, 0.0, 1.0).unwrap();
            sim.set_parameters(ramp, sim.method()).unwrap();
            for _ in 0..400 {
                t += 1.0;
                sim.advance_to(t).unwrap();
                history.push(&sim.snapshot());
                history.push_samples(sim.take_plot_samples());
            }
        }
        let measured = sim.snapshot().health.measured;
        assert_eq!(
            measured,
            Measured::default(),
            "the viscous disk measures none"
        );
        let sweep = history.csv(PlotData::AlphaSweep, measured);
        let rows: Vec<Vec<&str>> = sweep.lines().map(|l| l.split(',').collect()).collect();
        assert_eq!(
            rows[0],
            ["direction", "alpha", "inverse_period", "mass_ratio", "drag"]
        );
        assert!(
            rows[1..]
                .iter()
                .all(|r| r[3] == "0.0" && r[4] == "linear drag"),
            "the viscous model: m/m0 = 0, under linear drag\n{sweep}"
        );
        let series = history.csv(PlotData::Series, measured);
        assert!(
            series.starts_with("t,theta,theta_dot\n"),
            "a cylinder's columns"
        );
        assert_eq!(series.lines().count(), 1 + history.samples().count());
        assert!(rows.iter().any(|r| r[0] == "up") && rows.iter().any(|r| r[0] == "down"));
        let halted = rows.iter().find(|r| r[0] == "down" && r[2] == "0.0");
        assert!(
            halted.is_some(),
            "0.9 α* halts: 1/T = 0 on the way down\n{sweep}"
        );
        let health = history.csv(PlotData::Health, measured);
        assert_eq!(health.lines().next(), Some("t"));
        assert_eq!(health.lines().count(), 1 + history.samples().count());
        let crossings = history.csv(PlotData::Crossings, measured);
        assert_eq!(crossings.trim(), "mass_ratio,polar_angle,drag");
        // Every number parses back to the value plotted.
        for r in &rows[1..] {
            assert!(r[1].parse::<f64>().unwrap() > 0.0);
        }
    }

    /// The same α measured under two drag laws gives two points in two series, each named by
    /// its law, never one point of one series (issue 60).
    #[test]
    fn points_under_another_drag_law_are_a_series_of_their_own() {
        let setup = Scene::preset("cylinder-near-critical")
            .unwrap()
            .setup(None)
            .unwrap();
        let alpha = 2.0 * setup.alpha_star;
        let (sim, history) = under_linear_then_squared_drag(setup, alpha, 300);
        let series = history.sweep_by_regime(Branch::Up);
        assert_eq!(series.len(), 2, "{series:?}");
        let labels: Vec<String> = series.keys().map(Regime::label).collect();
        assert!(
            labels.iter().any(|l| l.contains("linear drag"))
                && labels.iter().any(|l| l.contains("drag_exponent = 2")),
            "{labels:?}"
        );
        // One point each, at the same α, with different 1/T (n = 2 rolls at another speed).
        let rates: Vec<f64> = series.values().map(|p| p[0][1]).collect();
        assert!(series.values().all(|p| p.len() == 1 && p[0][0] == alpha));
        assert!((rates[0] - rates[1]).abs() > 1e-3 * rates[0], "{rates:?}");
        let csv = history.csv(PlotData::AlphaSweep, sim.snapshot().health.measured);
        assert_eq!(csv.lines().count(), 3, "{csv}");
        // Saved and resumed, each point keeps its law (without the labels both were read as
        // the scene's law, and one replaced the other in their shared bin).
        let resume = crate::scene::ResumeSpec {
            alpha_sweep: history.alpha_sweep_points(),
            alpha_sweep_drag: history.alpha_sweep_drag(),
            ..Default::default()
        };
        let back = PlotHistory::resumed(&resume, alpha, &crate::dynamics::DragLaw::LINEAR);
        assert_eq!(back.sweep_by_regime(Branch::Up), series);
    }

    /// `setup` run at α = `alpha`, m/m0 = 0 for `span` under linear drag, then `span` more
    /// under drag_exponent = 2, its plots taking a snapshot every time unit.
    fn under_linear_then_squared_drag(
        setup: crate::scene::SceneSetup,
        alpha: f64,
        span: u32,
    ) -> (LiveRun, PlotHistory) {
        let mut sim = LiveRun::new(setup);
        let mut history = PlotHistory::default();
        let mut t = 0.0;
        for exponent in [1.0, 2.0] {
            let law = crate::dynamics::DragLaw::LINEAR
                .with("drag_exponent", exponent)
                .unwrap();
            let ramp = crate::dynamics::Ramp::with_drag(alpha, 0.0, 1.0)
                .unwrap()
                .with_drag_law(law);
            sim.set_parameters(ramp, sim.method()).unwrap();
            for _ in 0..span {
                t += 1.0;
                sim.advance_to(t).unwrap();
                history.push(&sim.snapshot());
            }
        }
        (sim, history)
    }

    /// The crossings plot keeps the points of each drag law apart, in its CSV's drag column and
    /// through a saved state (at one m/m0 another law rolls another orbit: mixed, its crossings
    /// read as a second branch).
    #[test]
    fn crossings_under_another_drag_law_are_kept_apart() {
        let setup = Scene::preset("sphere-cruising")
            .unwrap()
            .setup(None)
            .unwrap();
        let alpha = setup.ramp.alpha_rad;
        let (sim, history) = under_linear_then_squared_drag(setup, alpha, 500);
        let t = sim.time();
        let by_law = history.crossings_by_law();
        let laws: Vec<&str> = by_law.iter().map(|(l, _)| l.as_str()).collect();
        assert_eq!(laws, ["linear drag", "drag_exponent = 2"], "{by_law:?}");
        assert!(by_law.iter().all(|(_, points)| !points.is_empty()));
        let csv = history.csv(PlotData::Crossings, sim.snapshot().health.measured);
        let mut lines = csv.lines();
        assert_eq!(lines.next(), Some("mass_ratio,polar_angle,drag"));
        assert!(
            csv.contains(",linear drag") && csv.contains(",drag_exponent = 2"),
            "{csv}"
        );
        let resume = history.saved(t, Vec::new());
        assert_eq!(resume.crossings_drag.len(), resume.crossings.len());
        let back = PlotHistory::resumed(&resume, alpha, &crate::dynamics::DragLaw::LINEAR);
        assert_eq!(back.crossings_by_law(), by_law);
        // A file without the labels: every point is the scene's law.
        let unlabelled = crate::scene::ResumeSpec {
            crossings_drag: Vec::new(),
            ..resume
        };
        let back = PlotHistory::resumed(&unlabelled, alpha, &crate::dynamics::DragLaw::LINEAR);
        assert_eq!(back.crossings_by_law().len(), 1);
    }

    #[test]
    fn no_rate_is_recorded_for_a_body_that_left_the_ramp() {
        let setup = Scene::preset("cylinder-near-critical")
            .unwrap()
            .setup(None)
            .unwrap();
        let mut snap = LiveRun::new(setup).snapshot();
        snap.period = Some(12.0);
        snap.validity = Some("leaves the ramp at t = 3".into());
        let mut history = PlotHistory::default();
        history.push(&snap);
        assert!(history.sweep(super::Branch::Up).is_empty());
        snap.halted = true;
        history.push(&snap);
        assert!(history.sweep(super::Branch::Up).is_empty());
        // The same snapshot on the ramp is a point.
        snap.validity = None;
        snap.halted = false;
        snap.period = Some(13.0);
        history.push(&snap);
        assert_eq!(history.sweep(super::Branch::Up).len(), 1);
    }

    /// A doubled sphere's 1/T point is its whole cycle's, steady from crossing to crossing; the
    /// time between its last two crossings alternates and is neither.
    #[test]
    fn a_doubled_spheres_rate_is_its_whole_cycles() {
        let setup = Scene::preset("sphere-doubling")
            .unwrap()
            .setup(None)
            .unwrap();
        let mut snap = LiveRun::new(setup).snapshot();
        assert!(snap.theta.is_none(), "a sphere");
        let mut history = PlotHistory::default();
        // Undecided: the last crossing interval is a first look, stated as such.
        snap.period = Some(44.19);
        history.push(&snap);
        assert_eq!(history.sweep(super::Branch::Up)[0][1], 1.0 / 44.19);
        assert_eq!(
            snap.stated_period(),
            Some((44.19, super::super::PeriodSpan::LastCrossings))
        );
        // Decided period 2: the cycle, whichever crossing came last.
        snap.period_multiplicity = Some(2);
        for (last, cycle) in [(45.15, 89.34), (44.19, 89.33), (45.15, 89.34)] {
            snap.period = Some(last);
            snap.cycle_period = Some(cycle);
            history.push(&snap);
            let points = history.sweep(super::Branch::Up);
            assert_eq!(points.len(), 1);
            assert_eq!(points[0][1], 1.0 / cycle, "not 1/{last}");
        }
        assert_eq!(
            snap.stated_period(),
            Some((89.34, super::super::PeriodSpan::Cycle { crossings: 2 }))
        );
    }
}
