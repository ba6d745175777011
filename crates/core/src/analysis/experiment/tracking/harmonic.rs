//! The period to a fraction of a frame: the track fitted, at its own frames, as a line plus H
//! harmonics of 1/T, and T taken where the least-squares residual is smallest.
//!
//! Why not the cycles' own best shifts (the estimate before this one): a shift is read between
//! whole frames by interpolating the mismatch, and a short period's harmonics lie near or above
//! the frame rate's Nyquist limit, where no interpolation of the samples is right. Every cycle
//! then shares one bias, which their spread cannot see: 7.3 frames came back as 7.2467 ±
//! 0.0011. The regression evaluates its model at the frames themselves, so an aliased harmonic
//! is fitted where it truly is, and the least-squares T is unbiased at any period the search
//! accepts (6 frames and more).
//!
//! Its standard error is Gauss–Newton's, σ_T² = s² / |(I − P) ∂model/∂T|² (P the projection on
//! the linear part, s² the residual variance per real component), inflated by (1 + ρ)/(1 − ρ)
//! for residuals correlated from frame to frame (ρ their lag-1 correlation: a tracker's
//! smoothing, or a motion that is not exactly periodic). `bench calibration` measures its
//! coverage on synthetic tracks of known period.
//!
//! Written here because what is needed is one small linear solve per trial period: the Gram
//! matrix of exponentials depends only on differences of harmonics, so a trial costs O(n·H).
//! The search goes coarse to fine over longer and longer stretches of the track, each stretch's
//! grid finer than its residual's valley is wide, so a long track's narrow valley is never
//! stepped over.

use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64;

/// Most harmonics fitted (a rolling body's track is smooth: a few carry it).
pub const MAX_HARMONICS: usize = 32;
/// Harmonics fitted when the track's spectrum says nothing (too short to read).
const DEFAULT_HARMONICS: usize = 8;
/// A harmonic's strength above which it is no chance: Gamma(2, 1) exceeds 30 with
/// probability 31·e⁻³⁰ ≈ 3e-12.
pub const SIGNIFICANT_STRENGTH: f64 = 30.0;
/// The least share of the strongest harmonic's power a significant one carries (an amplitude of
/// 0.1 % of its): what is weaker in a noise-free track is the file's rounding, which repeats
/// with the samples. A circle of 29.4 frames written to six decimals repeats exactly only after
/// 147 frames, and its rounding's harmonics of 147 (amplitude 2e-6 of the circle's) made that
/// the period (a helper's finding, 2026-12-04). Strengths share one noise level across the
/// harmonics, so their ratio is the powers'.
pub const SIGNIFICANT_SHARE: f64 = 1e-6;
/// The floor of the noise a harmonic is measured against, relative to the track's mean square:
/// a noiseless track's residual is round-off.
const ROUND_OFF: f64 = 1e-20;
/// The period's error is at least this fraction of it: a noiseless track's fit reaches the
/// truth to about 1e-9 of it, and its Gauss–Newton error would be round-off alone.
const ERROR_FLOOR: f64 = 1e-8;
/// Cycles in the search's first stretch.
const FIRST_CYCLES: f64 = 32.0;
/// Grid points per valley half-width.
const POINTS_PER_WIDTH: f64 = 4.0;
/// Golden-section steps after the grid: the last cell shrinks by 0.618⁴⁰ ≈ 4e-9.
const GOLDEN_STEPS: usize = 40;

/// The regression's answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HarmonicPeriod {
    /// The period (frames).
    pub period_frames: f64,
    /// Its standard error (frames), correlation included.
    pub error_frames: f64,
    /// Harmonics fitted.
    pub harmonics: usize,
    /// Lag-1 correlation of the residuals (the error is inflated by (1 + ρ)/(1 − ρ) for ρ > 0).
    pub residual_correlation: f64,
    /// The residual's variance per frame, |z − fit|² summed over the frames less the fitted
    /// parameters: under measurement noise alone, half the track's mismatch at T.
    pub residual_variance: f64,
    /// Each harmonic's strength (1 … H, the rest 0): its fitted power over what noise alone
    /// gives it, Gamma(2, 1) distributed without a signal; above [`SIGNIFICANT_STRENGTH`] it is
    /// part of the motion.
    pub strengths: [f64; MAX_HARMONICS],
    /// The consistency check over blocks of the track ([`period_checked_by_blocks`]); `None`
    /// from [`harmonic_period`] alone or where the track is too short for three blocks.
    pub blocks: Option<BlockCheck>,
    /// The fitted line's slope: the track's mean velocity (units of z a frame, down + i·across).
    pub velocity: Complex64,
    /// Its standard errors (down, across), with T's uncertainty and the residuals' correlation
    /// taken in: the line and the harmonics are fitted together, so a shift in T moves the
    /// slope too.
    pub velocity_error: [f64; 2],
    /// The covariance of each velocity component with T (units of z).
    pub velocity_period_covariance: [f64; 2],
}

