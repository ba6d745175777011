//! `rollphase figure NAME`: regenerate one of the paper's figures as CSV + PNG + summary.json.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

use crate::figures::{self, FIGURES, FigureOptions};

/// Regenerate one of the paper's figures: OUT/NAME/data.csv, figure.png and summary.json.
///
/// Names (`rollphase figure --list` prints them with descriptions):
///   disk-transition, disk-hysteresis, disk-lag-time, disk-flow,
///   sphere-cruising, sphere-orbits, sphere-halting, sphere-poincare, sphere-doubling, sphere-tube.
/// Ensembles run on all cores; the numbers do not depend on the thread count.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct FigureArgs {
    /// Which figure.
    #[arg(required_unless_present = "list")]
    pub name: Option<String>,
    /// List the figures and exit.
    #[arg(long)]
    pub list: bool,
    /// Output folder (files go to OUT/NAME/).
    #[arg(long, default_value = "figures")]
    pub out: PathBuf,
    /// Seed of the random bodies and orientations.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Reduced run (for tests; each under ~20 s).
    #[arg(long)]
    pub quick: bool,
    /// Worker threads [default: all cores].
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Runs `figure`.
pub fn run(a: FigureArgs) -> Result<()> {
    if a.list {
        for (name, what) in FIGURES {
            println!("{name:<18} {what}");
        }
        return Ok(());
    }
    let name = a.name.unwrap_or_default();
    let opts = FigureOptions {
        out: a.out.clone(),
        seed: a.seed,
        quick: a.quick,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()?;
    let summary: serde_json::Value = pool.install(|| -> Result<serde_json::Value> {
        Ok(match name.as_str() {
            "disk-transition" => serde_json::to_value(figures::disk_transition::run(&opts)?)?,
            "disk-hysteresis" => serde_json::to_value(figures::disk_hysteresis::run(&opts)?)?,
            "disk-lag-time" => serde_json::to_value(figures::disk_lag_time::run(&opts)?)?,
            "disk-flow" => serde_json::to_value(figures::disk_flow::run(&opts)?)?,
            "sphere-poincare" => serde_json::to_value(figures::sphere_poincare::run(&opts)?)?,
            "sphere-cruising" => serde_json::to_value(figures::sphere_cruising::run(&opts)?)?,
            "sphere-doubling" => serde_json::to_value(figures::sphere_doubling::run(&opts)?)?,
            "sphere-halting" => serde_json::to_value(figures::sphere_halting::run(&opts)?)?,
            "sphere-tube" => serde_json::to_value(figures::sphere_tube::run(&opts)?)?,
            "sphere-orbits" => serde_json::to_value(figures::sphere_orbits::run(&opts)?)?,
            other => {
                let names: Vec<&str> = FIGURES.iter().map(|f| f.0).collect();
                bail!(
                    "unknown figure {other:?}; the figures are: {}",
                    names.join(", ")
                )
            }
        })
    })?;
    let headline = summary
        .as_object()
        .map(|o| {
            o.iter()
                .filter(|(_, v)| v.is_number() || v.is_boolean())
                .map(|(k, v)| format!("  {k}: {v}"))
                .collect::<Vec<_>>()
                .join("\n")
        })
        .unwrap_or_default();
    println!("{name}: wrote {}\n{headline}", a.out.join(&name).display());
    Ok(())
}

/// Fit measured lag times: t_lag = A (α − α*)^β per run (α* fitted) and with a shared β.
///
/// Input layout (as ../shared/data/experiments/cylinder_lag_times.csv):
///   run_idx,alpha*,alpha,t_lag      with t_lag a quoted list "[t1, t2, …]" of repeats (s).
/// Writes OUT/fit-lag/{data.csv, figure.png, summary.json}; uncertainties by bootstrap over the
/// repeats (seeded). The paper reports β = −1/2.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct FitLagArgs {
    /// The CSV file.
    pub csv: PathBuf,
    /// Output folder.
    #[arg(long, default_value = "figures")]
    pub out: PathBuf,
    /// Bootstrap resamples for the uncertainties.
    #[arg(long, default_value_t = 200)]
    pub bootstrap: usize,
    /// Seed of the bootstrap.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs `fit-lag`.
pub fn run_fit_lag(a: FitLagArgs) -> Result<()> {
    let s = figures::fit_lag::run(&a.csv, &a.out, a.bootstrap, a.seed)?;
    println!(
        "fit-lag: {} runs, shared exponent β = {:.4} ± {:.4} (paper: −0.5); wrote {}",
        s.runs,
        s.shared_exponent,
        s.shared_exponent_stderr,
        a.out.join("fit-lag").display()
    );
    for (k, f) in s.analysis.runs.iter().enumerate() {
        println!(
            "  run {k}: α* = {:.5} (file: {}), β = {:.3} ± {:.3}",
            f.alpha_star,
            s.alpha_star_reported[k]
                .map(|v| format!("{v:.5}"))
                .unwrap_or_else(|| "-".into()),
            f.exponent,
            s.analysis.run_exponent_stderr[k]
        );
    }
    Ok(())
}
