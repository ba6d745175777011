//! `rollphase fit-lag CSV` — paper Fig. 3b–c from measured data, not from the model: the lag
//! times of rolling cylinders, fitted with t_lag = A (α − α*)^β per run (α* a fit parameter) and
//! with one exponent shared by all runs ([`crate::analysis::experiment::lag_times`]); the paper reports β = −½.
//! The shared β also says which power-law drag exponent n = 1/(½ − β) the ramp supports.
//! Its own module, beside the figures whose output layout (data.csv, figure.png, summary.json)
//! it shares.

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use serde::Serialize;

use crate::analysis::experiment::lag_times::{
    ALPHA_STAR_RANGE, DragExponentEstimate, LagAnalysis, LagRun, SHARED_EXPONENT_RANGE,
    analyse_with_progress, drag_exponent_from_lag, parse_lag_csv,
};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::figures::FigureData;
use crate::output::{self, Inputs};

/// What `fit-lag` writes to summary.json.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The input file.
    pub input: String,
    /// Number of runs.
    pub runs: usize,
    /// Shared exponent β (expect −0.5).
    pub shared_exponent: f64,
    /// Its bootstrap standard deviation; null when β ended at the edge of the range searched
    /// (`shared_exponent_at_bound`): a bound has no σ.
    pub shared_exponent_stderr: Option<f64>,
    /// The shared β is the edge of the range searched (every β that a drag exponent
    /// 0.25 ≤ n ≤ 4 gives, −3.5 to 0.25), not a minimum: the data lie outside what the model's
    /// drag laws can make.
    pub shared_exponent_at_bound: bool,
    /// Some fitted value (β or a run's α*) is a bound, not a fit: see `warnings`. The command
    /// exits non-zero then, unless `--allow-bound`.
    pub at_bound: bool,
    /// The power-law drag exponent n = 1/(1/2 − β) the shared β implies, with its error and
    /// range (null when β ≥ 1/2, or when β is a bound).
    pub drag_exponent: Option<DragExponentEstimate>,
    /// α* reported in the file per run (null if absent).
    pub alpha_star_reported: Vec<Option<f64>>,
    /// Fitted values that sit at the edge of their search range, where the fit is not a
    /// minimum but a bound (printed as warnings too).
    pub warnings: Vec<String>,
    /// Full fit.
    pub analysis: LagAnalysis,
}

/// Refuses data the fit cannot determine: a run whose lag times are all equal says nothing
/// about β. (Too few angles per run are refused when the file is read.)
fn refuse_degenerate(runs: &[LagRun]) -> Result<()> {
    for r in runs {
        let times: Vec<f64> = r
            .points
            .iter()
            .flat_map(|p| p.times.iter().copied())
            .collect();
        if times.windows(2).all(|w| w[0] == w[1]) {
            anyhow::bail!(
                "run {}: every lag time is {} s, so the data say nothing about how t_lag changes \
                 with α; the exponent cannot be fitted",
                r.run,
                times.first().copied().unwrap_or(f64::NAN)
            );
        }
    }
    Ok(())
}

/// Whether the shared β sits at the edge of [`SHARED_EXPONENT_RANGE`] (golden section ends
/// within its 1e-9 tolerance of an edge it was pushed against; 1e-4 is far from any interior
/// minimum the scan's 0.1 grid would bracket).
fn shared_exponent_at_bound(beta: f64) -> bool {
    let (b_lo, b_hi) = SHARED_EXPONENT_RANGE;
    beta - b_lo < 1e-4 || b_hi - beta < 1e-4
}

/// Fitted α* or β at the edge of the range searched: a bound, not a fit.
fn bound_warnings(runs: &[LagRun], a: &LagAnalysis) -> Vec<String> {
    let mut out = Vec::new();
    for (k, r) in runs.iter().enumerate() {
        let a_min = r
            .points
            .iter()
            .map(|p| p.alpha)
            .fold(f64::INFINITY, f64::min);
        let (lo, hi) = (a_min - ALPHA_STAR_RANGE, a_min);
        for (what, star) in [
            ("β free", a.runs[k].alpha_star),
            ("shared β", a.shared_alpha_stars[k]),
        ] {
            if star - lo < 1e-4 * ALPHA_STAR_RANGE || hi - star < 1e-4 * ALPHA_STAR_RANGE {
                out.push(format!(
                    "run {}: the fitted α* = {star:.5} ({what}) is at the edge of the range \
                     searched ({lo:.5} to {hi:.5}): a bound, not a fit; check the angles (a point \
                     at or below the true α*?)",
                    r.run
                ));
            }
        }
    }
    let (b_lo, b_hi) = SHARED_EXPONENT_RANGE;
    if shared_exponent_at_bound(a.shared_exponent) {
        out.push(format!(
            "the shared exponent β = {:.4} is at the edge of the range searched ({b_lo} to \
             {b_hi}, every β = 1/2 − 1/n of a drag exponent 0.25 ≤ n ≤ 4): a bound, not a fit, \
             so it has no σ; the lag times fall {} than any drag law the model runs",
            a.shared_exponent,
            if a.shared_exponent < 0.0 {
                "more steeply"
            } else {
                "less steeply"
            }
        ));
    }
    out
}

