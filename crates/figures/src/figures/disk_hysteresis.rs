//! `disk-hysteresis` — paper Fig. 2e and SI §1D: the first-order transition of an inertial disk
//! (m/m0 = 10, σ = 0.12, M = 5).
//!
//! α is stepped up from rest and then down, the state carried over
//! ([`crate::analysis::studies::disk::hysteresis_sweep`]; α** by
//! [`crate::analysis::studies::disk::return_transition`]); each rolling speed is 2π/T with T the
//! event-located period, so `rollphase period` from the CSV's (θ, θ̇) gives the same T. On the way up the disk stays put until
//! α*, then jumps to a finite 2π/T; on the way down it keeps rolling below α* until the return
//! transition α**. α** is then located by bisection, each trial continuing from the rolling
//! state of the last α that still rolled. Near α** the SI predicts a logarithmically sharp
//! transition, T ≈ a − b ln(α − α**), i.e. 2π/T ∝ −1/ln δα: we measure T at α** + δα for
//! δα = 1e-7…1e-2 and fit T against ln δα (the log law) and ln T against ln δα (a power law,
//! which would give slope −½ at a saddle-node).

use anyhow::{Result, anyhow};
use serde::Serialize;

use super::{FigureData, FigureOptions, progress};
use crate::analysis::critical_angle;
use crate::analysis::fit::{line, logspace};
use crate::analysis::inertial_disk_period;
use crate::analysis::studies::disk::{
    SweepPoint, fixed_points, hysteresis_sweep, return_transition,
};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::dynamics::Ramp;
use crate::geometry::Body;

const MASS: f64 = 10.0;
const RTOL: f64 = 1e-10;

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Seed of the disk. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// α* (rad).
    pub alpha_star: f64,
    /// First α of the ascending sweep at which the disk rolls.
    pub alpha_jump_up: f64,
    /// Return transition α** (bisection, rad).
    pub alpha_return: f64,
    /// α**/α*.
    pub return_ratio: f64,
    /// Hysteresis present: α** < α*.
    pub hysteresis: bool,
    /// 2π/T just above α* on the way up (the size of the jump).
    pub jump_speed: f64,
    /// How each speed was measured.
    pub speed_method: &'static str,
    /// Rolling points whose period had not settled to 1e-8 within the measuring time (their
    /// speed is the mean over the periods measured; expect 0).
    pub unconverged_periods: usize,
    /// R² of T = a − b ln δα near α** (the SI's log law; expect ≈ 1).
    pub log_law_r2: f64,
    /// b of that fit.
    pub log_law_slope: f64,
    /// Slope of ln T against ln δα near α** (a saddle-node would give −0.5).
    pub power_law_slope: f64,
}

/// The sweep's two branches with α* and α** marked, and T against ln δα near α**.
fn panels(
    sweep: &[SweepPoint],
    summary: &Summary,
    jump_speed: f64,
    near: Vec<(f64, f64)>,
) -> Vec<Panel> {
    let pts = |asc: bool| -> Vec<(f64, f64)> {
        sweep
            .iter()
            .filter(|p| p.ascending == asc)
            .map(|p| (p.alpha, p.mean_angular_speed))
            .collect()
    };
    let mark = |a: f64, label: &str, c| Series {
        label: label.into(),
        points: vec![(a, 0.0), (a, 0.9 * jump_speed.max(0.02))],
        color: c,
        style: Style::Line,
    };
    vec![
        Panel {
            title: format!(
                "inertial disk m/m0 = {MASS}: hysteresis, α**/α* = {:.3}",
                summary.return_ratio
            ),
            x_label: "ramp angle α (rad)".into(),
            y_label: "mean angular speed 2π/T (1/t0)".into(),
            log_x: false,
            log_y: false,
            series: vec![
                Series {
                    label: "α increasing".into(),
                    points: pts(true),
                    color: PALETTE[0],
                    style: Style::LineMarkers,
                },
                Series {
                    label: "α decreasing".into(),
                    points: pts(false),
                    color: PALETTE[1],
                    style: Style::LineMarkers,
                },
                mark(summary.alpha_star, "α*", (0, 0, 0)),
                mark(summary.alpha_return, "α**", (120, 120, 120)),
            ],
            legend: SeriesLabelPosition::UpperLeft,
            equal_aspect: false,
        },
        Panel {
            title: format!("near α**: T = a − b ln δα (R² = {:.5})", summary.log_law_r2),
            x_label: "α − α** (rad)".into(),
            y_label: "period T (t0)".into(),
            log_x: true,
            log_y: false,
            series: vec![Series {
                label: "simulated".into(),
                points: near,
                color: PALETTE[2],
                style: Style::LineMarkers,
            }],
            legend: SeriesLabelPosition::UpperRight,
            equal_aspect: false,
        },
    ]
}