/// The track cut into blocks, each fitted on its own: under measurement noise alone their
/// periods scatter as their own errors say (reduced χ² near 1). A body whose turns take
/// varying times (a real ramp, a wobble that drifts) scatters them more: its phase wanders, a
/// single frequency no longer describes it, and the period is better read by counting turns
/// (the cycles' mean, [`super::period`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BlockCheck {
    /// Blocks fitted (2 to 8, each at least two periods long).
    pub blocks: usize,
    /// Σ (T_b − T)²/σ_b² / (blocks − 1); `None` with two blocks.
    pub reduced_chi2: Option<f64>,
    /// [`TURNS_VARY_CHI2`]: above it the turns' times vary.
    pub threshold: f64,
    /// Whether the blocks scatter beyond it (under 1 % of tracks with measurement noise
    /// alone, `bench calibration`'s "varying" column).
    pub turns_vary: bool,
    /// The whole track's residual variance over the blocks' mean: near 1 where one period
    /// describes the track, large where only short stretches repeat (two incommensurate
    /// periods nearly repeating, or turns whose times vary).
    pub residual_ratio: f64,
}

/// How many harmonics a period of `t` frames is fitted with: enough to reach the highest
/// frequency the track has power at (`bandwidth`, cycles a frame; 8 where unknown), up to half
/// its frames (so that no two harmonics alias onto each other) and [`MAX_HARMONICS`]. A long
/// period with quick features (a 240-frame near-repeat of a 30-frame motion) needs more than a
/// few: what they leave unexplained would read as the track not repeating.
fn harmonics_for(t: f64, bandwidth: Option<f64>) -> usize {
    let wanted = bandwidth.map_or(DEFAULT_HARMONICS, |f| (f * t).ceil() as usize + 1);
    wanted
        .min((t / 2.0).floor() as usize)
        .clamp(1, MAX_HARMONICS)
}

/// The highest frequency (cycles a frame) at which the detrended track's periodogram (Hann
/// window, so that a peak's leakage falls off fast) stands 30 times above its median (the noise
/// floor) and above 1e-4 of its peak (a harmonic of 1 % of the largest amplitude: what is
/// weaker leaves a residual no test reads), or `None` for a track under 64 frames.
fn bandwidth(z: &[Complex64]) -> Option<f64> {
    let n = z.len();
    if n < 64 {
        return None;
    }
    let mut spectrum: Vec<Complex64> = z
        .iter()
        .enumerate()
        .map(|(t, v)| v * (0.5 - 0.5 * (std::f64::consts::TAU * t as f64 / n as f64).cos()))
        .collect();
    rustfft::FftPlanner::new()
        .plan_fft_forward(n)
        .process(&mut spectrum);
    let power: Vec<f64> = spectrum.iter().map(|v| v.norm_sqr()).collect();
    let mut sorted = power.clone();
    sorted.sort_by(f64::total_cmp);
    let peak = sorted[n - 1];
    let floor = (30.0 * sorted[n / 2]).max(1e-4 * peak);
    power
        .iter()
        .enumerate()
        .filter(|&(_, &p)| p > floor)
        .map(|(k, _)| k.min(n - k) as f64 / n as f64)
        .fold(None, |best: Option<f64>, f| {
            Some(best.map_or(f, |b| b.max(f)))
        })
}

/// The fit at one trial period over z[..len]: the Gram matrix, the projections and the
/// solution, and the residual sum of squares.
struct Trial {
    gram: DMatrix<Complex64>,
    solution: DVector<Complex64>,
    rss: f64,
}

/// The basis at frame t: 1, ψ = (t − c)/s and e^{iωht} for h = ±1 … ±H, in that order.
fn basis_row(t: f64, c: f64, s: f64, omega: f64, h: usize, row: &mut [Complex64]) {
    row[0] = Complex64::new(1.0, 0.0);
    row[1] = Complex64::new((t - c) / s, 0.0);
    let w = Complex64::from_polar(1.0, omega * t);
    let mut p = w;
    for k in 0..h {
        row[2 + 2 * k] = p;
        row[3 + 2 * k] = p.conj();
        p *= w;
    }
}

/// The signed harmonic of basis column `a` ≥ 2: +1, −1, +2, −2, …
fn harmonic_of(a: usize) -> i64 {
    let k = ((a - 2) / 2 + 1) as i64;
    if a.is_multiple_of(2) { k } else { -k }
}

