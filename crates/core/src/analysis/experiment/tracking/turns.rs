//! Whether a track's turns follow from one another by a rule: the test that tells a chaotic or
//! quasi-periodic motion from a roll whose turns vary by chance, where all repeat only roughly.
//!
//! A chaotic motion whose phase keeps time (the Rössler attractor) passes every test of a
//! repeat in [`super::period`] and leaves as much unrepeated as the authors' real run (a
//! normalised mismatch of 0.14–0.24), so the mismatch cannot tell them apart. What tells them
//! apart is determinism: a chaotic attractor's turns are each a function of those before (the
//! peak of one turn fixes the next's: a return map, as Lorenz read his attractor's maxima),
//! while a roll disturbed by the ramp's roughness and the fluid varies from turn to turn by
//! chance. The reading, per coordinate (down and across, less the track's line):
//! - each turn's peak: the largest value within half a period on either side, refined by the
//!   parabola through the values within a sixth of a period (the frame grid's own rounding
//!   would otherwise scatter the peaks), and the peaks less their own line in time (the track's
//!   line, taken out over a span that is not a whole number of turns, leaves a slope in them);
//! - each next peak predicted from the 1 to [`MAX_LAGS`] peaks before, two ways: by the best
//!   straight line in them (which every linear random variation of the turns, with any
//!   correlation from turn to turn, follows as well as it can be followed), and by the method
//!   of analogues (the turn whose peaks before lie nearest, not the turn itself or its
//!   neighbours in time, and the peak that followed it); one peak is not always enough: a size
//!   eased from turn to turn mixes two turns' sizes into each peak, which two peaks untangle;
//! - the ratio of the analogues' mean squared error to the line's, the lowest over the
//!   coordinates and the numbers of peaks before.
//!
//! For turns that vary by chance the analogues do worse than the line (about 2: two draws of
//! the chance part instead of one); for a rule that is not a line they do far better. A rule is
//! stated (chaos) under [`RULE_RATIO`], over at least [`MIN_TURNS`] turns. No rule is read
//! where
//! - the peaks vary only with where the frames fall on each turn (a noise-free periodic track
//!   whose period is not a whole number of frames samples each turn elsewhere, and its peaks
//!   follow the frame grid's rule: the turn on which whole periods from the first peak fall
//!   most nearly alike between frames predicts it to under a tenth of what unrelated peaks
//!   leave; the grid's rotation, not the peaks' measured times, which an eased size moves too);
//! - a repeat after 1 to [`MAX_TURNS_REPEAT`] turns explains the peaks of a coordinate (its
//!   median error under a tenth of their variance and its mean within 2·min(k, 4) times the
//!   analogues'; seen three times at least): a period of a few turns, even with slips now and then at random, such as a
//!   doubling the centre alone cannot resolve, is a rule too, but a periodic one. A coordinate
//!   whose peaks do not vary beyond round-off is left out, and the rule read in the other.
//!
//! A second period (quasi-periodic motion) is read where the line in the two peaks before is a
//! rotation (complex roots of modulus at least [`QUASI_MODULUS`]), one sinusoid at its rate
//! (refined within ±5 %) explains at least [`QUASI_EXPLAINED`] of the peaks' variance over the
//! whole track (a damped resonance driven by chance turns too, but its phase and size wander:
//! 0.19–0.66), it turns through at least two cycles along the track and drifts over a turn from
//! the nearest whole-turn repeat: sizes that swing every 7.3 turns never repeat.
//!
//! Only the peaks' heights are read, not their times: a chaos that moves only the turns' times
//! (by 1–3 %) reads as chance (a helper's finding), and from 10 % is refused.
//!
//! Measured by `bench calibration --draws 400` (2026-12-04, [`super::turns_calibration`]):
//! 2,000 rolls whose turns' sizes follow AR(1) processes (ρ from −0.95 to 0.995, sizes varying
//! 3–20 %, turn times 0–5 %, noise 0.1–10 % of the wobble, 8–60 frames and 20–100 turns): none
//! called chaotic or quasi-periodic, the lowest of 1,820 ratios read 0.564, the median 1.73.
//! 100 rolls whose sizes the logistic map drives, eased from turn to turn: all refused as chaotic
//! (ratios 0.005–0.17). 100 with a second period of k + 0.3 to k + 0.7 turns: 96 refused as
//! quasi-periodic. The Rössler attractor (c = 5, 5.7; 100 stretches each): refused at noise
//! 0.2 % and 2 % of its size (399 of 400), 39 % and 80 % at 6 %, where noise hides the rule
//! and the turns read as chance does.

