//! `sphere-cruising` — paper Fig. 3b: the fraction of random initial orientations that cruise
//! (never come to rest) versus α, for the default body in the viscous model, against the 2D
//! step at the same α*.
//!
//! Each orientation (uniform contact point, uniform spin; seeded per index) is followed until it
//! halts (the verdict's rest: still, and the weight's torque gone) or settles on a closed orbit
//! (crossings of ∂Ω repeat to 1e-5); a run still undecided at t = 2000 is counted as neither, so
//! the fraction is the share of starts seen to cruise, and the summary gives the undecided
//! count beside it. In 2D the
//! state space is a loop, so a disk halts for every start below α* and cruises for every start
//! above: the 2D curve is a step. It is computed, not drawn: a convex disk with the sphere's α*
//! (low modes rescaled, see [`convex_disk_with_alpha_star`]) is simulated from as many starts θ₀.
//! In 3D halting loops and cruising orbits coexist below α*, so the fraction rises gradually and
//! reaches 1 at α*, above which no rest point exists.
//!
//! `--shard I/N` splits the 3D and 2D runs (one list, 3D first); `merge` only counts.

use anyhow::Result;
use serde::Serialize;

use super::shard::{Fields, Record};
use super::{Computed, FigureData, FigureOptions};
use crate::analysis::critical_angle;
use crate::analysis::orbits::sphere_orbits::{Settlement, settle};
use crate::analysis::rest::critical_angle::convex_disk_with_alpha_star;
use crate::analysis::studies::disk::disk_cruises;
use crate::analysis::studies::sphere::cruising_settle;
use crate::analysis::studies::sphere::random_orientation;
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::dynamics::Ramp;
use crate::geometry::Body;

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The body: the paper's by default, or `--seed`, or `--shape`.
    pub body: String,
    /// Seed of the sphere. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// α* of the sphere (and of the rescaled disk).
    pub alpha_star: f64,
    /// Orientations per α.
    pub orientations: usize,
    /// α values.
    pub alphas: Vec<f64>,
    /// 3D cruising fraction per α.
    pub fraction_3d: Vec<f64>,
    /// 2D cruising fraction per α.
    pub fraction_2d: Vec<f64>,
    /// Runs neither halted nor periodic within the time limit (classified by their final |ω|).
    pub undecided: usize,
}

/// One run of the ensemble: a sphere's fate, or whether a disk cruised.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Run {
    Sphere(Settlement),
    Disk(bool),
}

