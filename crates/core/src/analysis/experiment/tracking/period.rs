//! A track's period: the shift at which it repeats, found at every shift at once, refined to a
//! fraction of a frame, checked cycle by cycle and against chance, with a finite uncertainty.
//!
//! The track is read as one complex signal z = down + i·across, less its least-squares line
//! (the drift, which a shift only translates). The mismatch at a shift τ,
//! E(τ) = ⟨|z(t + τ) − z(t) − D(τ)|²⟩ (D the mean displacement over τ), normalised by twice
//! the track's variance, is ≈ 1 for unrelated points and falls to the noise floor where the
//! motion repeats. For every whole shift it is Σ|z|² sums (prefix sums) less twice the
//! autocorrelation, which one FFT gives (rustfft): O(n log n), where trying each shift would be
//! O(n²) (20,000 frames took 7.7 s that way, 10⁶ would take weeks).
//!
//! **Which dip is the period.** Small shifts match because the body has not moved on yet. The
//! mismatch is therefore read against its own mean over all smaller shifts (the cumulative-mean
//! normalisation of de Cheveigné and Kawahara's YIN pitch estimator): d′(τ) = E(τ)·τ / Σ_{s≤τ} E(s)
//! is ≥ 1 while E only grows, and falls below [`MAX_NORMALISED_DIP`] only where the track
//! repeats better than at the shifts before. That needs no frame rate and no smallest period,
//! so a 20-frame period is not skipped for its double (the old search started at half a
//! second and waited for a fixed rise). Each dip is refined by the parabola through its lowest
//! whole shift and the two beside it, which gives the floor between whole shifts too (never by
//! interpolated points, whose smaller noise pulls a period towards half frames); the smallest
//! dip within [`MULTIPLE_TOLERANCE`] of the best is the period, its multiples repeating too. Periods below [`MIN_PERIOD_FRAMES`] are refused.
//!
//! **Evidence that it is there.** A period is stated only when
//! - every whole cycle repeats on its own: its best shift against the next cycle lies inside
//!   ±[`CYCLE_WINDOW`] of the period, not on the window's edge, with a mismatch below
//!   [`MAX_MISMATCH`] (at most a quarter of the cycles may fail, the first and last aside);
//! - the track repeats beyond chance: [`SURROGATES`] surrogate tracks with the same power
//!   spectrum smoothed over ±[`SMOOTHING_RATIO`] in frequency (so a drifting random walk keeps
//!   its spectrum, while a periodic track's lines are spread into bands that decorrelate within a
//!   few cycles), random phases and a fixed seed, are searched the same way, and the track's
//!   dip must be below [`SURROGATE_MARGIN`] times the lowest any of them reached (past
//!   [`SURROGATE_FRAMES`] frames, surrogates of the track's beginning: stricter, and fast).
//!
//! **The number and its error.** Once the track is known to repeat, the period and its standard
//! error come from a harmonic regression started at the cycles' mean ([`super::harmonic`]): the
//! track fitted at its own frames as a line plus harmonics of 1/T. The cycles' shifts shared a
//! bias at short periods that their spread could not see (7.3 frames came back as 7.2467 ±
//! 0.0011). Where the regression cannot be fitted, the period is the cycles' mean with their
//! spread over √(cycles), or with fewer than three cycles the dip's, with its width
//! δτ = √(E_min / (a·(n − τ))) for E ≈ E_min + a(τ − T)². `bench calibration` measures how
//! often the stated 95 % interval holds a synthetic track's known period.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::mismatch::{Curve, Detrended, next_pow2, normalised};
use super::repeat::CLOSE_REPEAT_FLOOR;
pub use super::surrogates::SMOOTHING_RATIO;
use super::surrogates::surrogate_floor;
use super::turns::{TurnRule, turn_rule};
use super::{CleanTrack, NOTHING_VARIES, TrackError, harmonic};

/// The normalised mismatch above which a period is not stated.
pub const MAX_MISMATCH: f64 = 0.5;
/// A dip counts only where the mismatch is below this fraction of its mean over all smaller
/// shifts (the cumulative-mean-normalised d′).
pub const MAX_NORMALISED_DIP: f64 = 0.5;
/// Dips within this factor of the best count as repeats (the smallest is the period, the
/// others its multiples).
pub const MULTIPLE_TOLERANCE: f64 = 1.5;
/// … plus this much (a noiseless track's multiples can beat its period by round-off alone).
pub const MULTIPLE_SLACK: f64 = 0.02;
/// Fewer frames a period cannot be told from its multiples and the noise.
pub const MIN_PERIOD_FRAMES: f64 = 6.0;
/// Each cycle's own period is searched within this fraction of the period.
pub const CYCLE_WINDOW: f64 = 0.2;
/// Surrogate tracks searched for the chance level (p < 1/(SURROGATES + 1) = 0.05, with the
/// margin below on top).
pub const SURROGATES: usize = 19;
/// Surrogates of longer tracks are of their first this many frames (2¹⁸).
pub const SURROGATE_FRAMES: usize = 1 << 18;
/// The track's dip must be below this fraction of the lowest a surrogate reached.
pub const SURROGATE_MARGIN: f64 = 0.5;
/// A period is refused when the harmonic fit of the whole track leaves more than this many
/// times the residual its blocks leave ([`harmonic::BlockCheck::residual_ratio`]).
pub const MAX_FIT_EXCESS: f64 = 4.0;

