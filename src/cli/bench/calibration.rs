//! `bench calibration`: how often `track`'s stated 95 % interval holds a synthetic track's
//! known period, and its bias in units of the error, beside the estimate it replaced (the
//! cycles' mean and spread) on the same tracks; the same for the advance per period and the
//! speed; then the same for `fit-lag`'s exponent on
//! synthetic runs shaped like the authors', and for the mesh fit's ⟨r⟩ and α* on noisy
//! meshes of the paper's bodies. The data and statistics are the core's
//! ([`crate::analysis::experiment::tracking::calibration`],
//! [`crate::analysis::experiment::lag_calibration`],
//! [`crate::analysis::experiment::mesh_calibration`]).

use anyhow::{Result, bail};

use super::CalibrationBenchArgs;
use crate::analysis::experiment::tracking::calibration::{
    BENCH_CASES, CaseCalibration, Coverage, calibrate_case,
};

/// The median stated error, or a dash where none was stated.
fn median(c: &Coverage) -> String {
    if c.estimates == 0 {
        "—".to_string()
    } else {
        format!("{:.2e}", c.median_error)
    }
}

fn cells(c: &Coverage) -> String {
    if c.estimates == 0 {
        return format!("{:>9} {:>9}", "—", "—");
    }
    format!("{:>8.1}% {:>+9.2}", 100.0 * c.coverage, c.bias_in_errors)
}

/// Runs `bench calibration`.
pub fn run(a: CalibrationBenchArgs) -> Result<()> {
    // Every count is checked before the first table's minute of work.
    if !(a.lag_draws == 0 || (10..=10_000).contains(&a.lag_draws))
        || !(10..=100_000).contains(&a.lag_bootstrap)
    {
        bail!(
            "--lag-draws {} --lag-bootstrap {} is not allowed (needs 10 to 10000 data sets, or 0 \
             for none, and 10 to 100000 resamples)",
            a.lag_draws,
            a.lag_bootstrap
        );
    }
    if !(a.mesh_draws == 0 || (10..=10_000).contains(&a.mesh_draws)) {
        bail!(
            "--mesh-draws {} is not allowed (needs 10 to 10000 meshes per case, or 0 for none)",
            a.mesh_draws
        );
    }
    if !(10..=100_000).contains(&a.draws) {
        bail!(
            "--draws {} is not allowed (needs 10 to 100000 tracks per case; 200 gives each \
             coverage to ±1.5 %)",
            a.draws
        );
    }
    outln!(
        "track's period on synthetic tracks of known period (20 periods each, {} draws a case): \
         share of ±1.96σ intervals holding the truth (goal 93–97 %) and mean offset / σ (goal \
         |bias| < 0.33)",
        a.draws
    )?;
    outln!(
        "{:>8} {:>6} {:>8} {:>8} | {:>9} {:>9} | {:>9} {:>9} {:>11}",
        "period",
        "noise",
        "refused",
        "varying",
        "before",
        "bias",
        "now",
        "bias",
        "median σ"
    )?;
    let (mut covered, mut total) = (0.0, 0usize);
    let mut done = Vec::with_capacity(BENCH_CASES.len());
    for case in &BENCH_CASES {
        let c = calibrate_case(case, a.draws, a.seed);
        if c.stated.estimates > 0 {
            covered += c.stated.coverage * c.stated.estimates as f64;
            total += c.stated.estimates;
        }
        outln!(
            "{:>8.1} {:>6.2} {:>8} {:>8} | {} | {} {:>11.2e}",
            case.period_frames,
            case.noise,
            c.refused,
            c.read_as_varying,
            cells(&c.cycles_mean),
            cells(&c.stated),
            c.stated.median_error
        )?;
        done.push(c);
    }
    outln!(
        "all cases: {:.1} % of {total} stated intervals hold the truth",
        100.0 * covered / total.max(1) as f64
    )?;
    motion_table(&done)?;
    rule_table(&a)?;
    lag_table(&a)?;
    mesh_table(&a)
}

