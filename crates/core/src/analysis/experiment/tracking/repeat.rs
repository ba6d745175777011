//! How far a track's stated period is shown to be the motion's period: the centre's mismatch at
//! the period against what its frame-to-frame noise explains, and the markers' reading where
//! there is one. A chaotic motion whose phase keeps time (the Rössler attractor) passes every
//! test of a repeat in [`super::period`] at the mismatch the authors' real run has; its turns
//! following from one another by a rule ([`super::turns`]) refuse it a period there, and where
//! the turns are too few or too noisy to show a rule, this says the period is only roughly
//! shown.

use serde::Serialize;

use super::mismatch::Detrended;
use super::turns::TurnRule;
use super::{CleanTrack, PeriodFit, markers};

/// How many times the share of a track's variation that its frame-to-frame noise explains its
/// mismatch at the period may be, for the centre to repeat closely ([`repeat_shown`]). Tracks of
/// known period with white noise of 5–50 % of the wobble leave 0.75–1.06 times it from 17 frames
/// a period up (0.04–0.89 below, where the third differences count some of the motion as noise);
/// the authors' viscous run leaves 5.8 times it, the chaotic Rössler attractor (a = b = 0.2,
/// c = 5 and 5.7, 29 frames a turn, 0.1 % noise) 4,900–9,300 times (2026-12-03). Noise a
/// tracker smooths is read as less than it is: an AR(1) noise with ρ = 0.8 leaves 8.1 times.
pub const CLOSE_REPEAT_FACTOR: f64 = 3.0;
/// A mismatch at the period under which the centre repeats closely whatever its noise: a track
/// that repeats to 0.1 % of its variation is periodic for every purpose a period serves.
pub const CLOSE_REPEAT_FLOOR: f64 = 1e-3;

/// How far a track's stated period is shown to be the motion's period ([`repeat_shown`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "shown", rename_all = "snake_case")]
pub enum RepeatShown {
    /// The centre repeats as closely as its frame-to-frame noise allows.
    Closely {
        /// The mismatch at the period over the share of the variation the noise explains;
        /// null where the noise cannot be read (too few runs of evenly spaced measured frames,
        /// or none varies).
        beyond_noise: Option<f64>,
    },
    /// The centre leaves more unrepeated than its noise explains, but the markers on the body
    /// repeat after one period or two ([`markers::MarkerVerdict`]): its orientation repeats.
    ByMarkers {
        /// As in `Closely`.
        beyond_noise: Option<f64>,
        /// Periods after which the markers repeat: 1, or 2 where the body's orientation repeats
        /// every other period (period doubling).
        after: usize,
    },
    /// The centre leaves more unrepeated than its noise explains, and no markers show the
    /// orientation repeating: the period is the track's mean repeat, a roll's whose turns vary
    /// by chance, or a chaotic motion's whose rule too few turns or too much noise hide.
    Roughly {
        /// As in `Closely`.
        beyond_noise: Option<f64>,
        /// What the turns show of a rule between them ([`super::turns`]): none, or too few
        /// turns to read one (a track whose turns follow a rule gets no period at all).
        turn_rule: Option<TurnRule>,
    },
}

impl RepeatShown {
    /// Its word, as summary.json and Python write it ("closely", "by_markers", "roughly").
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::RepeatShown;
    /// assert_eq!(RepeatShown::ByMarkers { beyond_noise: Some(9.0), after: 1 }.name(), "by_markers");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            RepeatShown::Closely { .. } => "closely",
            RepeatShown::ByMarkers { .. } => "by_markers",
            RepeatShown::Roughly { .. } => "roughly",
        }
    }

    /// What it says of the period, for people: empty where the centre repeats closely.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::RepeatShown;
    /// let rough = RepeatShown::Roughly { beyond_noise: Some(12.0), turn_rule: None };
    /// assert!(rough.caveat().contains("chaotic"));
    /// assert!(RepeatShown::Closely { beyond_noise: Some(1.0) }.caveat().is_empty());
    /// let doubled = RepeatShown::ByMarkers { beyond_noise: Some(5.0), after: 2 };
    /// assert!(doubled.caveat().contains("every 2 periods"));
    /// ```
    pub fn caveat(self) -> String {
        let beyond = |b: Option<f64>| match b {
            Some(b) => format!(
                "leaves {b:.1} times as much unrepeated as white frame-to-frame noise would \
                 (over {CLOSE_REPEAT_FACTOR} is beyond it)"
            ),
            None => format!(
                "leaves over {CLOSE_REPEAT_FLOOR} of its variation unrepeated, and its \
                 frame-to-frame noise cannot be read (under {MIN_NOISE_RUNS} runs of four evenly \
                 spaced measured frames, or none varies), so how much of that is noise is not \
                 shown"
            ),
        };
        let rule = |r: Option<TurnRule>| {
            r.map(|r| format!("; its turns {}", r.said()))
                .unwrap_or_default()
        };
        let markers = "markers on the body (--markers) can show whether its orientation repeats";
        match self {
            RepeatShown::Closely { .. } => String::new(),
            RepeatShown::ByMarkers {
                beyond_noise,
                after: 1,
            } => format!(
                "the centre {}, but the markers repeat every period: the body's orientation \
                 repeats too",
                beyond(beyond_noise)
            ),
            RepeatShown::ByMarkers {
                beyond_noise,
                after,
            } => format!(
                "the centre {}, but the markers repeat every {after} periods: the body's \
                 orientation repeats after {after} periods (period doubling), not after one",
                beyond(beyond_noise)
            ),
            RepeatShown::Roughly {
                beyond_noise: Some(b),
                turn_rule,
            } => format!(
                "the centre repeats only roughly: it {}, so the period is its mean repeat: its \
                 turns differ beyond the noise, as those of a roll whose turns vary and of a \
                 chaotic motion both do, or its tracker smooths the noise{}; {markers}",
                beyond(Some(b)),
                rule(turn_rule)
            ),
            RepeatShown::Roughly {
                beyond_noise: None,
                turn_rule,
            } => format!(
                "how closely the centre repeats is not shown: it {}{}; {markers}",
                beyond(None),
                rule(turn_rule)
            ),
        }
    }
}

