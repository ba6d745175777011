//! `bench figures`: wall time of the full-size ensemble figures against their targets.

use std::time::Instant;

use anyhow::Result;

use super::FiguresBenchArgs;

/// Runs `bench figures`.
pub fn run(a: FiguresBenchArgs) -> Result<()> {
    let opts = crate::figures::FigureOptions {
        out: a.out.clone(),
        seed: 1,
        quick: false,
        ..crate::figures::FigureOptions::default()
    };
    let threads = rayon::current_num_threads();
    outln!(
        "{:<18} {:>10} {:>10}   ({threads} threads)",
        "figure",
        "wall s",
        "target s"
    )?;
    let timed = |name: &str, target: f64, f: &dyn Fn() -> Result<()>| -> Result<()> {
        let start = Instant::now();
        f()?;
        let wall = start.elapsed().as_secs_f64();
        outln!(
            "{name:<18} {wall:>10.1} {target:>10.0}{}",
            if wall <= target { "" } else { "   OVER TARGET" }
        )?;
        Ok(())
    };
    timed("sphere-poincare", 30.0, &|| {
        crate::figures::sphere_poincare::run(&opts).map(|_| ())
    })?;
    timed("sphere-cruising", 60.0, &|| {
        crate::figures::sphere_cruising::run(&opts).map(|_| ())
    })?;
    timed("sphere-doubling", 60.0, &|| {
        crate::figures::sphere_doubling::run(&opts).map(|_| ())
    })?;
    timed("sphere-bifurcation", 120.0, &|| {
        crate::figures::sphere_bifurcation::run(&opts).map(|_| ())
    })?;
    Ok(())
}
