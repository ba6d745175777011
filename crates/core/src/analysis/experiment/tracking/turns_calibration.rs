//! How often the turn rule ([`super::turns`]) calls a roll chaotic or quasi-periodic whose turns
//! vary by chance, and how often it refuses a chaotic or quasi-periodic one: synthetic rolls whose turn sizes follow AR(1)
//! processes (the turns' correlation from ρ = −0.95 to 0.995, sizes varying 3–20 %, turn times
//! 0–5 %, white noise 0.1–10 % of the wobble, 8–60 frames and 20–100 turns), turn sizes the
//! logistic map drives (chaos from a one-dimensional map), sizes that swing with a second period
//! that is not a whole number of turns (quasi-periodic), and the Rössler attractor
//! (phase-coherent chaos) at three noise levels, each measured by [`find_period`]
//! without surrogates (they decide whether a track repeats, not whether its turns follow a
//! rule). `rollphase bench calibration` prints the table; the tests use the same tracks.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;
use serde::Serialize;

use super::mismatch::Detrended;
use super::turns::turn_rule;
use super::{CleanTrack, PeriodSearch, TrackError, find_period};

/// A roll of `turns` turns of about `period` frames whose sizes are `sizes(k)`, eased from turn
/// to turn, each turn's time varying by `jitter` (a fraction, drawn from `seed`), white noise of
/// `noise` (the wobble is about 1): down the ramp 0.1 a frame plus the wobble, across the
/// wobble and its second harmonic; frames 0, 1, 2, ….
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::turns_calibration::roll_track;
/// // 40 turns of 30 frames, sizes alternating 1 and 0.8, no jitter, 1 % noise.
/// let track = roll_track(&|k| if k % 2 == 0 { 1.0 } else { 0.8 }, (40, 30.0), (0.0, 0.01), 7);
/// assert_eq!(track.frames.len(), 39 * 30);
/// ```
pub fn roll_track(
    sizes: &dyn Fn(usize) -> f64,
    (turns, period): (usize, f64),
    (jitter, noise): (f64, f64),
    seed: u64,
) -> CleanTrack {
    roll_track_with(
        sizes,
        (turns, period),
        (jitter, noise),
        &mut ChaCha8Rng::seed_from_u64(seed),
    )
}

fn roll_track_with(
    sizes: &dyn Fn(usize) -> f64,
    (turns, period): (usize, f64),
    (jitter, noise): (f64, f64),
    rng: &mut ChaCha8Rng,
) -> CleanTrack {
    let normal = Normal::new(0.0, 1.0).expect("a unit normal");
    let durations: Vec<f64> = (0..turns)
        .map(|_| period * (1.0 + jitter * normal.sample(rng)).max(0.5))
        .collect();
    let (mut down, mut across) = (Vec::new(), Vec::new());
    let (mut k, mut start, mut f) = (0, 0.0, 0.0);
    while k + 1 < turns {
        if f >= start + durations[k] {
            start += durations[k];
            k += 1;
            continue;
        }
        let u = (f - start) / durations[k];
        let s = sizes(k) + (sizes(k + 1) - sizes(k)) * u;
        let phase = std::f64::consts::TAU * u;
        down.push(0.1 * f + s * phase.sin() + noise * normal.sample(rng));
        across.push(s * phase.cos() + 0.3 * s * (2.0 * phase).cos() + noise * normal.sample(rng));
        f += 1.0;
    }
    CleanTrack::on_frames(down, across)
}

/// A roll whose turns vary by chance, its settings drawn from `seed` over the ranges of the
/// module doc; returns the track and its turns' correlation ρ.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::turns_calibration::chance_roll;
/// let (track, rho) = chance_roll(3);
/// assert!(track.frames.len() > 100 && (-0.95..1.0).contains(&rho));
/// ```
pub fn chance_roll(seed: u64) -> (CleanTrack, f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let rho = -0.95 + 1.945 * rng.random::<f64>();
    let spread = 10f64.powf(-1.5 + 0.8 * rng.random::<f64>());
    let jitter = 0.05 * rng.random::<f64>();
    let noise = 10f64.powf(-3.0 + 2.0 * rng.random::<f64>());
    let period = 8.0 + 52.0 * rng.random::<f64>();
    let turns = 20 + (80.0 * rng.random::<f64>()) as usize;
    let normal = Normal::new(0.0, 1.0).expect("a unit normal");
    let mut x: f64 = normal.sample(&mut rng);
    let sizes: Vec<f64> = (0..turns)
        .map(|_| {
            x = rho * x + (1.0 - rho * rho).sqrt() * normal.sample(&mut rng);
            1.0 + spread * x
        })
        .collect();
    (
        roll_track_with(&|k| sizes[k], (turns, period), (jitter, noise), &mut rng),
        rho,
    )
}

