//! How honest `track`'s period and its error are: synthetic tracks of known period (a drift
//! down the ramp, three harmonics with random amplitudes and phases, white noise), measured by
//! [`find_period`], with the share of stated 95 % intervals (±1.96 errors) that hold the truth
//! and the bias in units of the error. The estimate before the harmonic regression (the
//! cycles' mean, their spread over √(cycles)) is read from the same fit, so both stand side by
//! side on the same tracks. The advance per period (down and across) and the mean speed down
//! the ramp are measured the same way against the track's known drift. `rollphase bench
//! calibration` prints the table; a test holds the short periods, where the old estimate
//! failed, to the goal.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;
use serde::Serialize;

use super::{CleanTrack, PeriodSearch, find_period};

/// One kind of synthetic track.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrackCase {
    /// True period (frames).
    pub period_frames: f64,
    /// White noise per coordinate, in units of the first harmonic's amplitude.
    pub noise: f64,
    /// Periods in the track.
    pub cycles: f64,
}

/// The cases `bench calibration` runs: periods from 6.3 to 300 frames (whole and not), noise
/// 2 % and 20 % of the wobble.
pub const BENCH_CASES: [TrackCase; 16] = {
    const P: [f64; 8] = [6.3, 7.3, 10.4, 17.7, 30.0, 61.7, 150.0, 300.0];
    let mut out = [TrackCase {
        period_frames: 0.0,
        noise: 0.0,
        cycles: 0.0,
    }; 16];
    let mut k = 0;
    while k < 16 {
        out[k] = TrackCase {
            period_frames: P[k / 2],
            noise: if k % 2 == 0 { 0.02 } else { 0.2 },
            cycles: 20.0,
        };
        k += 1;
    }
    out
};

/// How one estimator did over the draws.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coverage {
    /// Draws it gave an estimate with an error for.
    pub estimates: usize,
    /// Share of them whose ±1.96-error interval holds the truth (goal 0.93–0.97).
    pub coverage: f64,
    /// Mean (estimate − truth) over the median stated error (goal: |bias| < 1/3).
    pub bias_in_errors: f64,
    /// The median stated error (in the estimate's units: frames for the period, the track's
    /// units for the advance, a frame for the speed).
    pub median_error: f64,
}

/// One case's calibration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseCalibration {
    /// The case.
    pub case: TrackCase,
    /// Draws made.
    pub draws: usize,
    /// Draws `find_period` gave no period for.
    pub refused: usize,
    /// Draws whose blocks read the turns' times as varying (then stated by the cycles' mean):
    /// about 1 % by design, as the tracks' turns do not vary.
    pub read_as_varying: usize,
    /// The cycles' mean with their spread over √(cycles) (the estimate before 2026-11-28).
    pub cycles_mean: Coverage,
    /// What `track` states now.
    pub stated: Coverage,
    /// The advance per period down the ramp and its stated error.
    pub advance_down: Coverage,
    /// The advance per period across the ramp (its truth is 0: the tracks drift straight down).
    pub advance_across: Coverage,
    /// The mean speed down the ramp (units a frame) and its stated error.
    pub speed: Coverage,
}

/// A synthetic track of `case`, seed `seed`.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::calibration::{TrackCase, synthetic_track};
/// let t = synthetic_track(&TrackCase { period_frames: 7.3, noise: 0.02, cycles: 20.0 }, 1);
/// assert_eq!(t.down.len(), 146);
/// ```
pub fn synthetic_track(case: &TrackCase, seed: u64) -> CleanTrack {
    synthetic_track_and_advance(case, seed).0
}

/// [`synthetic_track`] and its true advance per period down the ramp (units of the track).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::calibration::{TrackCase, synthetic_track_and_advance};
/// let (t, advance) = synthetic_track_and_advance(&TrackCase { period_frames: 7.3, noise: 0.02, cycles: 20.0 }, 1);
/// assert!((2.0..5.0).contains(&advance) && t.down.len() == 146);
/// ```
pub fn synthetic_track_and_advance(case: &TrackCase, seed: u64) -> (CleanTrack, f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, case.noise.max(0.0)).expect("a finite noise");
    let w = std::f64::consts::TAU / case.period_frames;
    let mut phase = || rng.random::<f64>() * std::f64::consts::TAU;
    let phases = [phase(), phase(), phase(), phase(), phase(), phase()];
    let amplitudes = [
        1.0,
        0.2 + 0.6 * rng.random::<f64>(),
        0.3 * rng.random::<f64>(),
    ];
    let advance = 2.0 + 3.0 * rng.random::<f64>();
    let frames = (case.period_frames * case.cycles).round() as usize;
    let (mut down, mut across) = (Vec::with_capacity(frames), Vec::with_capacity(frames));
    for i in 0..frames {
        let t = i as f64;
        let (mut d, mut a) = (advance * t / case.period_frames, 0.0);
        for (h, amplitude) in amplitudes.iter().enumerate() {
            let arg = (h + 1) as f64 * w * t;
            d += amplitude * (arg + phases[2 * h]).sin();
            a += 0.6 * amplitude * (arg + phases[2 * h + 1]).cos();
        }
        down.push(d + normal.sample(&mut rng));
        across.push(a + normal.sample(&mut rng));
    }
    let track = CleanTrack {
        frames: (0..frames).map(|i| i as f64).collect(),
        down,
        across,
        warnings: Vec::new(),
    };
    (track, advance)
}