/// The widest even spacing of frames (a track filmed every other frame, say) the noise is read
/// over.
const MAX_NOISE_STEP: usize = 4;
/// The least share of the variation read as noise: below it, floating-point round-off.
const ROUND_OFF_SHARE: f64 = 1e-15;
/// Runs of four evenly spaced measured frames needed to read the noise.
const MIN_NOISE_RUNS: usize = 20;

/// The share of the smallest squared third differences whose mean is the noise's: the largest
/// fifth (a tracker's glitches: a bad frame spoils four differences) are left out.
const NOISE_KEPT: f64 = 0.8;
/// The mean of a χ² variable with one degree of freedom below its [`NOISE_KEPT`] quantile
/// q = 1.281552² (its mean over all is 1): E[X; X < q] = P(χ²₃ < q) for χ²₁, so this is
/// (0.8 − √(2q/π)·e^(−q/2))/0.8.
const CHI2_1_KEPT_MEAN: f64 = 0.437_725;

/// The share of the track's variation (`track`, about its least-squares line, down and across)
/// that white noise of each measured position explains. The noise's variance comes from the
/// third differences of measured positions at four evenly spaced frames (`measured`: the rows
/// as read, frame, down, across; frames within the track's stretch, one to
/// [`MAX_NOISE_STEP`] apart): 20 σ² for white noise, while a motion of 8 steps or more a turn
/// leaves little there. Bridged gaps carry no noise and are left out; the mean of the smallest
/// [`NOISE_KEPT`] of the squared differences (over its χ²₁ value) stands for the mean of all,
/// so a few tracker glitches do not pass for noise, while a tracker's whole pixels, which leave
/// most differences 0, still read as noise. `None` under [`MIN_NOISE_RUNS`] such runs, where
/// nothing varies, or where the noise is under [`ROUND_OFF_SHARE`] of the variation.
fn noise_share(measured: &[(f64, f64, f64)], track: &CleanTrack) -> Option<f64> {
    let (first, last) = match (track.frames.first(), track.frames.last()) {
        (Some(&a), Some(&b)) => (a, b),
        _ => return None,
    };
    let rows: Vec<&(f64, f64, f64)> = measured
        .iter()
        .filter(|r| r.0 >= first && r.0 <= last && r.1.is_finite() && r.2.is_finite())
        .collect();
    let (mut down, mut across) = (Vec::new(), Vec::new());
    for w in rows.windows(4) {
        let step = w[1].0 - w[0].0;
        let even = (1..=MAX_NOISE_STEP).any(|h| step == h as f64)
            && (2..4).all(|k| w[k].0 - w[k - 1].0 == step);
        if even {
            let third =
                |c: fn(&(f64, f64, f64)) -> f64| c(w[3]) - 3.0 * c(w[2]) + 3.0 * c(w[1]) - c(w[0]);
            down.push(third(|r| r.1).powi(2));
            across.push(third(|r| r.2).powi(2));
        }
    }
    if down.len() < MIN_NOISE_RUNS {
        return None;
    }
    let noise = |mut d: Vec<f64>| {
        d.sort_by(f64::total_cmp);
        let kept = ((NOISE_KEPT * d.len() as f64) as usize).max(1);
        d[..kept].iter().sum::<f64>() / kept as f64 / (20.0 * CHI2_1_KEPT_MEAN)
    };
    // The variation about the least-squares line, down and across, as the mismatch is
    // normalised by it (its scale is twice that).
    let variance = Detrended::of(track).scale() / 2.0;
    let share = (noise(down) + noise(across)) / variance;
    // Below 1e-15 of the variation the differences are floating-point round-off, not a
    // tracker's noise (a noise-free sawtooth read "2401272461415361214939136.0 times" it).
    (share > ROUND_OFF_SHARE && share.is_finite()).then_some(share)
}

