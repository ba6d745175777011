//! `sphere-tube` — SI Fig. S3 (§2G): trajectories in SO(3) of a perfect sphere that pass through
//! one contact point. The sphere is put on the ramp touching body point u₀ and spun on the spot by
//! s ∈ [0, 2π) (the black closed curve: all orientations sharing that contact); from each, it rolls
//! straight down, q(t) = R_y(t sin α) q₀, closing after T = 2π/sin α. Drawn as the vector part of
//! ±q (q_w ≥ 0) in the unit ball, broken where it jumps to the antipode on ∂Ω; together the
//! trajectories form a tube through the ball. One trajectory is also integrated with DOP853 and
//! compared with the closed form. The numbers come from the core
//! ([`crate::analysis::studies::contact_tube`]); this file writes and draws them.

use anyhow::Result;
use glam::DVec3;
use serde::Serialize;

use super::{FigureData, FigureOptions};
use crate::analysis::studies::contact_tube::{contact_tube, split_at_jumps};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::colormap::viridis;

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// α.
    pub alpha: f64,
    /// The shared contact point (θ, φ).
    pub contact: [f64; 2],
    /// Trajectories.
    pub trajectories: usize,
    /// Period 2π/sin α.
    pub period: f64,
    /// Largest |q(T) ∓ q(0)| over the trajectories (closed: ~1e-16).
    pub closure_error: f64,
    /// Largest difference between DOP853 (rtol 1e-12) and the closed form over one period.
    pub integration_error: f64,
}

/// Runs the figure: computes it, then writes OUT/sphere-tube/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("sphere-tube")?;
    compute(opts)?.write_to(&dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<FigureData<Summary>> {
    opts.no_shape(
        "sphere-tube",
        "follows the perfect sphere, whose orbits have a closed form",
    )?;
    let alpha = opts.single_alpha("sphere-tube", 0.3)?;
    let n = if opts.quick { 16 } else { 48 };
    let tube = contact_tube(alpha, [1.0, 0.5], n, 400)?;
    let rows = tube
        .trajectories
        .iter()
        .enumerate()
        .flat_map(|(j, traj)| {
            traj.t
                .iter()
                .zip(&traj.ball)
                .map(move |(t, p)| vec![j as f64, *t, p.x, p.y, p.z])
        })
        .collect();
    let traj_series: Vec<(usize, Vec<DVec3>)> = tube
        .trajectories
        .iter()
        .enumerate()
        .flat_map(|(j, traj)| {
            split_at_jumps(&traj.ball)
                .into_iter()
                .map(move |pc| (j, pc))
        })
        .collect();
    let csv_header = "trajectory,t,bx,by,bz";
    let summary = Summary {
        alpha,
        contact: tube.contact,
        trajectories: n,
        period: tube.period,
        closure_error: tube.closure_error,
        integration_error: tube.integration_error,
    };
    // Three orthographic views of the ball.
    type Projection = fn(DVec3) -> (f64, f64);
    let views: [(&str, Projection); 3] = [
        ("x–y", |p| (p.x, p.y)),
        ("x–z", |p| (p.x, p.z)),
        ("y–z", |p| (p.y, p.z)),
    ];
    let rim: Vec<(f64, f64)> = (0..=120)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 120.0;
            (a.cos(), a.sin())
        })
        .collect();
    let panels: Vec<Panel> = views
        .iter()
        .map(|(name, proj)| {
            // The colour carries the start's spin s = 2πj/n about the ramp normal: the legend
            // names the scale's two ends.
            let mut labelled = [false, false];
            let mut series: Vec<Series> = traj_series
                .iter()
                .map(|(j, pc)| {
                    let end = if *j == 0 {
                        Some(0)
                    } else {
                        (*j == n - 1).then_some(1)
                    };
                    let label = match end {
                        Some(e) if !labelled[e] => {
                            labelled[e] = true;
                            format!(
                                "start spin s = {:.2} rad",
                                std::f64::consts::TAU * *j as f64 / n as f64
                            )
                        }
                        _ => String::new(),
                    };
                    Series {
                        label,
                        points: pc.iter().map(|p| proj(*p)).collect(),
                        color: viridis(*j as f64 / n as f64),
                        style: Style::Line,
                    }
                })
                .collect();
            // The ring of spins also wraps through ∂Ω: break it there instead of drawing a chord.
            let mut first = true;
            for piece in split_at_jumps(&tube.ring) {
                series.push(Series {
                    label: if first {
                        "orientations touching u₀".into()
                    } else {
                        String::new()
                    },
                    points: piece.iter().map(|p| proj(*p)).collect(),
                    color: (0, 0, 0),
                    style: Style::Line,
                });
                first = false;
            }
            series.push(Series {
                label: String::new(),
                points: rim.clone(),
                color: PALETTE[7],
                style: Style::Line,
            });
            Panel {
                title: format!(
                    "SO(3) ball, {name} view: {n} trajectories through one contact point"
                ),
                x_label: name.split('–').next().unwrap_or("x").into(),
                y_label: name.split('–').nth(1).unwrap_or("y").into(),
                log_x: false,
                log_y: false,
                series,
                legend: SeriesLabelPosition::LowerRight,
                equal_aspect: true,
            }
        })
        .collect();
    Ok(FigureData {
        panels,
        columns: 3,
        size: (1950, 680),
        header: csv_header,
        rows,
        summary,
    })
}
