//! The paper's figures as commands (`rollphase figure NAME`): each module computes one figure's
//! numbers with the core, and writes `data.csv`, `figure.png` and `summary.json` (the headline
//! numbers) to `OUT/NAME/`. Each module's doc says which paper figure it reproduces and how.
//!
//! Ensembles run in parallel with rayon; every member's inputs derive from its index and the
//! seed alone, and results are collected in index order, so the numbers (and files) are the same
//! for any thread count.

pub mod disk_flow;
pub mod disk_hysteresis;
pub mod disk_lag_time;
pub mod disk_transition;
pub mod model_validity;
pub mod shard;
pub mod sphere_bifurcation;
pub mod sphere_cruising;
pub mod sphere_doubling;
pub mod sphere_halting;
pub mod sphere_orbits;
pub mod sphere_poincare;
pub mod sphere_tube;
pub mod sweep;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::Serialize;

use crate::analysis::critical_angle;
use crate::chart::{Panel, png_bytes};
use crate::geometry::{Body, Disk, ShapeFile, Sphere, paper_sphere};
use crate::output::{self, Inputs, OutputSet};
use shard::ShardWritten;

/// The files every figure writes into OUT/NAME, committed together.
pub const FIGURE_FILES: [&str; 3] = ["data.csv", "summary.json", "figure.png"];

/// The paper's body for Figs. 3–4 (the authors' numpy seed 219, σ = 0.25, l ≤ 5), bundled as
/// `assets/shapes/paper-sphere.json`.
pub const PAPER_SPHERE_SEED: u32 = 219;

/// The paper's α for Figs. 3d and 4e.
pub const PAPER_ALPHA: f64 = 0.15;

/// Where a figure's body comes from.
#[derive(Debug, Clone, Default, PartialEq, Serialize, serde::Deserialize)]
#[serde(tag = "kind", content = "path", rename_all = "lowercase")]
pub enum BodyChoice {
    /// The figure's default: the paper's own body for the figures of paper Figs. 3–4, a seeded
    /// random body (`seed`) for the others.
    #[default]
    FigureDefault,
    /// A random body from `seed` (the command line's `--seed`).
    Seeded,
    /// A shape file (`--shape`).
    File(PathBuf),
}

/// Options shared by every figure.
#[derive(Debug, Clone, Default)]
pub struct FigureOptions {
    /// Output folder; files go to OUT/NAME/.
    pub out: PathBuf,
    /// Seed of the random bodies and orientations.
    pub seed: u64,
    /// A reduced run for tests (each under ~20 s).
    pub quick: bool,
    /// The body.
    pub body: BodyChoice,
    /// The ramp angle, for the figures that use one α (`--alpha`).
    pub alpha: Option<f64>,
    /// The whole ensemble here, one shard of it, or its shards merged (`--shard`, `merge`).
    pub ensemble: shard::Ensemble,
}

/// A figure's 3D body and how to name it in its summary.
#[derive(Debug, Clone)]
pub struct FigureSphere {
    /// The body.
    pub body: Sphere,
    /// Where it came from, e.g. "paper (numpy seed 219, σ = 0.25, l ≤ 5)".
    pub label: String,
    /// The seed it was generated from (the numpy seed for the paper's body; none for a file,
    /// written as null).
    pub seed: Option<u64>,
    /// Whether it is the paper's Figs. 3–4 body.
    pub is_paper: bool,
}

impl FigureOptions {
    /// OUT/NAME, checked before the figure's work (see [`crate::output::check_folder`]): it
    /// can hold [`FIGURE_FILES`], none of which is the body file. Created by
    /// [`FigureData::write_to`] once the figure is computed.
    pub fn dir(&self, name: &str) -> Result<PathBuf> {
        let d = self.out.join(name);
        output::check_folder(&d, &FIGURE_FILES, &self.inputs())?;
        Ok(d)
    }

    /// The files this figure reads (the `--shape` file, if any).
    pub fn inputs(&self) -> Inputs {
        match &self.body {
            BodyChoice::File(p) => Inputs::of([p]),
            _ => Inputs::none(),
        }
    }

