//! A filmed run read as a measurement: a body's tracked centre (frame, down, across in cm),
//! cleaned of what trackers produce (gaps, jumps, the release and the end of the ramp), its
//! period found automatically with an uncertainty, the advance per period, and the track folded
//! into local coordinates (the paper's Fig. 5c) so that every period lies on the first.
//!
//! The period search lives in [`period`]: every shift at once by FFT, the dip read against the
//! shifts before it, each cycle checked on its own and the whole against surrogate tracks, so
//! that no period is stated that the track does not show. [`model`] sets the measurement
//! beside the model's prediction for the same body (m/m0 and t0 found together). [`table`]
//! reads the files trackers write (the authors' CSV, Tracker's export, trackpy's table).
//! [`repeat_shown`] says how far a stated period is shown to be the motion's: closely, by the
//! markers, or only roughly (a chaotic motion repeats as roughly as a roll whose turns vary).

pub mod calibration;
pub mod harmonic;
pub mod markers;
mod mismatch;
pub mod model;
pub mod period;
mod repeat;
mod surrogates;
pub mod table;
pub mod turns;
pub mod turns_calibration;

pub use period::{
    ErrorSource, MAX_MISMATCH, MIN_PERIOD_FRAMES, PeriodFit, PeriodSearch, Significance,
    find_period,
};
pub use repeat::{CLOSE_REPEAT_FACTOR, CLOSE_REPEAT_FLOOR, RepeatShown, repeat_shown};

use serde::Serialize;
use thiserror::Error;

/// Why a track gives no answer.
#[derive(Debug, Error, PartialEq)]
pub enum TrackError {
    /// Too few usable frames.
    #[error(
        "{usable} usable frames ({what}); finding a period needs at least {needed}, two periods' \
         worth"
    )]
    TooShort {
        /// Frames left.
        usable: usize,
        /// Why the others were left out.
        what: String,
        /// Frames needed.
        needed: usize,
    },
    /// Frame numbers that do not increase.
    #[error("row {row}: frame {frame} does not come after frame {previous} (frames must increase)")]
    Order {
        /// The data row (1 = the first after the header).
        row: usize,
        /// Its frame.
        frame: f64,
        /// The frame before.
        previous: f64,
    },
    /// Too much of the track is missing or broken.
    #[error("{0}")]
    Damaged(String),
    /// No shift makes the track repeat well enough, or not beyond chance.
    #[error("no period can be found with confidence: {why}")]
    NoPeriod {
        /// The best shift (frames).
        best_frames: f64,
        /// What the evidence lacks.
        why: String,
    },
    /// The track repeats faster than the frame rate can resolve.
    #[error(
        "the track repeats every {period_frames:.1} frames: fewer than {min_frames} frames a \
         period cannot be told from its multiples and the noise (film at a higher frame rate)"
    )]
    TooFast {
        /// The shift it repeats at (frames).
        period_frames: f64,
        /// The fewest frames a period needs.
        min_frames: f64,
    },
    /// The period holds over too little of the track.
    #[error(
        "the track repeats only over frames {from}–{to}, {percent:.0} % of its {frames} usable \
         frames (at least half is needed): the rest is not steady periodic rolling, so no period \
         is stated for the run"
    )]
    MostlyUnsteady {
        /// First frame that repeats.
        from: f64,
        /// Last frame that repeats.
        to: f64,
        /// Its share of the usable frames (%).
        percent: f64,
        /// Usable frames.
        frames: usize,
    },
    /// A setting out of range.
    #[error("{0}")]
    BadArgument(String),
}

/// Gaps of at most this many frames are bridged (by cubics through the two measured frames on
/// each side, straight lines at a piece's ends); a longer one splits the track.
pub const MAX_BRIDGED_GAP: usize = 10;
/// A window of one period whose speed down the ramp differs from the median by more than this
/// fraction is not steady rolling (the release, the end of the ramp): over a period, steady
/// rolling's mean speed is constant.
pub const PERIOD_STEADY_TOLERANCE: f64 = 0.15;

/// The track on a regular frame grid, in cm, with what was done to get it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CleanTrack {
    /// Frame numbers, consecutive.
    pub frames: Vec<f64>,
    /// Down the ramp (cm).
    pub down: Vec<f64>,
    /// Across the ramp (cm).
    pub across: Vec<f64>,
    /// What was bridged, replaced or left out, for people.
    pub warnings: Vec<String>,
}

