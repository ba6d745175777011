//! `disk-lag-time` — paper Fig. 2f: the lag time t_lag versus α − α* for m/m0 ∈ {0.5, 2, 10} (and
//! the viscous limit), on one inertial disk (σ = 0.12, M = 5).
//!
//! t_lag: released from rest at the bottleneck θ* at α = α* + δα, the time until θ − θ* = π
//! ([`crate::analysis::studies::disk::lag_time`]; the law by
//! [`crate::analysis::studies::disk::lag_time_law`]). As for the period, t_lag = A δα^(−β) + C, so
//! β is fitted on differences t(δα) − t(2δα) over δα = 1e-7…1e-5 (expect β = 1/2 for every mass:
//! the time is spent at the saddle-node ghost, where inertia does not matter). Inertia adds
//! corrections of relative size ≈ (1.5 m)·√δα, so the heaviest disk needs δα ≲ 1e-5 to show it:
//! on the default disk m/m0 = 10 gives β = 0.4904 fitted on δα ≤ 1e-4 and 0.4959 on δα ≤ 1e-5,
//! while m/m0 = 0, 0.5, 2 give 0.4997, 0.4995, 0.4989.

use anyhow::Result;
use serde::Serialize;

use super::{FigureData, FigureOptions, progress};
use crate::analysis::critical_angle;
use crate::analysis::fit::logspace;
use crate::analysis::studies::disk::lag_time_law;
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::geometry::Body;

/// Per-mass fit.
#[derive(Debug, Clone, Serialize)]
pub struct MassFit {
    /// m/m0 (0: viscous).
    pub mass_ratio: f64,
    /// Fitted β of t_lag − C ∝ δα^(−β) (expect 0.5).
    pub exponent: f64,
    /// Its standard error.
    pub exponent_stderr: f64,
}

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Seed of the disk. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// Its α*.
    pub alpha_star: f64,
    /// Mean exponent over the masses (expect 0.5).
    pub exponent_mean: f64,
    /// Largest |β − ½|.
    pub exponent_max_deviation: f64,
    /// Per mass.
    pub fits: Vec<MassFit>,
}

/// Runs the figure: computes it, then writes OUT/disk-lag-time/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("disk-lag-time")?;
    compute(opts)?.write_to(&dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<FigureData<Summary>> {
    opts.no_alpha("disk-lag-time", "α above α*")?;
    let (disk, seed) = opts.disk("disk-lag-time", opts.seed, 0.12, 5)?;
    let ca = critical_angle(&Body::Disk(disk.clone()));
    let masses = [0.0, 0.5, 2.0, 10.0];
    let deltas = logspace(
        1e-8,
        if opts.quick { 1e-5 } else { 1e-2 },
        if opts.quick { 4 } else { 19 },
    );
    let bar = progress(2 * masses.len() * deltas.len(), "lag times");
    let laws = lag_time_law(&disk, &masses, &deltas, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let mut rows = Vec::new();
    let mut fits = Vec::new();
    let mut curves = Vec::new();
    for (mi, law) in laws.iter().enumerate() {
        let m = law.mass_ratio;
        rows.extend(law.lag_times.iter().map(|&(d, t)| vec![m, d, t]));
        fits.push(MassFit {
            mass_ratio: m,
            exponent: law.exponent,
            exponent_stderr: law.exponent_stderr,
        });
        curves.push(Series {
            label: if m == 0.0 {
                "viscous".into()
            } else {
                format!("m/m0 = {m}")
            },
            points: law.lag_times.clone(),
            color: PALETTE[mi],
            style: Style::LineMarkers,
        });
    }
    let csv_header = "mass_ratio,delta_alpha,t_lag";
    let summary = Summary {
        seed,
        alpha_star: ca.alpha_star,
        exponent_mean: fits.iter().map(|f| f.exponent).sum::<f64>() / fits.len() as f64,
        exponent_max_deviation: fits
            .iter()
            .map(|f| (f.exponent - 0.5).abs())
            .fold(0.0, f64::max),
        fits,
    };
    let t0 = curves[0].points[0].1;
    curves.push(Series {
        label: "slope −1/2".into(),
        points: vec![
            (deltas[0], t0),
            (
                deltas[deltas.len() - 1],
                t0 * (deltas[deltas.len() - 1] / deltas[0]).powf(-0.5),
            ),
        ],
        color: (0, 0, 0),
        style: Style::Line,
    });
    let panel = Panel {
        title: format!(
            "lag time from rest at θ* (disk α* = {:.4}); fitted exponent −{:.4}",
            ca.alpha_star, summary.exponent_mean
        ),
        x_label: "α − α* (rad)".into(),
        y_label: "t_lag: time to roll half a turn (t0)".into(),
        log_x: true,
        log_y: true,
        series: curves,
        legend: SeriesLabelPosition::UpperRight,
        equal_aspect: false,
    };
    Ok(FigureData {
        panels: vec![panel],
        columns: 1,
        size: (900, 650),
        header: csv_header,
        rows,
        summary,
    })
}