/// Runs the figure: computes it, then writes OUT/disk-hysteresis/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("disk-hysteresis")?;
    compute(opts)?.write_to(&dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<FigureData<Summary>> {
    opts.no_alpha("disk-hysteresis", "α up and down")?;
    let (disk, seed) = opts.disk("disk-hysteresis", opts.seed, 0.12, 5)?;
    let a_star = critical_angle(&Body::Disk(disk.clone())).alpha_star;
    let n = if opts.quick { 17 } else { 41 };
    let alphas: Vec<f64> = (0..n)
        .map(|i| a_star * (0.5 + 0.8 * i as f64 / (n - 1) as f64))
        .collect();
    let rest = fixed_points(&disk, alphas[0])
        .into_iter()
        .find(|p| p.stable)
        .ok_or_else(|| anyhow!("no rest point at α = {}", alphas[0]))?;
    let dwell = if opts.quick { 600.0 } else { 1200.0 };
    let bar = progress(2 * n - 1, "sweep");
    let sweep = hysteresis_sweep(&disk, MASS, &alphas, [rest.theta, 0.0], dwell, RTOL, || {
        bar.inc(1)
    })?;
    bar.finish_and_clear();
    let rows: Vec<Vec<f64>> = sweep
        .iter()
        .map(|p| {
            vec![
                p.alpha,
                if p.ascending { 1.0 } else { 0.0 },
                p.mean_angular_speed,
                p.period.unwrap_or(f64::NAN),
                if p.period_converged { 1.0 } else { 0.0 },
                p.state[0],
                p.state[1],
            ]
        })
        .collect();
    let csv_header = "alpha,ascending,mean_angular_speed,period,period_converged,theta,theta_dot";
    let unconverged_periods = sweep
        .iter()
        .filter(|p| p.period.is_some() && !p.period_converged)
        .count();
    let moving = |p: &&SweepPoint| p.mean_angular_speed > 0.0;
    let up = sweep
        .iter()
        .filter(|p| p.ascending)
        .find(moving)
        .ok_or_else(|| anyhow!("never rolled on the way up"))?;
    let iterations = if opts.quick { 14 } else { 30 };
    let bar = progress(iterations, "α** bisection");
    let back = return_transition(
        &disk,
        MASS,
        &sweep,
        &alphas,
        dwell,
        iterations,
        RTOL,
        &|| bar.inc(1),
    )?;
    bar.finish_and_clear();
    let (alpha_return, hi, state) = (back.alpha_return, back.lowest_rolling, back.state);
    // Periods just above α**, each continued from the rolling state found at `hi`.
    let deltas = logspace(
        if opts.quick { 1e-5 } else { 1e-7 },
        1e-2,
        if opts.quick { 4 } else { 11 },
    );
    let mut near = Vec::new();
    for &d in &deltas {
        let a = alpha_return + d.max(hi - alpha_return);
        let p = inertial_disk_period(
            &disk,
            &Ramp::new(a, MASS)?,
            state[0],
            state[1],
            RTOL,
            40_000.0,
        )?;
        if let Some(t) = p.period {
            near.push((a - alpha_return, t));
        }
    }
    let log_fit = line(&near.iter().map(|&(d, t)| (d.ln(), t)).collect::<Vec<_>>())
        .ok_or_else(|| anyhow!("no fit near α**"))?;
    let pow_fit = line(
        &near
            .iter()
            .map(|&(d, t)| (d.ln(), t.ln()))
            .collect::<Vec<_>>(),
    )
    .ok_or_else(|| anyhow!("no fit near α**"))?;
    let summary = Summary {
        seed,
        alpha_star: a_star,
        alpha_jump_up: up.alpha,
        alpha_return,
        return_ratio: alpha_return / a_star,
        hysteresis: alpha_return < a_star,
        jump_speed: up.mean_angular_speed,
        speed_method: "2π/T, T the event-located time of one whole turn after the dwell (as `rollphase period`); the CSV's theta, theta_dot are the state it was measured from",
        unconverged_periods,
        log_law_r2: log_fit.r2,
        log_law_slope: -log_fit.slope,
        power_law_slope: pow_fit.slope,
    };
    let panels = panels(&sweep, &summary, up.mean_angular_speed, near);
    Ok(FigureData {
        panels,
        columns: 2,
        size: (1500, 620),
        header: csv_header,
        rows,
        summary,
    })
}
