//! How far a track's stated period is shown to be the motion's period: the centre's mismatch at
//! the period against what its frame-to-frame noise explains, and the markers' reading where
//! there is one. A chaotic motion whose phase keeps time (the Rössler attractor) passes every
//! test of a repeat in [`super::period`] at the mismatch the authors' real run has; the noise
//! tells them apart, and where it does not, the markers can.

use serde::Serialize;

use super::{CleanTrack, PeriodFit, markers};

/// How many times the share of a track's variation that its frame-to-frame noise explains its
/// mismatch at the period may be, for the centre to repeat closely ([`repeat_shown`]). Tracks of
/// known period with white noise of 5–50 % of the wobble leave 0.8–1.03 times it from 17 frames
/// a period up (0.05–0.9 below, where the third differences count some of the motion as noise);
/// the authors' viscous run leaves 4 times it, the chaotic Rössler attractor (a = b = 0.2,
/// c = 5 and 5.7, 29 frames a turn, 0.1 % noise) about 1,900 times (2026-12-03).
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
        /// null for a track without frame-to-frame noise.
        beyond_noise: Option<f64>,
    },
    /// The centre leaves more unrepeated than its noise explains, but the markers on the body
    /// repeat after one period or two ([`markers::MarkerVerdict`]): its orientation repeats.
    ByMarkers {
        /// As in `Closely`.
        beyond_noise: Option<f64>,
    },
    /// The centre leaves more unrepeated than its noise explains, and no markers show the
    /// orientation repeating: the period is the track's mean repeat, which a periodic roll
    /// whose turns vary and a motion that never repeats exactly (a chaotic one) both have.
    Roughly {
        /// As in `Closely`.
        beyond_noise: Option<f64>,
    },
}

impl RepeatShown {
    /// Its word, as summary.json and Python write it ("closely", "by_markers", "roughly").
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::RepeatShown;
    /// assert_eq!(RepeatShown::ByMarkers { beyond_noise: Some(9.0) }.name(), "by_markers");
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
    /// assert!(RepeatShown::Roughly { beyond_noise: Some(12.0) }.caveat().contains("chaotic"));
    /// assert!(RepeatShown::Closely { beyond_noise: Some(1.0) }.caveat().is_empty());
    /// ```
    pub fn caveat(self) -> String {
        let beyond = |b: Option<f64>| match b {
            Some(b) => {
                format!("{b:.0} times as much unrepeated as its frame-to-frame noise explains")
            }
            None => "more unrepeated than a track without frame-to-frame noise should".to_string(),
        };
        match self {
            RepeatShown::Closely { .. } => String::new(),
            RepeatShown::ByMarkers { beyond_noise } => format!(
                "the centre leaves {}, but the markers repeat: the body's orientation repeats too",
                beyond(beyond_noise)
            ),
            RepeatShown::Roughly { beyond_noise } => format!(
                "the centre repeats only roughly: it leaves {}, so the period is its mean repeat, \
                 which a periodic roll whose turns vary and a chaotic motion both have; markers \
                 on the body (--markers) can show whether its orientation repeats",
                beyond(beyond_noise)
            ),
        }
    }
}

/// The share of the track's variation (about its least-squares line, down and across) that
/// white noise of each frame's position explains: the noise's variance, from the third
/// differences of consecutive frames (20 σ² for white noise, while a motion of 8 frames or more
/// a turn leaves under 6 % of its own variance there), over the variation.
fn noise_share(track: &CleanTrack) -> f64 {
    let spread = |v: &[f64]| {
        let n = v.len() as f64;
        let (mx, my) = ((n - 1.0) / 2.0, v.iter().sum::<f64>() / n);
        let sxx: f64 = (0..v.len()).map(|i| (i as f64 - mx).powi(2)).sum();
        let sxy: f64 = v
            .iter()
            .enumerate()
            .map(|(i, y)| (i as f64 - mx) * (y - my))
            .sum();
        let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
        let variance = v
            .iter()
            .enumerate()
            .map(|(i, y)| (y - my - b * (i as f64 - mx)).powi(2))
            .sum::<f64>()
            / n;
        let third: Vec<f64> = v
            .windows(4)
            .map(|w| w[3] - 3.0 * w[2] + 3.0 * w[1] - w[0])
            .collect();
        let noise = third.iter().map(|d| d * d).sum::<f64>() / (20.0 * third.len().max(1) as f64);
        (noise, variance)
    };
    let ((nd, vd), (na, va)) = (spread(&track.down), spread(&track.across));
    if vd + va > 0.0 {
        (nd + na) / (vd + va)
    } else {
        0.0
    }
}

/// What a track's period shows of the motion repeating: the one decision `track`, its
/// summary.json and Python's `measure_track` state, from the centre's mismatch at the period
/// (`fit`, on `track`) against what its frame-to-frame noise explains, and, where markers were
/// read, whether their pattern repeats (`markers`). A period is stated only where the track
/// repeats ([`super::find_period`]); this says how closely. A centre that leaves more than
/// [`CLOSE_REPEAT_FACTOR`] times what its noise explains (and over [`CLOSE_REPEAT_FLOOR`])
/// unrepeated varies from turn to turn smoothly, as a roll whose turns vary does and as a
/// chaotic motion does: from the centre alone the two cannot be told apart (the authors' run
/// and the Rössler attractor leave the same mismatch, 0.24), and the markers can.
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
/// assert_eq!(repeat_shown(&track, &fit, None).name(), "closely");
/// // Each turn's size drawn by a logistic map in its chaotic range (and eased from turn to
/// // turn): the turns repeat one by one well enough for a period, but only roughly.
/// let mut x = 0.3f64;
/// let size: Vec<f64> = (0..42).map(|_| { x = 3.9 * x * (1.0 - x); 0.5 + x }).collect();
/// let s = |f: f64| {
///     let (k, u) = ((f / 30.0).floor() as usize, f / 30.0 - (f / 30.0).floor());
///     size[k] + (size[k + 1] - size[k]) * u
/// };
/// let across: Vec<f64> = frames.iter().map(|&f| s(f) * (w * f).cos()).collect();
/// let down: Vec<f64> = frames.iter().map(|&f| 0.1 * f + s(f) * (w * f).sin()).collect();
/// let (track, fit) = measure(&frames, &down, &across, &|_, _| {})?;
/// assert_eq!(repeat_shown(&track, &fit, None).name(), "roughly");
/// # Ok::<(), rollphase_core::analysis::experiment::tracking::TrackError>(())
/// ```
pub fn repeat_shown(
    track: &CleanTrack,
    fit: &PeriodFit,
    markers: Option<&markers::MarkerReading>,
) -> RepeatShown {
    use markers::MarkerVerdict::{EveryOtherPeriod, EveryPeriod};
    let noise = noise_share(track);
    let beyond_noise = (noise > 0.0).then(|| fit.mismatch / noise);
    if fit.mismatch <= CLOSE_REPEAT_FLOOR.max(CLOSE_REPEAT_FACTOR * noise) {
        RepeatShown::Closely { beyond_noise }
    } else if markers.is_some_and(|m| matches!(m.verdict, EveryPeriod | EveryOtherPeriod)) {
        RepeatShown::ByMarkers { beyond_noise }
    } else {
        RepeatShown::Roughly { beyond_noise }
    }
}
