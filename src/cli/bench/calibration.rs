//! `bench calibration`: how often `track`'s stated 95 % interval holds a synthetic track's
//! known period, and its bias in units of the error, beside the estimate it replaced (the
//! cycles' mean and spread) on the same tracks. The tracks and statistics are the core's
//! ([`crate::analysis::experiment::tracking::calibration`]).

use anyhow::{Result, bail};

use super::CalibrationBenchArgs;
use crate::analysis::experiment::tracking::calibration::{BENCH_CASES, Coverage, calibrate_case};

fn cells(c: &Coverage) -> String {
    if c.estimates == 0 {
        return format!("{:>9} {:>9}", "—", "—");
    }
    format!("{:>8.1}% {:>+9.2}", 100.0 * c.coverage, c.bias_in_errors)
}

/// Runs `bench calibration`.
pub fn run(a: CalibrationBenchArgs) -> Result<()> {
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
            c.stated.median_error_frames
        )?;
    }
    outln!(
        "all cases: {:.1} % of {total} stated intervals hold the truth",
        100.0 * covered / total.max(1) as f64
    )?;
    Ok(())
}
