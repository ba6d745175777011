//! `rollphase sweep SPEC.toml`: a general parameter scan of 3D rolling, bodies × α × m/m0 ×
//! initial orientations × integrators, one CSV row per run with its fate in the words every
//! surface uses (halted, periodic, left_model where the body left the ramp, or undecided at
//! `t_max`), period, 1/T, period multiplicity, RHS evaluations, and whether the
//! run's own integrator gave that answer (`answer_check`; what it said instead in the `fast_…`
//! columns when the reference corrected it). It runs through
//! the same ensemble as the figures, so `--shard I/N` and `rollphase merge DIR` work the same
//! way (see [`super::shard`] and docs/guide/cluster.md).
//!
//! Each run is the core's [`Scan::run`] ([`crate::analysis::orbits::sphere_orbits::settle_checked`]):
//! released from rest (viscous if m/m0 = 0), followed until it halts (the verdict's rest),
//! closes a steady cycle of k ≤ `max_multiplicity` crossings of ∂Ω (`settled_cycle`, points to
//! `point_tol`; a fast setting's period is checked against the reference's to `period_rtol`), or
//! reaches `t_max`. Only a periodic run cruises; an undecided one is not counted (as in
//! `sphere-cruising`). Orientation o of a body is
//! [`crate::analysis::studies::sphere::random_orientation`]`(body, orientation_seed, o)`, the one the
//! figures use. A fate found with a setting coarser than DOP853 at rtol 1e-10 is re-decided with
//! that reference before it is written (a cycle from its last crossing, a halt or an undecided
//! run from the start), so a row's fate, period and multiplicity never depend on the integrator
//! picked for speed. This module reads and checks the spec, shards the runs and writes the rows.
//!
//! A spec (all keys but `alpha` and one body source optional; TOML puts the plain keys before
//! the `[bodies]` table):
//! ```toml
//! alpha = [0.12, 0.15]       # or { from = 0.1, to = 0.2, count = 11 }
//! mass_ratio = [0.0, 6.0]    # 0: viscous; same list-or-range forms
//! orientations = 20
//! orientation_seed = 1
//! integrators = ["balanced"] # fast, balanced, precise, dop853:RTOL, rk4:DT, cf4:DT
//! t_max = 2000.0
//!
//! [bodies]
//! paper_seeds = [219]        # the authors' numpy generator (σ, l below)
//! seeds = [1, 2, 3]          # our random bodies
//! files = ["body.json"]      # shape files, relative to the spec's folder
//! sigma = 0.25
//! max_degree = 5
//! ```
//! Generated bodies that are not strictly convex are skipped (the rolling model needs a convex
//! body) and counted in the summary; a non-convex file is an error.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};

use super::shard::{
    Ensemble, Ensembled, Fields, JobId, Record, ShardSet, ShardSpec, ShardWritten, run_ensemble,
};
use super::{number_field, par_map};
use crate::analysis::orbits::sphere_orbits::{AnswerCheck, Settle, Settlement};
use crate::analysis::studies::sweep::{Scan, ScanRun, ScanTally};
use crate::dynamics::Ramp;
use crate::dynamics::validity::ContactReport;
use crate::geometry::shape_file::{MAX_INPUT_FILE_BYTES, read_text_capped};
use crate::geometry::{Body, ShapeFile, Sphere, paper_sphere, random_sphere};
use crate::integrate::{Method, readable};
use crate::output::{self, Inputs, OutputFile, OutputSet};
use rayon::prelude::*;

/// Most runs one sweep may hold (all shards together): at the measured ~10 ms a run (paper body,
/// t_max = 2000, docs/guide/cluster.md) 10⁷ runs are ~28 core-hours, a night on a small cluster or a
/// day on one 2-core machine; memory stays flat (~10 MB measured at 10⁴, 10⁵ and 10⁶ runs), and
/// sweep.csv is ~70 bytes a run (0.7 GB).
pub const MAX_RUNS: usize = 10_000_000;
/// Most values in one axis (α, m/m0, bodies, integrators) and most orientations.
pub const MAX_AXIS: usize = 1_000_000;