    /// The 3D body of a figure of paper Figs. 3–4: the paper's own by default.
    pub fn sphere(&self, figure: &str) -> Result<FigureSphere> {
        match &self.body {
            BodyChoice::FigureDefault => Ok(FigureSphere {
                body: paper_sphere(PAPER_SPHERE_SEED, 0.25, 5)?,
                label: format!("paper (numpy seed {PAPER_SPHERE_SEED}, σ = 0.25, l ≤ 5)"),
                seed: Some(PAPER_SPHERE_SEED as u64),
                is_paper: true,
            }),
            BodyChoice::Seeded => {
                let (body, used) = convex_sphere(self.seed)?;
                Ok(FigureSphere {
                    body,
                    label: format!("seed {used} (σ = 0.25, l ≤ 5)"),
                    seed: Some(used),
                    is_paper: false,
                })
            }
            BodyChoice::File(path) => match load_convex(path)? {
                Body::Sphere(body) => Ok(FigureSphere {
                    body,
                    label: format!("file {}", path.display()),
                    seed: None,
                    is_paper: false,
                }),
                Body::Disk(_) => bail!(
                    "{figure} needs a 3D body, but --shape {} is a 2D disk",
                    path.display()
                ),
            },
        }
    }

    /// The 2D body of a disk figure: the first convex random disk at or after `seed` (σ, M), or
    /// the `--shape` file. Returns the disk and the seed used (none for a file).
    pub fn disk(
        &self,
        figure: &str,
        seed: u64,
        sigma: f64,
        modes: u32,
    ) -> Result<(Disk, Option<u64>)> {
        match &self.body {
            BodyChoice::File(path) => match load_convex(path)? {
                Body::Disk(d) => Ok((d, None)),
                Body::Sphere(_) => bail!(
                    "{figure} needs a 2D body, but --shape {} is a 3D sphere",
                    path.display()
                ),
            },
            _ => convex_disk(seed, sigma, modes).map(|(d, used)| (d, Some(used))),
        }
    }

    /// The figure's one ramp angle: `--alpha`, else `default`, in (0, π/2). Below a 3D
    /// body's α* it is allowed: α* is where *every* orientation rolls, and below it rolling
    /// orbits still exist beside the halting ones (sphere-cruising finds 97 % cruising at
    /// 0.84 α* on the paper's body); each figure reports the runs that halt, and refuses only
    /// when none rolls.
    pub fn single_alpha(&self, figure: &str, default: f64) -> Result<f64> {
        let alpha = self.alpha.unwrap_or(default);
        if !(crate::dynamics::MIN_ALPHA..std::f64::consts::FRAC_PI_2).contains(&alpha) {
            bail!(
                "{figure}: --alpha {} is not allowed (needs 1e-9 ≤ α < π/2 rad)",
                crate::integrate::readable(alpha)
            );
        }
        Ok(alpha)
    }

    /// Refuses `--alpha` for a figure that sweeps α itself.
    pub fn no_alpha(&self, figure: &str, sweeps: &str) -> Result<()> {
        if let Some(a) = self.alpha {
            bail!("{figure} sweeps {sweeps} itself; --alpha {a} does not apply to it");
        }
        Ok(())
    }

    /// Refuses `--shape` for a figure that has no generated body.
    pub fn no_shape(&self, figure: &str, why: &str) -> Result<()> {
        if let BodyChoice::File(p) = &self.body {
            bail!(
                "{figure} {why}; --shape {} does not apply to it",
                p.display()
            );
        }
        Ok(())
    }
}

/// Decodes merged shards as the records of `name` (a sharded figure of [`FIGURES`], or
/// `sweep`, the scan): each record range-checked as it is decoded ([`shard::Record`]); the
/// count: exactly what a merge does before its reduction, so the checks a forged or damaged
/// shard meets (the shard-file fuzz target and tests use it). The type comes from the figure's
/// entry, so the list of figures is written once.
pub fn decode_merged(name: &str, merged: shard::Merged) -> Result<usize> {
    let decode = if name == SCAN_NAME {
        decode_as::<crate::analysis::studies::sweep::ScanRun>
    } else {
        match figure(name) {
            Some(FigureEntry {
                records: Some(decode),
                ..
            }) => *decode,
            _ => bail!("{name} has no shard records"),
        }
    };
    decode(name, merged)
}