/// How the period search runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodSearch {
    /// The smallest period reported (frames).
    pub min_frames: f64,
    /// Surrogate tracks for the chance level (0: no check against chance, for a first look).
    pub surrogates: usize,
    /// Whether the turns are read for a rule between them ([`super::turns`]), which refuses a
    /// chaotic or quasi-periodic track (false for a first look, whose period only sizes a
    /// window: it may be a multiple of the one the whole search states).
    pub read_turns: bool,
}

impl Default for PeriodSearch {
    fn default() -> Self {
        PeriodSearch {
            min_frames: MIN_PERIOD_FRAMES,
            surrogates: SURROGATES,
            read_turns: true,
        }
    }
}

/// Where the period's uncertainty comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorSource {
    /// The spread of the whole cycles' own periods over √(cycles), the period their mean:
    /// where the regression's blocks show the turns' times vary (a wandering phase, which no
    /// one frequency fits), or where the regression cannot be fitted.
    Cycles,
    /// Too few cycles for a spread: the mismatch dip's width against its floor.
    DipWidth,
    /// The harmonic regression's Gauss–Newton error, inflated for residuals correlated from
    /// frame to frame ([`super::harmonic`]): the period's error wherever it can be fitted.
    Harmonics,
}

/// The check against chance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Significance {
    /// Surrogate tracks searched.
    pub surrogates: usize,
    /// The lowest normalised dip d′ any surrogate reached, anywhere in the search range.
    pub surrogate_floor: f64,
    /// The track's normalised dip d′ at the period.
    pub normalised_dip: f64,
    /// The chance of a surrogate beating the track by the margin, bounded: 1/(surrogates + 1).
    pub p_bound: f64,
}

/// A track's period, found and measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PeriodFit {
    /// The period in frames (to a fraction of a frame).
    pub period_frames: f64,
    /// Standard error of the period (frames); always finite.
    pub period_error_frames: f64,
    /// Where the standard error comes from.
    pub period_error_from: ErrorSource,
    /// Spread (standard deviation) of the cycles' own periods (frames); `None` with fewer than
    /// three cycles.
    pub period_spread_frames: Option<f64>,
    /// Each whole cycle's own period (frames), against the next cycle (cycles that repeat).
    pub cycle_periods: Vec<f64>,
    /// Cycles whose best repeat lies on the edge of their window or above [`MAX_MISMATCH`].
    pub unrepeated_cycles: usize,
    /// Whole periods in the track.
    pub periods_seen: usize,
    /// The normalised mismatch at the period (0: a perfect repeat, 1: none).
    pub mismatch: f64,
    /// Advance per period down the ramp (cm).
    pub advance_down: f64,
    /// Advance per period across the ramp (cm).
    pub advance_across: f64,
    /// Standard errors of the advance per period (down, across; cm), from the harmonic
    /// regression's slope and the stated period error; `None` where the regression could not be
    /// fitted (then no error is stated).
    pub advance_error: Option<[f64; 2]>,
    /// The mean velocity (down, across; cm a frame) and its standard errors, from the same
    /// regression; `None` likewise.
    pub velocity: Option<([f64; 2], [f64; 2])>,
    /// The check against chance (`None` when the search ran without surrogates).
    pub significance: Option<Significance>,
    /// The regression's check over blocks of the track (`None` under six periods, or where
    /// the regression could not be fitted).
    pub block_check: Option<harmonic::BlockCheck>,
    /// The normalised mismatch at every whole shift (shift in frames, mismatch).
    pub mismatch_curve: Vec<[f64; 2]>,
    /// Whether the turns follow from one another by a rule ([`super::turns`]), read where the
    /// track repeats less closely than [`super::CLOSE_REPEAT_FLOOR`]; `None` where it repeats
    /// more closely. A period is never stated where they do (a chaotic motion).
    pub turn_rule: Option<TurnRule>,
}

/// The dips of d′ below [`MAX_NORMALISED_DIP`] from shift 2 on, each as its lowest whole
/// shift by `e`; a dip that runs into the end of the range may be cut off and is left out.
fn dips(e: &[f64], dn: &[f64]) -> Vec<usize> {
    let last = e.len() - 1;
    let mut out = Vec::new();
    let mut k = 2;
    while k < last {
        if dn[k] < MAX_NORMALISED_DIP {
            let end = (k..=last)
                .find(|&j| dn[j] >= MAX_NORMALISED_DIP)
                .unwrap_or(last + 1);
            let low = (k..end).min_by(|&a, &b| e[a].total_cmp(&e[b])).unwrap_or(k);
            if low < last {
                out.push(low);
            }
            k = end;
        } else {
            k += 1;
        }
    }
    out
}

