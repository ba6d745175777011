//! `rollphase figure NAME`: regenerate one of the paper's figures as CSV + PNG + summary.json.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

use crate::figures::shard::{Ensemble, ShardSpec};
use crate::figures::{self, BodyChoice, FIGURES, FigureOptions, Ran};

/// Regenerate one of the paper's figures: OUT/NAME/data.csv, figure.png and summary.json.
///
/// `rollphase figure --list` prints every name with what it shows. The figures of paper
/// Figs. 3–4 (sphere-*) run on the paper's own body by default (the authors' numpy seed 219,
/// σ = 0.25, l ≤ 5; assets/shapes/paper-sphere.json) at the paper's α = 0.15 where it names one;
/// --seed N gives them a random body of ours instead, and --shape FILE any body. The disk
/// figures use seeded random disks (--seed, default 1) or --shape FILE. --alpha sets the ramp
/// angle of the figures that use one α (sphere-poincare, sphere-doubling, sphere-bifurcation,
/// sphere-tube); the others sweep α themselves and refuse it.
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
    /// Seed of the random orientations (1 when not given). Giving it also replaces the figure's
    /// default body (for sphere-*, the paper's) with a random body of ours from this seed, even
    /// --seed 1; to keep the paper's body with other orientations, add
    /// --shape assets/shapes/paper-sphere.json.
    #[arg(long)]
    pub seed: Option<u64>,
    /// A shape file to use in place of the figure's body.
    #[arg(long)]
    pub shape: Option<PathBuf>,
    /// Ramp angle α in radians, for the figures that use one α.
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// Reduced run (for tests; each under ~20 s).
    #[arg(long)]
    pub quick: bool,
    /// Worker threads [default: all cores].
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run only shard I of N (1-based) of the figure's runs, e.g. 3/8, and write them to
    /// OUT/NAME/shard-I-of-N.json without the plot; `rollphase merge OUT/NAME` then writes the
    /// figure once all N are there. For the ensemble figures, which `figure --list` marks
    /// [--shard]; see docs/guide/cluster.md.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<ShardSpec>,
}

/// Runs `figure`.
pub fn run(a: FigureArgs) -> Result<()> {
    if a.list {
        for f in FIGURES {
            let mark = if f.sharded() { " [--shard]" } else { "" };
            outln!("{:<20} {}{mark}", f.name, f.about)?;
        }
        return Ok(());
    }
    let name = a.name.unwrap_or_default();
    let Some(entry) = figures::figure(&name) else {
        let names: Vec<&str> = FIGURES.iter().map(|f| f.name).collect();
        bail!(
            "unknown figure {name:?}; the figures are: {}",
            names.join(", ")
        )
    };
    let body = match (&a.shape, a.seed) {
        // Absolute, so shards (which store it) merge from any folder, and the summary says
        // which file it was.
        (Some(p), _) => BodyChoice::File(std::fs::canonicalize(p).unwrap_or_else(|_| p.clone())),
        (None, Some(_)) => BodyChoice::Seeded,
        (None, None) => BodyChoice::FigureDefault,
    };
    let opts = FigureOptions {
        out: a.out.clone(),
        seed: a.seed.unwrap_or(1),
        quick: a.quick,
        body,
        alpha: a.alpha,
        ensemble: match a.shard {
            Some(s) => Ensemble::Shard(s),
            None => Ensemble::Whole,
        },
    };
    let pool = thread_pool(a.threads)?;
    if a.shard.is_some() && !entry.sharded() {
        bail!(
            "{name} has no ensemble to split; --shard applies to {}",
            crate::figures::sharded_figures().join(", ")
        );
    }
    let summary = match pool.install(|| (entry.run)(&opts))? {
        Ran::Figure(s) => s,
        Ran::Shard(w) => {
            outln!("{name}: {w}; {}", w.next_step(&a.out.join(&name)))?;
            return Ok(());
        }
    };
    let headline = summary
        .as_object()
        .map(|o| {
            o.iter()
                .filter(|(_, v)| v.is_number() || v.is_boolean() || v.is_string())
                .map(|(k, v)| format!("  {k}: {v}"))
                .collect::<Vec<_>>()
                .join("\n")
        })
        .unwrap_or_default();
    outln!("{name}: wrote {}\n{headline}", a.out.join(&name).display())?;
    Ok(())
}