use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::NOTHING_VARIES;

/// The analogues' error over the line's under which the turns follow a rule.
pub const RULE_RATIO: f64 = 0.25;
/// The analogues' error over the line's above which the turns read as chance does: about the
/// lowest that rolls whose turns vary by chance reach (0.564 in `bench calibration`'s 2,000);
/// between this and [`RULE_RATIO`] neither is shown.
pub const CHANCE_RATIO: f64 = 0.55;
/// The fewest turns read for a rule: at 12 turns chance read 0.19 once in 300 rolls.
pub const MIN_TURNS: usize = 20;
/// The most turns read (the first ones): the analogues are found among all pairs.
pub const MAX_TURNS: usize = 2000;
/// The longest repeat, in turns, that is tried as the explanation of a rule before the rule is
/// called chaotic (one seen three times at least): gaps bridged every 10 frames on a track of
/// 6.5 frames a turn repeat with the turns after 20 of them, and their rule read 0.24.
pub const MAX_TURNS_REPEAT: usize = 24;
/// The most turns before a turn that its peak is predicted from (the analogues' and the line's
/// embedding): a size eased from turn to turn mixes two turns' sizes into each peak, which one
/// peak alone cannot untangle and two can.
pub const MAX_LAGS: usize = 3;
/// A second period is read where one sinusoid at the rotation of the line in the two peaks
/// before (of modulus at least [`QUASI_MODULUS`]) explains at least this share of the peaks'
/// variance over the whole track.
pub const QUASI_EXPLAINED: f64 = 0.9;
/// See [`QUASI_EXPLAINED`].
pub const QUASI_MODULUS: f64 = 0.9;

/// What a track's turns show of a rule between them ([`turn_rule`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TurnRule {
    /// Turns read (the fewer of down's and across's peaks, at most [`MAX_TURNS`]).
    pub turns: usize,
    /// The analogues' mean squared error in predicting each turn's peak from the `lags` before,
    /// over the best straight line's in them, the lowest over down and across and 1 to
    /// [`MAX_LAGS`] lags: about 2 for turns that vary by chance, under [`RULE_RATIO`] for a
    /// rule. `None` under [`MIN_TURNS`] turns, where the peaks do not vary, or where a repeat
    /// after a few turns predicts them as well.
    pub ratio: Option<f64>,
    /// The turns before that the lowest ratio predicts from (0 with no ratio).
    pub lags: usize,
    /// A second period of the turns' peaks, in turns, not a whole number of them (a
    /// quasi-periodic motion): the line in the two peaks before is a rotation of modulus at
    /// least [`QUASI_MODULUS`], one sinusoid at its rate explains at least [`QUASI_EXPLAINED`]
    /// of their variance over the whole track, and it drifts over a turn from the nearest
    /// whole-turn repeat along the track.
    pub second_period_turns: Option<f64>,
    /// Whether the peaks vary only with where the frames fall on each turn (a period that is not
    /// a whole number of frames samples each turn elsewhere, so the peaks of a periodic motion
    /// follow a rule of their own, the frame grid's): then no rule is read.
    pub frame_grid: bool,
}

impl TurnRule {
    /// Whether the turns follow a rule that is not a repeat: a chaotic motion.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::turns::TurnRule;
    /// let rule = |ratio| TurnRule {
    ///     turns: 60,
    ///     ratio,
    ///     lags: 1,
    ///     second_period_turns: None,
    ///     frame_grid: false,
    /// };
    /// assert!(rule(Some(0.02)).chaotic());
    /// assert!(!rule(Some(1.9)).chaotic());
    /// assert!(!rule(None).chaotic());
    /// ```
    pub fn chaotic(&self) -> bool {
        self.ratio.is_some_and(|r| r < RULE_RATIO)
    }

    /// Whether the turns swing with a second period that is not a whole number of turns: a
    /// quasi-periodic motion.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::turns::TurnRule;
    /// let rule = |second_period_turns| TurnRule {
    ///     turns: 60,
    ///     ratio: Some(1.8),
    ///     lags: 2,
    ///     second_period_turns,
    ///     frame_grid: false,
    /// };
    /// assert!(rule(Some(7.3)).quasi_periodic() && !rule(None).quasi_periodic());
    /// ```
    pub fn quasi_periodic(&self) -> bool {
        self.second_period_turns.is_some()
    }