/// A dip at whole shift `k` refined: [`Curve::at`] at quarter frames over k ± 1, then the
/// parabola through the lowest and its neighbours. Returns the vertex's shift, its value (the
/// dip's floor), the mean displacement there and the curvature a of E ≈ E_min + a(τ − T)², all
/// normalised by `scale`.
///
/// Not linear interpolation between frames: its averaging halves the noise at half frames and
/// pulled periods there (a 230.10-frame model period came back as 229.51). Not a parabola
/// through whole shifts alone: a dip a few frames wide is not parabolic over ±1 frame (a
/// 6.7-frame period lost to its triple by its misjudged floor).
fn refine(curve: &Curve, k: usize, scale: f64) -> (f64, f64, Complex64, f64) {
    let top = (curve.e.len() - 1) as f64;
    let grid: Vec<(f64, f64)> = (0..=8)
        .map(|j| k as f64 - 1.0 + 0.25 * f64::from(j))
        .filter(|&t| t >= 1.0 && t <= top)
        .map(|t| (t, curve.at(t).0 / scale))
        .collect();
    let j = (0..grid.len())
        .min_by(|&a, &b| grid[a].1.total_cmp(&grid[b].1))
        .unwrap_or(0);
    let (mut tau, mut floor, mut curvature) = (grid[j].0, grid[j].1, 0.0);
    if j > 0 && j + 1 < grid.len() {
        let (e0, e1, e2) = (grid[j - 1].1, grid[j].1, grid[j + 1].1);
        let denominator = e0 - 2.0 * e1 + e2;
        if denominator > 0.0 {
            let shift = (0.5 * (e0 - e2) / denominator).clamp(-0.5, 0.5);
            tau += 0.25 * shift;
            floor = (e1 - 0.25 * (e0 - e2) * shift).max(0.0);
            curvature = denominator / (2.0 * 0.25 * 0.25);
        }
    }
    (tau, floor, curve.at(tau).1, curvature)
}