/// Fits `csv` and writes OUT/fit-lag/{data.csv, figure.png, summary.json}.
pub fn run(csv: &Path, out: &Path, bootstrap: usize, seed: u64) -> Result<Summary> {
    let inputs = Inputs::of([csv]);
    let dir = out.join("fit-lag");
    output::check_folder(&dir, &crate::figures::FIGURE_FILES, &inputs)?;
    let text = crate::geometry::shape_file::read_text_capped(csv, 64 << 20)
        .with_context(|| format!("cannot read {}", csv.display()))?;
    let data = compute(&text, &csv.display().to_string(), bootstrap, seed)
        .map_err(|e| anyhow!("{}: {e:#}", csv.display()))?;
    #[derive(Serialize)]
    struct Options {
        bootstrap: usize,
        seed: u64,
    }
    data.write_files(&dir, &inputs, &Options { bootstrap, seed })
}

/// Fits the lag times in `text` (CSV, named `input` in the summary); writes nothing.
pub fn compute(
    text: &str,
    input: &str,
    bootstrap: usize,
    seed: u64,
) -> Result<FigureData<Summary>> {
    let runs = parse_lag_csv(text).map_err(|e| anyhow!("{e}"))?;
    refuse_degenerate(&runs)?;
    // A bar on a terminal: the bootstrap is the slow part (each resample refits every run and
    // the shared exponent).
    let bar = crate::figures::progress(bootstrap, "bootstrap");
    let analysis = analyse_with_progress(&runs, bootstrap, seed, &|| bar.inc(1))
        .ok_or_else(|| anyhow!("the fit failed (too few angles in a run?)"))?;
    bar.finish_and_clear();
    let warnings = bound_warnings(&runs, &analysis);
    let beta_at_bound = shared_exponent_at_bound(analysis.shared_exponent);
    let beta_stderr = (!beta_at_bound).then_some(analysis.shared_exponent_stderr);
    let mut rows = Vec::new();
    let mut series = Vec::new();
    for (k, r) in runs.iter().enumerate() {
        let star = analysis.shared_alpha_stars[k];
        let pts: Vec<(f64, f64)> = r
            .points
            .iter()
            .map(|p| {
                let mean = p.times.iter().sum::<f64>() / p.times.len() as f64;
                let sd = (p.times.iter().map(|t| (t - mean).powi(2)).sum::<f64>()
                    / (p.times.len().max(2) - 1) as f64)
                    .sqrt();
                rows.push(vec![r.run as f64, p.alpha, star, p.alpha - star, mean, sd]);
                (p.alpha - star, mean)
            })
            .collect();
        let fit = analysis.runs[k];
        series.push(Series {
            label: format!(
                "run {}: β = {:.3} ± {:.3}",
                r.run, fit.exponent, analysis.run_exponent_stderr[k]
            ),
            points: pts,
            color: PALETTE[k % PALETTE.len()],
            style: Style::Markers,
        });
    }
    let csv_header = "run,alpha,alpha_star_fit,alpha_minus_alpha_star,t_lag_mean,t_lag_sd";
    let xs: Vec<f64> = rows.iter().map(|r| r[3]).filter(|x| *x > 0.0).collect();
    let (x0, x1) = (
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(0.0, f64::max),
    );
    let y_at = |x: f64| {
        rows.iter().map(|r| r[4]).sum::<f64>() / rows.len() as f64
            * (x / x0.sqrt() / x1.sqrt()).powf(analysis.shared_exponent)
    };
    series.push(Series {
        label: match beta_stderr {
            Some(sd) => format!("shared fit β = {:.3} ± {sd:.3}", analysis.shared_exponent),
            None => format!(
                "shared β at its bound {:.3} (no fit)",
                analysis.shared_exponent
            ),
        },
        points: vec![(x0, y_at(x0)), (x1, y_at(x1))],
        color: (0, 0, 0),
        style: Style::Line,
    });
    let summary = Summary {
        input: input.to_string(),
        runs: runs.len(),
        shared_exponent: analysis.shared_exponent,
        shared_exponent_stderr: beta_stderr,
        shared_exponent_at_bound: beta_at_bound,
        at_bound: !warnings.is_empty(),
        drag_exponent: beta_stderr
            .and_then(|sd| drag_exponent_from_lag(analysis.shared_exponent, sd)),
        alpha_star_reported: runs.iter().map(|r| r.alpha_star_reported).collect(),
        warnings,
        analysis,
    };
    let panel = Panel {
        title: "measured lag times of rolling cylinders (α* fitted per run)".into(),
        x_label: "α − α* (rad)".into(),
        y_label: "t_lag (s), mean of repeats".into(),
        log_x: true,
        log_y: true,
        series,
        legend: SeriesLabelPosition::UpperRight,
        equal_aspect: false,
    };
    Ok(FigureData {
        panels: vec![panel],
        columns: 1,
        size: (1000, 700),
        header: csv_header,
        rows,
        summary,
    })
}
