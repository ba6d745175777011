//! The paper's figures as commands (`rollphase figure NAME`): each module computes one figure's
//! numbers with the core, and writes `data.csv`, `figure.png` and `summary.json` (the headline
//! numbers) to `OUT/NAME/`. Each module's doc says which paper figure it reproduces and how.
//!
//! Ensembles run in parallel with rayon; every member's inputs derive from its index and the
//! seed alone, and results are collected in index order, so the numbers (and files) are the same
//! for any thread count.

pub mod disk_flow;
pub mod disk_hysteresis;
pub mod disk_lag_time;
pub mod disk_transition;
pub mod fit_lag;
pub mod sphere_cruising;
pub mod sphere_doubling;
pub mod sphere_halting;
pub mod sphere_orbits;
pub mod sphere_poincare;
pub mod sphere_tube;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde::Serialize;

use crate::geometry::{Body, Disk, Sphere, random_disk, random_sphere};

/// Options shared by every figure.
#[derive(Debug, Clone)]
pub struct FigureOptions {
    /// Output folder; files go to OUT/NAME/.
    pub out: PathBuf,
    /// Seed of the random bodies and orientations.
    pub seed: u64,
    /// A reduced run for tests (each under ~20 s).
    pub quick: bool,
}

impl FigureOptions {
    /// Creates and returns OUT/NAME.
    pub fn dir(&self, name: &str) -> Result<PathBuf> {
        let d = self.out.join(name);
        std::fs::create_dir_all(&d).with_context(|| format!("cannot create {}", d.display()))?;
        Ok(d)
    }
}

/// The names `rollphase figure` accepts, with a one-line description each.
pub const FIGURES: &[(&str, &str)] = &[
    (
        "disk-transition",
        "Fig. 2d: 2π/T versus α for random disks; the √(α − α*) law and its prefactor",
    ),
    (
        "disk-hysteresis",
        "Fig. 2e: inertial disk (m/m0 = 10), α swept up and down: α*, α** and hysteresis",
    ),
    (
        "disk-lag-time",
        "Fig. 2f: lag time versus α − α* for m/m0 = 0.5, 2, 10; exponent −1/2",
    ),
    (
        "disk-flow",
        "SI Fig. S2: the (θ, θ̇) flow at six α around α*, fixed points and a trajectory",
    ),
];

/// Writes rows of numbers as CSV; non-finite values become empty fields.
pub fn write_csv(path: &Path, header: &str, rows: &[Vec<f64>]) -> Result<()> {
    let mut s = String::with_capacity(rows.len() * 64);
    s.push_str(header);
    s.push('\n');
    for r in rows {
        let line: Vec<String> = r
            .iter()
            .map(|v| {
                if v.is_finite() {
                    v.to_string()
                } else {
                    String::new()
                }
            })
            .collect();
        let _ = writeln!(s, "{}", line.join(","));
    }
    std::fs::write(path, s).with_context(|| format!("cannot write {}", path.display()))
}

/// Writes the summary as pretty JSON.
pub fn write_summary(path: &Path, summary: &impl Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(summary)? + "\n";
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// A progress bar on standard error (hidden when it is not a terminal).
pub fn progress(len: usize, what: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg:>18} {bar:40} {pos}/{len} {elapsed}/{eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_message(what.to_string());
    bar
}

/// `f(i)` for i in 0..n in parallel, results in index order (thread-count independent).
pub fn par_map<T: Send>(
    n: usize,
    bar: &indicatif::ProgressBar,
    f: impl Fn(usize) -> T + Sync + Send,
) -> Vec<T> {
    let out = (0..n)
        .into_par_iter()
        .map(|i| {
            let r = f(i);
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    out
}

/// The first strictly convex random disk at seed, seed + 1, …: (disk, seed used).
pub fn convex_disk(seed: u64, sigma: f64, modes: u32) -> Result<(Disk, u64)> {
    for s in seed..seed.saturating_add(1000) {
        let d = random_disk(s, sigma, modes)?;
        if Body::Disk(d.clone()).check_convex().is_ok() {
            return Ok((d, s));
        }
    }
    anyhow::bail!("no convex disk among 1000 seeds from {seed} (σ = {sigma}, M = {modes})")
}

/// The first strictly convex random sphere (σ = 0.25, l ≤ 5) at seed, seed + 1, …
pub fn convex_sphere(seed: u64) -> Result<(Sphere, u64)> {
    for s in seed..seed.saturating_add(1000) {
        let b = random_sphere(s, 0.25, 5)?;
        if Body::Sphere(b.clone()).check_convex().is_ok() {
            return Ok((b, s));
        }
    }
    anyhow::bail!("no convex sphere among 1000 seeds from {seed}")
}