/// The Rössler attractor ẋ = −y − z, ẏ = x + ay, ż = b + z(x − c) (a = b = 0.2) as a track: x
/// and y (times 0.05) down and across, a drift of 0.02 a frame down, white noise of `noise`
/// (the attractor spans about 0.5 across), 5 frames per time unit (a turn of about 29 frames),
/// after a transient of 3,000 frames from a start drawn by `seed` (classical Runge–Kutta, 10
/// steps a frame).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::turns_calibration::rossler_track;
/// let track = rossler_track(5.7, 600, 0.001, 1);
/// let widest = track.across.iter().fold(0.0f64, |m, v| m.max(v.abs()));
/// assert!(track.frames.len() == 600 && (0.3..1.0).contains(&widest));
/// ```
pub fn rossler_track(c: f64, frames: usize, noise: f64, seed: u64) -> CleanTrack {
    let f = |y: [f64; 3]| [-y[1] - y[2], y[0] + 0.2 * y[1], 0.2 + y[2] * (y[0] - c)];
    let axpy = |y: [f64; 3], k: [f64; 3], s: f64| [0, 1, 2].map(|i| y[i] + s * k[i]);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Each seed starts elsewhere on the way to the attractor, so its stretch is another.
    let (mut y, h) = ([1.0 + rng.random::<f64>(), 1.0, 0.0], 0.02);
    let normal = Normal::new(0.0, noise.max(0.0)).expect("a finite noise");
    let (mut down, mut across) = (Vec::new(), Vec::new());
    for i in 0..3000 + frames {
        if i >= 3000 {
            let t = (i - 3000) as f64;
            down.push(0.02 * t + 0.05 * y[0] + normal.sample(&mut rng));
            across.push(0.05 * y[1] + normal.sample(&mut rng));
        }
        for _ in 0..10 {
            let k1 = f(y);
            let k2 = f(axpy(y, k1, h / 2.0));
            let k3 = f(axpy(y, k2, h / 2.0));
            let k4 = f(axpy(y, k3, h));
            y = [0, 1, 2].map(|j| y[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]));
        }
    }
    CleanTrack::on_frames(down, across)
}

/// What the turn rule made of one set of tracks.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RuleReading {
    /// Tracks measured.
    pub tracks: usize,
    /// Refused as chaotic (their turns follow a rule).
    pub chaotic: usize,
    /// Refused as quasi-periodic (their turns swing with a second period).
    pub quasi_periodic: usize,
    /// Refused for another reason (no period with confidence, too short, …).
    pub refused_otherwise: usize,
    /// Given a period with a ratio read (the rest repeat closely or read none).
    pub read: usize,
    /// The ratios read, and those of the tracks refused as chaotic, sorted.
    pub ratios: Vec<f64>,
}

impl RuleReading {
    /// The `q` quantile of the ratios (NaN with none).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::turns_calibration::RuleReading;
    /// let r = RuleReading {
    ///     tracks: 3,
    ///     chaotic: 0,
    ///     quasi_periodic: 0,
    ///     refused_otherwise: 0,
    ///     read: 3,
    ///     ratios: vec![0.5, 1.0, 2.0],
    /// };
    /// assert_eq!((r.quantile(0.0), r.quantile(0.5), r.quantile(1.0)), (0.5, 1.0, 2.0));
    /// ```
    pub fn quantile(&self, q: f64) -> f64 {
        if self.ratios.is_empty() {
            return f64::NAN;
        }
        let k = ((q * (self.ratios.len() - 1) as f64).round() as usize).min(self.ratios.len() - 1);
        self.ratios[k]
    }
}