    /// What it shows, for people, after "its turns": where the rule was read and where not.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::turns::TurnRule;
    /// let rule = |turns, ratio| TurnRule {
    ///     turns,
    ///     ratio,
    ///     lags: 1,
    ///     second_period_turns: None,
    ///     frame_grid: false,
    /// };
    /// assert!(rule(60, Some(0.02)).said().starts_with("follow from one another by a rule"));
    /// assert!(rule(60, Some(0.4)).said().contains("neither is shown"));
    /// assert!(rule(9, None).said().contains("too few (9)"));
    /// ```
    pub fn said(&self) -> String {
        let lags = match self.lags {
            1 => "peak before".to_string(),
            k => format!("{k} peaks before"),
        };
        if let Some(p) = self.second_period_turns {
            return format!(
                "swing with a second period of {p:.2} turns, not a whole number of them: over {} \
                 turns, one sinusoid of that period leaves under {:.0} % of their peaks' \
                 variation",
                self.turns,
                100.0 * (1.0 - QUASI_EXPLAINED)
            );
        }
        match self.ratio {
            Some(r) if r < RULE_RATIO => format!(
                "follow from one another by a rule: over {} turns, each turn's peak predicted \
                 from its nearest analogue (the turn with the nearest {lags}, and the peak that \
                 followed it) misses by {r:.3} of what the best straight line in the {lags} \
                 misses \
                 (turns that vary by chance read about 2, a rule under {RULE_RATIO})",
                self.turns
            ),
            Some(r) if r < CHANCE_RATIO => format!(
                "may follow from one another by a rule that noise or the reading blurs: over {} \
                 turns, each \
                 turn's peak predicted from its nearest analogue misses by {r:.2} of what a \
                 straight line misses, between a rule's (under {RULE_RATIO}) and the least that \
                 turns varying by chance read ({CHANCE_RATIO}), so neither is shown",
                self.turns
            ),
            Some(r) => format!(
                "do not follow from one another by a rule that noise lets show: over {} turns, \
                 each turn's peak predicted from its nearest analogue misses by {r:.2} of what a \
                 straight line misses (a rule reads under {RULE_RATIO}, chance about 2)",
                self.turns
            ),
            None if self.frame_grid => "vary only with where the frames fall on each turn (its \
                                          period is not a whole number of frames), so no rule \
                                          between them is read"
                .into(),
            None if self.turns < MIN_TURNS => format!(
                "are too few ({}) to tell a chaotic motion, whose turns follow from one another, \
                 from a roll whose turns vary by chance ({MIN_TURNS} are needed)",
                self.turns
            ),
            None => "change little from one turn to the next or repeat after a few, so no rule \
                     between them is read"
                .into(),
        }
    }
}

/// The turns' peaks of `x` (frames on a regular grid) for a period of `period` frames, at most
/// [`MAX_TURNS`] + 1, each with the time it lies at (frames, between frames).
fn peaks(x: &[f64], period: f64) -> Vec<(f64, f64)> {
    let half = (period / 2.0).round().max(1.0) as usize;
    let near = ((period / 6.0).round() as usize).max(2);
    let n = x.len();
    let mut out = Vec::new();
    if n < 2 * half + 1 {
        return out;
    }
    let mut i = half;
    while i + half < n && out.len() <= MAX_TURNS {
        let window = &x[i - half..=i + half];
        if window.iter().all(|&v| v <= x[i]) && (i == half || x[i - 1] < x[i]) {
            out.push(vertex(x, i, near));
            i += half;
        } else {
            i += 1;
        }
    }
    out
}

/// The peaks (time, value) less their least-squares line in time: the track's own line, taken
/// out over a span that is not a whole number of turns, leaves a slope in the peaks that is no
/// part of how one turn follows another.
fn less_line(mut p: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    if p.len() < 3 {
        return p;
    }
    let n = p.len() as f64;
    let (mt, mv) = (
        p.iter().map(|v| v.0).sum::<f64>() / n,
        p.iter().map(|v| v.1).sum::<f64>() / n,
    );
    let stt: f64 = p.iter().map(|v| (v.0 - mt).powi(2)).sum();
    let stv: f64 = p.iter().map(|v| (v.0 - mt) * (v.1 - mv)).sum();
    let slope = if stt > 0.0 { stv / stt } else { 0.0 };
    for v in &mut p {
        v.1 -= mv + slope * (v.0 - mt);
    }
    p
}