/// A list of numbers, or an evenly spaced range. Read by hand (not serde's untagged enum) so a
/// mistake is named in plain words: which key, and what is allowed.
#[derive(Debug, Clone)]
pub enum Axis {
    /// The values.
    List(Vec<f64>),
    /// `count` values from `from` to `to`, both included.
    Range {
        /// First value.
        from: f64,
        /// Last value.
        to: f64,
        /// Values (≥ 2; 1 gives `from`).
        count: usize,
    },
}

/// How an axis is written, for messages.
const AXIS_FORMS: &str = "a list of numbers like [0.1, 0.2], or a range like \
                          { from = 0.1, to = 0.2, count = 11 }";

impl<'de> Deserialize<'de> for Axis {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let number = |v: &toml::Value| match v {
            toml::Value::Float(x) => Some(*x),
            toml::Value::Integer(i) => Some(*i as f64),
            _ => None,
        };
        match toml::Value::deserialize(d)? {
            toml::Value::Array(items) => items
                .iter()
                .map(|v| {
                    number(v).ok_or_else(|| {
                        D::Error::custom(format!("{v} is not a number; an axis is {AXIS_FORMS}"))
                    })
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Axis::List),
            v @ (toml::Value::Float(_) | toml::Value::Integer(_)) => {
                Ok(Axis::List(vec![number(&v).unwrap_or(f64::NAN)]))
            }
            toml::Value::Table(t) => {
                if let Some(k) = t
                    .keys()
                    .find(|k| !["from", "to", "count"].contains(&k.as_str()))
                {
                    return Err(D::Error::custom(format!(
                        "a range has the keys from, to and count; {k:?} is not one of them"
                    )));
                }
                let get = |k: &str| {
                    t.get(k).ok_or_else(|| {
                        D::Error::custom(format!(
                            "a range needs from, to and count; {k} is missing"
                        ))
                    })
                };
                let from = number(get("from")?)
                    .ok_or_else(|| D::Error::custom("a range's from must be a number"))?;
                let to = number(get("to")?)
                    .ok_or_else(|| D::Error::custom("a range's to must be a number"))?;
                let count = match get("count")? {
                    toml::Value::Integer(c) if *c >= 1 && *c as u64 <= MAX_AXIS as u64 => {
                        *c as usize
                    }
                    other => {
                        return Err(D::Error::custom(format!(
                            "a range's count = {other} is not allowed (needs a whole number from \
                             1 to {MAX_AXIS})"
                        )));
                    }
                };
                Ok(Axis::Range { from, to, count })
            }
            other => Err(D::Error::custom(format!(
                "{other} is not an axis; an axis is {AXIS_FORMS}"
            ))),
        }
    }
}

impl Axis {
    fn values(&self, key: &str) -> Result<Vec<f64>> {
        let v = match *self {
            Axis::List(ref v) => v.clone(),
            Axis::Range { from, to, count } => {
                if !(1..=MAX_AXIS).contains(&count) {
                    bail!("{key}.count = {count} is not allowed (needs 1 ≤ count ≤ {MAX_AXIS})");
                }
                if count == 1 {
                    vec![from]
                } else {
                    (0..count)
                        .map(|i| from + (to - from) * i as f64 / (count - 1) as f64)
                        .collect()
                }
            }
        };
        if v.is_empty() || v.len() > MAX_AXIS {
            bail!("{key} has {} values (needs 1 to {MAX_AXIS})", v.len());
        }
        Ok(v)
    }
}

/// Where the bodies come from.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodiesSpec {
    /// Seeds of the authors' numpy generator.
    #[serde(default)]
    pub paper_seeds: Vec<u32>,
    /// Seeds of our generator.
    #[serde(default)]
    pub seeds: Vec<u64>,
    /// Shape files (3D), relative to the spec's folder.
    #[serde(default)]
    pub files: Vec<PathBuf>,
    /// σ of generated bodies.
    #[serde(default = "default_sigma")]
    pub sigma: f64,
    /// Highest degree l of generated bodies.
    #[serde(default = "default_degree")]
    pub max_degree: u32,
}