/// How a figure's merged shards decode ([`decode_as`] at its record type).
pub type DecodeRecords = fn(&str, shard::Merged) -> Result<usize>;

/// The shard name of `rollphase sweep` (the scan), whose records [`decode_merged`] also reads.
pub const SCAN_NAME: &str = "sweep";

/// Decodes merged shards as records of type `R`: the count.
fn decode_as<R: shard::Record + Send>(name: &str, merged: shard::Merged) -> Result<usize> {
    use shard::{Ensemble, run_ensemble};
    let n = merged.records.len();
    let ensemble = Ensemble::Merge(std::sync::Arc::new(merged));
    let place = || -> Result<(PathBuf, shard::JobId, Inputs)> {
        bail!("internal error: a merge writes no shard")
    };
    let never = |_: usize| -> Result<R> { bail!("internal error: a merge runs nothing") };
    Ok(run_ensemble::<R, _>(&ensemble, name, n, "", place, never)?
        .all()?
        .len())
}

/// Below this α* a body is a perfect sphere (or a disk) to double precision.
pub const PERFECT_ALPHA_STAR: f64 = 1e-9;

/// Refuses a perfect sphere (α* = 0) for a figure about what irregularity does, saying why it
/// does not apply.
pub fn refuse_perfect_sphere(figure: &str, alpha_star: f64, why: &str) -> Result<()> {
    if alpha_star < PERFECT_ALPHA_STAR {
        bail!(
            "{figure} does not apply to a perfect sphere (α* = {alpha_star:.1e}): {why}; \
             sphere-tube shows its orbits in closed form"
        );
    }
    Ok(())
}

/// α* of a 3D body.
pub fn sphere_alpha_star(body: &Sphere) -> f64 {
    critical_angle(&Body::Sphere(body.clone())).alpha_star
}

fn load_convex(path: &Path) -> Result<Body> {
    let body = ShapeFile::load(path)?;
    if let Body::Disk(d) = &body
        && let Some(p) = d.printed_section()
    {
        bail!(
            "--shape {} was fitted to a print and rolls on its {} flat sides; the figures sweep \
             angles around a smooth body's α* and need one (`period`, `predict` and `simulate` \
             roll the print). Refit the mesh with `--ignore-facets` if its facets are only the \
             export's tessellation of a round body",
            path.display(),
            p.vertices.len()
        );
    }
    body.check_convex()
        .with_context(|| format!("--shape {}", path.display()))?;
    Ok(body)
}

/// One figure: its name on the command line, what it shows, and how to run it.
pub struct FigureEntry {
    /// `rollphase figure NAME`.
    pub name: &'static str,
    /// One line for `figure --list`.
    pub about: &'static str,
    /// Computes and writes the figure (its summary), or writes one shard of its ensemble.
    pub run: fn(&FigureOptions) -> Result<Ran>,
    /// For a figure whose runs go through [`FigureOptions::ensemble`] (so that `--shard`
    /// splits them and `merge` puts them back): how its merged records decode, at the type
    /// its runs return. `None`: not sharded.
    pub records: Option<DecodeRecords>,
}

impl FigureEntry {
    /// Whether `--shard` splits its runs.
    pub fn sharded(&self) -> bool {
        self.records.is_some()
    }
}

/// The names of the figures whose runs `--shard` splits, in [`FIGURES`] order.
pub fn sharded_figures() -> Vec<&'static str> {
    FIGURES
        .iter()
        .filter(|f| f.sharded())
        .map(|f| f.name)
        .collect()
}

/// A figure's computation: the figure's data, or, for a `--shard I/N` run, the shard file its
/// ensemble wrote instead (a normal outcome: the figure stops there, with no plot).
pub enum Computed<T> {
    /// The figure's rows, summary and chart.
    Figure(T),
    /// One shard of its runs, written.
    Shard(ShardWritten),
}