/// One trial period. The Gram matrix of exponentials depends only on differences of
/// harmonics, so the pass sums S(k) = Σ e^{iωkt} (k ≤ 2H) and S₁(k) = Σ ψ e^{iωkt} (k ≤ H)
/// and the projections: O(n·H) a trial, not O(n·H²).
fn trial(z: &[Complex64], period: f64, h: usize) -> Option<Trial> {
    let n = z.len();
    let dim = 2 + 2 * h;
    let (c, s) = ((n as f64 - 1.0) / 2.0, n as f64 / 2.0);
    let omega = std::f64::consts::TAU / period;
    let zero = Complex64::new(0.0, 0.0);
    let (mut sums, mut sums_psi) = (vec![zero; 2 * h + 1], vec![zero; h + 1]);
    let (mut psi_sum, mut psi_squares, mut total) = (0.0, 0.0, 0.0);
    let mut proj = DVector::<Complex64>::zeros(dim);
    let mut powers = vec![zero; 2 * h + 1];
    for (t, &v) in z.iter().enumerate() {
        let psi = (t as f64 - c) / s;
        let w = Complex64::from_polar(1.0, omega * t as f64);
        powers[0] = Complex64::new(1.0, 0.0);
        for k in 1..=2 * h {
            powers[k] = powers[k - 1] * w;
        }
        for (sum, p) in sums.iter_mut().zip(&powers) {
            *sum += p;
        }
        for (sum, p) in sums_psi.iter_mut().zip(&powers) {
            *sum += p * psi;
        }
        psi_sum += psi;
        psi_squares += psi * psi;
        total += v.norm_sqr();
        proj[0] += v;
        proj[1] += v * psi;
        for k in 1..=h {
            // conj(e^{+iωkt}) z and conj(e^{−iωkt}) z.
            proj[2 * k] += powers[k].conj() * v;
            proj[2 * k + 1] += powers[k] * v;
        }
    }
    let signed = |sums: &[Complex64], k: i64| {
        let v = sums[k.unsigned_abs() as usize];
        if k >= 0 { v } else { v.conj() }
    };
    let mut gram = DMatrix::<Complex64>::zeros(dim, dim);
    gram[(0, 0)] = Complex64::new(n as f64, 0.0);
    gram[(0, 1)] = Complex64::new(psi_sum, 0.0);
    gram[(1, 1)] = Complex64::new(psi_squares, 0.0);
    for b in 2..dim {
        let hb = harmonic_of(b);
        gram[(0, b)] = signed(&sums, hb);
        gram[(1, b)] = signed(&sums_psi, hb);
        for a in 2..=b {
            gram[(a, b)] = signed(&sums, hb - harmonic_of(a));
        }
    }
    for a in 0..dim {
        for b in 0..a {
            gram[(a, b)] = gram[(b, a)].conj();
        }
    }
    let solution = gram.clone().cholesky()?.solve(&proj);
    let explained = proj.dotc(&solution).re;
    Some(Trial {
        gram,
        solution,
        rss: (total - explained).max(0.0),
    })
}