/// The mesh fit's ⟨r⟩ and α*: `--mesh-draws` noisy meshes of the paper's bodies a case.
fn mesh_table(a: &CalibrationBenchArgs) -> Result<()> {
    use crate::analysis::experiment::mesh_calibration::{BENCH_MESH_CASES, calibrate_mesh_case};
    if a.mesh_draws == 0 {
        return Ok(());
    }
    outln!(
        "\nthe mesh fit's ⟨r⟩ and α* on meshes of the paper's bodies (3D: icospheres of the \
         seed-219 sphere; 2D: extrusions of the seed-84 disk), each vertex moved along its ray by \
         Gaussian noise ({} meshes a case, fitted at degree 5): share of ±1.96σ intervals \
         holding the noiseless mesh's fit, mean offset / σ, and the median σ (⟨r⟩ ≈ 1; α* in \
         rad)",
        a.mesh_draws
    )?;
    outln!(
        "{:>3} {:>9} {:>7} {:>9} | {:>9} {:>9} {:>9} | {:>9} {:>9} {:>9} {:>9}",
        "dim",
        "triangles",
        "noise",
        "no error",
        "⟨r⟩",
        "bias",
        "σ",
        "α* none",
        "α*−bias",
        "bias",
        "σ"
    )?;
    let mut pooled = [(0.0, 0usize); 2];
    for case in &BENCH_MESH_CASES {
        let c = calibrate_mesh_case(case, a.mesh_draws, a.seed)?;
        for (k, p) in [&c.scale, &c.alpha_star].into_iter().zip(&mut pooled) {
            if k.estimates > 0 {
                p.0 += k.coverage * k.estimates as f64;
                p.1 += k.estimates;
            }
        }
        outln!(
            "{:>3} {:>9} {:>6.2}% {:>9} | {} {:>9} | {:>9} {} {:>9}",
            case.dimension,
            case.triangles(),
            100.0 * case.noise,
            c.without_errors,
            cells(&c.scale),
            median(&c.scale),
            c.alpha_without_error,
            cells(&c.alpha_star),
            median(&c.alpha_star)
        )?;
    }
    let share = |p: (f64, usize)| 100.0 * p.0 / p.1.max(1) as f64;
    outln!(
        "all cases: {:.1} % of {} stated ⟨r⟩ intervals and {:.1} % of {} α* intervals hold the \
         truth",
        share(pooled[0]),
        pooled[0].1,
        share(pooled[1]),
        pooled[1].1
    )?;
    Ok(())
}

/// The same tracks' advance per period (down, and across where the truth is 0) and mean speed
/// down the ramp, against the drift the tracks were drawn with.
fn motion_table(done: &[CaseCalibration]) -> Result<()> {
    outln!(
        "\ntrack's advance per period and speed on the same tracks (the drift drawn uniformly in 2–5 units a period, straight down): coverage and bias / σ as above"
    )?;
    outln!(
        "{:>8} {:>6} | {:>9} {:>9} | {:>9} {:>9} | {:>9} {:>9}",
        "period",
        "noise",
        "down",
        "bias",
        "across",
        "bias",
        "speed",
        "bias"
    )?;
    // Pooled over the cases: intervals holding the truth and intervals stated, per column.
    let mut pooled = [(0.0, 0usize); 3];
    for c in done {
        for (k, p) in [&c.advance_down, &c.advance_across, &c.speed]
            .into_iter()
            .zip(&mut pooled)
        {
            if k.estimates > 0 {
                p.0 += k.coverage * k.estimates as f64;
                p.1 += k.estimates;
            }
        }
        outln!(
            "{:>8.1} {:>6.2} | {} | {} | {}",
            c.case.period_frames,
            c.case.noise,
            cells(&c.advance_down),
            cells(&c.advance_across),
            cells(&c.speed)
        )?;
    }
    let share = |p: (f64, usize)| 100.0 * p.0 / p.1.max(1) as f64;
    outln!(
        "all cases: {:.1} % (down), {:.1} % (across) and {:.1} % (speed) of {} stated intervals \
         each hold the truth",
        share(pooled[0]),
        share(pooled[1]),
        share(pooled[2]),
        pooled[0].1
    )?;
    Ok(())
}