/// What running a figure did.
pub enum Ran {
    /// Wrote data.csv, summary.json and figure.png; the summary.
    Figure(serde_json::Value),
    /// Wrote one shard of its runs.
    Shard(ShardWritten),
}

/// The figure `name` for [`FIGURES`]: checks its folder, computes, and writes the figure (or
/// hands back the shard written).
fn ran<S: Serialize>(
    opts: &FigureOptions,
    name: &str,
    compute: impl FnOnce(&FigureOptions) -> Result<Computed<FigureData<S>>>,
) -> Result<Ran> {
    let dir = opts.dir(name)?;
    Ok(match compute(opts)? {
        Computed::Figure(data) => Ran::Figure(serde_json::to_value(data.write_to(&dir, opts)?)?),
        Computed::Shard(w) => Ran::Shard(w),
    })
}

/// A figure module's `run`: the whole figure, written, and its summary. A `--shard` run has
/// no figure to give back; it goes through [`FIGURES`], which reports the shard.
pub fn written<S: Serialize>(
    computed: Computed<FigureData<S>>,
    dir: &Path,
    opts: &FigureOptions,
) -> Result<S> {
    match computed {
        Computed::Figure(data) => data.write_to(dir, opts),
        Computed::Shard(w) => bail!(
            "{w}: this entry point writes a whole figure; run a shard through figures::FIGURES"
        ),
    }
}

/// The results of an ensemble, or, from a `--shard` run, a return from the figure's `compute`
/// with the shard it wrote.
macro_rules! all_runs {
    ($ensemble:expr) => {
        match $ensemble? {
            $crate::figures::shard::Ensembled::All(results) => results,
            $crate::figures::shard::Ensembled::Shard(written) => {
                return Ok($crate::figures::Computed::Shard(written));
            }
        }
    };
}
pub(crate) use all_runs;