impl CleanTrack {
    /// A track at frames 0, 1, 2, … as given, nothing cleaned (synthetic tracks, tests).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::CleanTrack;
    /// let t = CleanTrack::on_frames(vec![0.0, 1.0, 2.0], vec![0.5, 0.4, 0.5]);
    /// assert_eq!(t.frames, vec![0.0, 1.0, 2.0]);
    /// ```
    pub fn on_frames(down: Vec<f64>, across: Vec<f64>) -> Self {
        CleanTrack {
            frames: (0..down.len()).map(|i| i as f64).collect(),
            down,
            across,
            warnings: vec![],
        }
    }
}

/// The share of the positions' size under which a track's variation is round-off (1e-16 of the
/// positions can look periodic): the period search calls such a track a straight line, and the
/// turn rule ([`turns`]) leaves out a coordinate whose peaks vary less.
pub const NOTHING_VARIES: f64 = 1e-9;

/// The largest |position| a track may hold: squares and sums of squares of such numbers stay
/// finite in double precision.
pub const MAX_POSITION: f64 = 1e100;

/// The cubic through (xs[i], ys[i]) at x (Lagrange's form; the xs distinct).
fn cubic_through(xs: [f64; 4], ys: [f64; 4], x: f64) -> f64 {
    (0..4)
        .map(|i| {
            let weight: f64 = (0..4)
                .filter(|&j| j != i)
                .map(|j| (x - xs[j]) / (xs[i] - xs[j]))
                .product();
            weight * ys[i]
        })
        .sum()
}

/// A stretch of the track without a long gap: (frame, down, across) per frame.
type Piece = Vec<(f64, f64, f64)>;

/// The measured rows (row, frame, down, across) in pieces split at gaps longer than
/// [`MAX_BRIDGED_GAP`], shorter gaps bridged, and how many frames were bridged.
fn bridged_pieces(rows: &[(usize, f64, f64, f64)]) -> (Vec<Piece>, usize) {
    let mut pieces: Vec<Piece> = vec![Vec::new()];
    let mut bridged = 0usize;
    for (k, &(_, f, d, a)) in rows.iter().enumerate() {
        if k > 0 {
            let (_, f0, d0, a0) = rows[k - 1];
            let gap = (f - f0).round() as usize - 1;
            if gap > MAX_BRIDGED_GAP {
                pieces.push(Vec::new());
            } else {
                // Two measured frames on each side, no farther than the gap is wide: a cubic
                // through them. A straight line across a gap cuts the corner of every turn (12 %
                // of the swing for one frame missing at 12.5 frames a period), and gaps that
                // recur then repeat on their own, which the period search took for the motion.
                let outer = (k >= 2 && k + 1 < rows.len())
                    .then(|| (rows[k - 2], rows[k + 1]))
                    .filter(|(before, after)| {
                        f0 - before.1 <= (gap + 1) as f64 && after.1 - f <= (gap + 1) as f64
                    });
                for g in 1..=gap {
                    let x = f0 + g as f64;
                    let (dx, ax) = match outer {
                        Some((b, n)) => {
                            let at = |v: [f64; 4]| cubic_through([b.1, f0, f, n.1], v, x);
                            (at([b.2, d0, d, n.2]), at([b.3, a0, a, n.3]))
                        }
                        None => {
                            let s = g as f64 / (gap + 1) as f64;
                            (d0 + s * (d - d0), a0 + s * (a - a0))
                        }
                    };
                    let piece = pieces.last_mut().expect("one piece at least");
                    piece.push((x, dx, ax));
                    bridged += 1;
                }
            }
        }
        pieces
            .last_mut()
            .expect("one piece at least")
            .push((f, d, a));
    }
    (pieces, bridged)
}

