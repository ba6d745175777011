//! `disk-transition` — paper Fig. 2d and SI §1B: the second-order halting–cruising transition of
//! viscous disks.
//!
//! For random disks (σ = 0.08, M = 10) and the perfect disk, 2π/T is computed by quadrature of
//! T = ∫dθ/θ̇ over α. Near α*, T = T*·δα^(−β) + C + O(√δα) with a regular part C that biases a
//! plain log–log fit of 2π/T (it gives β ≈ 0.49 on δα = 1e-8…1e-5, also reported). The exponent
//! is therefore fitted on differences T(δα) − T(2δα) = T*(1 − 2^(−β)) δα^(−β), which cancel C
//! (expect β = 1/2), and the prefactor T* is measured from T(1e-8) − T(1e-6) and compared with
//! the analytic value.
//!
//! **The SI's T* is low by √2.** Expanding Q(θ* + δθ) = Q* + ½Q''δθ² (the SI drops the ½) gives
//! T* = √2 · G(θ*) π / √(−Q''(θ*)), G = (r² + r'²)κ/r², γ = F = 1. The measured prefactors agree
//! with this to ~1e-5; the printed SI formula is smaller by exactly √2.
//!
//! `--shard I/N` splits the disks; `merge` adds the perfect disk's closed form.

use anyhow::Result;
use serde::Serialize;

use super::shard::{Fields, Record};
use super::{Computed, FigureData, FigureOptions};
use crate::analysis::fit::logspace;
use crate::analysis::studies::disk::saddle_node_law;
use crate::analysis::viscous_disk_period;
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::colormap::viridis;
use crate::dynamics::Ramp;
use crate::geometry::Disk;

/// Per-disk results.
#[derive(Debug, Clone, Serialize)]
pub struct DiskTransition {
    /// Seed the disk was generated with. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// α* (rad).
    pub alpha_star: f64,
    /// Fitted exponent β of T − C ∝ (α − α*)^(−β), from differences (expect 1/2).
    pub exponent: f64,
    /// Its standard error.
    pub exponent_stderr: f64,
    /// Plain log–log slope of 2π/T on δα = 1e-8…1e-5, biased by the regular part C.
    pub exponent_naive: f64,
    /// Measured T* (difference method).
    pub t_star_measured: f64,
    /// T* = √2 G π/√(−Q'') (expansion with the ½).
    pub t_star_analytic: f64,
    /// T* as printed in the SI (without the ½).
    pub t_star_si_printed: f64,
}

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Number of random disks.
    pub disks: usize,
    /// Mean fitted exponent (expect 0.5).
    pub exponent_mean: f64,
    /// Largest |β − ½| over the disks.
    pub exponent_max_deviation: f64,
    /// Mean plain log–log exponent (biased low by the regular part of T).
    pub exponent_naive_mean: f64,
    /// Mean of T*_measured / T*_analytic (expect 1).
    pub t_star_ratio_analytic: f64,
    /// Mean of T*_measured / T*_SI-printed (√2 = 1.414 if the SI drops the ½).
    pub t_star_ratio_si_printed: f64,
    /// Perfect disk: max |2π/T − sin α| over the α grid.
    pub perfect_disk_max_error: f64,
    /// Per disk.
    pub per_disk: Vec<DiskTransition>,
}

impl Record for DiskTransition {
    fn encode(&self, out: &mut Vec<f64>) {
        self.seed.encode(out);
        out.extend([
            self.alpha_star,
            self.exponent,
            self.exponent_stderr,
            self.exponent_naive,
            self.t_star_measured,
            self.t_star_analytic,
            self.t_star_si_printed,
        ]);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok(DiskTransition {
            seed: Option::<u64>::decode(f)?,
            alpha_star: f.number()?,
            exponent: f.number()?,
            exponent_stderr: f.number()?,
            exponent_naive: f.number()?,
            t_star_measured: f.number()?,
            t_star_analytic: f.number()?,
            t_star_si_printed: f.number()?,
        })
    }
}