/// Every figure `rollphase figure` knows: the one list behind `--list`, the dispatch and the
/// benchmarks.
pub const FIGURES: &[FigureEntry] = &[
    FigureEntry {
        name: "disk-transition",
        records: Some(
            decode_as::<(
                disk_transition::DiskTransition,
                Vec<Vec<f64>>,
                Vec<Vec<f64>>,
            )>,
        ),
        about: "Fig. 2d: 2π/T versus α for random disks; the √(α − α*) law and its prefactor",
        run: |o| ran(o, "disk-transition", disk_transition::compute),
    },
    FigureEntry {
        name: "disk-hysteresis",
        records: None,
        about: "Fig. 2e: inertial disk (m/m0 = 10), α swept up and down: α*, α** and hysteresis",
        run: |o| {
            ran(o, "disk-hysteresis", |o| {
                disk_hysteresis::compute(o).map(Computed::Figure)
            })
        },
    },
    FigureEntry {
        name: "disk-lag-time",
        records: None,
        about: "Fig. 2f: lag time versus α − α* for m/m0 = 0.5, 2, 10; exponent −1/2",
        run: |o| {
            ran(o, "disk-lag-time", |o| {
                disk_lag_time::compute(o).map(Computed::Figure)
            })
        },
    },
    FigureEntry {
        name: "disk-flow",
        records: None,
        about: "SI Fig. S2: the (θ, θ̇) flow at six α around α*, fixed points and a trajectory",
        run: |o| {
            ran(o, "disk-flow", |o| {
                disk_flow::compute(o).map(Computed::Figure)
            })
        },
    },
    FigureEntry {
        name: "sphere-cruising",
        records: Some(decode_as::<sphere_cruising::Run>),
        about: "Fig. 3b: fraction of orientations that cruise versus α/α*, 3D against 2D",
        run: |o| ran(o, "sphere-cruising", sphere_cruising::compute),
    },
    FigureEntry {
        name: "sphere-orbits",
        records: Some(decode_as::<crate::analysis::orbits::sphere_orbits::Settlement>),
        about: "Fig. 3c: 1/T versus α for 6 orientations; all collapse onto two closed orbits",
        run: |o| ran(o, "sphere-orbits", sphere_orbits::compute),
    },
    FigureEntry {
        name: "sphere-poincare",
        records: Some(decode_as::<Option<(glam::DVec3, f64)>>),
        about: "Fig. 3d: the Poincaré map on ∂Ω of the SO(3) ball at α = 0.15; two attractor pairs",
        run: |o| ran(o, "sphere-poincare", sphere_poincare::compute),
    },
    FigureEntry {
        name: "sphere-doubling",
        records: Some(decode_as::<sphere_doubling::Run>),
        about: "Fig. 4e: contact paths at m/m0 = 0, 6, 10 (α = 0.15); period 1, 2, 1; other bodies",
        run: |o| ran(o, "sphere-doubling", sphere_doubling::compute),
    },
    FigureEntry {
        name: "sphere-bifurcation",
        records: Some(decode_as::<crate::analysis::orbits::orbit_diagram::LateRun>),
        about: "beyond Fig. 4e: orbit diagram in m/m0, Floquet multipliers, the flip masses",
        run: |o| ran(o, "sphere-bifurcation", sphere_bifurcation::compute),
    },
    FigureEntry {
        name: "model-validity",
        records: Some(decode_as::<crate::dynamics::validity::ContactReport>),
        about: "where the model holds: lift-off and slip (μ = 0.5, 1) over α × m/m0, experiments marked",
        run: |o| ran(o, "model-validity", model_validity::compute),
    },
    FigureEntry {
        name: "sphere-halting",
        records: None,
        about: "SI §2D–E: the halting loops Q = tan α and their stability, checked by simulation",
        run: |o| {
            ran(o, "sphere-halting", |o| {
                sphere_halting::compute(o).map(Computed::Figure)
            })
        },
    },
    FigureEntry {
        name: "sphere-tube",
        records: None,
        about: "SI Fig. S3: perfect-sphere orbits through one contact point (closed form)",
        run: |o| {
            ran(o, "sphere-tube", |o| {
                sphere_tube::compute(o).map(Computed::Figure)
            })
        },
    },
];

/// The figure called `name`.
pub fn figure(name: &str) -> Option<&'static FigureEntry> {
    FIGURES.iter().find(|f| f.name == name)
}

/// What a figure computed, before anything is written: its data rows (data.csv), its headline
/// numbers (summary.json) and its chart (figure.png). Each figure's `compute` returns one and
/// writes nothing; its `run` creates the folder and calls [`FigureData::write_to`].
pub struct FigureData<S> {
    /// The chart's panels.
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// Chart size in pixels.
    pub size: (u32, u32),
    /// data.csv's header, "a,b,c".
    pub header: &'static str,
    /// data.csv's rows (non-finite values become empty fields).
    pub rows: Vec<Vec<f64>>,
    /// The headline numbers.
    pub summary: S,
}

impl<S: Serialize> FigureData<S> {
    /// Writes `dir`/data.csv, summary.json and figure.png for the figure run with `opts` (see
    /// [`Self::write_files`]); summary.json ends with the options used.
    pub fn write_to(self, dir: &Path, opts: &FigureOptions) -> Result<S> {
        self.write_files(dir, &opts.inputs(), &opts.record())
    }

    /// Writes `dir`/data.csv, summary.json and figure.png as one set (all three new, or the
    /// old three left whole), and hands back the summary. `inputs` are the figure's input
    /// files, which it refuses to overwrite; `options` go into summary.json as "options".
    pub fn write_files(self, dir: &Path, inputs: &Inputs, options: &impl Serialize) -> Result<S> {
        let csv = rows_csv(self.header, &self.rows)?;
        let summary = summary_text(&WithOptions {
            summary: &self.summary,
            options,
        })?;
        let png = png_bytes(&self.panels, self.columns, self.size)?;
        output::create_folder(dir)?;
        let mut set = OutputSet::new();
        for (name, bytes) in FIGURE_FILES
            .iter()
            .zip([csv.as_bytes(), summary.as_bytes(), &png])
        {
            set.write(&dir.join(name), bytes, inputs)?;
        }
        set.commit()?;
        Ok(self.summary)
    }
}