/// Cleans a raw track: rows with a non-finite value dropped, gaps of up to
/// [`MAX_BRIDGED_GAP`] frames bridged by cubics through the two measured frames on each side
/// (a longer gap splits it: the longest piece is kept),
/// jumps (a point ten median steps, or ten of the positions' smallest step where that is larger,
/// from the median of its four nearest neighbours) replaced by
/// straight lines between good points.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::clean;
/// // Rolling at 1 cm a frame with a wobble across, one frame missing and one glitch.
/// let frames: Vec<f64> = (0..200).filter(|&i| i != 50).map(f64::from).collect();
/// let down: Vec<f64> = frames.iter().map(|&f| if f == 120.0 { 500.0 } else { f }).collect();
/// let across: Vec<f64> = frames.iter().map(|f| (f / 10.0).sin()).collect();
/// let track = clean(&frames, &down, &across)?;
/// assert_eq!(track.frames.len(), 200);
/// assert!((track.down[120] - 120.0).abs() < 1e-9, "the glitch is replaced");
/// assert_eq!(track.warnings.len(), 2);
/// # Ok::<(), rollphase_core::analysis::experiment::tracking::TrackError>(())
/// ```
pub fn clean(frames: &[f64], down: &[f64], across: &[f64]) -> Result<CleanTrack, TrackError> {
    if frames.len() != down.len() || frames.len() != across.len() {
        return Err(TrackError::BadArgument(
            "frames, down and across must have the same length".into(),
        ));
    }
    let mut warnings = Vec::new();
    let rows: Vec<(usize, f64, f64, f64)> = (0..frames.len())
        .filter(|&i| frames[i].is_finite() && down[i].is_finite() && across[i].is_finite())
        .map(|i| (i, frames[i], down[i], across[i]))
        .collect();
    // The period search squares positions (its mismatch and variances): past 1e100 those
    // overflow, and a periodic track read as a straight line. No tracker writes such numbers.
    if let Some(&(i, _, d, a)) = rows
        .iter()
        .find(|r| r.2.abs() > MAX_POSITION || r.3.abs() > MAX_POSITION)
    {
        return Err(TrackError::Damaged(format!(
            "row {}: a position of {:e} is too large for the period search, which squares \
             positions (needs |position| ≤ {MAX_POSITION:e}); give the track in sensible units",
            i + 1,
            if d.abs() > MAX_POSITION { d } else { a }
        )));
    }
    let dropped = frames.len() - rows.len();
    if dropped > 0 {
        if dropped * 5 > frames.len() {
            return Err(TrackError::Damaged(format!(
                "{dropped} of {} rows have a missing or non-finite value: more than a fifth of \
                 the track is not there",
                frames.len()
            )));
        }
        warnings.push(format!(
            "{dropped} row(s) with a missing or non-finite value left out"
        ));
    }
    for w in rows.windows(2) {
        if w[1].1 <= w[0].1 {
            return Err(TrackError::Order {
                row: w[1].0 + 1,
                frame: w[1].1,
                previous: w[0].1,
            });
        }
        if w[1].1.fract() != w[0].1.fract() {
            return Err(TrackError::Damaged(format!(
                "row {}: frame {} is not a whole number of frames after frame {}",
                w[1].0 + 1,
                w[1].1,
                w[0].1
            )));
        }
    }
    let (pieces, bridged) = bridged_pieces(&rows);
    if bridged > 0 {
        warnings.push(format!(
            "{bridged} missing frame(s) in gaps of up to {MAX_BRIDGED_GAP} frames bridged by \
             cubics through the two measured frames on each side"
        ));
    }
    if pieces.len() > 1 {
        let longest = pieces.iter().map(Vec::len).max().unwrap_or(0);
        warnings.push(format!(
            "the track has {} gap(s) longer than {MAX_BRIDGED_GAP} frames; its longest piece \
             ({longest} frames) is used",
            pieces.len() - 1
        ));
    }
    let piece = pieces.into_iter().max_by_key(Vec::len).unwrap_or_default();
    let fr: Vec<f64> = piece.iter().map(|p| p.0).collect();
    let mut dn: Vec<f64> = piece.iter().map(|p| p.1).collect();
    let mut ac: Vec<f64> = piece.iter().map(|p| p.2).collect();
    let needed = 16;
    if fr.len() < needed {
        return Err(TrackError::TooShort {
            usable: fr.len(),
            what: "after gaps and missing values".into(),
            needed,
        });
    }
    // Single-frame jumps: far from the midpoint of both neighbours, by the track's own scale.
    let mut steps: Vec<f64> = (1..fr.len())
        .map(|i| (dn[i] - dn[i - 1]).hypot(ac[i] - ac[i - 1]))
        .collect();
    steps.sort_by(f64::total_cmp);
    // A tracker that writes whole pixels moves a slow body by 0 or 1 of them a frame: the
    // median step is then 0, and every step of one pixel was called a jump (a 3-pixel wobble
    // was refused as "the tracker lost the body too often", a helper's finding). The smallest
    // step the positions take, their quantum, is the least scale.
    let quantum = [&dn, &ac]
        .iter()
        .flat_map(|v| v.windows(2).map(|w| (w[1] - w[0]).abs()))
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    let median_step = steps[steps.len() / 2]
        .max(if quantum.is_finite() { quantum } else { 0.0 })
        .max(1e-12);
    // Each point against the median of its four nearest neighbours, which one bad point
    // cannot move.
    let median4 = |v: &[f64], i: usize| {
        let mut w = [v[i - 2], v[i - 1], v[i + 1], v[i + 2]];
        w.sort_by(f64::total_cmp);
        (w[1] + w[2]) / 2.0
    };
    let jumps: Vec<usize> = (2..fr.len() - 2)
        .filter(|&i| {
            let (md, ma) = (median4(&dn, i), median4(&ac, i));
            (dn[i] - md).hypot(ac[i] - ma) > 10.0 * median_step
        })
        .collect();
    if jumps.len() * 20 > fr.len() {
        return Err(TrackError::Damaged(format!(
            "{} of {} frames jump more than ten median steps from their neighbours: the tracker \
             lost the body too often",
            jumps.len(),
            fr.len()
        )));
    }
    let mut jumped = vec![false; fr.len()];
    for &i in &jumps {
        jumped[i] = true;
    }
    for &i in &jumps {
        // Between the nearest good points on either side.
        let before = (0..i).rev().find(|&j| !jumped[j]).unwrap_or(0);
        let after = (i + 1..fr.len())
            .find(|&j| !jumped[j])
            .unwrap_or(fr.len() - 1);
        let s = (i - before) as f64 / (after - before) as f64;
        dn[i] = dn[before] + s * (dn[after] - dn[before]);
        ac[i] = ac[before] + s * (ac[after] - ac[before]);
    }
    if !jumps.is_empty() {
        warnings.push(format!(
            "{} jump(s) of the tracker (first at frame {}) replaced by straight lines between \
             their good neighbours",
            jumps.len(),
            fr[jumps[0]]
        ));
    }
    Ok(CleanTrack {
        frames: fr,
        down: dn,
        across: ac,
        warnings,
    })
}