fn default_sigma() -> f64 {
    0.25
}
fn default_degree() -> u32 {
    5
}
fn default_orientations() -> usize {
    1
}
fn default_seed() -> u64 {
    1
}
fn default_integrators() -> Vec<String> {
    vec!["balanced".into()]
}
fn default_t_max() -> f64 {
    2000.0
}
fn default_mass() -> Axis {
    Axis::List(vec![0.0])
}
fn default_max_k() -> usize {
    4
}
fn default_tol() -> f64 {
    1e-5
}

/// The sweep spec (TOML).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// The bodies.
    pub bodies: BodiesSpec,
    /// Ramp angles (rad).
    pub alpha: Axis,
    /// Mass ratios m/m0 (0: viscous).
    #[serde(default = "default_mass")]
    pub mass_ratio: Axis,
    /// Random initial orientations per body, α and m/m0.
    #[serde(default = "default_orientations")]
    pub orientations: usize,
    /// Seed of the orientations.
    #[serde(default = "default_seed")]
    pub orientation_seed: u64,
    /// Integrators: a preset (fast, balanced, precise) or dop853:RTOL, rk4:DT, cf4:DT.
    #[serde(default = "default_integrators")]
    pub integrators: Vec<String>,
    /// Longest simulated time per run.
    #[serde(default = "default_t_max")]
    pub t_max: f64,
    /// Longest cycle of ∂Ω crossings searched (period multiplicity).
    #[serde(default = "default_max_k")]
    pub max_multiplicity: usize,
    /// Distance within which a cycle's ∂Ω points must repeat.
    #[serde(default = "default_tol")]
    pub point_tol: f64,
    /// Relative tolerance within which a cycle's duration must repeat.
    #[serde(default = "default_tol")]
    pub period_rtol: f64,
}

/// An integrator named in a spec.
fn parse_integrator(s: &str) -> Result<Method> {
    s.parse::<Method>()
        .map_err(|e| anyhow::anyhow!("integrators: {e}"))
}

/// A sweep ready to run: its bodies built and checked, its axes expanded into the core's
/// [`Scan`], which runs it.
pub struct Sweep {
    /// The spec's text, as read (stored in shard files).
    pub text: String,
    /// The spec's folder (for relative body files).
    pub base: PathBuf,
    /// The bodies' labels ("paper:219", "seed:3", or the file), in the order of `scan.bodies`.
    pub labels: Vec<String>,
    /// Generated seeds skipped as not convex.
    pub skipped: Vec<String>,
    /// The integrators' names in the spec, in the order of `scan.methods`.
    pub integrator_names: Vec<String>,
    /// The grid of runs.
    pub scan: Scan,
    /// The spec.
    pub spec: SweepSpec,
    /// The SHA-256 of each of `spec.bodies.files`, as read (recorded in shard files).
    pub body_sha256: Vec<String>,
}