impl Record for Run {
    fn encode(&self, out: &mut Vec<f64>) {
        match self {
            Run::Sphere(f) => {
                out.push(0.0);
                f.encode(out);
            }
            Run::Disk(c) => {
                out.push(1.0);
                c.encode(out);
            }
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok(match f.count()? {
            0 => Run::Sphere(Settlement::decode(f)?),
            1 => Run::Disk(bool::decode(f)?),
            v => anyhow::bail!("{v} is not a run kind"),
        })
    }
}

use crate::analysis::studies::sphere::cruises;

/// Runs the figure: computes it, then writes OUT/sphere-cruising/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("sphere-cruising")?;
    super::written(compute(opts)?, &dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<Computed<FigureData<Summary>>> {
    opts.no_alpha("sphere-cruising", "α from 0.4 α* upwards")?;
    let fig = opts.sphere("sphere-cruising")?;
    let (body, seed) = (fig.body.clone(), fig.seed);
    let a_star = critical_angle(&Body::Sphere(body.clone())).alpha_star;
    let (n_or, n_a) = if opts.quick { (40, 8) } else { (300, 30) };
    let alphas: Vec<f64> = (1..=n_a)
        .map(|i| 1.2 * a_star * i as f64 / n_a as f64)
        .collect();
    let jobs: Vec<(usize, usize)> = (0..n_a)
        .flat_map(|a| (0..n_or).map(move |o| (a, o)))
        .collect();
    // The 2D comparison: a disk with the same α*, from as many evenly spaced θ₀.
    let disk = convex_disk_with_alpha_star(opts.seed, a_star)?;
    let settle_opts = cruising_settle();
    // One ensemble: the 3D runs, then the 2D runs (one shardable list).
    let runs = super::all_runs!(opts.ensemble(
        "sphere-cruising",
        2 * jobs.len(),
        "3D and 2D runs",
        |k| -> Result<Run> {
            let (a, o) = jobs[k % jobs.len()];
            if k < jobs.len() {
                let ramp = Ramp::new(alphas[a], 0.0)?;
                let q0 = random_orientation(&body, opts.seed, o);
                Ok(Run::Sphere(settle(&body, &ramp, q0, &settle_opts)?.0))
            } else {
                let theta0 = std::f64::consts::TAU * o as f64 / n_or as f64;
                Ok(Run::Disk(disk_cruises(
                    &disk,
                    &Ramp::new(alphas[a], 0.0)?,
                    theta0,
                )?))
            }
        },
    ));
    let (sphere_runs, disk_runs) = runs.split_at(jobs.len());
    let fates: Vec<&Settlement> = sphere_runs
        .iter()
        .filter_map(|r| match r {
            Run::Sphere(f) => Some(f),
            Run::Disk(_) => None,
        })
        .collect();
    let cruise2: Vec<bool> = disk_runs
        .iter()
        .filter_map(|r| match r {
            Run::Disk(c) => Some(*c),
            Run::Sphere(_) => None,
        })
        .collect();
    if fates.len() != jobs.len() || cruise2.len() != jobs.len() {
        anyhow::bail!("sphere-cruising: the runs came back in the wrong order");
    }
    let undecided = fates
        .iter()
        .filter(|f| matches!(f, Settlement::Undecided { .. }))
        .count();
    let fraction_3d: Vec<f64> = (0..n_a)
        .map(|a| (0..n_or).filter(|&o| cruises(fates[a * n_or + o])).count() as f64 / n_or as f64)
        .collect();
    let fraction_2d: Vec<f64> = (0..n_a)
        .map(|a| (0..n_or).filter(|&o| cruise2[a * n_or + o]).count() as f64 / n_or as f64)
        .collect();
    let rows: Vec<Vec<f64>> = (0..n_a)
        .map(|a| {
            vec![
                alphas[a],
                alphas[a] / a_star,
                fraction_3d[a],
                fraction_2d[a],
            ]
        })
        .collect();
    let csv_header = "alpha,alpha_over_alpha_star,cruising_fraction_3d,cruising_fraction_2d";
    let summary = Summary {
        body: fig.label,
        seed,
        alpha_star: a_star,
        orientations: n_or,
        alphas: alphas.clone(),
        fraction_3d: fraction_3d.clone(),
        fraction_2d: fraction_2d.clone(),
        undecided,
    };
    let panel = Panel {
        title: format!("cruising probability over {n_or} initial orientations (α* = {a_star:.4})"),
        x_label: "α / α*".into(),
        y_label: "fraction of starts that cruise".into(),
        log_x: false,
        log_y: false,
        series: vec![
            Series {
                label: "3D sphere (viscous)".into(),
                points: rows.iter().map(|r| (r[1], r[2])).collect(),
                color: PALETTE[0],
                style: Style::LineMarkers,
            },
            Series {
                label: "2D disk with the same α*".into(),
                points: rows.iter().map(|r| (r[1], r[3])).collect(),
                color: PALETTE[1],
                style: Style::LineMarkers,
            },
        ],
        legend: SeriesLabelPosition::UpperLeft,
        equal_aspect: false,
    };
    Ok(Computed::Figure(FigureData {
        panels: vec![panel],
        columns: 1,
        size: (1000, 650),
        header: csv_header,
        rows,
        summary,
    }))
}
