//! The check of a track's period against chance: surrogate tracks with the track's power
//! spectrum smoothed in frequency and random phases (a fixed seed per surrogate), searched as the
//! track is; the track's dip must be well below the lowest any of them reaches. The rules and
//! their constants are [`super::period`]'s (its module doc, "Evidence that it is there").

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;

use super::mismatch::{Curve, Detrended, lowest_dip, next_pow2, normalised};

/// A surrogate's spectrum is the track's averaged over frequencies f/ρ … f·ρ.
pub const SMOOTHING_RATIO: f64 = 1.5;

/// The surrogates' seed: the same track gives the same answer on every run.
const SURROGATE_SEED: u64 = 0x5EED_7AC4;

/// The lowest d′ that `count` surrogate tracks ([`super::period::SURROGATES`] by default) reach: the track's spectrum (of z, so
/// the sense of any rotation is kept) averaged over f/ρ … f·ρ on each side, random phases, a
/// fixed seed per surrogate (the same on every run, whatever the thread count).
pub(super) fn surrogate_floor(
    det: &Detrended,
    count: usize,
    max_tau: usize,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> f64 {
    // The spectrum and the surrogates at a power-of-two length (the track zero-padded, each
    // surrogate cut to the track's length): a track of awkward length would otherwise take
    // Bluestein's three FFTs per transform, and the spectrum is smoothed over ±50 % anyway.
    let len = det.z.len();
    let n = next_pow2(len);
    let mut planner = FftPlanner::new();
    let mut spectrum = det.z.clone();
    spectrum.resize(n, Complex64::new(0.0, 0.0));
    planner.plan_fft_forward(n).process(&mut spectrum);
    // Signed frequency index of bin k: k for k ≤ n/2, k − n above.
    let power: Vec<f64> = spectrum.iter().map(Complex64::norm_sqr).collect();
    let half = n / 2;
    let mut smoothed = vec![0.0; n];
    for sign in [1i64, -1] {
        // |f| = 1 … half on this side, prefix sums over |f|.
        let bin = |f: usize| -> usize { if sign > 0 { f } else { (n - f) % n } };
        let mut prefix = vec![0.0; half + 2];
        for f in 1..=half {
            prefix[f + 1] = prefix[f] + power[bin(f)];
        }
        for f in 1..=half {
            let a = ((f as f64 / SMOOTHING_RATIO).ceil() as usize).max(1);
            let b = ((f as f64 * SMOOTHING_RATIO).floor() as usize).clamp(a, half);
            smoothed[bin(f)] = (prefix[b + 1] - prefix[a]) / (b + 1 - a) as f64;
        }
    }
    let amplitude: Vec<f64> = smoothed.iter().map(|p| p.sqrt()).collect();
    let done = std::sync::atomic::AtomicUsize::new(0);
    (0..count)
        .into_par_iter()
        .map(|s| {
            let mut rng = ChaCha8Rng::seed_from_u64(SURROGATE_SEED.wrapping_add(s as u64));
            let mut z: Vec<Complex64> = amplitude
                .iter()
                .map(|&a| Complex64::from_polar(a, rng.random::<f64>() * std::f64::consts::TAU))
                .collect();
            z[0] = Complex64::new(0.0, 0.0);
            let mut planner = FftPlanner::new();
            planner.plan_fft_inverse(n).process(&mut z);
            z.truncate(len);
            let det = Detrended::of_signal(z);
            let scale = det.scale();
            let e: Vec<f64> = Curve::of(&det.z, max_tau, &mut planner)
                .e
                .into_iter()
                .map(|v| v / scale)
                .collect();
            let floor = lowest_dip(&normalised(&e));
            progress(
                done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                count,
            );
            floor
        })
        .collect::<Vec<f64>>()
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}