impl Sweep {
    /// Reads `path` and prepares the sweep.
    pub fn load(path: &Path) -> Result<Self> {
        let text = read_text_capped(path, MAX_INPUT_FILE_BYTES)
            .with_context(|| format!("cannot read sweep spec {}", path.display()))?;
        let base = path
            .parent()
            .map(|p| {
                if p.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    p
                }
            })
            .unwrap_or(Path::new("."));
        // Absolute, so shards (which store it) can be merged from any folder.
        let base = std::fs::canonicalize(base).unwrap_or_else(|_| base.to_path_buf());
        Self::from_text(&text, &base).with_context(|| format!("sweep spec {}", path.display()))
    }

    /// Prepares a sweep from a spec's text; files are relative to `base`.
    #[expect(
        clippy::too_many_lines,
        reason = "it validates every key in the spec's order, each with its own message (which \
                  key, which value, what is allowed), before any run; split up, the checks would \
                  only be scattered"
    )]
    pub fn from_text(text: &str, base: &Path) -> Result<Self> {
        let spec: SweepSpec = toml::from_str(text)
            .map_err(|e| anyhow::anyhow!("{}", clip_long_lines(&e.to_string())))?;
        let alphas = spec.alpha.values("alpha")?;
        for &a in &alphas {
            if !(crate::dynamics::MIN_ALPHA..std::f64::consts::FRAC_PI_2).contains(&a) {
                bail!(
                    "alpha = {} is not allowed (needs 1e-9 ≤ α < π/2 rad)",
                    readable(a)
                );
            }
        }
        let masses = spec.mass_ratio.values("mass_ratio")?;
        for &m in &masses {
            if !(m.is_finite() && (0.0..=1e6).contains(&m)) {
                bail!(
                    "mass_ratio = {} is not allowed (needs 0 ≤ m/m0 ≤ 1e6; 0 is viscous)",
                    readable(m)
                );
            }
        }
        if !(1..=MAX_AXIS).contains(&spec.orientations) {
            bail!(
                "orientations = {} is not allowed (needs 1 ≤ orientations ≤ {MAX_AXIS})",
                spec.orientations
            );
        }
        if !(spec.t_max.is_finite() && spec.t_max > 0.0 && spec.t_max <= 1e7) {
            bail!(
                "t_max = {} is not allowed (needs 0 < t_max ≤ 1e7)",
                readable(spec.t_max)
            );
        }
        if !(1..=16).contains(&spec.max_multiplicity) {
            bail!(
                "max_multiplicity = {} is not allowed (needs 1 to 16)",
                spec.max_multiplicity
            );
        }
        for (key, v) in [
            ("point_tol", spec.point_tol),
            ("period_rtol", spec.period_rtol),
        ] {
            if !(v.is_finite() && v > 0.0 && v < 1.0) {
                bail!(
                    "{key} = {} is not allowed (needs 0 < {key} < 1)",
                    readable(v)
                );
            }
        }
        if spec.integrators.is_empty() || spec.integrators.len() > 100 {
            bail!("integrators needs 1 to 100 entries");
        }
        let integrators = spec
            .integrators
            .iter()
            .map(|s| Ok((s.clone(), parse_integrator(s)?)))
            .collect::<Result<Vec<_>>>()?;
        for (name, m) in &integrators {
            if let Method::Rk4 { dt } | Method::Cf4 { dt } = m {
                if spec.t_max / dt > 1e9 {
                    bail!(
                        "integrators: {name:?} needs t_max/dt = {:.3e} steps per run, more than 1e9",
                        spec.t_max / dt
                    );
                }
                if *dt > spec.t_max {
                    bail!(
                        "integrators: {name:?} has a step longer than the whole run (t_max = {}); \
                         use dt ≤ t_max",
                        crate::integrate::readable(spec.t_max)
                    );
                }
            }
        }
        let b = &spec.bodies;
        let max_l = rollphase_core::geometry::MAX_SPHERE_L;
        if !(2..=max_l).contains(&b.max_degree) {
            bail!(
                "bodies.max_degree = {} is not allowed (needs 2 ≤ max_degree ≤ {max_l}: the \
                 highest degree l of the generated bodies' modes)",
                b.max_degree
            );
        }
        let n_bodies = b.paper_seeds.len() + b.seeds.len() + b.files.len();
        if n_bodies == 0 {
            bail!("bodies: give at least one of paper_seeds, seeds or files");
        }
        if n_bodies > MAX_AXIS {
            bail!("bodies: {n_bodies} bodies is more than {MAX_AXIS}");
        }
        let runs = n_bodies
            .saturating_mul(alphas.len())
            .saturating_mul(masses.len())
            .saturating_mul(spec.orientations)
            .saturating_mul(integrators.len());
        if runs > MAX_RUNS {
            bail!(
                "the sweep has {runs} runs, more than {MAX_RUNS} (at ~10 ms a run, 10⁷ runs are \
                 already ~28 core-hours); split it into several specs"
            );
        }
        // Generated bodies, in parallel (each is checked for convexity).
        let generated: Vec<(String, Result<Sphere>)> = b
            .paper_seeds
            .iter()
            .map(|&s| {
                let body = paper_sphere(s, b.sigma, b.max_degree);
                (format!("paper:{s}"), body.map_err(anyhow::Error::from))
            })
            .chain(b.seeds.iter().map(|&s| {
                let body = random_sphere(s, b.sigma, b.max_degree);
                (format!("seed:{s}"), body.map_err(anyhow::Error::from))
            }))
            .collect();
        let bar = indicatif::ProgressBar::hidden();
        let checked = par_map(generated.len(), &bar, |i| -> Result<Option<Sphere>> {
            let body = match &generated[i].1 {
                Ok(s) => s.clone(),
                Err(e) => bail!("bodies: {}: {e}", generated[i].0),
            };
            Ok(Body::Sphere(body.clone())
                .check_convex()
                .is_ok()
                .then_some(body))
        });
        let mut bodies = Vec::new();
        let mut skipped = Vec::new();
        for (i, c) in checked.into_iter().enumerate() {
            match c? {
                Some(s) => bodies.push((generated[i].0.clone(), s)),
                None => skipped.push(generated[i].0.clone()),
            }
        }
        let mut body_sha256 = Vec::with_capacity(b.files.len());
        for f in &b.files {
            let path = base.join(f);
            body_sha256.push(super::shard::body_digest(&path)?);
            let body = ShapeFile::load(&path)?;
            body.check_convex()
                .with_context(|| format!("bodies.files: {}", path.display()))?;
            match body {
                Body::Sphere(s) => bodies.push((f.display().to_string(), s)),
                Body::Disk(_) => bail!(
                    "bodies.files: {} is a 2D disk; sweep runs 3D bodies",
                    path.display()
                ),
            }
        }
        if bodies.is_empty() {
            bail!(
                "bodies: none of the {} generated bodies is convex (σ = {}); lower sigma",
                skipped.len(),
                b.sigma
            );
        }
        // Every fixed step against the drag relaxation's stability limit, before the first run
        // (the limit depends on the body and m/m0 only).
        for (name, m) in integrators
            .iter()
            .filter(|(_, m)| !matches!(m, Method::Dop853 { .. }))
        {
            for (label, body) in &bodies {
                for &mass in &masses {
                    let ramp = Ramp::new(alphas[0], mass)?;
                    crate::simulate::choose_model(&Body::Sphere(body.clone()), ramp, *m)
                        .with_context(|| format!("integrators: {name:?} on body {label}"))?;
                }
            }
        }
        let (labels, bodies) = bodies.into_iter().unzip();
        let (integrator_names, methods) = integrators.into_iter().unzip();
        let scan = Scan {
            bodies,
            alphas,
            masses,
            orientations: spec.orientations,
            orientation_seed: spec.orientation_seed,
            methods,
            settle: Settle {
                t_max: spec.t_max,
                point_tol: spec.point_tol,
                period_rtol: spec.period_rtol,
                max_k: spec.max_multiplicity,
                ..Settle::default()
            },
        };
        scan.check()?;
        Ok(Sweep {
            text: text.into(),
            base: base.to_path_buf(),
            labels,
            skipped,
            integrator_names,
            scan,
            spec,
            body_sha256,
        })
    }

    /// Runs in the sweep.
    pub fn runs(&self) -> usize {
        self.scan.runs()
    }

    /// Run k, with the run named in its error (body label, α, m/m0, orientation, integrator).
    fn run_one(&self, k: usize) -> Result<ScanRun> {
        self.scan.run(k).with_context(|| {
            let p = self.scan.point(k);
            format!(
                "run {k}: body {}, α = {}, m/m0 = {}, orientation {}, {}",
                self.labels[p.body],
                self.scan.alphas[p.alpha],
                self.scan.masses[p.mass],
                p.orientation,
                self.integrator_names[p.method]
            )
        })
    }

    /// Runs one shard of the sweep and writes its shard file, through the ensemble machinery.
    fn run_shard(&self, spec: ShardSpec, out: &Path, inputs: &Inputs) -> Result<ShardWritten> {
        let place = || Ok((out.to_path_buf(), self.job_id(), inputs.clone()));
        let done = run_ensemble(
            &Ensemble::Shard(spec),
            super::SCAN_NAME,
            self.runs(),
            "sweep runs",
            place,
            |k| self.run_one(k),
        )?;
        match done {
            Ensembled::Shard(written) => Ok(written),
            Ensembled::All(_) => bail!("internal error: a shard run returned every run"),
        }
    }

    /// Runs the whole sweep, streaming rows to `out`/sweep.csv in blocks of [`BLOCK`] runs, so
    /// memory does not grow with the run count; sweep.csv and summary.json are committed
    /// together at the end (nothing is written if a run fails).
    fn run_whole(&self, out: &Path, inputs: &Inputs) -> Result<SweepSummary> {
        let n = self.runs();
        let mut rows = self.rows(out, inputs)?;
        let bar = super::progress(n, "sweep runs");
        for start in (0..n).step_by(BLOCK) {
            let end = (start + BLOCK).min(n);
            // One task per run (their costs differ by orders of magnitude); results come back
            // in index order, so the bytes do not depend on the thread count.
            let results: Vec<Result<ScanRun>> = (start..end)
                .into_par_iter()
                .with_max_len(1)
                .map(|k| {
                    let r = self.run_one(k);
                    bar.inc(1);
                    r
                })
                .collect();
            for (k, r) in (start..end).zip(results) {
                rows.push(k, &r?)?;
            }
        }
        bar.finish_and_clear();
        rows.finish()
    }

    /// What this sweep is, for its shard files.
    pub fn job_id(&self) -> JobId {
        JobId::Sweep {
            spec: self.text.clone(),
            base: self.base.clone(),
            body_sha256: self.body_sha256.clone(),
        }
    }

    /// A writer of sweep.csv's rows (staged in `out`) and the summary's counts.
    fn rows(&self, out: &Path, inputs: &Inputs) -> Result<SweepRows<'_>> {
        output::create_folder(out)?;
        let file = OutputFile::create(&out.join(SWEEP_FILES[0]), inputs)?;
        let mut csv = csv::Writer::from_writer(file);
        csv.write_record(CSV_HEADER.split(','))?;
        Ok(SweepRows {
            sweep: self,
            csv,
            tally: ScanTally::default(),
            out: out.to_path_buf(),
            inputs: inputs.clone(),
            next: 0,
        })
    }

    /// Run k's CSV row.
    fn row(&self, k: usize, r: &ScanRun) -> [String; 21] {
        let p = self.scan.point(k);
        // A run that left the ramp is reported as such: its period, multiplicity and rest are
        // the model's past the lift-off (lift_off_t says when), not a motion the body makes.
        let left = r.left_model();
        let (period, mult, halt, omega_end) = fate_fields(&r.fate);
        let (period, mult, halt) = if left {
            (f64::NAN, String::new(), f64::NAN)
        } else {
            (period, mult, halt)
        };
        let fate = r.fate(&self.scan.settle).name();
        let (fast_fate, fast_period, fast_mult) = match &r.check {
            AnswerCheck::Corrected { fast } => {
                let (period, mult, ..) = fate_fields(fast);
                (
                    fast.fate(&self.scan.settle).name().to_string(),
                    number_field(period),
                    mult,
                )
            }
            _ => (String::new(), String::new(), String::new()),
        };
        [
            self.labels[p.body].clone(),
            number_field(self.scan.alphas[p.alpha]),
            number_field(self.scan.masses[p.mass]),
            p.orientation.to_string(),
            self.integrator_names[p.method].clone(),
            fate.to_string(),
            r.cruises().to_string(),
            number_field(period),
            number_field(1.0 / period),
            mult,
            number_field(halt),
            number_field(omega_end),
            r.rhs_evals.to_string(),
            r.check.name().to_string(),
            fast_fate,
            fast_period,
            fast_mult,
            number_field(r.contact.min_normal_force),
            number_field(r.contact.max_normal_force),
            // Infinite once the body left the ramp: "inf", not an empty field.
            if r.contact.max_friction_needed.is_infinite() {
                "inf".to_string()
            } else {
                number_field(r.contact.max_friction_needed)
            },
            r.contact.lift_off_t.map_or_else(String::new, number_field),
        ]
    }

    /// The files this sweep reads: its body files (the spec itself is added by [`run`]).
    pub fn inputs(&self) -> Inputs {
        Inputs::of(self.spec.bodies.files.iter().map(|f| self.base.join(f)))
    }
}