/// The turn rule: `--draws` × 5 rolls whose turns vary by chance, none of which may be called
/// chaotic or quasi-periodic, and `--draws` / 4 each of logistic-map rolls, rolls with a second
/// period, and stretches of the Rössler attractor at each of two c and three noises, which it
/// should refuse where the noise lets the rule show.
fn rule_table(a: &CalibrationBenchArgs) -> Result<()> {
    use crate::analysis::experiment::tracking::turns::{MIN_TURNS, RULE_RATIO};
    use crate::analysis::experiment::tracking::turns_calibration::{
        RuleReading, chance_rolls, logistic_rolls, quasi_periodic_rolls, rossler_runs,
    };
    outln!(
        "\ntrack's turn rule (a chaotic or quasi-periodic track gets no period): each turn's peak \
         predicted by its nearest analogue's successor (from 1 to 3 peaks before), the error over \
         the best straight line's (turns that vary by chance read about 2; a rule, under \
         {RULE_RATIO} over {MIN_TURNS} turns or more, is refused as chaotic), and a second period \
         of the turns (refused as quasi-periodic)"
    )?;
    outln!(
        "{:<34} {:>6} {:>8} {:>8} {:>8} {:>6} {:>8} {:>8} {:>8} {:>8}",
        "tracks",
        "count",
        "chaotic",
        "quasi",
        "refused",
        "read",
        "lowest",
        "ratio 1%",
        "median",
        "99%"
    )?;
    let share = |k: usize, r: &RuleReading| 100.0 * k as f64 / r.tracks.max(1) as f64;
    // A quantile, or a dash where no ratio was read (a second period refuses before one is).
    let q = |r: &RuleReading, at: f64| {
        let v = r.quantile(at);
        if v.is_nan() {
            format!("{:>8}", "—")
        } else {
            format!("{v:>8.3}")
        }
    };
    let row = |name: String, r: &RuleReading| {
        outln!(
            "{:<34} {:>6} {:>7.1}% {:>7.1}% {:>8} {:>6} {} {} {} {}",
            name,
            r.tracks,
            share(r.chaotic, r),
            share(r.quasi_periodic, r),
            r.refused_otherwise,
            r.read,
            q(r, 0.0),
            q(r, 0.01),
            q(r, 0.5),
            q(r, 0.99)
        )
    };
    let few = (a.draws / 4).max(10);
    row(
        "turns varying by chance (AR(1))".into(),
        &chance_rolls(5 * a.draws, a.seed),
    )?;
    row(
        "logistic-map sizes, eased".into(),
        &logistic_rolls(few, a.seed),
    )?;
    row(
        "sizes with a second period".into(),
        &quasi_periodic_rolls(few, a.seed),
    )?;
    for c in [5.0, 5.7] {
        for noise in [0.001, 0.01, 0.03] {
            row(
                format!("Rössler c = {c}, noise {:.1} %", 100.0 * noise / 0.5),
                &rossler_runs(c, noise, few, a.seed),
            )?;
        }
    }
    outln!(
        "(chaotic, quasi: refused as such, the goal 0 % for turns that vary by chance and 100 % \
         for the maps, the second periods and the attractor where its noise lets the rule show; \
         refused: no period for another reason; read: given a period, with a ratio)"
    )?;
    Ok(())
}

/// fit-lag's exponent: `--lag-draws` data sets a true β, each fitted as `fit-lag` fits (with
/// `--lag-bootstrap` resamples).
fn lag_table(a: &CalibrationBenchArgs) -> Result<()> {
    use crate::analysis::experiment::lag_calibration::{LagCoverage, calibrate_lag};
    if a.lag_draws == 0 {
        return Ok(());
    }
    let cell = |c: &LagCoverage| {
        format!(
            "{:>8.1}% {:>+9.2} {:>9.4} {:>6.2}",
            100.0 * c.coverage,
            c.bias_in_errors,
            c.median_error,
            c.rms_z
        )
    };
    outln!(
        "\nfit-lag's exponent on synthetic runs shaped like the authors' five ({} data sets a β, \
         {} bootstrap resamples each): share of β ± 1.96σ holding the true β, mean offset / σ, \
         median σ, and rms of (β − truth)/σ (1 when σ is honest)",
        a.lag_draws,
        a.lag_bootstrap
    )?;
    outln!(
        "{:>6} {:>8} | {:>9} {:>9} {:>9} {:>6} | {:>9} {:>9} {:>9} {:>6}",
        "β",
        "refused",
        "shared",
        "bias",
        "σ",
        "rms z",
        "per run",
        "bias",
        "σ",
        "rms z"
    )?;
    for beta in [-0.5, -1.5] {
        let c = calibrate_lag(beta, a.lag_draws, a.lag_bootstrap, a.seed);
        outln!(
            "{beta:>6.2} {:>8} | {} | {}",
            c.refused,
            cell(&c.shared),
            cell(&c.per_run)
        )?;
    }
    Ok(())
}