/// Least squares y ≈ X·c by the normal equations (X has at most [`MAX_LAGS`] + 1 centred
/// columns); `None` where they are singular.
fn least_squares(x: &DMatrix<f64>, y: &DVector<f64>) -> Option<DVector<f64>> {
    let xt = x.transpose();
    (&xt * x).lu().solve(&(&xt * y))
}

/// The peak of the parabola through `x` within `near` frames of `i` (least squares), where it
/// lies and its value, or frame `i` and `x[i]` where it opens upward or its vertex lies outside
/// the span.
fn vertex(x: &[f64], i: usize, near: usize) -> (f64, f64) {
    let (lo, hi) = (i.saturating_sub(near), (i + near).min(x.len() - 1));
    let rows = hi + 1 - lo;
    let t = DMatrix::from_fn(rows, 3, |r, c| ((lo + r) as f64 - i as f64).powi(c as i32));
    let y = DVector::from_fn(rows, |r, _| x[lo + r] - x[i]);
    let Some(c) = least_squares(&t, &y) else {
        return (i as f64, x[i]);
    };
    let top = -c[1] / (2.0 * c[2]);
    if c[2] < 0.0 && top.abs() <= near as f64 {
        (i as f64 + top, x[i] + c[0] - c[1] * c[1] / (4.0 * c[2]))
    } else {
        (i as f64, x[i])
    }
}