/// A fate's evidence as CSV fields: its period, multiplicity, halt time and end |ω| (its word
/// is the verdict's, [`Settlement::fate`]).
fn fate_fields(fate: &Settlement) -> (f64, String, f64, f64) {
    match *fate {
        Settlement::Halts { t } => (f64::NAN, String::new(), t, 0.0),
        Settlement::Periodic { period, k, .. } => (period, k.to_string(), f64::NAN, f64::NAN),
        Settlement::Undecided { omega_end } => (f64::NAN, String::new(), f64::NAN, omega_end),
    }
}

/// Longest line of a spec's text quoted in an error: TOML's messages quote the offending line,
/// which in a generated spec can be hundreds of kB.
const MAX_QUOTED_LINE: usize = 200;

/// `text` with every line over [`MAX_QUOTED_LINE`] characters cut there (and marked).
fn clip_long_lines(text: &str) -> String {
    text.lines()
        .map(|l| match l.char_indices().nth(MAX_QUOTED_LINE) {
            Some((cut, _)) => format!("{} … ({} characters in all)", &l[..cut], l.chars().count()),
            None => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// sweep.csv's header.
const CSV_HEADER: &str = "body,alpha,mass_ratio,orientation,integrator,fate,cruising,period,\
                          inverse_period,multiplicity,halt_time,omega_end,rhs_evals,answer_check,\
                          fast_fate,fast_period,fast_multiplicity,min_normal_force,\
                          max_normal_force,max_friction_needed,lift_off_t";

/// Runs computed (and held) at a time by a whole sweep: enough to keep every core busy, small
/// enough that memory stays flat (a result is ~80 bytes).
pub const BLOCK: usize = 4096;

/// sweep.csv being written row by row, with the summary's counts.
struct SweepRows<'a> {
    sweep: &'a Sweep,
    csv: csv::Writer<OutputFile>,
    tally: ScanTally,
    out: PathBuf,
    inputs: Inputs,
    next: usize,
}

impl SweepRows<'_> {
    /// Adds run k (runs arrive in index order).
    fn push(&mut self, k: usize, r: &ScanRun) -> Result<()> {
        if k != self.next {
            bail!(
                "internal error: sweep run {k} arrived before run {}",
                self.next
            );
        }
        self.next += 1;
        // A full disk is named with the file it stopped (the csv error says only "I/O error").
        self.csv
            .write_record(self.sweep.row(k, r))
            .with_context(|| format!("cannot write {}", self.out.join(SWEEP_FILES[0]).display()))?;
        self.tally.add(r);
        Ok(())
    }

    /// Commits sweep.csv with summary.json.
    fn finish(self) -> Result<SweepSummary> {
        let file = self.csv.into_inner().map_err(|e| {
            anyhow::anyhow!(
                "cannot write {}: {}",
                self.out.join(SWEEP_FILES[0]).display(),
                e.error()
            )
        })?;
        let t = self.tally;
        let summary = SweepSummary {
            runs: t.runs,
            bodies: self.sweep.labels.clone(),
            skipped_not_convex: self.sweep.skipped.clone(),
            halts: t.halts,
            periodic: t.periodic,
            undecided: t.undecided,
            left_model: t.left_model,
            cruising: t.cruising,
            corrected: t.corrected,
            rhs_evals: t.rhs_evals,
        };
        let mut set = OutputSet::new();
        set.add(file)?;
        let json = super::summary_text(&summary)?;
        set.write(
            &self.out.join(SWEEP_FILES[1]),
            json.as_bytes(),
            &self.inputs,
        )?;
        set.commit()?;
        Ok(summary)
    }
}

/// Headline numbers of a sweep (summary.json).
#[derive(Debug, Serialize)]
pub struct SweepSummary {
    /// Runs.
    pub runs: usize,
    /// The bodies swept.
    pub bodies: Vec<String>,
    /// Generated bodies left out as not convex.
    pub skipped_not_convex: Vec<String>,
    /// Runs that came to rest.
    pub halts: usize,
    /// Runs that closed a cycle.
    pub periodic: usize,
    /// Runs neither at t_max.
    pub undecided: usize,
    /// Runs whose body left the ramp (sweep.csv's `left_model`; in no other count of fates).
    pub left_model: usize,
    /// Runs that cruise: the periodic ones (an undecided run is not counted).
    pub cruising: usize,
    /// Runs whose own integrator's fate the reference corrected (sweep.csv's `answer_check`).
    pub corrected: usize,
    /// RHS evaluations, all runs (the reference's re-decisions included).
    pub rhs_evals: u64,
}

impl Record for ScanRun {
    fn encode(&self, out: &mut Vec<f64>) {
        self.fate.encode(out);
        self.rhs_evals.encode(out);
        self.contact.encode(out);
        match &self.check {
            AnswerCheck::Reference => out.push(0.0),
            AnswerCheck::Confirmed => out.push(1.0),
            AnswerCheck::Corrected { fast } => {
                out.push(2.0);
                fast.encode(out);
            }
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let fate = Settlement::decode(f)?;
        let rhs_evals = u64::decode(f)?;
        let contact = ContactReport::decode(f)?;
        let check = match f.count()? {
            0 => AnswerCheck::Reference,
            1 => AnswerCheck::Confirmed,
            2 => AnswerCheck::Corrected {
                fast: Settlement::decode(f)?,
            },
            v => bail!("{v} is not an answer check (0 reference, 1 confirmed, 2 corrected)"),
        };
        Ok(ScanRun {
            fate,
            check,
            rhs_evals,
            contact,
        })
    }
}

/// Merges a sweep's shards (read from `dir`) into `dir`/sweep.csv and summary.json, one shard
/// file at a time: rows stream out as each shard's records are decoded, so memory is one
/// shard's, not the sweep's.
pub fn merge(dir: &Path, shards: &ShardSet) -> Result<SweepSummary> {
    let JobId::Sweep {
        spec,
        base,
        body_sha256,
    } = shards.job.clone()
    else {
        bail!("{} holds a figure's shards, not a sweep's", dir.display());
    };
    let sweep = Sweep::from_text(&spec, &base).context("the sweep spec stored in the shards")?;
    // The bodies as they are now against the ones the shards ran on, file by file.
    for (k, f) in sweep.spec.bodies.files.iter().enumerate() {
        super::shard::check_body_unchanged(&base.join(f), body_sha256.get(k).map(String::as_str))?;
    }
    if shards.jobs != sweep.runs() {
        bail!(
            "sweep: the shards hold {} runs, but their spec has {}; were they written by another \
             rollphase version?",
            shards.jobs,
            sweep.runs()
        );
    }
    let inputs = sweep.inputs().extend(&Inputs::of(shards.files()));
    output::check_folder(dir, &SWEEP_FILES, &inputs)?;
    // The spec itself is no input of a merge (its text is in the shards), but it may sit in the
    // folder under an output's name: a file there holding exactly the spec's text is it.
    for name in SWEEP_FILES {
        let path = dir.join(name);
        if std::fs::metadata(&path).is_ok_and(|m| m.is_file() && m.len() == spec.len() as u64)
            && std::fs::read_to_string(&path).is_ok_and(|t| t == spec)
        {
            bail!(
                "{} holds the sweep spec these shards ran; merge writes {name} there and would \
                 replace it. Move the spec elsewhere and merge again",
                path.display()
            );
        }
    }
    let mut rows = sweep.rows(dir, &inputs)?;
    shards.for_each_record(|k, record| {
        let r: ScanRun = shards.decode(super::SCAN_NAME, k, record)?;
        rows.push(k, &r)
    })?;
    rows.finish()
}

/// What a sweep did.
pub enum SweepRan {
    /// Ran all of it and wrote sweep.csv and summary.json.
    Whole(SweepSummary),
    /// Ran one shard and wrote its shard file.
    Shard(ShardWritten),
}

/// Runs a sweep: all of it, writing `out`/sweep.csv and summary.json, or one shard, writing
/// `out`/shard-I-of-N.json.
pub fn run(spec: &Path, out: &Path, shard: Option<ShardSpec>) -> Result<SweepRan> {
    let sweep = Sweep::load(spec)?;
    let inputs = sweep.inputs().with(spec);
    // The output folder is checked before the first run, not after the whole sweep.
    match shard {
        Some(s) => {
            output::check_folder(out, &[s.file_name().as_str()], &inputs)?;
            Ok(SweepRan::Shard(sweep.run_shard(s, out, &inputs)?))
        }
        None => {
            output::check_folder(out, &SWEEP_FILES, &inputs)?;
            Ok(SweepRan::Whole(sweep.run_whole(out, &inputs)?))
        }
    }
}

/// The files a whole sweep (or a merge) writes into its folder, committed together.
pub const SWEEP_FILES: [&str; 2] = ["sweep.csv", "summary.json"];
