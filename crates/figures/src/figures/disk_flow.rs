//! `disk-flow` — SI Fig. S2: the flow (θ̇, θ̈) of the inertial disk (m/m0 = 10) in the (θ, θ̇) plane
//! at six α around α*, its fixed points (θ̇ = 0, r sin α = r' cos α; stable or saddle) and the
//! trajectory from (π/2, 0.04), on one disk (σ = 0.12, M = 5).
//!
//! Above α* there is no fixed point and the trajectory cruises; at α* one appears at θ*; just
//! below, a stable/saddle pair separates but the cruising orbit survives (hysteresis) until the
//! orbit meets the saddle at α**, below which it falls into the stable point.

use anyhow::Result;
use serde::Serialize;

use super::{FigureData, FigureOptions};
use crate::analysis::critical_angle;
use crate::analysis::studies::disk::{FixedPoint, fixed_points, phase_path};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::dynamics::{DiskInertial, Ramp};
use crate::geometry::Body;

/// One panel's numbers.
#[derive(Debug, Serialize)]
pub struct FlowPanel {
    /// α (rad).
    pub alpha: f64,
    /// α/α*.
    pub alpha_over_alpha_star: f64,
    /// Fixed points.
    pub fixed_points: Vec<FixedPoint>,
    /// Whether the trajectory from (π/2, 0.04) is still rolling at the end.
    pub trajectory_rolls: bool,
}

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Seed of the disk. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// α*.
    pub alpha_star: f64,
    /// Number of fixed points above α* (expect 0).
    pub fixed_points_above: usize,
    /// Panels.
    pub panels: Vec<FlowPanel>,
}

const MASS: f64 = 10.0;

/// Runs the figure: computes it, then writes OUT/disk-flow/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("disk-flow")?;
    compute(opts)?.write_to(&dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<FigureData<Summary>> {
    opts.no_alpha("disk-flow", "six α around α*")?;
    let (disk, seed) = opts.disk("disk-flow", opts.seed, 0.12, 5)?;
    let ca = critical_angle(&Body::Disk(disk.clone()));
    let factors = [1.2, 1.0 + 1e-9, 0.9, 0.75, 0.6, 0.3];
    let t_end = if opts.quick { 300.0 } else { 1500.0 };
    let (th_lo, th_hi) = (-0.04, 0.16);
    let mut rows = Vec::new();
    let mut panels = Vec::new();
    let mut out = Vec::new();
    for &f in factors.iter() {
        let alpha = ca.alpha_star * f;
        let ramp = Ramp::new(alpha, MASS)?;
        let model = DiskInertial::new(&disk, &ramp);
        let arrows = flow_arrows(&model, alpha, (th_lo, th_hi), &mut rows);
        let (pieces, rolls) = trajectory(&model, t_end)?;
        let fps = fixed_points(&disk, alpha);
        let mut series = vec![Series {
            label: String::new(),
            points: arrows,
            color: (150, 150, 150),
            style: Style::Arrows,
        }];
        for (k, p) in pieces.into_iter().enumerate() {
            series.push(Series {
                label: if k == 0 {
                    "trajectory from (π/2, 0.04)".into()
                } else {
                    String::new()
                },
                points: p,
                color: (0, 0, 0),
                style: Style::Line,
            });
        }
        let stable: Vec<(f64, f64)> = fps
            .iter()
            .filter(|p| p.stable)
            .map(|p| (p.theta, 0.0))
            .collect();
        let saddle: Vec<(f64, f64)> = fps
            .iter()
            .filter(|p| !p.stable)
            .map(|p| (p.theta, 0.0))
            .collect();
        series.push(Series {
            label: if stable.is_empty() {
                String::new()
            } else {
                "stable point".into()
            },
            points: stable,
            color: PALETTE[2],
            style: Style::Markers,
        });
        series.push(Series {
            label: if saddle.is_empty() {
                String::new()
            } else {
                "saddle".into()
            },
            points: saddle,
            color: PALETTE[1],
            style: Style::Markers,
        });
        series.push(Series {
            label: "start".into(),
            points: vec![(std::f64::consts::FRAC_PI_2, 0.04)],
            color: PALETTE[0],
            style: Style::Markers,
        });
        panels.push(Panel {
            title: format!(
                "α = {alpha:.4} = {f:.2} α*{}",
                if rolls { ", rolls" } else { ", halts" }
            ),
            x_label: "contact angle θ (rad)".into(),
            y_label: "dθ/dt (1/t0)".into(),
            log_x: false,
            log_y: false,
            series,
            legend: SeriesLabelPosition::UpperRight,
            equal_aspect: false,
        });
        out.push(FlowPanel {
            alpha,
            alpha_over_alpha_star: f,
            fixed_points: fps,
            trajectory_rolls: rolls,
        });
    }
    let csv_header = "alpha,theta,theta_dot,flow_theta,flow_theta_dot";
    let summary = Summary {
        seed,
        alpha_star: ca.alpha_star,
        fixed_points_above: out[0].fixed_points.len(),
        panels: out,
    };
    Ok(FigureData {
        panels,
        columns: 3,
        size: (1800, 1000),
        header: csv_header,
        rows,
        summary,
    })
}

/// The flow field of the inertial disk at one α: unit arrows of (θ̇, θ̈) on a 36 × 15 grid of
/// (θ, θ̇) in [0, 2π) × [`th_lo`, `th_hi`], scaled to the plot's aspect, as (tail, head) point
/// pairs; each arrow's row (α, θ, θ̇, flow) goes to `rows`.
fn flow_arrows(
    model: &DiskInertial,
    alpha: f64,
    (th_lo, th_hi): (f64, f64),
    rows: &mut Vec<Vec<f64>>,
) -> Vec<(f64, f64)> {
    let mut arrows = Vec::new();
    let (nx, ny) = (36, 14);
    let (sx, sy) = (
        std::f64::consts::TAU / nx as f64,
        (th_hi - th_lo) / ny as f64,
    );
    for i in 0..nx {
        for j in 0..=ny {
            let (t, w) = ((i as f64 + 0.5) * sx, th_lo + j as f64 * sy);
            let acc = model.theta_ddot(t, w);
            let (dx, dy) = (w / sx, acc / sy);
            let len = (dx * dx + dy * dy).sqrt();
            if len > 0.0 && len.is_finite() {
                let k = 0.42 / len;
                arrows.push((t, w));
                arrows.push((t + dx * k * sx, w + dy * k * sy));
                rows.push(vec![alpha, t, w, w, acc]);
            }
        }
    }
    arrows
}

/// Points of one unbroken piece of a drawn curve.
type Polyline = Vec<(f64, f64)>;

/// The trajectory from (θ, θ̇) = (π/2, 0.04) to `t_end`, sampled 4001 times
/// ([`phase_path`]), broken where θ wraps at 2π; and whether the disk still rolls at the end.
fn trajectory(model: &DiskInertial, t_end: f64) -> Result<(Vec<Polyline>, bool)> {
    let (points, rolls) = phase_path(model, [std::f64::consts::FRAC_PI_2, 0.04], t_end, 4000)?;
    let mut pieces: Vec<Polyline> = vec![Vec::new()];
    for [th, w] in points {
        let wrapped = pieces
            .last()
            .and_then(|p| p.last())
            .is_some_and(|last| (th - last.0).abs() > std::f64::consts::PI);
        if wrapped {
            pieces.push(Vec::new());
        }
        if let Some(p) = pieces.last_mut() {
            p.push((th, w));
        }
    }
    Ok((pieces, rolls))
}