/// Measures `tracks` (each made from its index) and reads what the turn rule says.
fn read_rule(tracks: usize, make: &(dyn Fn(u64) -> CleanTrack + Sync)) -> RuleReading {
    let search = PeriodSearch {
        surrogates: 0,
        ..PeriodSearch::default()
    };
    let outcomes: Vec<(u8, Option<f64>)> = (0..tracks as u64)
        .into_par_iter()
        .map(|k| {
            let track = make(k);
            match find_period(&track, &search, &|_, _| {}) {
                Ok(fit) => (0, fit.turn_rule.and_then(|r| r.ratio)),
                Err(TrackError::NoPeriod { best_frames, why })
                    if why.ends_with("has no period") =>
                {
                    let rule = turn_rule(&Detrended::of(&track).z, best_frames);
                    (if rule.quasi_periodic() { 3 } else { 1 }, rule.ratio)
                }
                Err(_) => (2, None),
            }
        })
        .collect();
    let mut ratios: Vec<f64> = outcomes.iter().filter_map(|o| o.1).collect();
    ratios.sort_by(f64::total_cmp);
    RuleReading {
        tracks,
        chaotic: outcomes.iter().filter(|o| o.0 == 1).count(),
        quasi_periodic: outcomes.iter().filter(|o| o.0 == 3).count(),
        refused_otherwise: outcomes.iter().filter(|o| o.0 == 2).count(),
        read: outcomes
            .iter()
            .filter(|o| o.0 == 0 && o.1.is_some())
            .count(),
        ratios,
    }
}

/// `draws` rolls whose turns vary by chance ([`chance_roll`], seeds from `seed`).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::turns_calibration::chance_rolls;
/// let r = chance_rolls(20, 1);
/// assert_eq!((r.tracks, r.chaotic, r.quasi_periodic), (20, 0, 0));
/// ```
pub fn chance_rolls(draws: usize, seed: u64) -> RuleReading {
    read_rule(draws, &|k| chance_roll(seed.wrapping_add(k)).0)
}

/// `draws` rolls of 100 turns of 30 frames whose sizes (±15 %) follow the logistic map at r = 4
/// from a start drawn by the seed, eased from turn to turn (each peak mixes two turns' sizes),
/// with 0.2 % noise: chaos from a one-dimensional map.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::turns_calibration::logistic_rolls;
/// assert_eq!(logistic_rolls(4, 1).chaotic, 4);
/// ```
pub fn logistic_rolls(draws: usize, seed: u64) -> RuleReading {
    read_rule(draws, &|k| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(k));
        let mut x = 0.05 + 0.9 * rng.random::<f64>();
        let sizes: Vec<f64> = (0..100)
            .map(|_| {
                x = 4.0 * x * (1.0 - x);
                1.0 + 0.3 * (x - 0.5)
            })
            .collect();
        roll_track_with(&|k| sizes[k], (100, 30.0), (0.0, 0.002), &mut rng)
    })
}

/// `draws` rolls of 100 turns of 30 frames whose sizes swing by ±10 % with a second period of
/// k + 0.3 to k + 0.7 turns (k from 3 to 15, drawn by the seed), 1 % noise: quasi-periodic
/// motions, each drifting at least two turns from any whole-turn repeat along the track.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::turns_calibration::quasi_periodic_rolls;
/// assert_eq!(quasi_periodic_rolls(4, 1).quasi_periodic, 4);
/// ```
pub fn quasi_periodic_rolls(draws: usize, seed: u64) -> RuleReading {
    read_rule(draws, &|k| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(k));
        let second =
            (3 + (13.0 * rng.random::<f64>()) as usize) as f64 + 0.3 + 0.4 * rng.random::<f64>();
        let phase = std::f64::consts::TAU * rng.random::<f64>();
        let size = |k: usize| 1.0 + 0.1 * (std::f64::consts::TAU * k as f64 / second + phase).sin();
        roll_track_with(&size, (100, 30.0), (0.0, 0.01), &mut rng)
    })
}

/// `draws` stretches of 3,000 frames of the Rössler attractor at `c` with white noise `noise`
/// ([`rossler_track`], seeds from `seed`).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::turns_calibration::rossler_runs;
/// assert_eq!(rossler_runs(5.7, 0.001, 2, 1).chaotic, 2);
/// ```
pub fn rossler_runs(c: f64, noise: f64, draws: usize, seed: u64) -> RuleReading {
    read_rule(draws, &|k| {
        rossler_track(c, 3000, noise, seed.wrapping_add(k))
    })
}
