//! `bench stiff`: the inertial models as m/m0 → 0, their cost (stiffness) and their distance
//! from the viscous model.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use serde::Serialize;

use super::{bundled, fmt_num, write};
use crate::analysis::accuracy::trajectories::{self, Case, REFERENCE};
use crate::assets::{DISK as BUNDLED_DISK, SPHERE as BUNDLED_SPHERE};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style, render_png};
use crate::dynamics::Ramp;
use crate::integrate::Method;

/// Options of `bench stiff`.
///
/// For m/m0 from 1e-4 to 1: DOP853 (rtol 1e-8) work for t = 0..100 and the inertial model's
/// distance from the viscous one (state at t = 100, and relative period difference).
/// Writes OUT/stiff.csv and OUT/stiff.png.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct StiffArgs {
    /// Output folder.
    #[arg(long, default_value = "bench-stiff")]
    pub out: PathBuf,
    /// Reduced run for tests.
    #[arg(long)]
    pub quick: bool,
}

/// One row of the stiffness table.
#[derive(Debug, Serialize)]
struct StiffRow {
    model: &'static str,
    mass_ratio: f64,
    rhs_evals: u64,
    steps: u64,
    distance_from_viscous: f64,
    period_difference: f64,
}

/// Runs `bench stiff`.
pub fn run(a: StiffArgs) -> Result<()> {
    crate::output::create_folder(&a.out)?;
    let masses: Vec<f64> = if a.quick {
        vec![1e-3, 1e-2, 1e-1, 1.0]
    } else {
        vec![1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1, 3e-1, 1.0]
    };
    let t_end = if a.quick { 30.0 } else { 100.0 };
    let bodies = [
        ("disk", bundled(BUNDLED_DISK)?, 0.25, [0.0; 3]),
        ("sphere", bundled(BUNDLED_SPHERE)?, 0.3, [1.0, 2.0, 0.5]),
    ];
    let method = Method::dop853(1e-8);
    let mut rows = Vec::new();
    outln!(
        "{:<8} {:>8} {:>11} {:>9} {:>18} {:>14}",
        "body",
        "m/m0",
        "RHS evals",
        "steps",
        "|state − viscous|",
        "ΔT/T viscous"
    )?;
    for (name, body, alpha, start) in &bodies {
        let viscous = Case {
            body: body.clone(),
            ramp: Ramp::new(*alpha, 0.0)?,
            start: *start,
            t_end,
        };
        let v = trajectories::run_case(&viscous, REFERENCE)?;
        let tv = trajectories::period_estimate(&v.crossings, t_end);
        for &m in &masses {
            let case = Case {
                body: body.clone(),
                ramp: Ramp::new(*alpha, m)?,
                start: *start,
                t_end,
            };
            let o = trajectories::run_case(&case, method)
                .with_context(|| format!("{name} at m/m0 = {m}"))?;
            let period_difference = match (trajectories::period_estimate(&o.crossings, t_end), tv) {
                (Some(p), Some(r)) => ((p - r) / r).abs(),
                _ => f64::NAN,
            };
            let row = StiffRow {
                model: name,
                mass_ratio: m,
                rhs_evals: o.stats.rhs_evals,
                steps: o.stats.steps,
                distance_from_viscous: trajectories::state_error(&o, &v),
                period_difference,
            };
            outln!(
                "{:<8} {:>8.0e} {:>11} {:>9} {:>18.3e} {:>14.3e}",
                row.model,
                row.mass_ratio,
                row.rhs_evals,
                row.steps,
                row.distance_from_viscous,
                row.period_difference
            )?;
            rows.push(row);
        }
    }
    let csv = crate::figures::csv_text(
        "body,mass_ratio,rhs_evals,steps,distance_from_viscous,period_difference",
        rows.iter().map(|r| {
            vec![
                r.model.to_string(),
                format!("{:e}", r.mass_ratio),
                r.rhs_evals.to_string(),
                r.steps.to_string(),
                fmt_num(r.distance_from_viscous),
                fmt_num(r.period_difference),
            ]
        }),
    )?;
    write(&a.out.join("stiff.csv"), &csv)?;
    let series = |f: &dyn Fn(&StiffRow) -> f64| -> Vec<Series> {
        ["disk", "sphere"]
            .iter()
            .enumerate()
            .map(|(i, b)| Series {
                label: format!("{b} (DOP853, rtol 1e-8)"),
                points: rows
                    .iter()
                    .filter(|r| r.model == *b)
                    .map(|r| (r.mass_ratio, f(r)))
                    .collect(),
                color: PALETTE[i],
                style: Style::LineMarkers,
            })
            .collect()
    };
    let panels = vec![
        Panel {
            title: "cost of the inertial model, t = 0..100".into(),
            x_label: "mass ratio m/m0".into(),
            y_label: "right-hand-side evaluations".into(),
            log_x: true,
            log_y: true,
            series: series(&|r| r.rhs_evals as f64),
            legend: SeriesLabelPosition::UpperRight,
            equal_aspect: false,
        },
        Panel {
            title: "inertial minus viscous".into(),
            x_label: "mass ratio m/m0".into(),
            y_label: "relative period difference".into(),
            log_x: true,
            log_y: true,
            series: series(&|r| r.period_difference),
            legend: SeriesLabelPosition::UpperLeft,
            equal_aspect: false,
        },
    ];
    render_png(&panels, 2, (1400, 560), &a.out.join("stiff.png"))?;
    outln!("wrote {}", a.out.display())?;
    Ok(())
}