/// The worker pool for `--threads` (all cores when not given).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    if let Some(t) = threads
        && !(1..=MAX_THREADS).contains(&t)
    {
        bail!(
            "--threads {t} is not allowed (needs 1 ≤ threads ≤ {MAX_THREADS}; leave it out for all cores)"
        );
    }
    Ok(rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()?)
}

/// Fit measured lag times: t_lag = A (α − α*)^β per run (α* fitted) and with a shared β.
///
/// Input layout (as ../shared/data/experiments/cylinder_lag_times.csv):
///   run_idx,alpha*,alpha,t_lag      with t_lag a quoted list "[t1, t2, …]" of repeats (s).
/// Writes OUT/fit-lag/{data.csv, figure.png, summary.json}; uncertainties by bootstrap over the
/// repeats (seeded). The paper reports β = −1/2. With the power-law drag (torque
/// −γ |ω|^(n−1) ω, `--drag-exponent`) the lag time scales as (α − α*)^(1/2 − 1/n), so the
/// shared β gives the exponent n = 1/(1/2 − β) the ramp supports, printed with its error.
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
    /// Exit 0 even when a fitted value (the shared β, or a run's α*) ends at the edge of the
    /// range searched. Such a value is a bound, not a fit: it is printed without a σ, and
    /// without this flag the command writes its files and exits 1.
    #[arg(long)]
    pub allow_bound: bool,
}

/// Most worker threads a figure may ask for.
pub const MAX_THREADS: usize = 1024;
/// Bootstrap resamples allowed: enough for a standard error, few enough to finish in seconds.
pub const BOOTSTRAP_RANGE: std::ops::RangeInclusive<usize> = 10..=100_000;

/// Runs `fit-lag`.
pub fn run_fit_lag(a: FitLagArgs) -> Result<()> {
    if !BOOTSTRAP_RANGE.contains(&a.bootstrap) {
        bail!(
            "--bootstrap {} is not allowed (needs {} ≤ resamples ≤ {}: fewer give no meaningful \
             uncertainty)",
            a.bootstrap,
            BOOTSTRAP_RANGE.start(),
            BOOTSTRAP_RANGE.end()
        );
    }
    let s = crate::fit_lag::run(&a.csv, &a.out, a.bootstrap, a.seed)?;
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    let beta = match s.shared_exponent_stderr {
        Some(sd) => format!("β = {:.4} ± {sd:.4}", s.shared_exponent),
        None => format!(
            "β = {:.4}, the edge of the range searched (a bound, no σ)",
            s.shared_exponent
        ),
    };
    outln!(
        "fit-lag: {} runs, shared exponent {beta} (paper: −0.5); wrote {}",
        s.runs,
        a.out.join("fit-lag").display()
    )?;
    match &s.drag_exponent {
        None if s.shared_exponent_at_bound => outln!(
            "  drag exponent: none (β is a bound: no power-law drag with 0.25 ≤ n ≤ 4 fits)"
        )?,
        Some(e) => outln!(
            "  drag exponent n = 1/(½ − β) = {:.3} ± {} (β ± 2σ: {:.3} to {}); the paper's \
             linear drag, n = 1, is {:.1}σ away",
            e.n,
            // Under a thousandth (a steep β's tiny σ_n), in two significant digits, not 0.000.
            if e.stderr >= 1e-3 {
                format!("{:.3}", e.stderr)
            } else {
                format!("{:.1e}", e.stderr)
            },
            e.low,
            if e.high.is_finite() {
                format!("{:.3}", e.high)
            } else {
                "no bound".into()
            },
            e.linear_sigmas
        )?,
        None => outln!(
            "  drag exponent: none (β ≥ ½: no power-law drag gives a lag time that does not \
             grow at α*)"
        )?,
    }
    for (k, f) in s.analysis.runs.iter().enumerate() {
        outln!(
            "  run {k}: α* = {:.5} (file: {}), β = {:.3} ± {:.3}",
            f.alpha_star,
            s.alpha_star_reported[k]
                .map(|v| format!("{v:.5}"))
                .unwrap_or_else(|| "-".into()),
            f.exponent,
            s.analysis.run_exponent_stderr[k]
        )?;
    }
    if s.at_bound && !a.allow_bound {
        bail!(
            "a fitted value is a bound, not a fit (the warnings above; files written to {}); \
             pass --allow-bound to accept it with exit 0",
            a.out.join("fit-lag").display()
        );
    }
    Ok(())
}