/// The longest stretch of `track` whose speed down the ramp, averaged over a window of
/// `window` frames (each point's displacement `window` frames later) centred on each frame, is
/// within `tolerance` of the median (or within four robust σ of the windowed speeds' own
/// scatter, where that is wider): steady rolling,
/// without the release or the end of the ramp. Over a window of one period the speed of a
/// periodic motion is constant, so `tolerance` can then be tight; over a shorter window the
/// speed-up and slow-down within a period show.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::{CleanTrack, steady_stretch};
/// // Rolling at 1 cm a frame, then stuck at the end of the ramp from frame 150.
/// let frames: Vec<f64> = (0..200).map(f64::from).collect();
/// let down = frames.iter().map(|&f| f.min(150.0)).collect();
/// let track = CleanTrack { frames: frames.clone(), down, across: vec![0.0; 200], warnings: vec![] };
/// let steady = steady_stretch(&track, 20, 0.15)?;
/// assert_eq!(steady.frames[0], 0.0);
/// // Cut within a window of where it stuck.
/// let last = *steady.frames.last().unwrap();
/// assert!(last > 130.0 && last <= 150.0, "{last}");
/// # Ok::<(), rollphase_core::analysis::experiment::tracking::TrackError>(())
/// ```
pub fn steady_stretch(
    track: &CleanTrack,
    window: usize,
    tolerance: f64,
) -> Result<CleanTrack, TrackError> {
    let (fr, dn) = (&track.frames, &track.down);
    let mut warnings = track.warnings.clone();
    let n = fr.len();
    if n < 8 {
        return Err(TrackError::TooShort {
            usable: n,
            what: "after cleaning".into(),
            needed: 8,
        });
    }
    let w = window.max(2);
    // The mean speed over a window: each point's displacement one window later, averaged over
    // the window's points (the tracker's noise averages out; a least-squares slope would weigh
    // the speed within a period unevenly). Window s spans frames s … s + 2w − 1, centred on
    // s + w.
    let w = w.min(n / 3).max(2);
    let half = w;
    // Frames are consecutive, so the window's mean speed is a difference of two sums over w
    // points: prefix sums make it O(n) for any window.
    let mut prefix = vec![0.0; n + 1];
    for i in 0..n {
        prefix[i + 1] = prefix[i] + dn[i];
    }
    let per_frame = (fr[n - 1] - fr[0]) / (n - 1) as f64;
    let speeds: Vec<f64> = (0..=n - 2 * w)
        .map(|s| {
            let later = prefix[s + 2 * w] - prefix[s + w];
            let earlier = prefix[s + w] - prefix[s];
            (later - earlier) / (w as f64 * w as f64 * per_frame)
        })
        .collect();
    let mut sorted = speeds.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    if median.abs() < 1e-12 {
        return Err(TrackError::Damaged(
            "the body does not move down the ramp (median speed 0)".into(),
        ));
    }
    // Steady within `tolerance` of the median, or within the windowed speeds' own scatter (4
    // robust σ, from their median absolute deviation) where that is wider: a slow drift under
    // a large wobble scatters its windowed speed by more than 15 % of itself, and a track that
    // advanced 1 unit a period under a wobble of 10 was cut to 1 % of its frames and refused.
    let mut deviations: Vec<f64> = speeds.iter().map(|v| (v - median).abs()).collect();
    deviations.sort_by(f64::total_cmp);
    let scatter = 4.0 * 1.4826 * deviations[deviations.len() / 2];
    let allowed = (tolerance * median.abs()).max(scatter);
    let steady: Vec<bool> = speeds
        .iter()
        .map(|v| (v - median).abs() <= allowed)
        .collect();
    let (mut best, mut run_start) = ((0, 0), None);
    for (s, &ok) in steady.iter().chain(std::iter::once(&false)).enumerate() {
        match (ok, run_start) {
            (true, None) => run_start = Some(s),
            (false, Some(a)) => {
                if s - a > best.1 - best.0 {
                    best = (a, s);
                }
                run_start = None;
            }
            _ => {}
        }
    }
    if best.1 == best.0 {
        return Err(TrackError::Damaged(format!(
            "no stretch of the track rolls at a steady speed (within {:.0} % over {w} frames)",
            100.0 * tolerance
        )));
    }
    // Windows a … b − 1 are steady: their centres a + w … b − 1 + w, out to the track's ends
    // where the first or last window is steady.
    let from = if best.0 == 0 { 0 } else { best.0 + half };
    let to = if best.1 == speeds.len() {
        n
    } else {
        (best.1 + half).min(n)
    };
    if from > 0 || to < n {
        warnings.push(format!(
            "frames {}–{} used: the rest ({} frames) is not steady rolling (its speed down the \
             ramp over {w} frames differs from the median {:.4} cm a frame by more than {:.0} %: \
             the release, the end of the ramp)",
            fr[from],
            fr[to - 1],
            n - (to - from),
            median,
            100.0 * tolerance
        ));
    }
    Ok(CleanTrack {
        frames: fr[from..to].to_vec(),
        down: dn[from..to].to_vec(),
        across: track.across[from..to].to_vec(),
        warnings,
    })
}