/// Each whole cycle against the next: the best whole shift within ±[`CYCLE_WINDOW`] of `tau`,
/// refined by a parabola, or `None` where the best lies on the window's edge or does not
/// repeat (above [`MAX_MISMATCH`]). One FFT cross-correlation per cycle: O(n log τ) in all.
fn cycles(
    det: &Detrended,
    tau: f64,
    scale: f64,
    planner: &mut FftPlanner<f64>,
) -> Vec<Option<f64>> {
    let n = det.z.len();
    let len = tau.round() as usize;
    let lo = ((tau * (1.0 - CYCLE_WINDOW)).floor() as usize).max(1);
    let periods = ((n - 1) as f64 / tau).floor() as usize;
    let mut out = Vec::new();
    for c in 0..periods.saturating_sub(1) {
        let from = (c as f64 * tau).round() as usize;
        let hi = ((tau * (1.0 + CYCLE_WINDOW)).ceil() as usize).min(n.saturating_sub(from + len));
        if hi < len + 1 || hi <= lo + 1 {
            continue;
        }
        let w = &det.z[from..from + len];
        let s = &det.z[from + lo..from + hi + len];
        let m = next_pow2(s.len());
        let mut sb = vec![Complex64::new(0.0, 0.0); m];
        sb[..s.len()].copy_from_slice(s);
        let mut wb = vec![Complex64::new(0.0, 0.0); m];
        wb[..len].copy_from_slice(w);
        planner.plan_fft_forward(m).process(&mut sb);
        planner.plan_fft_forward(m).process(&mut wb);
        for (a, b) in sb.iter_mut().zip(&wb) {
            *a *= b.conj();
        }
        planner.plan_fft_inverse(m).process(&mut sb);
        let (mut p1, mut p2) = (
            vec![Complex64::new(0.0, 0.0); s.len() + 1],
            vec![0.0; s.len() + 1],
        );
        for (i, v) in s.iter().enumerate() {
            p1[i + 1] = p1[i] + v;
            p2[i + 1] = p2[i] + v.norm_sqr();
        }
        let wsum = w.iter().sum::<Complex64>();
        let wsq = w.iter().map(Complex64::norm_sqr).sum::<f64>();
        let l = len as f64;
        let e: Vec<f64> = (0..=hi - lo)
            .map(|j| {
                let cross = sb[j].re / m as f64;
                let sq = (p2[j + len] - p2[j]) + wsq - 2.0 * cross;
                let mean = (p1[j + len] - p1[j] - wsum) / l;
                (sq / l - mean.norm_sqr()).max(0.0) / scale
            })
            .collect();
        let j = (0..e.len())
            .min_by(|&a, &b| e[a].total_cmp(&e[b]))
            .unwrap_or(0);
        if j == 0 || j + 1 == e.len() || e[j] > MAX_MISMATCH {
            out.push(None);
            continue;
        }
        let (a, b, d) = (e[j - 1], e[j], e[j + 1]);
        let den = a - 2.0 * b + d;
        let shift = if den > 0.0 {
            (0.5 * (a - d) / den).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        out.push(Some((lo + j) as f64 + shift));
    }
    out
}

/// Why no dip of d′ counts as a repeat: the best shift's mismatch, or its dip cut off by the
/// end of the search.
fn no_dip(e: &[f64], dn: &[f64], max_tau: usize) -> TrackError {
    let k = (2..e.len())
        .min_by(|&a, &b| dn[a].total_cmp(&dn[b]))
        .unwrap_or(2.min(e.len() - 1));
    // A dip that reaches the end of the range is cut off: its floor may lie beyond.
    let why = if dn[k] < MAX_NORMALISED_DIP {
        format!(
            "the track repeats best after about {k} frames, but its repeat runs into the end \
             of the search (shifts up to {max_tau} frames, half the track), so its floor \
             cannot be told from a longer period's: a period needs a track of at least 2.5 \
             of them"
        )
    } else {
        format!(
            "no shift from 2 to {max_tau} frames makes the track repeat better than the \
             shifts before it: the best (shift {k} frames) leaves {:.2} of the variation \
             unexplained, {:.2} of its mean over smaller shifts (a repeat needs below \
             {MAX_NORMALISED_DIP})",
            e[k], dn[k]
        )
    };
    TrackError::NoPeriod {
        best_frames: k as f64,
        why,
    }
}

/// The period, its error and where it comes from, by the harmonic regression started at
/// `start` (the cycles' mean, or the dip) with the estimate so far (`before`): the cycles' shifts
/// share a bias at short periods that their spread cannot see (harmonic.rs says why). The
/// search spans the start's own error five times over and at least 3 % (the shifts' bias stayed
/// under 1 %). Turns whose times vary keep the cycles' mean and spread; a track the regression
/// describes over its stretches but not as a whole is refused (`m`: its mismatch, for saying so).
fn regression(
    z: &[Complex64],
    start: f64,
    before: (f64, ErrorSource),
    m: f64,
) -> Result<(f64, f64, ErrorSource, Option<harmonic::HarmonicPeriod>), TrackError> {
    let (error, from) = before;
    let fit = harmonic::period_checked_by_blocks(z, start, (0.03 * start).max(5.0 * error));
    let block_check = fit.and_then(|f| f.blocks);
    // Turns whose times vary are read by counting them: the cycles' mean and spread.
    let turns_vary = block_check.is_some_and(|b| b.turns_vary) && from == ErrorSource::Cycles;
    if let Some(fit) = fit.filter(|_| !turns_vary)
        && let Some(blocks) = fit.blocks
        && blocks.residual_ratio > MAX_FIT_EXCESS
    {
        // One test of "it repeats": a track that repeats after T frames is described by one
        // set of harmonics of 1/T over its whole length as well as over any stretch of it. Two
        // incommensurate periods nearly repeat (8 turns of one against 5 of the other), so
        // short stretches fit and the whole does not.
        return Err(TrackError::NoPeriod {
            best_frames: fit.period_frames,
            why: format!(
                "the track nearly repeats after {:.1} frames (mismatch {m:.3}), but no one period \
                 describes it: harmonics of that period leave {:.1} times as much unexplained \
                 over the whole track as over {} stretches of it (at most {MAX_FIT_EXCESS}), as \
                 two or more incommensurate periods do (a quasi-periodic motion), or a motion \
                 whose shape drifts along the track (a transient not yet settled: on a track \
                 without noise a drift of 1 % in the wobble's size is enough)",
                fit.period_frames, blocks.residual_ratio, blocks.blocks
            ),
        });
    }
    Ok(match fit {
        Some(fit) if !turns_vary => (
            fit.period_frames,
            fit.error_frames,
            ErrorSource::Harmonics,
            Some(fit),
        ),
        _ => (start, error, from, fit),
    })
}

/// The advance per period, its errors (down, across), and the velocity (down, across) with its
/// errors.
type Motion = (Complex64, Option<[f64; 2]>, Option<([f64; 2], [f64; 2])>);

/// The advance per period (down + i·across), its errors and the mean velocity with its errors,
/// from the regression `harmonic` (its velocity the whole track's) and the period stated
/// (`tau` ± `error`, from `from`); `displaced` is the mean displacement over one period, the
/// advance where the regression does not state the period.
fn motion(
    harmonic: Option<harmonic::HarmonicPeriod>,
    (tau, error, from): (f64, f64, ErrorSource),
    displaced: Complex64,
) -> Motion {
    // Where the regression states the period, the advance is its velocity × T (the same fit);
    // otherwise the mean displacement over one period, with an error only where it was fitted.
    let (advance, advance_error) = match harmonic {
        Some(fit) if from == ErrorSource::Harmonics => {
            let (a, e) = fit.advance();
            (a, Some(e))
        }
        // The turns' times vary, and the period is the mean turn's: the advance is the mean
        // displacement over it, and its error the velocity's with the regression's own error of
        // this track's mean turn, not the stated error of the mean turn time (a body rolls the
        // same path each turn, however long it takes; with the stated one the advance's error
        // was 6 times too large, a helper's finding).
        Some(fit) => {
            let mut at_cycles_mean = fit;
            at_cycles_mean.period_frames = tau;
            (displaced, Some(at_cycles_mean.advance().1))
        }
        None => (displaced, None),
    };
    // Where the turns' times vary, the mean speed is as uncertain as the mean turn's time (a
    // body rolls the same path each turn, slower or faster): the relative error of the period
    // joins the slope's, which sees only this run's positions.
    let velocity = harmonic.map(|fit| {
        let v = [fit.velocity.re, fit.velocity.im];
        let e = if from == ErrorSource::Harmonics {
            fit.velocity_error
        } else {
            [0, 1].map(|k| fit.velocity_error[k].hypot(v[k] * error / tau))
        };
        (v, e)
    });
    (advance, advance_error, velocity)
}

/// What the harmonics say of a repeat found at `tau`.
enum Fundamental {
    /// It is the period.
    Keep,
    /// The period is this (frames): a fraction of `tau` whose harmonics are all the
    /// significant ones, or a multiple with harmonics between its own.
    Period(f64),
    /// The motion's strongest repeat is this many frames, under [`MIN_PERIOD_FRAMES`]: the
    /// frame rate cannot tell it from its multiples.
    TooFast(f64),
}

/// The period the harmonic regression says, from a repeat found at `tau` frames:
/// - its strongest harmonic k gives the motion's main repeat, τ/k; under
///   [`MIN_PERIOD_FRAMES`] the frame rate aliases its harmonics onto a slower period's, and it
///   is refused as too fast (a 3.5-frame motion sampled once a frame repeats exactly after 7);
/// - its significant harmonics sharing a factor g mean the track repeats after τ/g;
/// - a multiple k·τ (up to 8, within the search) with a significant harmonic that is not a
///   multiple of k means the track repeats only after k·τ (a third harmonic that dominates a
///   weak fundamental made the dips pick a third of the period), and that multiple's own
///   multiples are tried in turn.
fn fundamental(z: &[Complex64], tau: f64, longest: f64) -> Fundamental {
    let fit_at = |t: f64| harmonic::harmonic_period(z, t, (0.03 * t).min(t / 4.0));
    let Some(fit) = fit_at(tau) else {
        return Fundamental::Keep;
    };
    let main = fit.period_frames / fit.strongest() as f64;
    if main < MIN_PERIOD_FRAMES {
        return Fundamental::TooFast(main);
    }
    let strong = fit.significant();
    let shared = strong.iter().fold(0, |g, &k| gcd(g, k));
    if shared > 1 {
        return Fundamental::Period(fit.period_frames / shared as f64);
    }
    // A multiple found, its own multiples are tried in turn: a pattern of four turns whose
    // halves nearly repeat showed harmonics off the doubled turn, and was stated as two turns
    // (a helper's finding, 2026-12-04), where four repeat.
    let (mut base, mut found) = (fit.period_frames, None);
    'multiples: loop {
        for k in 2..=8usize {
            let t = k as f64 * base;
            if t > longest {
                break;
            }
            let at = harmonic::harmonics_at(z, t);
            if at.is_some_and(|f| f.significant().iter().any(|h| h % k != 0)) {
                (base, found) = (t, Some(t));
                continue 'multiples;
            }
        }
        break;
    }
    found.map_or(Fundamental::Keep, Fundamental::Period)
}

