//! `bench figures`: wall time of every figure at full size, beside the same figures measured
//! before the ensemble speed-up and the targets (sphere-cruising ≤ 25 s, all ≤ 60 s on the
//! 2-core development machine).

use std::time::Instant;

use anyhow::Result;

use super::FiguresBenchArgs;
use crate::figures::{FIGURES, FigureOptions};

/// Seconds per figure at 8344286 (before the ensemble speed-up), measured with the release
/// build on the 2-core development machine, each figure as one whole `rollphase figure NAME`
/// process. When the issue was filed (before the 3D right-hand side was made 3× cheaper) the
/// whole paper took 97 s and sphere-cruising 44–65 s.
const BEFORE: &[(&str, f64)] = &[
    ("disk-transition", 15.1),
    ("disk-hysteresis", 0.17),
    ("disk-lag-time", 0.18),
    ("disk-flow", 0.05),
    ("sphere-cruising", 12.3),
    ("sphere-orbits", 0.68),
    ("sphere-poincare", 2.21),
    ("sphere-doubling", 9.93),
    ("sphere-bifurcation", 25.3),
    ("sphere-halting", 0.05),
    ("sphere-tube", 0.08),
];
const BEFORE_TOTAL: f64 = 66.0;
const CRUISING_TARGET: f64 = 25.0;
const TOTAL_TARGET: f64 = 60.0;

/// Runs `bench figures`.
pub fn run(a: FiguresBenchArgs) -> Result<()> {
    let opts = FigureOptions {
        out: a.out.clone(),
        seed: 1,
        quick: a.quick,
        ..FigureOptions::default()
    };
    let threads = rayon::current_num_threads();
    outln!(
        "{:<20} {:>10} {:>10} {:>10}   ({threads} threads, {})",
        "figure",
        "before s",
        "now s",
        "target s",
        if a.quick {
            "--quick: no targets"
        } else {
            "full size"
        }
    )?;
    let mut total = 0.0;
    for f in FIGURES {
        let start = Instant::now();
        (f.run)(&opts)?;
        let wall = start.elapsed().as_secs_f64();
        total += wall;
        let before = BEFORE
            .iter()
            .find(|b| b.0 == f.name && !a.quick)
            .map_or("-".to_string(), |b| format!("{:.2}", b.1));
        let target = (f.name == "sphere-cruising" && !a.quick).then_some(CRUISING_TARGET);
        outln!(
            "{:<20} {before:>10} {wall:>10.2} {:>10}{}",
            f.name,
            target.map_or("-".into(), |t| format!("{t:.0}")),
            if target.is_some_and(|t| wall > t) {
                "   OVER TARGET"
            } else {
                ""
            }
        )?;
    }
    if a.quick {
        outln!(
            "{:<20} {:>10} {total:>10.1} {:>10}",
            "all figures",
            "-",
            "-"
        )?;
        return Ok(());
    }
    outln!(
        "{:<20} {BEFORE_TOTAL:>10.1} {total:>10.1} {TOTAL_TARGET:>10.0}{}",
        "all figures",
        if total > TOTAL_TARGET {
            "   OVER TARGET"
        } else {
            ""
        }
    )?;
    Ok(())
}