/// A raw track measured: [`clean`]ed, a first period found ([`find_period`] without the check
/// against chance) on its middle 80 %, the track cut to its steady stretch over windows of that
/// period (where steady rolling has a constant mean speed: within 15 %, or the windowed speeds'
/// own scatter where that is wider) and its ends cut where
/// they do not repeat one period apart, and the period found again on what is left, with every
/// check. A period that holds over less than half of the usable frames is refused
/// ([`TrackError::MostlyUnsteady`]). `progress` hears of the surrogates searched.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::measure;
/// // A steady roll with a 40-frame period, stuck for its last 60 frames.
/// let frames: Vec<f64> = (0..600).map(f64::from).collect();
/// let w = std::f64::consts::TAU / 40.0;
/// let down: Vec<f64> = frames.iter().map(|&f| {
///     let f = f.min(540.0);
///     0.5 * f + 3.0 * (w * f).sin()
/// }).collect();
/// let across: Vec<f64> = frames.iter().map(|&f| (w * f.min(540.0)).cos()).collect();
/// let (track, fit) = measure(&frames, &down, &across, &|_, _| {})?;
/// assert!((fit.period_frames - 40.0).abs() < 0.05, "{}", fit.period_frames);
/// assert!(*track.frames.last().unwrap() <= 545.0);
/// # Ok::<(), rollphase_core::analysis::experiment::tracking::TrackError>(())
/// ```
pub fn measure(
    frames: &[f64],
    down: &[f64],
    across: &[f64],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(CleanTrack, PeriodFit), TrackError> {
    let track = clean(frames, down, across)?;
    // A first period from the middle 80 %, away from the release and the end of the ramp.
    let n = track.frames.len();
    let (a, b) = (n / 10, n - n / 10);
    let middle = CleanTrack {
        frames: track.frames[a..b].to_vec(),
        down: track.down[a..b].to_vec(),
        across: track.across[a..b].to_vec(),
        warnings: Vec::new(),
    };
    let first_look = PeriodSearch {
        surrogates: 0,
        read_turns: false,
        ..PeriodSearch::default()
    };
    let first = find_period(&middle, &first_look, &|_, _| {})?;
    let window = first.period_frames.round() as usize;
    let steady = steady_stretch(&track, window, PERIOD_STEADY_TOLERANCE)?;
    let fine = trim_unrepeated_ends(&steady, &first);
    let used = fine.frames.len();
    if 2 * used < n {
        return Err(TrackError::MostlyUnsteady {
            from: fine.frames[0],
            to: fine.frames[used - 1],
            percent: 100.0 * used as f64 / n as f64,
            frames: n,
        });
    }
    let fit = find_period(&fine, &PeriodSearch::default(), progress)?;
    gaps_do_not_make_the_repeat(&fine, (frames, down, across), &fit)?;
    let mut fine = fine;
    if fit.advance_down < 0.0 {
        // A body rolls down: a track that climbs has its down axis the wrong way round (image
        // rows grow downwards, a tracker's y upwards). Said by every surface alike.
        fine.warnings.push(format!(
            "the body moves up the ramp ({:.4} cm a period down it): if it rolled down, the down \
             coordinate has the wrong sign (flip it: the command line's --scale down factor, or \
             -down in Python)",
            fit.advance_down
        ));
    }
    Ok((fine, fit))
}

/// Where frames were bridged, the period checked on the measured frames alone. A bridge is not
/// the motion, and gaps that recur (a marker hidden every 20 frames) repeat on their own: a
/// 12.5-frame track with one frame missing every 20 repeated best after 50 frames, bridged
/// frames included, and was stated so. If a fraction T/q of the period repeats on the measured
/// frames as well as T does (the search's own rule: within [`period::MULTIPLE_TOLERANCE`] of it,
/// plus [`period::MULTIPLE_SLACK`]), T is a multiple made by the gaps and no period is stated.
fn gaps_do_not_make_the_repeat(
    track: &CleanTrack,
    (frames, down, across): (&[f64], &[f64], &[f64]),
    fit: &PeriodFit,
) -> Result<(), TrackError> {
    // Measured: a row with all three values (a tracker writes an empty cell where it lost the
    // body, and that row is bridged like a missing one).
    let mut raw: Vec<f64> = (0..frames.len())
        .filter(|&i| frames[i].is_finite() && down[i].is_finite() && across[i].is_finite())
        .map(|i| frames[i])
        .collect();
    raw.sort_by(f64::total_cmp);
    let measured: Vec<bool> = track
        .frames
        .iter()
        .map(|f| {
            let i = raw.partition_point(|r| *r < f - 1e-6);
            raw.get(i).is_some_and(|r| (r - f).abs() <= 1e-6)
        })
        .collect();
    let bridged = measured.iter().filter(|m| !**m).count();
    if bridged == 0 {
        return Ok(());
    }
    let n = track.frames.len();
    let z = |i: usize| (track.down[i], track.across[i]);
    // The mismatch over pairs of measured frames (i, i + τ), the point at i + τ by the cubic
    // through the four measured frames around it; with the least-squares line's variance, as
    // the search normalises it. `None` with too few pairs to tell.
    let mismatch = |tau: f64| -> Option<f64> {
        let k = tau.floor() as usize;
        let s = tau - k as f64;
        let whole = s < 1e-9;
        let mut d = Vec::new();
        for i in (0..n).filter(|&i| measured[i]) {
            let base = i + k;
            let (lo, hi) = if whole {
                (base, base)
            } else {
                (base.checked_sub(1)?, base + 2)
            };
            if hi >= n || !(lo..=hi).all(|j| measured[j]) {
                continue;
            }
            let p = if whole {
                z(base)
            } else {
                let xs = [-1.0, 0.0, 1.0, 2.0];
                let c = |f: &dyn Fn(usize) -> f64| {
                    cubic_through(xs, [f(lo), f(lo + 1), f(lo + 2), f(hi)], s)
                };
                (c(&|j| track.down[j]), c(&|j| track.across[j]))
            };
            d.push((p.0 - z(i).0, p.1 - z(i).1));
        }
        (d.len() >= 20).then(|| {
            let c = d.len() as f64;
            let mean = (
                d.iter().map(|v| v.0).sum::<f64>() / c,
                d.iter().map(|v| v.1).sum::<f64>() / c,
            );
            d.iter()
                .map(|v| (v.0 - mean.0).powi(2) + (v.1 - mean.1).powi(2))
                .sum::<f64>()
                / c
        })
    };
    let points: Vec<usize> = (0..n).filter(|&i| measured[i]).collect();
    let c = points.len() as f64;
    let mid = points.iter().map(|&i| i as f64).sum::<f64>() / c;
    let variance = |v: &[f64]| {
        let mean = points.iter().map(|&i| v[i]).sum::<f64>() / c;
        let sxx: f64 = points.iter().map(|&i| (i as f64 - mid).powi(2)).sum();
        let slope = points
            .iter()
            .map(|&i| (i as f64 - mid) * (v[i] - mean))
            .sum::<f64>()
            / sxx.max(1e-300);
        points
            .iter()
            .map(|&i| (v[i] - mean - slope * (i as f64 - mid)).powi(2))
            .sum::<f64>()
            / c
    };
    let scale = 2.0 * (variance(&track.down) + variance(&track.across));
    let period = fit.period_frames;
    let Some(at_period) = mismatch(period) else {
        return Ok(());
    };
    let tolerance = period::MULTIPLE_TOLERANCE * at_period / scale + period::MULTIPLE_SLACK;
    for q in (2..=8usize).rev() {
        let fraction = period / q as f64;
        if fraction < MIN_PERIOD_FRAMES {
            continue;
        }
        if let Some(m) = mismatch(fraction)
            && m / scale <= tolerance
        {
            return Err(TrackError::NoPeriod {
                best_frames: period,
                why: format!(
                    "the track repeats best after {period:.2} frames, but on its measured frames \
                     alone (its {bridged} bridged frame(s) left out) it repeats as well after \
                     {fraction:.2} frames ({period:.2}/{q}): the gaps, bridged the same way at \
                     recurring frames, make the longer repeat. A track with fewer gaps, or \
                     gaps that do not recur, would decide between the two"
                ),
            });
        }
    }
    Ok(())
}

/// The track without the ends that do not repeat: each point's distance from where the period
/// `fit` says it should be (one period before or after, plus or minus the advance; the nearer),
/// averaged over a quarter period, is compared with the median distance; ends where it is more
/// than four times that are cut (the body stuck at the end of the ramp, the last jolts of the
/// release), and said.
fn trim_unrepeated_ends(track: &CleanTrack, fit: &PeriodFit) -> CleanTrack {
    let n = track.frames.len();
    let tau = fit.period_frames;
    let p = |x: f64| (at(&track.down, x), at(&track.across, x));
    let off = |i: usize| -> f64 {
        let x = i as f64;
        let (d, a) = (track.down[i], track.across[i]);
        let mut best = f64::INFINITY;
        if x - tau >= 0.0 {
            let (d0, a0) = p(x - tau);
            best = best.min((d - d0 - fit.advance_down).hypot(a - a0 - fit.advance_across));
        }
        if x + tau <= (n - 1) as f64 {
            let (d1, a1) = p(x + tau);
            best = best.min((d1 - d - fit.advance_down).hypot(a1 - a - fit.advance_across));
        }
        best
    };
    let r: Vec<f64> = (0..n).map(off).collect();
    let mut sorted: Vec<f64> = r.iter().copied().filter(|v| v.is_finite()).collect();
    if sorted.len() < 8 {
        return track.clone();
    }
    sorted.sort_by(f64::total_cmp);
    let typical = sorted[sorted.len() / 2].max(1e-12);
    let half = ((tau / 8.0).round() as usize).max(1);
    // Means over a quarter period by prefix sums (of the finite values and their count).
    let (mut sum, mut count) = (vec![0.0; n + 1], vec![0usize; n + 1]);
    for i in 0..n {
        let ok = r[i].is_finite();
        sum[i + 1] = sum[i] + if ok { r[i] } else { 0.0 };
        count[i + 1] = count[i] + usize::from(ok);
    }
    let smooth = |i: usize| {
        let (a, b) = (i.saturating_sub(half), (i + half + 1).min(n));
        (sum[b] - sum[a]) / (count[b] - count[a]).max(1) as f64
    };
    let bad = |i: usize| smooth(i) > 4.0 * typical;
    let from = (0..n / 3).find(|&i| !bad(i)).unwrap_or(0);
    let to = (n - n / 3..n).rev().find(|&i| !bad(i)).map_or(n, |i| i + 1);
    let mut out = CleanTrack {
        frames: track.frames[from..to].to_vec(),
        down: track.down[from..to].to_vec(),
        across: track.across[from..to].to_vec(),
        warnings: track.warnings.clone(),
    };
    if from > 0 || to < n {
        out.warnings.push(format!(
            "frames {}–{} used: {} frame(s) at the start and {} at the end do not repeat one \
             period apart (more than four times the typical {:.3} cm off: the release, the end \
             of the ramp)",
            out.frames[0],
            out.frames[out.frames.len() - 1],
            from,
            n - to,
            typical
        ));
    }
    out
}

/// The track at the fractional index `x` (linear between frames).
fn at(v: &[f64], x: f64) -> f64 {
    let i = (x.floor() as usize).min(v.len() - 2);
    let s = x - i as f64;
    v[i] + s * (v[i + 1] - v[i])
}

/// A point in local coordinates: which period it falls in and where in it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Folded {
    /// The period it falls in (0, 1, …).
    pub period: usize,
    /// Frames since the period began.
    pub t_local: f64,
    /// Down the ramp since the period began, less the advance of earlier periods (cm).
    pub down_local: f64,
    /// Across, likewise (cm).
    pub across_local: f64,
}