/// Repeats of a period that spans several of the motion's main repeats needed before it is
/// stated: turns whose times vary by a few percent line up again by chance after several
/// turns, and over two or three such spans that chance alignment fits as well as a true
/// longer period (20 turns of 60 ± 3 frames were stated as 412 frames, a helper's finding).
const MIN_REPEATS_OF_A_MULTIPLE: f64 = 4.0;

/// The main repeat (frames, at least `min_frames`) where the track's period `tau` spans k ≥ 2
/// of its strongest harmonic's repeats and the track holds fewer than
/// [`MIN_REPEATS_OF_A_MULTIPLE`] periods, or 2k. A true period of two turns (period doubling)
/// seen four times or more stands. (20 turns of 60 ± 1.8 frames once came back as 5 turns,
/// seen 4 times.)
fn too_few_repeats(z: &[Complex64], tau: f64, min_frames: f64) -> Option<f64> {
    let seen = (z.len() as f64 - 1.0) / tau;
    let fit = harmonic::harmonic_period(z, tau, (0.03 * tau).min(tau / 4.0))?;
    let k = fit.strongest();
    // A span of more turns lines up by chance more easily: at least 2k repeats of it.
    let needed = MIN_REPEATS_OF_A_MULTIPLE.max(2.0 * k as f64);
    let main = fit.period_frames / k as f64;
    (k >= 2 && seen < needed && main >= min_frames).then_some(main)
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// The largest |position| of the track, down or across.
fn extent_of(track: &CleanTrack) -> f64 {
    let all = track.down.iter().chain(&track.across);
    all.fold(0.0f64, |m, v| m.max(v.abs()))
}

/// What the turns show of a rule between them ([`super::turns`]), read where the track with
/// period `tau` repeats less closely than [`CLOSE_REPEAT_FLOOR`] (mismatch `m`): a chaotic
/// motion repeats only on average, its turns following from one another by a rule where a
/// roll's vary by chance, and a quasi-periodic one swings with a second period that is not a
/// whole number of turns; both are refused.
fn no_rule_between_turns(
    det: &Detrended,
    tau: f64,
    m: f64,
) -> Result<Option<TurnRule>, TrackError> {
    let turn_rule = (m > 0.0).then(|| turn_rule(&det.z, tau));
    let what = |rule: &TurnRule| {
        if rule.quasi_periodic() {
            Some("a quasi-periodic motion, which never repeats exactly")
        } else if rule.chaotic() {
            Some("a chaotic motion, which repeats only on average")
        } else {
            None
        }
    };
    match turn_rule.as_ref().and_then(|r| Some((r, what(r)?))) {
        Some((rule, what)) => Err(TrackError::NoPeriod {
            best_frames: tau,
            why: format!(
                "the track repeats after {tau:.1} frames only in the mean (mismatch {}): its \
                 turns {}: {what}, and so has no period",
                // Closer than a close repeat's floor, in powers of ten (0.000 says nothing).
                if m < CLOSE_REPEAT_FLOOR {
                    format!("{m:.1e}")
                } else {
                    format!("{m:.3}")
                },
                rule.said()
            ),
        }),
        None => Ok(turn_rule),
    }
}

/// The check against chance (see the module doc) of the period `tau` with normalised
/// mismatch `m`, or `None` without surrogates.
fn against_chance(
    det: &Detrended,
    e: &[f64],
    (tau, m): (f64, f64),
    search: &PeriodSearch,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Option<Significance>, TrackError> {
    if search.surrogates == 0 {
        return Ok(None);
    }
    // Past SURROGATE_FRAMES the surrogates are of the track's first SURROGATE_FRAMES frames:
    // shorter tracks reach lower dips by chance, so the test only gets stricter, and a million
    // frames take seconds instead of tens.
    let floor = if det.z.len() > SURROGATE_FRAMES {
        let head = Detrended::of_signal(det.z[..SURROGATE_FRAMES].to_vec());
        surrogate_floor(
            &head,
            search.surrogates,
            (e.len() - 1).min((SURROGATE_FRAMES - 1) / 2),
            progress,
        )
    } else {
        surrogate_floor(det, search.surrogates, e.len() - 1, progress)
    };
    let k = (tau.round() as usize).clamp(1, e.len() - 1);
    let mean_before = e[1..=k].iter().sum::<f64>() / k as f64;
    let dip = if mean_before > 0.0 {
        m / mean_before
    } else {
        0.0
    };
    if dip >= SURROGATE_MARGIN * floor {
        return Err(TrackError::NoPeriod {
            best_frames: tau,
            why: format!(
                "the track repeats after {tau:.1} frames no better than chance: its normalised \
                 mismatch there is {dip:.3}, while {} surrogate tracks with the same smoothed \
                 spectrum and random phases reach {floor:.3} (a period needs below \
                 {SURROGATE_MARGIN} × that)",
                search.surrogates
            ),
        });
    }
    Ok(Some(Significance {
        surrogates: search.surrogates,
        surrogate_floor: floor,
        normalised_dip: dip,
        p_bound: 1.0 / (search.surrogates + 1) as f64,
    }))
}

/// The period's spread and standard error (frames) and where the error comes from: the
/// cycles' spread over √(cycles) with three cycles or more, else the dip's width
/// √(E_min / (a·(n − τ))).
fn uncertainty(
    cycle_periods: &[f64],
    m: f64,
    curvature: f64,
    n: usize,
    tau: f64,
) -> (Option<f64>, f64, ErrorSource) {
    if cycle_periods.len() >= 3 {
        let k = cycle_periods.len() as f64;
        let mean = cycle_periods.iter().sum::<f64>() / k;
        let var = cycle_periods
            .iter()
            .map(|p| (p - mean).powi(2))
            .sum::<f64>()
            / (k - 1.0);
        // Each cycle's period is its shift against the next cycle, so it spans two turns and
        // consecutive ones share a turn: c_i ≈ (d_i + d_{i+1})/2 for turns of times d_i. Their
        // spread is the turns' over √2, and their mean varies as the turns' mean does, by
        // 2·var(c)/k. Spread over √k alone held the true mean period 66–80 % of the time on
        // tracks whose turns vary by 5 % (a helper's finding, 2026-11-28); this, 92 %.
        let factor = 2.0;
        (
            Some(var.sqrt()),
            (factor * var / k).sqrt(),
            ErrorSource::Cycles,
        )
    } else {
        // a ≤ 0 only on a flat dip, which the quarter-frame grid cannot resolve: a quarter frame.
        let width = if curvature > 0.0 {
            (m / (curvature * (n as f64 - tau))).sqrt()
        } else {
            0.25
        };
        (None, width, ErrorSource::DipWidth)
    }
}

/// The normalised mismatch d′ at every whole shift from 1 frame to half the track, as
/// [`find_period`] reads it, without deciding anything: for showing why a track was refused.
/// Empty for a track under 8 frames or one that does not vary.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::CleanTrack;
/// use rollphase_core::analysis::experiment::tracking::period::mismatch_curve;
/// let frames: Vec<f64> = (0..400).map(f64::from).collect();
/// let w = std::f64::consts::TAU / 40.0;
/// let down = frames.iter().map(|f| 0.5 * f + 2.0 * (w * f).sin()).collect();
/// let across = frames.iter().map(|f| (w * f).cos()).collect();
/// let track = CleanTrack { frames, down, across, warnings: vec![] };
/// let curve = mismatch_curve(&track);
/// // It dips to the noise floor at the period, 40 frames.
/// assert!(curve[39][0] == 40.0 && curve[39][1] < 1e-6);
/// ```
pub fn mismatch_curve(track: &CleanTrack) -> Vec<[f64; 2]> {
    let n = track.down.len();
    if n < 8 {
        return Vec::new();
    }
    let det = Detrended::of(track);
    let scale = det.scale();
    if !(scale > 0.0 && scale.is_finite()) {
        return Vec::new();
    }
    let whole = Curve::of(&det.z, (n - 1) / 2, &mut FftPlanner::new());
    let e: Vec<f64> = whole.e.iter().map(|v| v / scale).collect();
    normalised(&e)
        .into_iter()
        .enumerate()
        .skip(1)
        .map(|(t, d)| [t as f64, d])
        .collect()
}

/// Finds the track's period (see the module doc), between `search.min_frames` and half the
/// track; `progress` hears of each surrogate searched (done, of).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::{CleanTrack, PeriodSearch, find_period};
/// // A body rolling 0.5 cm a frame whose speed and sideways wobble repeat every 37.5 frames.
/// let frames: Vec<f64> = (0..400).map(f64::from).collect();
/// let w = std::f64::consts::TAU / 37.5;
/// let down = frames.iter().map(|f| 0.5 * f + 2.0 * (w * f).sin()).collect();
/// let across = frames.iter().map(|f| 0.01 * f + (w * f).cos()).collect();
/// let track = CleanTrack { frames: frames.clone(), down, across, warnings: vec![] };
/// let fit = find_period(&track, &PeriodSearch::default(), &|_, _| {})?;
/// assert!((fit.period_frames - 37.5).abs() < 0.05, "{}", fit.period_frames);
/// assert!((fit.advance_down - 18.75).abs() < 0.05);
/// assert_eq!(fit.periods_seen, 10);
/// assert!(fit.period_error_frames.is_finite());
/// # Ok::<(), rollphase_core::analysis::experiment::tracking::TrackError>(())
/// ```
pub fn find_period(
    track: &CleanTrack,
    search: &PeriodSearch,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<PeriodFit, TrackError> {
    let n = track.down.len();
    let min_tau = search.min_frames.max(2.0);
    let needed = (2.0 * min_tau).ceil() as usize + 3;
    if n < needed {
        return Err(TrackError::TooShort {
            usable: n,
            what: "in the steady stretch".into(),
            needed,
        });
    }
    let max_tau = (n - 1) / 2;
    let det = Detrended::of(track);
    let scale = det.scale();
    if scale <= (NOTHING_VARIES * extent_of(track)).powi(2) {
        return Err(TrackError::Damaged(
            "the track is a straight line at constant speed: nothing repeats that could give a \
             period"
                .into(),
        ));
    }
    let mut planner = FftPlanner::new();
    let whole = Curve::of(&det.z, max_tau, &mut planner);
    let e: Vec<f64> = whole.e.iter().map(|v| v / scale).collect();
    let dn = normalised(&e);
    let curve: Vec<[f64; 2]> = e
        .iter()
        .enumerate()
        .skip(1)
        .map(|(t, &v)| [t as f64, v])
        .collect();
    let found = dips(&e, &dn);
    let Some(&best_whole) = found.iter().min_by(|&&a, &&b| e[a].total_cmp(&e[b])) else {
        return Err(no_dip(&e, &dn, max_tau));
    };
    let best = refine(&whole, best_whole, scale);
    // The smallest dip within the tolerance of the best, refined (a period that is not a whole
    // number of frames can lose to its double at whole shifts); the first few are enough, as
    // the period is the first.
    let chosen = found
        .iter()
        .take(8)
        .map(|&k| {
            if k == best_whole {
                best
            } else {
                refine(&whole, k, scale)
            }
        })
        .find(|r| r.1 <= MULTIPLE_TOLERANCE * best.1 + MULTIPLE_SLACK)
        .unwrap_or(best);
    // A dip at a fraction of the chosen shift that is as low is the period, even where the
    // noise kept its d′ just above the level: the period, never a multiple of it.
    let tolerance = MULTIPLE_TOLERANCE * best.1 + MULTIPLE_SLACK;
    let chosen = (2..=8usize)
        .rev()
        .map(|q| chosen.0 / q as f64)
        .filter(|&t| t >= 2.0 && t + 1.0 < max_tau as f64)
        .map(|t| (t, refine(&whole, t.round() as usize, scale)))
        .find(|(t, r)| (r.0 - t).abs() < 0.5 && r.1 <= tolerance)
        .map(|(_, r)| r)
        .unwrap_or(chosen);
    let (tau, m, mean, curvature) = chosen;
    // The harmonics have the last word on which repeat is the period (a dip cannot tell a
    // period from its multiples where the frame rate aliases its harmonics).
    let (tau, m, mean, curvature) = match fundamental(&det.z, tau, max_tau as f64) {
        Fundamental::Keep => (tau, m, mean, curvature),
        Fundamental::Period(t) => {
            let r = refine(&whole, (t.round() as usize).clamp(2, max_tau - 1), scale);
            (t, r.1, r.2, r.3)
        }
        Fundamental::TooFast(t) => {
            return Err(TrackError::TooFast {
                period_frames: t,
                min_frames: search.min_frames,
            });
        }
    };
    // Too few repeats of a span of several main repeats: the main repeat is the period, and the
    // checks below (each cycle against the next, the blocks) say whether the turns keep time.
    let (tau, m, mean, curvature) = too_few_repeats(&det.z, tau, search.min_frames)
        .map_or((tau, m, mean, curvature), |main| {
            refine(&whole, (main.round() as usize).clamp(2, max_tau - 1), scale)
        });
    if m > MAX_MISMATCH {
        return Err(TrackError::NoPeriod {
            best_frames: tau,
            why: format!(
                "the best repeat (shift {tau:.1} frames) leaves {m:.2} of the track's variation \
                 unexplained (at most {MAX_MISMATCH} is accepted)"
            ),
        });
    }
    if tau < search.min_frames {
        return Err(TrackError::TooFast {
            period_frames: tau,
            min_frames: search.min_frames,
        });
    }
    let periods_seen = ((n - 1) as f64 / tau).floor() as usize;
    let cycle_fits = cycles(&det, tau, scale, &mut planner);
    let tested = cycle_fits.len();
    let cycle_periods: Vec<f64> = cycle_fits.iter().flatten().copied().collect();
    let unrepeated = tested - cycle_periods.len();
    // The first and last cycle may hold the release or the end of the ramp.
    if tested == 0 || unrepeated * 4 > tested.max(4) || cycle_periods.is_empty() {
        return Err(TrackError::NoPeriod {
            best_frames: tau,
            why: format!(
                "the whole track repeats best after {tau:.1} frames, but {unrepeated} of its \
                 {tested} cycle(s) do not repeat on their own (their best shift against the next \
                 cycle lies on the edge of ±{:.0} % or leaves more than {MAX_MISMATCH} \
                 unexplained)",
                100.0 * CYCLE_WINDOW
            ),
        });
    }
    let significance = against_chance(&det, &e, (tau, m), search, progress)?;
    let (spread, error, from) = uncertainty(&cycle_periods, m, curvature, n, tau);
    let start = if from == ErrorSource::Cycles {
        cycle_periods.iter().sum::<f64>() / cycle_periods.len() as f64
    } else {
        tau
    };
    let (tau, error, from, harmonic) = regression(&det.z, start, (error, from), m)?;
    let turn_rule = if search.read_turns {
        no_rule_between_turns(&det, tau, m)? // at the period as stated
    } else {
        None
    };
    // The regression saw the track less its line: the line's slope goes back into its velocity.
    let harmonic = harmonic.map(|mut fit| {
        fit.velocity += det.slope;
        fit
    });
    let block_check = harmonic.and_then(|f| f.blocks);
    let (m, mean) = if tau == start && from == ErrorSource::DipWidth {
        (m, mean)
    } else {
        let (e_at, d_at) = whole.at(tau);
        (e_at / scale, d_at)
    };
    let (advance, advance_error, velocity) =
        motion(harmonic, (tau, error, from), mean + det.slope * tau);
    Ok(PeriodFit {
        period_frames: tau,
        period_error_frames: error,
        period_error_from: from,
        period_spread_frames: spread,
        cycle_periods,
        unrepeated_cycles: unrepeated,
        periods_seen,
        mismatch: m,
        advance_down: advance.re,
        advance_across: advance.im,
        advance_error,
        velocity,
        significance,
        block_check,
        mismatch_curve: curve,
        turn_rule,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fft_curve_is_the_direct_mismatch_at_every_whole_shift() {
        let n = 257;
        let down: Vec<f64> = (0..n)
            .map(|i| 0.3 * i as f64 + (0.21 * i as f64).sin() + 0.01 * ((i * i) % 7) as f64)
            .collect();
        let across: Vec<f64> = (0..n)
            .map(|i| (0.13 * i as f64).cos() - 0.002 * i as f64)
            .collect();
        let det = Detrended::of(&CleanTrack::on_frames(down, across));
        let curve = Curve::of(&det.z, 128, &mut FftPlanner::new());
        for tau in [0usize, 1, 5, 37, 100, 127] {
            let direct = det.mismatch_at(tau).0;
            assert!(
                (curve.e[tau] - direct).abs() < 1e-10 * (1.0 + direct),
                "τ = {tau}: {} against {direct}",
                curve.e[tau]
            );
            // The evaluation between whole shifts is exact at them.
            let between = curve.at(tau as f64).0;
            assert!(
                (between - direct).abs() < 1e-9 * (1.0 + direct),
                "τ = {tau}: {between} against {direct}"
            );
        }
    }

    #[test]
    fn the_cycles_fft_agrees_with_the_direct_shift() {
        let n = 600;
        let w = std::f64::consts::TAU / 41.3;
        let down: Vec<f64> = (0..n)
            .map(|i| 0.5 * i as f64 + 3.0 * (w * i as f64).sin())
            .collect();
        let across: Vec<f64> = (0..n).map(|i| (w * i as f64 + 0.4).cos()).collect();
        let det = Detrended::of(&CleanTrack::on_frames(down, across));
        let scale = det.scale();
        let fits = cycles(&det, 41.3, scale, &mut FftPlanner::new());
        assert_eq!(fits.len(), 13);
        for p in fits {
            let p = p.expect("every cycle repeats");
            assert!((p - 41.3).abs() < 0.2, "{p}");
        }
    }
}