/// A number as a CSV field: Rust's shortest round-trip form; empty when not finite.
pub fn number_field(v: f64) -> String {
    if v.is_finite() {
        v.to_string()
    } else {
        String::new()
    }
}

/// CSV text (the `csv` crate: fields with commas or quotes are quoted) from a header written as
/// "a,b,c" and records of fields.
pub fn csv_text<R, F>(header: &str, records: R) -> Result<String>
where
    R: IntoIterator<Item = Vec<F>>,
    F: AsRef<[u8]>,
{
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header.split(','))?;
    for r in records {
        w.write_record(r)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("CSV: {}", e.error()))?;
    Ok(String::from_utf8(bytes)?)
}

/// A summary followed by the options that produced it.
#[derive(Serialize)]
struct WithOptions<'a, S, O> {
    #[serde(flatten)]
    summary: &'a S,
    options: &'a O,
}

/// What a figure was run with, as its summary.json records it.
#[derive(Debug, Serialize)]
pub struct RunRecord {
    /// `--seed`: the random orientations' seed, and a random body's when `body` is "seeded".
    pub seed: u64,
    /// "figure default", "seeded" (`--seed` gave the body too) or "file".
    pub body: &'static str,
    /// The shape file, when `body` is "file".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<PathBuf>,
    /// `--alpha`, when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// `--quick`.
    pub quick: bool,
}

impl FigureOptions {
    /// The options as summary.json records them.
    pub fn record(&self) -> RunRecord {
        let (body, shape) = match &self.body {
            BodyChoice::FigureDefault => ("figure default", None),
            BodyChoice::Seeded => ("seeded", None),
            BodyChoice::File(p) => ("file", Some(p.clone())),
        };
        RunRecord {
            seed: self.seed,
            body,
            shape,
            alpha: self.alpha,
            quick: self.quick,
        }
    }
}

/// Rows of numbers as CSV text; non-finite values become empty fields.
pub fn rows_csv(header: &str, rows: &[Vec<f64>]) -> Result<String> {
    csv_text(
        header,
        rows.iter()
            .map(|r| r.iter().map(|&v| number_field(v)).collect::<Vec<_>>()),
    )
}

/// A summary as pretty JSON text, as every summary.json holds it.
pub fn summary_text(summary: &impl Serialize) -> Result<String> {
    Ok(serde_json::to_string_pretty(summary)? + "\n")
}

/// A progress bar on standard error (hidden when it is not a terminal).
pub fn progress(len: usize, what: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg:>18} {bar:40} {pos}/{len} {elapsed}/{eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_message(what.to_string());
    bar
}

/// `f(i)` for i in 0..n in parallel, results in index order (thread-count independent).
pub fn par_map<T: Send>(
    n: usize,
    bar: &indicatif::ProgressBar,
    f: impl Fn(usize) -> T + Sync + Send,
) -> Vec<T> {
    // One task per index: ensemble members differ in cost by orders of magnitude (a run that
    // halts at once beside one followed to t_max), and rayon's default splitting hands whole
    // contiguous blocks of the slow ones to one thread. Each member costs ≥ 0.1 ms, so the
    // per-task overhead (~1 µs) does not show.
    let out = (0..n)
        .into_par_iter()
        .with_max_len(1)
        .map(|i| {
            let r = f(i);
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    out
}

/// The first strictly convex random disk at seed, seed + 1, …: (disk, seed used).
pub fn convex_disk(seed: u64, sigma: f64, modes: u32) -> Result<(Disk, u64)> {
    Ok(crate::geometry::first_convex_disk(seed, sigma, modes)?)
}

/// The first strictly convex random sphere (σ = 0.25, l ≤ 5) at seed, seed + 1, …
pub fn convex_sphere(seed: u64) -> Result<(Sphere, u64)> {
    Ok(crate::geometry::first_convex_sphere(seed, 0.25, 5)?)
}