/// Folds `points` (frame, down, across in cm) on `track`'s period as `fit` measured it: period
/// k begins at the track's first frame plus k periods and is shifted back by k advances, from
/// the track's first position, as `rollphase track` folds its centre and its markers (data.csv,
/// the folded figure) and Python's `measure_track` its centre ([`fold`]).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::{fold_on_track, measure};
/// // 30 periods of 20 frames, 5 cm down each, a wobble across.
/// let frames: Vec<f64> = (0..600).map(f64::from).collect();
/// let phase = |f: f64| 2.0 * std::f64::consts::PI * f / 20.0;
/// let down: Vec<f64> = frames.iter().map(|&f| 0.25 * f + 0.3 * phase(f).sin()).collect();
/// let across: Vec<f64> = frames.iter().map(|&f| 0.2 * phase(f).cos()).collect();
/// let (track, fit) = measure(&frames, &down, &across, &|_, _| {})?;
/// let points: Vec<(f64, f64, f64)> = (0..600).map(|i| (frames[i], down[i], across[i])).collect();
/// let folded = fold_on_track(&track, &fit, &points);
/// // Every period lies on the first: frame 25 (period 1) on frame 5.
/// let (a, b) = (folded[5], folded[25]);
/// assert_eq!((a.period, b.period), (0, 1));
/// assert!((a.down_local - b.down_local).abs() < 1e-3 && (a.across_local - b.across_local).abs() < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fold_on_track(
    track: &CleanTrack,
    fit: &PeriodFit,
    points: &[(f64, f64, f64)],
) -> Vec<Folded> {
    fold(
        points,
        track.frames[0],
        (track.down[0], track.across[0]),
        fit.period_frames,
        (fit.advance_down, fit.advance_across),
    )
}