/// Coverage of (estimate, error, truth) triples.
pub(crate) fn coverage(triples: &[(f64, f64, f64)]) -> Coverage {
    let n = triples.len();
    if n == 0 {
        return Coverage {
            estimates: 0,
            coverage: f64::NAN,
            bias_in_errors: f64::NAN,
            median_error: f64::NAN,
        };
    }
    let covered = triples
        .iter()
        .filter(|(e, s, truth)| (e - truth).abs() <= 1.96 * s)
        .count();
    let mut errors: Vec<f64> = triples.iter().map(|p| p.1).collect();
    errors.sort_by(f64::total_cmp);
    let median = errors[n / 2];
    let bias = triples.iter().map(|p| p.0 - p.2).sum::<f64>() / n as f64;
    Coverage {
        estimates: n,
        coverage: covered as f64 / n as f64,
        bias_in_errors: bias / median,
        median_error: median,
    }
}

/// Coverage of (estimate, error) pairs against one truth.
fn coverage_of(pairs: &[(f64, f64)], truth: f64) -> Coverage {
    coverage(
        &pairs
            .iter()
            .map(|&(e, s)| (e, s, truth))
            .collect::<Vec<_>>(),
    )
}

/// The coverage of what `pick` reads from each fit (estimate, error, truth), given the true
/// advance per period its track was drawn with.
fn covered(
    runs: &[(Option<super::PeriodFit>, f64)],
    pick: impl Fn(&super::PeriodFit, f64) -> Option<(f64, f64, f64)>,
) -> Coverage {
    let triples: Vec<_> = runs
        .iter()
        .filter_map(|(f, truth)| f.as_ref().and_then(|f| pick(f, *truth)))
        .collect();
    coverage(&triples)
}

/// Runs `draws` synthetic tracks of `case` (seeds `seed`, `seed + 1`, …, in parallel, the same
/// answer on every run) through [`find_period`] without surrogates (they decide whether a
/// period is stated, not its value), and measures both estimates.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::calibration::{TrackCase, calibrate_case};
/// let c = calibrate_case(&TrackCase { period_frames: 30.0, noise: 0.2, cycles: 20.0 }, 20, 1);
/// assert_eq!(c.draws, 20);
/// assert!(c.stated.coverage > 0.7);
/// ```
pub fn calibrate_case(case: &TrackCase, draws: usize, seed: u64) -> CaseCalibration {
    let search = PeriodSearch {
        surrogates: 0,
        ..PeriodSearch::default()
    };
    let runs: Vec<_> = (0..draws as u64)
        .into_par_iter()
        .map(|k| {
            let (track, advance) = synthetic_track_and_advance(case, seed.wrapping_add(k));
            (find_period(&track, &search, &|_, _| {}).ok(), advance)
        })
        .collect();
    let fits: Vec<_> = runs.iter().map(|r| r.0.clone()).collect();
    let stated: Vec<(f64, f64)> = fits
        .iter()
        .flatten()
        .map(|f| (f.period_frames, f.period_error_frames))
        .collect();
    let advance_down = covered(&runs, |f, truth| {
        f.advance_error.map(|e| (f.advance_down, e[0], truth))
    });
    let advance_across = covered(&runs, |f, _| {
        f.advance_error.map(|e| (f.advance_across, e[1], 0.0))
    });
    let cycles: Vec<(f64, f64)> = fits
        .iter()
        .flatten()
        .filter(|f| f.cycle_periods.len() >= 3)
        .map(|f| {
            let k = f.cycle_periods.len() as f64;
            let mean = f.cycle_periods.iter().sum::<f64>() / k;
            let var = f
                .cycle_periods
                .iter()
                .map(|p| (p - mean).powi(2))
                .sum::<f64>()
                / (k - 1.0);
            (mean, (var / k).sqrt())
        })
        .collect();
    let speed = covered(&runs, |f, truth| {
        f.velocity
            .map(|(v, e)| (v[0], e[0], truth / case.period_frames))
    });
    CaseCalibration {
        case: *case,
        draws,
        refused: fits.iter().filter(|f| f.is_none()).count(),
        read_as_varying: fits
            .iter()
            .flatten()
            .filter(|f| f.block_check.is_some_and(|b| b.turns_vary))
            .count(),
        cycles_mean: coverage_of(&cycles, case.period_frames),
        stated: coverage_of(&stated, case.period_frames),
        advance_down,
        advance_across,
        speed,
    }
}
