//! How honest `fit-lag`'s exponent and its error are: synthetic lag times drawn like the
//! authors' five runs (`assets/data/cylinder_lag_times.csv`: each run's α*, its number of angles
//! and how far above α* they reach, five repeats an angle, each run's scatter), from
//! t = A (α − α*)^β with log-normal noise, fitted by [`analyse`]. For the shared exponent and
//! each run's own, the share of stated 95 % intervals (±1.96 standard errors) that hold the
//! true β, and the bias in units of the error. `rollphase bench calibration` prints the table.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::Serialize;

use super::lag_times::{LagPoint, LagRun, analyse};

/// One run of the authors' data as the synthetic runs copy it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LagRunShape {
    /// Its α* (rad).
    pub alpha_star: f64,
    /// Angles measured.
    pub angles: usize,
    /// The lowest and highest angle's distance above α* (rad).
    pub above: (f64, f64),
    /// The repeats' scatter: standard deviation of ln t (≈ their coefficient of variation).
    pub log_scatter: f64,
}

/// The authors' five runs (median coefficient of variation of each run's five repeats).
pub const AUTHORS_RUNS: [LagRunShape; 5] = [
    LagRunShape {
        alpha_star: 0.18347,
        angles: 16,
        above: (0.00023, 0.0292),
        log_scatter: 0.187,
    },
    LagRunShape {
        alpha_star: 0.1549,
        angles: 48,
        above: (0.0002, 0.0668),
        log_scatter: 0.088,
    },
    LagRunShape {
        alpha_star: 0.2089,
        angles: 15,
        above: (0.0002, 0.0286),
        log_scatter: 0.167,
    },
    LagRunShape {
        alpha_star: 0.1224,
        angles: 12,
        above: (0.0004, 0.0154),
        log_scatter: 0.131,
    },
    LagRunShape {
        alpha_star: 0.058,
        angles: 9,
        above: (0.0004, 0.0091),
        log_scatter: 0.233,
    },
];

/// Repeats per angle, as measured.
pub const REPEATS: usize = 5;

/// Synthetic runs shaped like [`AUTHORS_RUNS`] with true exponent `beta` (t = 3 s at each run's
/// highest angle), seed `seed`.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::lag_calibration::{AUTHORS_RUNS, synthetic_lag_runs};
/// let runs = synthetic_lag_runs(-0.5, 1);
/// assert_eq!(runs.len(), 5);
/// assert_eq!(runs[1].points.len(), AUTHORS_RUNS[1].angles);
/// assert!(runs.iter().all(|r| r.points.iter().all(|p| p.times.len() == 5)));
/// ```
pub fn synthetic_lag_runs(beta: f64, seed: u64) -> Vec<LagRun> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    AUTHORS_RUNS
        .iter()
        .enumerate()
        .map(|(k, shape)| {
            let noise = Normal::new(0.0, shape.log_scatter).expect("a finite scatter");
            let (lo, hi) = shape.above;
            let prefactor = 3.0 / hi.powf(beta);
            let points = (0..shape.angles)
                .map(|i| {
                    let d = lo + (hi - lo) * i as f64 / (shape.angles - 1).max(1) as f64;
                    let t = prefactor * d.powf(beta);
                    LagPoint {
                        alpha: shape.alpha_star + d,
                        times: (0..REPEATS)
                            .map(|_| t * noise.sample(&mut rng).exp())
                            .collect(),
                    }
                })
                .collect();
            LagRun {
                run: k as i64,
                alpha_star_reported: Some(shape.alpha_star),
                points,
            }
        })
        .collect()
}

/// How one estimate did over the draws.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LagCoverage {
    /// Draws with an estimate and a finite, positive error.
    pub estimates: usize,
    /// Share whose ±1.96-error interval holds the true β (goal 0.93–0.97).
    pub coverage: f64,
    /// Mean (estimate − truth) over the median stated error (goal |bias| < 1/3).
    pub bias_in_errors: f64,
    /// The median stated error.
    pub median_error: f64,
    /// √(mean ((estimate − truth)/error)²): 1 for honest errors, above 1 when they are too
    /// small, below when too large.
    pub rms_z: f64,
}

fn coverage(pairs: &[(f64, f64)], truth: f64) -> LagCoverage {
    let good: Vec<(f64, f64)> = pairs
        .iter()
        .copied()
        .filter(|(v, e)| v.is_finite() && e.is_finite() && *e > 0.0)
        .collect();
    let n = good.len();
    let held = good
        .iter()
        .filter(|(v, e)| (v - truth).abs() <= 1.96 * e)
        .count();
    let mut errors: Vec<f64> = good.iter().map(|p| p.1).collect();
    errors.sort_by(f64::total_cmp);
    let median = errors.get(n / 2).copied().unwrap_or(f64::NAN);
    let bias = good.iter().map(|(v, _)| v - truth).sum::<f64>() / n.max(1) as f64;
    let z2 = good
        .iter()
        .map(|(v, e)| ((v - truth) / e).powi(2))
        .sum::<f64>()
        / n.max(1) as f64;
    LagCoverage {
        estimates: n,
        coverage: held as f64 / n.max(1) as f64,
        bias_in_errors: bias / median,
        median_error: median,
        rms_z: z2.sqrt(),
    }
}

/// The calibration of one true β.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LagCalibration {
    /// The true exponent.
    pub beta: f64,
    /// Data sets drawn.
    pub draws: usize,
    /// Bootstrap resamples each fit used.
    pub bootstrap: usize,
    /// Data sets the analysis gave no answer for.
    pub refused: usize,
    /// The shared exponent.
    pub shared: LagCoverage,
    /// Each run's own exponent, all runs pooled.
    pub per_run: LagCoverage,
}

/// Draws `draws` data sets with true exponent `beta` and fits each with `bootstrap` resamples.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::lag_calibration::calibrate_lag;
/// let c = calibrate_lag(-0.5, 2, 10, 1);
/// assert_eq!((c.draws, c.shared.estimates), (2, 2));
/// assert!(c.shared.median_error > 0.0 && c.shared.median_error < 0.2);
/// ```
pub fn calibrate_lag(beta: f64, draws: usize, bootstrap: usize, seed: u64) -> LagCalibration {
    let fits: Vec<_> = (0..draws as u64)
        .map(|k| {
            let runs = synthetic_lag_runs(beta, seed.wrapping_add(k));
            analyse(&runs, bootstrap, seed.wrapping_add(k).wrapping_mul(7919))
        })
        .collect();
    let shared: Vec<(f64, f64)> = fits
        .iter()
        .flatten()
        .map(|a| (a.shared_exponent, a.shared_exponent_stderr))
        .collect();
    let per_run: Vec<(f64, f64)> = fits
        .iter()
        .flatten()
        .flat_map(|a| {
            a.runs
                .iter()
                .zip(&a.run_exponent_stderr)
                .map(|(r, e)| (r.exponent, *e))
                .collect::<Vec<_>>()
        })
        .collect();
    LagCalibration {
        beta,
        draws,
        bootstrap,
        refused: fits.iter().filter(|f| f.is_none()).count(),
        shared: coverage(&shared, beta),
        per_run: coverage(&per_run, beta),
    }
}