/// The centre track itself, folded ([`fold_on_track`]): one point a frame of the cleaned track.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::{fold_centre, measure};
/// let frames: Vec<f64> = (0..600).map(f64::from).collect();
/// let phase = |f: f64| 2.0 * std::f64::consts::PI * f / 20.0;
/// let down: Vec<f64> = frames.iter().map(|&f| 0.25 * f + 0.3 * phase(f).sin()).collect();
/// let across: Vec<f64> = frames.iter().map(|&f| 0.2 * phase(f).cos()).collect();
/// let (track, fit) = measure(&frames, &down, &across, &|_, _| {})?;
/// let folded = fold_centre(&track, &fit);
/// assert_eq!(folded.len(), track.frames.len());
/// // Every period lies on the first, within a few µm of each other.
/// assert!(folded.iter().all(|f| f.t_local < fit.period_frames + 1e-9));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fold_centre(track: &CleanTrack, fit: &PeriodFit) -> Vec<Folded> {
    let points: Vec<(f64, f64, f64)> = (0..track.frames.len())
        .map(|i| (track.frames[i], track.down[i], track.across[i]))
        .collect();
    fold_on_track(track, fit, &points)
}

/// Folds points (frame, down, across) into local coordinates: period k starts at
/// `start_frame` + k·τ and is shifted back by k times the advance, from the track's position at
/// `start_frame` (`origin`), so that every period lies on the first (the paper's Fig. 5c).
/// Points before `start_frame` are left out.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::fold;
/// // Two periods of 10 frames advancing 5 cm: the second lies on the first.
/// let f = fold(&[(0.0, 0.0, 0.0), (3.0, 1.0, 0.2), (13.0, 6.0, 0.2)], 0.0, (0.0, 0.0), 10.0, (5.0, 0.0));
/// assert_eq!((f[1].period, f[2].period), (0, 1));
/// assert_eq!((f[2].t_local, f[2].down_local, f[2].across_local), (3.0, 1.0, 0.2));
/// ```
pub fn fold(
    points: &[(f64, f64, f64)],
    start_frame: f64,
    origin: (f64, f64),
    period_frames: f64,
    advance: (f64, f64),
) -> Vec<Folded> {
    points
        .iter()
        .filter(|p| p.0 >= start_frame)
        .map(|&(f, d, a)| {
            let k = ((f - start_frame) / period_frames).floor();
            Folded {
                period: k as usize,
                t_local: f - start_frame - k * period_frames,
                down_local: d - origin.0 - k * advance.0,
                across_local: a - origin.1 - k * advance.1,
            }
        })
        .collect()
}