/// One disk's headline numbers, its rows on the α grid and its curve near α*.
type PerDisk = (DiskTransition, Vec<Vec<f64>>, Vec<Vec<f64>>);

/// One disk of the ensemble: disk `i`'s [`saddle_node_law`] as the figure's record and rows.
fn one_disk(opts: &FigureOptions, i: usize, alphas: &[f64]) -> Result<PerDisk> {
    let (d, used) = opts.disk("disk-transition", opts.seed + 1000 * i as u64, 0.08, 10)?;
    let law = saddle_node_law(&d, alphas).map_err(|e| anyhow::anyhow!("disk {i}: {e}"))?;
    let rows = law
        .speeds
        .iter()
        .map(|&(a, speed)| vec![i as f64, law.alpha_star, a, speed])
        .collect();
    let near_curve = law
        .near
        .iter()
        .map(|&(da, speed)| vec![i as f64, da, speed])
        .collect();
    Ok((
        DiskTransition {
            seed: used,
            alpha_star: law.alpha_star,
            exponent: law.exponent,
            exponent_stderr: law.exponent_stderr,
            exponent_naive: law.exponent_naive,
            t_star_measured: law.t_star_measured,
            t_star_analytic: law.t_star_analytic,
            t_star_si_printed: law.t_star_analytic / 2f64.sqrt(),
        },
        rows,
        near_curve,
    ))
}

/// Panel 1: 2π/T versus α, coloured by α*; panel 2: log-log near α*.
fn panels(
    per_disk: &[DiskTransition],
    rows: &[Vec<f64>],
    near_rows: &[Vec<f64>],
    perfect: Vec<(f64, f64)>,
    exponent_mean: f64,
) -> Vec<Panel> {
    // Panel 1: 2π/T versus α, coloured by α*; panel 2: log-log near α*.
    // The colour scale spans the α* drawn, smallest (dark) to largest (yellow).
    let a_max = per_disk
        .iter()
        .map(|t| t.alpha_star)
        .fold(0.0, f64::max)
        .max(1e-9);
    let a_min = per_disk
        .iter()
        .map(|t| t.alpha_star)
        .fold(f64::INFINITY, f64::min)
        .min(a_max);
    let shade = |star: f64| viridis(((star - a_min) / (a_max - a_min).max(1e-12)).clamp(0.0, 1.0));
    // The colour carries α*: the legend names the two ends of the scale (the smallest and the
    // largest α* drawn), so the colours can be read.
    let by_star = |pick: fn(f64, f64) -> bool| {
        (0..per_disk.len()).reduce(|a, b| {
            if pick(per_disk[b].alpha_star, per_disk[a].alpha_star) {
                b
            } else {
                a
            }
        })
    };
    let (lowest, highest) = (by_star(|x, y| x < y), by_star(|x, y| x > y));
    let mut curves: Vec<Series> = per_disk
        .iter()
        .enumerate()
        .map(|(i, t)| Series {
            label: if Some(i) == lowest || Some(i) == highest {
                format!("α* = {:.4}", t.alpha_star)
            } else {
                String::new()
            },
            points: rows
                .iter()
                .filter(|r| r[0] == i as f64)
                .map(|r| (r[2], r[3]))
                .collect(),
            color: shade(t.alpha_star),
            style: Style::Line,
        })
        .collect();
    curves.push(Series {
        label: "perfect disk, sin α".into(),
        points: perfect,
        color: (0, 0, 0),
        style: Style::Line,
    });
    let mut near: Vec<Series> = Vec::new();
    for (i, t) in per_disk.iter().enumerate() {
        let pts: Vec<(f64, f64)> = near_rows
            .iter()
            .filter(|r| r[0] == i as f64)
            .map(|r| (r[1], r[2]))
            .collect();
        near.push(Series {
            label: if i == 0 {
                "random disks".into()
            } else {
                String::new()
            },
            points: pts,
            color: shade(t.alpha_star),
            style: Style::Line,
        });
    }
    let guide: Vec<(f64, f64)> = logspace(1e-8, 1e-2, 2)
        .into_iter()
        .map(|x| (x, 1.0 * x.sqrt()))
        .collect();
    near.push(Series {
        label: "slope 1/2".into(),
        points: guide,
        color: PALETTE[1],
        style: Style::Line,
    });
    vec![
        Panel {
            title: "order parameter 2π/T (viscous disks, coloured by α*: dark low, yellow high)"
                .into(),
            x_label: "ramp angle α (rad)".into(),
            y_label: "mean angular speed 2π/T (1/t0)".into(),
            log_x: false,
            log_y: false,
            series: curves,
            legend: SeriesLabelPosition::UpperLeft,
            equal_aspect: false,
        },
        Panel {
            title: format!("near α*: fitted exponent {:.4} (expect 0.5)", exponent_mean),
            x_label: "α − α* (rad)".into(),
            y_label: "2π/T (1/t0)".into(),
            log_x: true,
            log_y: true,
            series: near,
            legend: SeriesLabelPosition::UpperLeft,
            equal_aspect: false,
        },
    ]
}