/// The least-squares period near `start` (frames), searched over `start ± half_range`, and its
/// standard error. `z` is the track as down + i·across, one sample a frame. `None` when the
/// track is shorter than two trial periods or the fit is singular.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::harmonic::harmonic_period;
/// use rustfft::num_complex::Complex64;
/// // 7.3 frames a turn, three harmonics, 60 cycles, no noise.
/// let w = std::f64::consts::TAU / 7.3;
/// let z: Vec<Complex64> = (0..438)
///     .map(|t| {
///         let t = t as f64;
///         Complex64::new(0.4 * t + (w * t).sin() + 0.3 * (2.0 * w * t).cos(), 0.5 * (3.0 * w * t).sin())
///     })
///     .collect();
/// let fit = harmonic_period(&z, 7.25, 0.2).unwrap();
/// assert!((fit.period_frames - 7.3).abs() < 1e-9);
/// ```
pub fn harmonic_period(z: &[Complex64], start: f64, half_range: f64) -> Option<HarmonicPeriod> {
    let n = z.len();
    if !(start.is_finite() && start >= 2.0 && half_range.is_finite() && half_range > 0.0)
        || (n as f64) < 2.0 * start
    {
        return None;
    }
    // The line is in the model; taking it out first keeps Σ|z|² − explained (the residual) from
    // cancelling a drift's large squares.
    let (detrended, slope) = detrend(z);
    let z = &detrended[..];
    let h = harmonics_for(start, bandwidth(z));
    let (mut centre, mut half) = (start, half_range.min(start / 4.0));
    let mut len = ((FIRST_CYCLES * start).ceil() as usize).clamp(1, n);
    loop {
        // The residual's valley: harmonic h drifts by half a turn over the stretch when T is
        // off by T²/(2·h·len).
        let width = centre * centre / (2.0 * h as f64 * len as f64);
        let step = (width / POINTS_PER_WIDTH).min(half / 4.0);
        let points = (2.0 * half / step).ceil() as usize;
        let grid: Vec<f64> = (0..=points)
            .map(|k| centre - half + k as f64 * (2.0 * half / points as f64))
            .filter(|&t| t >= 2.0)
            .collect();
        let rss: Vec<f64> = grid
            .iter()
            .map(|&t| trial(&z[..len], t, h).map_or(f64::INFINITY, |f| f.rss))
            .collect();
        let j = (0..rss.len()).min_by(|&a, &b| rss[a].total_cmp(&rss[b]))?;
        if !rss[j].is_finite() {
            return None;
        }
        centre = grid[j];
        let spacing = 2.0 * half / points as f64;
        if j > 0 && j + 1 < rss.len() {
            let den = rss[j - 1] - 2.0 * rss[j] + rss[j + 1];
            if den > 0.0 {
                centre += spacing * (0.5 * (rss[j - 1] - rss[j + 1]) / den).clamp(-0.5, 0.5);
            }
        }
        if len == n {
            half = spacing;
            break;
        }
        half = 2.0 * spacing;
        len = (len * 4).min(n);
    }
    // Golden section inside the last grid cell on either side: the valley is a parabola only
    // near its floor.
    let rss_at = |t: f64| trial(z, t, h).map_or(f64::INFINITY, |f| f.rss);
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (centre - half, centre + half);
    let (mut x1, mut x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
    let (mut f1, mut f2) = (rss_at(x1), rss_at(x2));
    for _ in 0..GOLDEN_STEPS {
        if f1 <= f2 {
            (hi, x2, f2) = (x2, x1, f1);
            x1 = hi - ratio * (hi - lo);
            f1 = rss_at(x1);
        } else {
            (lo, x1, f1) = (x1, x2, f2);
            x2 = lo + ratio * (hi - lo);
            f2 = rss_at(x2);
        }
    }
    let centre = if f1 <= f2 { x1 } else { x2 };
    let fit = trial(z, centre, h)?;
    Some(error_of(z, centre, h, (&fit, slope)))
}

/// z less its least-squares line, and the line's slope.
fn detrend(z: &[Complex64]) -> (Vec<Complex64>, Complex64) {
    let n = z.len() as f64;
    let c = (n - 1.0) / 2.0;
    let mean = z.iter().sum::<Complex64>() / n;
    let (mut cross, mut squares) = (Complex64::new(0.0, 0.0), 0.0);
    for (t, v) in z.iter().enumerate() {
        let d = t as f64 - c;
        cross += v * d;
        squares += d * d;
    }
    let slope = if squares > 0.0 {
        cross / squares
    } else {
        cross
    };
    let rest = z
        .iter()
        .enumerate()
        .map(|(t, v)| v - mean - slope * (t as f64 - c))
        .collect();
    (rest, slope)
}

/// The fit at exactly `period` frames, no search: for asking a known period's multiples which
/// harmonics they hold. `None` for a track under two periods or a singular fit.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::harmonic::harmonics_at;
/// use rustfft::num_complex::Complex64;
/// // A 25-frame motion seen at twice its period: its harmonics there are the even ones.
/// let w = std::f64::consts::TAU / 25.0;
/// let z: Vec<Complex64> = (0..500)
///     .map(|t| {
///         let t = t as f64;
///         let noise = 0.01 * ((t * 12.9898).sin() * 43758.5453).fract();
///         Complex64::new(t + (w * t).sin() + noise, (w * t).cos())
///     })
///     .collect();
/// assert_eq!(harmonics_at(&z, 50.0).unwrap().significant(), vec![2]);
/// ```
pub fn harmonics_at(z: &[Complex64], period: f64) -> Option<HarmonicPeriod> {
    if !(period.is_finite() && period >= 2.0) || (z.len() as f64) < 2.0 * period {
        return None;
    }
    let (detrended, slope) = detrend(z);
    let h = harmonics_for(period, bandwidth(&detrended));
    let fit = trial(&detrended, period, h)?;
    Some(error_of(&detrended, period, h, (&fit, slope)))
}

/// ∂model/∂T at frame `tf` (`row` its basis row): ∂/∂T of x e^{i·2π·k·t/T} is
/// x·(−i·2π·k·t/T²)·e^{…}, k = ±1 … ±H.
fn period_derivative(
    row: &[Complex64],
    solution: &DVector<Complex64>,
    h: usize,
    tf: f64,
    period: f64,
) -> Complex64 {
    let mut d = Complex64::new(0.0, 0.0);
    for k in 0..h {
        let factor = -std::f64::consts::TAU * (k + 1) as f64 * tf / (period * period);
        d += Complex64::new(0.0, factor) * row[2 + 2 * k] * solution[2 + 2 * k];
        d += Complex64::new(0.0, -factor) * row[3 + 2 * k] * solution[3 + 2 * k];
    }
    d
}

/// A residual's variance per frame in one coordinate, inflated by (1 + ρ)/(1 − ρ) for its
/// lag-1 correlation ρ > 0, from its sum of squares `rr`, lagged products `lag` and `dof`.
fn inflated_variance(rr: f64, lag: f64, dof: f64) -> f64 {
    let rho = if rr > 0.0 { lag / rr } else { 0.0 };
    let inflation = if rho > 0.0 {
        (1.0 + rho) / (1.0 - rho).max(1e-6)
    } else {
        1.0
    };
    rr / dof.max(1.0) * inflation
}

/// Standard errors of T and of the line's slope at the fit (z detrended by `slope` first).
///
/// Each estimate is a linear function of the residuals near the fit: δT = Re(fᴴε)/F, with
/// f = (I − P)∂model/∂T the derivative less what the linear part absorbs and F = |f|², and
/// δβ = G⁻¹Xᴴε − (G⁻¹Xᴴ∂model/∂T)·δT for the coefficients (G = XᴴX). Their variances are
/// summed over the frames with each coordinate's own residual variance (down and across may be
/// measured with different noise, or scaled differently: one shared variance put the better
/// coordinate's error on the worse one), each inflated for its residuals' lag-1 correlation.
/// With equal variances this is Gauss–Newton's σ²/F and σ²·((G⁻¹)ₐₐ + |gₐ|²/F).
fn error_of(
    z: &[Complex64],
    period: f64,
    h: usize,
    (fit, slope): (&Trial, Complex64),
) -> HarmonicPeriod {
    let n = z.len();
    let dim = 2 + 2 * h;
    let (c, s) = ((n as f64 - 1.0) / 2.0, n as f64 / 2.0);
    let omega = std::f64::consts::TAU / period;
    let mut row = vec![Complex64::new(0.0, 0.0); dim];
    let mut proj = DVector::<Complex64>::zeros(dim);
    let (mut jj, mut power) = (0.0, 0.0);
    // Per coordinate (down, across): squares and lagged products of the residuals.
    let (mut rr, mut lag, mut previous) = ([0.0f64; 2], [0.0f64; 2], None::<Complex64>);
    for (t, &v) in z.iter().enumerate() {
        let tf = t as f64;
        power += v.norm_sqr();
        basis_row(tf, c, s, omega, h, &mut row);
        let model: Complex64 = row
            .iter()
            .zip(fit.solution.iter())
            .map(|(b, x)| b * x)
            .sum();
        let r = v - model;
        rr[0] += r.re * r.re;
        rr[1] += r.im * r.im;
        if let Some(p) = previous {
            lag[0] += p.re * r.re;
            lag[1] += p.im * r.im;
        }
        previous = Some(r);
        let d = period_derivative(&row, &fit.solution, h, tf, period);
        jj += d.norm_sqr();
        for a in 0..dim {
            proj[a] += row[a].conj() * d;
        }
    }
    let cholesky = fit.gram.clone().cholesky();
    let coupling = cholesky.as_ref().map(|ch| ch.solve(&proj));
    let explained = coupling.as_ref().map_or(0.0, |g| proj.dotc(g).re);
    let free = (jj - explained).max(f64::MIN_POSITIVE);
    let total = rr[0] + rr[1];
    let rho = if total > 0.0 {
        (lag[0] + lag[1]) / total
    } else {
        0.0
    };
    let inflation = if rho > 0.0 {
        (1.0 + rho) / (1.0 - rho).max(1e-6)
    } else {
        1.0
    };
    let residual_variance = total / (n as f64 - dim as f64).max(1.0);
    // Each coefficient's variance is σ²·(G⁻¹)ₐₐ; a harmonic's strength sums |x|²/var over its
    // two senses (Gamma(2, 1) under noise alone). A noiseless fit's σ² is round-off: floored.
    let noise = (residual_variance * inflation).max(ROUND_OFF * power / n as f64);
    let mut strengths = [0.0; MAX_HARMONICS];
    if let Some(ch) = &cholesky {
        for (k, strength) in strengths.iter_mut().enumerate().take(h) {
            for a in [2 + 2 * k, 3 + 2 * k] {
                let mut unit = DVector::<Complex64>::zeros(dim);
                unit[a] = Complex64::new(1.0, 0.0);
                let g_aa = ch.solve(&unit)[a].re.max(f64::MIN_POSITIVE);
                *strength += fit.solution[a].norm_sqr() / (noise * g_aa);
            }
        }
    }
    // Each coordinate's residual variance (its share of the 2n − (2·dim + 1) degrees of freedom).
    let dof = n as f64 - dim as f64 - 0.5;
    let variance = [0, 1].map(|k| inflated_variance(rr[k], lag[k], dof));
    // Second pass: each frame's weight in δT and in the slope's δβ₁ (real and imaginary parts),
    // as coefficients of the residual's down and across parts.
    let zero = Complex64::new(0.0, 0.0);
    let g = coupling.unwrap_or_else(|| DVector::<Complex64>::zeros(dim));
    let column = cholesky.as_ref().map_or_else(
        || DVector::<Complex64>::zeros(dim),
        |ch| {
            let mut unit = DVector::<Complex64>::zeros(dim);
            unit[1] = Complex64::new(1.0, 0.0);
            ch.solve(&unit)
        },
    );
    let g1 = g[1];
    // Sums of squares: [T][coordinate], [slope down][coordinate], [slope across][coordinate],
    // and the slope's products with T.
    let (mut t_sq, mut down_sq, mut across_sq) = ([0.0f64; 2], [0.0f64; 2], [0.0f64; 2]);
    let (mut down_t, mut across_t) = ([0.0f64; 2], [0.0f64; 2]);
    for t in 0..n {
        let tf = t as f64;
        basis_row(tf, c, s, omega, h, &mut row);
        let d = period_derivative(&row, &fit.solution, h, tf, period);
        let mut absorbed = zero;
        let mut h_t = zero;
        for a in 0..dim {
            absorbed += row[a] * g[a];
            // (G⁻¹)₁ₐ = conj((G⁻¹)ₐ₁): h_t = Σₐ (G⁻¹)₁ₐ conj(rowₐ).
            h_t += (column[a] * row[a]).conj();
        }
        let f = d - absorbed;
        let w_t = [f.re / free, f.im / free];
        let w_down = [h_t.re - g1.re * w_t[0], -h_t.im - g1.re * w_t[1]];
        let w_across = [h_t.im - g1.im * w_t[0], h_t.re - g1.im * w_t[1]];
        for k in 0..2 {
            t_sq[k] += w_t[k] * w_t[k];
            down_sq[k] += w_down[k] * w_down[k];
            across_sq[k] += w_across[k] * w_across[k];
            down_t[k] += w_down[k] * w_t[k];
            across_t[k] += w_across[k] * w_t[k];
        }
    }
    let sum = |sq: [f64; 2]| variance[0] * sq[0] + variance[1] * sq[1];
    // A noiseless fit's error is round-off: floored (ERROR_FLOOR).
    let error = if cholesky.is_some() {
        sum(t_sq).sqrt()
    } else {
        f64::INFINITY
    }
    .max(ERROR_FLOOR * period);
    // The slope is the ψ column's coefficient over s (ψ = (t − c)/s), plus the line taken out.
    let velocity = slope + fit.solution[1] / s;
    let floor = ERROR_FLOOR * velocity.norm();
    let velocity_error = [sum(down_sq), sum(across_sq)]
        .map(|v| {
            if cholesky.is_some() {
                v.sqrt() / s
            } else {
                f64::INFINITY
            }
        })
        .map(|e| e.max(floor));
    let velocity_period_covariance = [sum(down_t) / s, sum(across_t) / s];
    HarmonicPeriod {
        period_frames: period,
        error_frames: error,
        harmonics: h,
        residual_correlation: rho,
        residual_variance,
        strengths,
        blocks: None,
        velocity,
        velocity_error,
        velocity_period_covariance,
    }
}

impl HarmonicPeriod {
    /// The advance per period, velocity × T (units of z, down + i·across), and its standard
    /// errors (down, across): (T²σ_v² + v²σ_T² + 2Tv·cov)^½ with the regression's own σ_T
    /// ([`HarmonicPeriod::error_frames`]) and its covariance with the velocity.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::harmonic::harmonic_period;
    /// use rustfft::num_complex::Complex64;
    /// let w = std::f64::consts::TAU / 12.5;
    /// let z: Vec<Complex64> = (0..500)
    ///     .map(|t| {
    ///         let t = t as f64;
    ///         Complex64::new(0.4 * t + (w * t).sin(), 0.5 * (w * t).cos() - 0.01 * t)
    ///     })
    ///     .collect();
    /// let fit = harmonic_period(&z, 12.4, 0.3).unwrap();
    /// let (advance, errors) = fit.advance();
    /// assert!((advance.re - 5.0).abs() < 1e-6 && (advance.im + 0.125).abs() < 1e-6);
    /// assert!(errors[0] < 1e-6 && errors[1] < 1e-6);
    /// ```
    pub fn advance(&self) -> (Complex64, [f64; 2]) {
        let (t, e) = (self.period_frames, self.error_frames);
        let v = [self.velocity.re, self.velocity.im];
        let errors = [0, 1].map(|k| {
            (t * t * self.velocity_error[k].powi(2)
                + v[k] * v[k] * e * e
                + 2.0 * t * v[k] * self.velocity_period_covariance[k])
                .max(0.0)
                .sqrt()
        });
        (self.velocity * t, errors)
    }

    /// The harmonics (1 … H) that stand out of the noise ([`SIGNIFICANT_STRENGTH`]) and carry
    /// at least [`SIGNIFICANT_SHARE`] of the strongest one's power.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::harmonic::harmonic_period;
    /// use rustfft::num_complex::Complex64;
    /// // A 30-frame motion with a first and a third harmonic: those two, not the second.
    /// let w = std::f64::consts::TAU / 30.0;
    /// let z: Vec<Complex64> = (0..600)
    ///     .map(|t| {
    ///         let t = t as f64;
    ///         let noise = 0.01 * ((t * 0.618034).fract() - 0.5); // a line at 0.38 a frame
    ///         Complex64::new(t + (w * t).sin() + 0.3 * (3.0 * w * t).sin() + noise, (w * t).cos())
    ///     })
    ///     .collect();
    /// assert_eq!(harmonic_period(&z, 30.0, 0.5).unwrap().significant(), vec![1, 3]);
    /// ```
    pub fn significant(&self) -> Vec<usize> {
        let strongest = self.strengths.iter().fold(0.0f64, |m, &v| m.max(v));
        (1..=self.harmonics)
            .filter(|&k| {
                let s = self.strengths[k - 1];
                s > SIGNIFICANT_STRENGTH && s >= SIGNIFICANT_SHARE * strongest
            })
            .collect()
    }

    /// The strongest harmonic (1 … H): the one the motion's main repeat is (1 for most tracks;
    /// k when the track repeats k times a period as far as the eye goes).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::harmonic::harmonics_at;
    /// use rustfft::num_complex::Complex64;
    /// // A 3.5-frame motion sampled once a frame repeats exactly after 7 frames; seen at 7, its
    /// // strongest harmonic is the second.
    /// let w = std::f64::consts::TAU / 3.5;
    /// let z: Vec<Complex64> = (0..700)
    ///     .map(|t| {
    ///         let t = t as f64;
    ///         Complex64::new(t + (w * t).sin() + 0.2 * (2.0 * w * t).cos(), 0.6 * (w * t).cos())
    ///     })
    ///     .collect();
    /// assert_eq!(harmonics_at(&z, 7.0).unwrap().strongest(), 2);
    /// ```
    pub fn strongest(&self) -> usize {
        (1..=self.harmonics)
            .max_by(|&a, &b| self.strengths[a - 1].total_cmp(&self.strengths[b - 1]))
            .unwrap_or(1)
    }
}

/// The reduced χ² of the blocks above which the turns' times are read as varying. Measured, not
/// taken from χ²'s table: the blocks' own errors run about 20 % small (two periods each), so on
/// synthetic tracks of fixed period (30 and 61.7 frames, noise 2 % and 20 %, 200 each) the
/// reduced χ² had its median at 1.1–1.3 and its 99th percentile at 4.2–6.9, where the table's
/// 99 % points (2.6–4.6) flagged 3–7 % of them. A real ramp's turns scatter far beyond: the
/// authors' sphere gives 26.6.
pub const TURNS_VARY_CHI2: f64 = 8.0;
/// Most blocks of the consistency check.
pub const MAX_BLOCKS: usize = 8;

/// [`harmonic_period`], then the same fit on 3 to [`MAX_BLOCKS`] blocks of the track (each at
/// least two periods and ten samples per real parameter), and whether their periods scatter more than their errors allow (reduced
/// χ² above [`TURNS_VARY_CHI2`]): the turns' times vary beyond measurement noise.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::harmonic::period_checked_by_blocks;
/// use rustfft::num_complex::Complex64;
/// // Turns of 20 frames, then of 22 from the middle on: no one frequency fits both halves.
/// let mut phase = 0.0;
/// let z: Vec<Complex64> = (0..800)
///     .map(|t| {
///         phase += std::f64::consts::TAU / if t < 400 { 20.0 } else { 22.0 };
///         Complex64::new(0.2 * t as f64 + phase.sin(), phase.cos())
///     })
///     .collect();
/// let fit = period_checked_by_blocks(&z, 21.0, 1.0).unwrap();
/// assert!(fit.blocks.unwrap().turns_vary);
/// ```
pub fn period_checked_by_blocks(
    z: &[Complex64],
    start: f64,
    half_range: f64,
) -> Option<HarmonicPeriod> {
    let mut fit = harmonic_period(z, start, half_range)?;
    let t = fit.period_frames;
    // A block must hold two periods and ten samples per real parameter: shorter ones' own
    // errors are too rough for χ² (blocks of 15 frames flagged 9 % of 6.3-frame tracks).
    let dim = 2 + 2 * fit.harmonics;
    let shortest = (2.0 * t).max((10 * 2 * dim) as f64 / 2.0);
    let count = ((z.len() as f64 / shortest).floor() as usize).min(MAX_BLOCKS);
    if count < 2 {
        return Some(fit);
    }
    let size = z.len() / count;
    let (mut chi2, mut block_variance) = (0.0, 0.0);
    for b in 0..count {
        let block = harmonic_period(&z[b * size..(b + 1) * size], t, (0.03 * t).min(t / 4.0))?;
        chi2 += ((block.period_frames - t) / block.error_frames).powi(2);
        block_variance += block.residual_variance / count as f64;
    }
    let power = z.iter().map(|v| v.norm_sqr()).sum::<f64>() / z.len() as f64;
    // Residuals under 1e-12 of the track's mean square (a millionth of its size) are round-off
    // or a fit's own limit: no tracker is that quiet, and their ratio means nothing.
    let floor = 1e-12 * power;
    let reduced = (count >= 3).then(|| chi2 / (count - 1) as f64);
    fit.blocks = Some(BlockCheck {
        blocks: count,
        reduced_chi2: reduced,
        threshold: TURNS_VARY_CHI2,
        turns_vary: reduced.is_some_and(|r| r > TURNS_VARY_CHI2),
        residual_ratio: fit.residual_variance.max(floor) / block_variance.max(floor),
    });
    Some(fit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    fn track(period: f64, cycles: f64, noise: f64, seed: u64) -> Vec<Complex64> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let normal = Normal::new(0.0, noise).unwrap();
        let w = std::f64::consts::TAU / period;
        (0..(period * cycles) as usize)
            .map(|t| {
                let t = t as f64;
                Complex64::new(
                    0.3 * t
                        + (w * t).sin()
                        + 0.4 * (2.0 * w * t + 1.0).cos()
                        + normal.sample(&mut rng),
                    0.6 * (w * t + 0.5).cos() + 0.2 * (3.0 * w * t).sin() + normal.sample(&mut rng),
                )
            })
            .collect()
    }

    #[test]
    fn a_noiseless_track_gives_its_period_to_round_off_at_any_length() {
        for period in [6.3, 7.3, 10.4, 17.7, 61.25] {
            for cycles in [3.0, 40.0, 2000.0] {
                let z = track(period, cycles, 0.0, 1);
                let fit = harmonic_period(&z, period * 1.01, 0.03 * period).unwrap();
                assert!(
                    (fit.period_frames - period).abs() < 1e-7 * period,
                    "{period} × {cycles}: {}",
                    fit.period_frames
                );
            }
        }
    }

    #[test]
    fn with_noise_the_truth_is_within_the_error_as_often_as_it_says() {
        // 6.3 frames: the case the cycles' shifts put 31 errors off.
        let (mut inside, mut sum) = (0, 0.0);
        let draws = 200;
        for seed in 0..draws {
            let z = track(6.3, 50.0, 0.05, seed);
            let fit = harmonic_period(&z, 6.25, 0.2).unwrap();
            let off = (fit.period_frames - 6.3) / fit.error_frames;
            sum += off;
            if off.abs() < 1.96 {
                inside += 1;
            }
        }
        assert!((180..=198).contains(&inside), "{inside} of {draws} inside");
        assert!(
            (sum / draws as f64).abs() < 0.25,
            "mean offset {} errors",
            sum / draws as f64
        );
    }

    #[test]
    fn too_short_or_bad_starts_give_none() {
        let z = track(10.0, 1.9, 0.0, 1);
        assert!(harmonic_period(&z, 10.0, 0.5).is_none());
        let z = track(10.0, 10.0, 0.0, 1);
        assert!(harmonic_period(&z, f64::NAN, 0.5).is_none());
        assert!(harmonic_period(&z, 1.0, 0.5).is_none());
        assert!(harmonic_period(&z, 10.0, 0.0).is_none());
    }
}