/// The peaks `p` less their mean, as the states of `lags` peaks (the newest first) and the
/// peak after each.
fn embedded(p: &[f64], lags: usize) -> (DMatrix<f64>, DVector<f64>) {
    let mean = p.iter().sum::<f64>() / p.len() as f64;
    let n = p.len() - lags;
    let x = DMatrix::from_fn(n, lags + 1, |r, c| {
        if c == 0 { 1.0 } else { p[r + lags - c] - mean }
    });
    let y = DVector::from_fn(n, |r, _| p[r + lags] - mean);
    (x, y)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The analogues' mean squared error and the line's for the peaks `p` predicted from `lags`
/// peaks before, `None` where there are too few.
fn predictions(p: &[f64], lags: usize) -> Option<(f64, f64)> {
    if p.len() < lags + 4 {
        return None;
    }
    let (x, y) = embedded(p, lags);
    let n = y.len();
    let fit = least_squares(&x, &y)?;
    let line = (&y - &x * fit).norm_squared() / n as f64;
    // The nearest state that is not the turn itself or its neighbour in time (a slow drift
    // would otherwise predict itself).
    let errors: Vec<f64> = (0..n)
        .filter_map(|i| {
            let distance =
                |j: usize| -> f64 { (1..=lags).map(|c| (x[(i, c)] - x[(j, c)]).powi(2)).sum() };
            let best = (0..n)
                .filter(|j| j.abs_diff(i) > 1)
                .min_by(|&j, &k| distance(j).total_cmp(&distance(k)))?;
            Some((y[i] - y[best]).powi(2))
        })
        .collect();
    if errors.len() < n {
        return None;
    }
    Some((errors.iter().sum::<f64>() / n as f64, line))
}

/// Whether a repeat after k ≤ [`MAX_TURNS_REPEAT`] turns explains the peaks `p` as well as the
/// analogues do (`analogues`, their least mean squared error): predicting each peak by the one
/// k turns before leaves, typically (the median), under a tenth of their variance, and on
/// average within 2·min(k, 4) times what the analogues leave (a slip spoils k of the repeat's
/// predictions, and one or two of the analogues'). A repeat with rare slips (a period of three
/// turns that now and then skips one, at random) is still a repeat, the analogues predicting
/// the slips no better; turns that vary by chance or by a chaotic rule leave about twice their
/// variance, a chaotic motion's slow spirals (the Rössler attractor's) that change little from
/// turn to turn end in jumps the analogues predict and a repeat does not, and a second period
/// that is not a whole number of turns drifts away from every such repeat.
fn repeats_after_a_few(p: &[f64], analogues: f64) -> bool {
    let mean = p.iter().sum::<f64>() / p.len() as f64;
    let variance = p.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / p.len() as f64;
    (1..=MAX_TURNS_REPEAT)
        .filter(|&k| 3 * k <= p.len())
        .any(|k| {
            let errors: Vec<f64> = (k..p.len()).map(|i| (p[i] - p[i - k]).powi(2)).collect();
            let mean_error = errors.iter().sum::<f64>() / errors.len() as f64;
            median(errors) < 0.1 * variance && mean_error <= 2.0 * k.min(4) as f64 * analogues
        })
}

/// A second period of the peaks `p`, in turns (see [`TurnRule::second_period_turns`]).
fn second_period(p: &[f64]) -> Option<f64> {
    let (x, y) = embedded(p, 2);
    let n = y.len() as f64;
    let c = least_squares(&x, &y)?;
    let (b1, b2) = (c[1], c[2]);
    // p' = b1·p + b2·p₋₁ turns through ω a turn where its roots are complex: r·e^(±iω).
    if b1 * b1 + 4.0 * b2 >= 0.0 {
        return None;
    }
    let modulus = (-b2).sqrt();
    let omega = (b1 / (2.0 * modulus)).clamp(-1.0, 1.0).acos();
    // A random swing driven by chance (a damped resonance) turns too, but its phase and size
    // wander: one sinusoid over the whole track explains little of it (0.19–0.66 for
    // x' = 1.6x − 0.8x₋₁ + noise), where a second period's explains nearly all (0.98–0.996).
    let explained = (-20..=20)
        .map(|k| sine_explains(p, omega * (1.0 + 0.0025 * f64::from(k))))
        .fold(0.0f64, f64::max);
    let turns = std::f64::consts::TAU / omega;
    // Two swings along the track at least, and a drift of over a turn from the nearest repeat
    // of a whole number of turns (which the period search's repeat would be).
    let drift = (turns - turns.round()).abs() * n / turns;
    (modulus >= QUASI_MODULUS && explained >= QUASI_EXPLAINED && n / turns >= 2.0 && drift > 1.0)
        .then_some(turns)
}

/// The share of the variance of the peaks `p` (about their mean) that one sinusoid of `omega`
/// radians a turn, fitted over all of them, explains.
fn sine_explains(p: &[f64], omega: f64) -> f64 {
    let n = p.len();
    let mean = p.iter().sum::<f64>() / n as f64;
    let x = DMatrix::from_fn(n, 3, |r, c| match c {
        0 => 1.0,
        1 => (omega * r as f64).cos(),
        _ => (omega * r as f64).sin(),
    });
    let y = DVector::from_fn(n, |r, _| p[r] - mean);
    let total = y.norm_squared();
    match least_squares(&x, &y) {
        Some(c) if total > 0.0 => 1.0 - (&y - &x * c).norm_squared() / total,
        _ => 0.0,
    }
}

/// What the turns of `z` (a track as down + i·across less its line, one value a frame) with a
/// period of `period` frames show of a rule between them (see the module doc).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::turns::turn_rule;
/// use rustfft::num_complex::Complex64;
/// // 60 turns of 30 frames whose sizes follow the logistic map in its chaotic range.
/// let mut x = 0.3f64;
/// let size: Vec<f64> = (0..61).map(|_| { x = 3.9 * x * (1.0 - x); 0.5 + x }).collect();
/// let z: Vec<Complex64> = (0..1800)
///     .map(|f| {
///         let (k, u) = (f / 30, (f % 30) as f64 / 30.0);
///         let s = size[k] + (size[k + 1] - size[k]) * u;
///         let w = std::f64::consts::TAU * u;
///         Complex64::new(s * w.sin(), s * w.cos())
///     })
///     .collect();
/// assert!(turn_rule(&z, 30.0).chaotic());
/// // The same turns in a random order (a fixed shuffle): the rule is gone.
/// let mut shuffled = size.clone();
/// let mut state = 7u64;
/// for i in (1..shuffled.len()).rev() {
///     state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
///     shuffled.swap(i, (state >> 33) as usize % (i + 1));
/// }
/// let z: Vec<Complex64> = (0..1800)
///     .map(|f| {
///         let (k, u) = (f / 30, (f % 30) as f64 / 30.0);
///         let s = shuffled[k] + (shuffled[k + 1] - shuffled[k]) * u;
///         let w = std::f64::consts::TAU * u;
///         Complex64::new(s * w.sin(), s * w.cos())
///     })
///     .collect();
/// assert!(!turn_rule(&z, 30.0).chaotic());
/// ```
pub fn turn_rule(z: &[Complex64], period: f64) -> TurnRule {
    let down: Vec<f64> = z.iter().map(|v| v.re).collect();
    let across: Vec<f64> = z.iter().map(|v| v.im).collect();
    let (pd, pa) = (
        less_line(peaks(&down, period)),
        less_line(peaks(&across, period)),
    );
    let turns = pd.len().min(pa.len());
    let none = |frame_grid| TurnRule {
        turns,
        ratio: None,
        lags: 0,
        second_period_turns: None,
        frame_grid,
    };
    if turns < MIN_TURNS {
        return none(false);
    }
    if [&pd, &pa]
        .into_iter()
        .any(|p| frame_grid_explains(p, period))
    {
        return none(true);
    }
    let values = |p: &[(f64, f64)]| p.iter().map(|v| v.1).collect::<Vec<f64>>();
    let (pd, pa) = (values(&pd), values(&pa));
    // Per coordinate and number of peaks before: (ratio, lags). A coordinate whose peaks do not
    // vary (beyond round-off of the wobble) is left out; one that a repeat after a few turns
    // explains shows the motion repeating, and no rule is read.
    let wobble = z.iter().map(|v| v.norm_sqr()).sum::<f64>() / z.len().max(1) as f64;
    let varies = |p: &[f64]| {
        let spread = p.iter().map(|v| v * v).sum::<f64>() / p.len() as f64;
        spread > NOTHING_VARIES.powi(2) * wobble
    };
    let varying: Vec<&Vec<f64>> = [&pd, &pa].into_iter().filter(|p| varies(p)).collect();
    if varying.is_empty() {
        return none(false);
    }
    // A second period first: it also repeats, nearly, after a whole number of its swings (5.3
    // turns after 16), which the repeats below would take for the motion's.
    if let Some(turns_of) = varying.iter().find_map(|p| second_period(p)) {
        return TurnRule {
            second_period_turns: Some(turns_of),
            ..none(false)
        };
    }
    let mut best = None::<(f64, usize)>;
    for p in varying {
        let fits: Vec<(f64, f64, usize)> = (1..=MAX_LAGS)
            .filter_map(|lags| predictions(p, lags).map(|(a, l)| (a, l, lags)))
            .collect();
        let least = fits.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
        if !least.is_finite() {
            continue;
        }
        if repeats_after_a_few(p, least) {
            // One motion drives both coordinates: a repeat in one is the motion's.
            return none(false);
        }
        for (analogues, line, lags) in fits {
            let ratio = analogues / line;
            if line > 0.0 && ratio.is_finite() && best.is_none_or(|b| ratio < b.0) {
                best = Some((ratio, lags));
            }
        }
    }
    TurnRule {
        turns,
        ratio: best.map(|b| b.0),
        lags: best.map_or(0, |b| b.1),
        second_period_turns: None,
        frame_grid: false,
    }
}

/// Whether the peaks `p` (time, value) vary with where the frames fall on each turn: each
/// predicted by the turn whose frames fall most nearly alike, not itself or its neighbour in
/// time, leaves under a tenth of what unrelated peaks would (twice their variance). Where the
/// frames fall is the grid's own rotation, the fraction of a frame by which whole periods
/// `period` from the first peak miss a frame, not the peaks' measured times (which a size eased
/// from turn to turn moves too). A period within a frame over the track of a whole number of
/// frames falls alike on every turn, and nothing is explained by it. A chaotic motion or turns
/// that vary by chance have no such order.
fn frame_grid_explains(p: &[(f64, f64)], period: f64) -> bool {
    let n = p.len();
    if (period - period.round()).abs() * n as f64 <= 1.0 {
        return false;
    }
    let phase: Vec<f64> = p
        .iter()
        .map(|&(t, _)| {
            let turn = ((t - p[0].0) / period).round();
            (p[0].0 + turn * period).rem_euclid(1.0)
        })
        .collect();
    let mean = p.iter().map(|v| v.1).sum::<f64>() / n as f64;
    let variance = p.iter().map(|v| (v.1 - mean).powi(2)).sum::<f64>() / n as f64;
    let apart = |a: f64, b: f64| {
        let d = (a - b).abs();
        d.min(1.0 - d)
    };
    let error = (0..n)
        .filter_map(|i| {
            let best = (0..n)
                .filter(|j| j.abs_diff(i) > 1)
                .min_by(|&j, &k| apart(phase[i], phase[j]).total_cmp(&apart(phase[i], phase[k])))?;
            Some((p[i].1 - p[best].1).powi(2))
        })
        .sum::<f64>()
        / n as f64;
    variance > 0.0 && error < 0.1 * 2.0 * variance
}