/// Runs the figure: computes it, then writes OUT/disk-transition/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("disk-transition")?;
    super::written(compute(opts)?, &dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<Computed<FigureData<Summary>>> {
    opts.no_alpha("disk-transition", "α over [0.005, 0.4]")?;
    // With --shape the ensemble is that one disk.
    let n = if matches!(opts.body, super::BodyChoice::File(_)) {
        1
    } else if opts.quick {
        6
    } else {
        24
    };
    let alphas: Vec<f64> = (1..=80).map(|i| 0.4 * i as f64 / 80.0).collect();
    // Each disk i uses the first convex seed at or after seed + 1000·i: independent of threads.
    let results = super::all_runs!(opts.ensemble("disk-transition", n, "disks", |i| one_disk(
        opts, i, &alphas
    )));
    let mut per_disk = Vec::new();
    let mut rows = Vec::new();
    let mut near_rows = Vec::new();
    for (t, mut rs, mut nr) in results {
        per_disk.push(t);
        rows.append(&mut rs);
        near_rows.append(&mut nr);
    }
    let perfect: Vec<(f64, f64)> = alphas
        .iter()
        .map(|&a| {
            Ok((
                a,
                viscous_disk_period(&Disk::perfect(), &Ramp::new(a, 0.0)?).mean_angular_speed,
            ))
        })
        .collect::<Result<_>>()?;
    for (a, w) in &perfect {
        rows.push(vec![-1.0, 0.0, *a, *w]);
    }
    let csv_header = "disk,alpha_star,alpha,mean_angular_speed";

    let mean = |f: &dyn Fn(&DiskTransition) -> f64| {
        per_disk.iter().map(f).sum::<f64>() / per_disk.len() as f64
    };
    let summary = Summary {
        disks: n,
        exponent_mean: mean(&|t| t.exponent),
        exponent_max_deviation: per_disk
            .iter()
            .map(|t| (t.exponent - 0.5).abs())
            .fold(0.0, f64::max),
        exponent_naive_mean: mean(&|t| t.exponent_naive),
        t_star_ratio_analytic: mean(&|t| t.t_star_measured / t.t_star_analytic),
        t_star_ratio_si_printed: mean(&|t| t.t_star_measured / t.t_star_si_printed),
        perfect_disk_max_error: perfect
            .iter()
            .map(|(a, w)| (w - a.sin()).abs())
            .fold(0.0, f64::max),
        per_disk: per_disk.clone(),
    };

    let panels = panels(&per_disk, &rows, &near_rows, perfect, summary.exponent_mean);
    Ok(Computed::Figure(FigureData {
        panels,
        columns: 2,
        size: (1500, 620),
        header: csv_header,
        rows,
        summary,
    }))
}