/// What a track's period shows of the motion repeating: the one decision `track`, its
/// summary.json and Python's `measure_track` state, from the centre's mismatch at the period
/// (`fit`, on `track`) against what its frame-to-frame noise explains (read from `measured`, the
/// rows as given: frame, down, across), and, where markers were read, whether their pattern
/// repeats (`markers`). A period is stated only where the track
/// repeats ([`super::find_period`]); this says how closely. A centre that leaves more than
/// [`CLOSE_REPEAT_FACTOR`] times what its noise explains (and over [`CLOSE_REPEAT_FLOOR`])
/// unrepeated varies from turn to turn smoothly, as a roll whose turns vary does and as a
/// chaotic motion does (the authors' run and the Rössler attractor leave the same mismatch,
/// 0.24): [`super::find_period`] has already refused a track whose turns follow a rule
/// ([`super::turns`]), so what is left varies by chance or has too few turns to tell, which
/// the caveat says; the markers can show the orientation repeating.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::{RepeatShown, measure, repeat_shown};
/// let frames: Vec<f64> = (0..1200).map(f64::from).collect();
/// let w = std::f64::consts::TAU / 30.0;
/// // A roll that repeats every 30 frames: shown closely.
/// let across: Vec<f64> = frames.iter().map(|&f| (w * f).cos()).collect();
/// let down: Vec<f64> = frames.iter().map(|&f| 0.1 * f + (w * f).sin()).collect();
/// let (track, fit) = measure(&frames, &down, &across, &|_, _| {})?;
/// let rows: Vec<(f64, f64, f64)> = (0..1200).map(|i| (frames[i], down[i], across[i])).collect();
/// assert_eq!(repeat_shown(&rows, &track, &fit, None).name(), "closely");
/// // Each turn's size drawn at random (a fixed generator) and eased from turn to turn: the
/// // turns repeat one by one well enough for a period, but only roughly, and by chance.
/// let mut state = 11u64;
/// let size: Vec<f64> = (0..42)
///     .map(|_| {
///         state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
///         0.5 + (state >> 11) as f64 / (1u64 << 53) as f64
///     })
///     .collect();
/// let s = |size: &[f64], f: f64| {
///     let (k, u) = ((f / 30.0).floor() as usize, f / 30.0 - (f / 30.0).floor());
///     size[k] + (size[k + 1] - size[k]) * u
/// };
/// let across: Vec<f64> = frames.iter().map(|&f| s(&size, f) * (w * f).cos()).collect();
/// let down: Vec<f64> = frames.iter().map(|&f| 0.1 * f + s(&size, f) * (w * f).sin()).collect();
/// let (track, fit) = measure(&frames, &down, &across, &|_, _| {})?;
/// let rows: Vec<(f64, f64, f64)> = (0..1200).map(|i| (frames[i], down[i], across[i])).collect();
/// assert_eq!(repeat_shown(&rows, &track, &fit, None).name(), "roughly");
/// // The sizes drawn by the logistic map in its chaotic range instead: each turn follows from
/// // the one before by a rule, a chaotic motion, and no period is stated.
/// let mut x = 0.3f64;
/// let size: Vec<f64> = (0..42).map(|_| { x = 3.9 * x * (1.0 - x); 0.5 + x }).collect();
/// let across: Vec<f64> = frames.iter().map(|&f| s(&size, f) * (w * f).cos()).collect();
/// let down: Vec<f64> = frames.iter().map(|&f| 0.1 * f + s(&size, f) * (w * f).sin()).collect();
/// let refused = measure(&frames, &down, &across, &|_, _| {}).unwrap_err();
/// assert!(refused.to_string().contains("chaotic"), "{refused}");
/// # Ok::<(), rollphase_core::analysis::experiment::tracking::TrackError>(())
/// ```
pub fn repeat_shown(
    measured: &[(f64, f64, f64)],
    track: &CleanTrack,
    fit: &PeriodFit,
    markers: Option<&markers::MarkerReading>,
) -> RepeatShown {
    use markers::MarkerVerdict::{EveryOtherPeriod, EveryPeriod};
    let noise = noise_share(measured, track);
    let beyond_noise = noise.map(|noise| fit.mismatch / noise);
    if fit.mismatch <= CLOSE_REPEAT_FLOOR.max(CLOSE_REPEAT_FACTOR * noise.unwrap_or(0.0)) {
        RepeatShown::Closely { beyond_noise }
    } else if let Some(after) = markers.and_then(|m| match m.verdict {
        EveryPeriod => Some(1),
        EveryOtherPeriod => Some(2),
        _ => None,
    }) {
        RepeatShown::ByMarkers {
            beyond_noise,
            after,
        }
    } else {
        RepeatShown::Roughly {
            beyond_noise,
            turn_rule: fit.turn_rule,
        }
    }
}
