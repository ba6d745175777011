//! A filmed run read as a measurement: a body's tracked centre (frame, down, across in cm),
//! cleaned of what trackers produce (gaps, jumps, the release and the end of the ramp), its
//! period found automatically with an uncertainty, the advance per period, and the track folded
//! into local coordinates (the paper's Fig. 5c) so that every period lies on the first.
//!
//! The period is the shift τ at which the track repeats up to a translation: the mismatch
//! E(τ) = ⟨|p(t + τ) − p(t) − D(τ)|²⟩ (D the mean displacement over τ), normalised by twice
//! the variance of the detrended track, is ≈ 1 for unrelated points and falls towards the noise
//! floor where the motion repeats. The smallest shift whose mismatch is within a factor of
//! [`MULTIPLE_TOLERANCE`] of the best is the period (its multiples repeat too); shifts are tried
//! every quarter frame, and a parabola through the three nearest refines it. Each whole cycle then
//! gets its own best shift against the next, and their spread is the uncertainty: nothing is
//! hand-picked. A track whose best mismatch is above [`MAX_MISMATCH`], or that holds fewer than
//! two periods, has no period that can be stated with confidence, and says so.

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
    /// No shift makes the track repeat well enough.
    #[error(
        "no period can be found with confidence: the best repeat (shift {best_frames:.1} frames) \
         leaves {mismatch:.2} of the track's variation unexplained (at most {limit} is accepted)"
    )]
    NoPeriod {
        /// The best shift.
        best_frames: f64,
        /// Its normalised mismatch.
        mismatch: f64,
        /// The limit.
        limit: f64,
    },
    /// A setting out of range.
    #[error("{0}")]
    BadArgument(String),
}

/// The normalised mismatch above which a period is not stated.
pub const MAX_MISMATCH: f64 = 0.5;
/// Local minima within this factor of the best mismatch count as repeats (the smallest is the
/// period, the others its multiples).
pub const MULTIPLE_TOLERANCE: f64 = 1.5;
/// … plus this much (a noiseless track's multiples can beat its period by round-off alone).
pub const MULTIPLE_SLACK: f64 = 0.02;
/// A dip must lie this far below the mismatch at some smaller shift (the track having moved on
/// since): small shifts match only because the body has not gone anywhere yet.
pub const RISE: f64 = 0.25;
/// Gaps of at most this many frames are bridged by straight lines; a longer one splits the track.
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

/// Cleans a raw track: rows with a non-finite value dropped, gaps of up to
/// [`MAX_BRIDGED_GAP`] frames bridged (a longer gap splits it: the longest piece is kept),
/// jumps (a point ten median steps from the median of its four nearest neighbours) replaced by
/// straight lines between good points.
///
/// # Example
/// ```
/// use rollphase_core::analysis::tracking::clean;
/// // Rolling at 1 cm a frame with a wobble across, one frame missing and one glitch.
/// let frames: Vec<f64> = (0..200).filter(|&i| i != 50).map(f64::from).collect();
/// let down: Vec<f64> = frames.iter().map(|&f| if f == 120.0 { 500.0 } else { f }).collect();
/// let across: Vec<f64> = frames.iter().map(|f| (f / 10.0).sin()).collect();
/// let track = clean(&frames, &down, &across)?;
/// assert_eq!(track.frames.len(), 200);
/// assert!((track.down[120] - 120.0).abs() < 1e-9, "the glitch is replaced");
/// assert_eq!(track.warnings.len(), 2);
/// # Ok::<(), rollphase_core::analysis::tracking::TrackError>(())
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
    // Pieces split at gaps longer than the bridge; the longest is kept.
    let mut pieces: Vec<Vec<(f64, f64, f64)>> = vec![Vec::new()];
    let mut bridged = 0usize;
    for (k, &(_, f, d, a)) in rows.iter().enumerate() {
        if k > 0 {
            let (_, f0, d0, a0) = rows[k - 1];
            let gap = (f - f0).round() as usize - 1;
            if gap > MAX_BRIDGED_GAP {
                pieces.push(Vec::new());
            } else {
                for g in 1..=gap {
                    let s = g as f64 / (gap + 1) as f64;
                    let piece = pieces.last_mut().expect("one piece at least");
                    piece.push((f0 + g as f64, d0 + s * (d - d0), a0 + s * (a - a0)));
                    bridged += 1;
                }
            }
        }
        pieces
            .last_mut()
            .expect("one piece at least")
            .push((f, d, a));
    }
    if bridged > 0 {
        warnings.push(format!(
            "{bridged} missing frame(s) in gaps of up to {MAX_BRIDGED_GAP} frames bridged by \
             straight lines"
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
    let median_step = steps[steps.len() / 2].max(1e-12);
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
    for &i in &jumps {
        // Between the nearest good points on either side.
        let before = (0..i).rev().find(|j| !jumps.contains(j)).unwrap_or(0);
        let after = (i + 1..fr.len())
            .find(|j| !jumps.contains(j))
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
/// within `tolerance` of the median: steady rolling,
/// without the release or the end of the ramp. Over a window of one period the speed of a
/// periodic motion is constant, so `tolerance` can then be tight; over a shorter window the
/// speed-up and slow-down within a period show.
///
/// # Example
/// ```
/// use rollphase_core::analysis::tracking::{CleanTrack, steady_stretch};
/// // Rolling at 1 cm a frame, then stuck at the end of the ramp from frame 150.
/// let frames: Vec<f64> = (0..200).map(f64::from).collect();
/// let down = frames.iter().map(|&f| f.min(150.0)).collect();
/// let track = CleanTrack { frames: frames.clone(), down, across: vec![0.0; 200], warnings: vec![] };
/// let steady = steady_stretch(&track, 20, 0.15)?;
/// assert_eq!(steady.frames[0], 0.0);
/// // Cut within a window of where it stuck.
/// let last = *steady.frames.last().unwrap();
/// assert!(last > 130.0 && last <= 150.0, "{last}");
/// # Ok::<(), rollphase_core::analysis::tracking::TrackError>(())
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
    let speeds: Vec<f64> = (0..=n - 2 * w)
        .map(|s| {
            (s..s + w)
                .map(|i| (dn[i + w] - dn[i]) / (fr[i + w] - fr[i]))
                .sum::<f64>()
                / w as f64
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
    let steady: Vec<bool> = speeds
        .iter()
        .map(|v| ((v - median) / median).abs() <= tolerance)
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

/// A raw track measured: [`clean`]ed, a first period found ([`find_period`], at least
/// `min_frames`) on its middle 80 %, the track cut to its steady stretch over windows of that
/// period (where steady rolling has a constant mean speed: within 15 %) and its ends cut where
/// they do not repeat one period apart, and the period found again on what is left.
///
/// # Example
/// ```
/// use rollphase_core::analysis::tracking::measure;
/// // A steady roll with a 40-frame period, stuck for its last 60 frames.
/// let frames: Vec<f64> = (0..600).map(f64::from).collect();
/// let w = std::f64::consts::TAU / 40.0;
/// let down: Vec<f64> = frames.iter().map(|&f| {
///     let f = f.min(540.0);
///     0.5 * f + 3.0 * (w * f).sin()
/// }).collect();
/// let across: Vec<f64> = frames.iter().map(|&f| (w * f.min(540.0)).cos()).collect();
/// let (track, fit) = measure(&frames, &down, &across, 10.0)?;
/// assert!((fit.period_frames - 40.0).abs() < 0.05, "{}", fit.period_frames);
/// assert!(*track.frames.last().unwrap() <= 545.0);
/// # Ok::<(), rollphase_core::analysis::tracking::TrackError>(())
/// ```
pub fn measure(
    frames: &[f64],
    down: &[f64],
    across: &[f64],
    min_frames: f64,
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
    let first = find_period(&middle, min_frames)?;
    let window = first.period_frames.round() as usize;
    let steady = steady_stretch(&track, window, PERIOD_STEADY_TOLERANCE)?;
    let fine = trim_unrepeated_ends(&steady, &first);
    let fit = find_period(&fine, min_frames)?;
    Ok((fine, fit))
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
    let smooth = |i: usize| {
        let (a, b) = (i.saturating_sub(half), (i + half + 1).min(n));
        let v: Vec<f64> = r[a..b].iter().copied().filter(|v| v.is_finite()).collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
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

/// Least-squares slope of y against x.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
    }
    sxy / sxx
}

/// A track's period, found and measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PeriodFit {
    /// The period in frames (to a fraction of a frame).
    pub period_frames: f64,
    /// Standard error of the period (frames): the spread of the cycles' own periods over √n.
    pub period_error_frames: f64,
    /// Spread (standard deviation) of the cycles' own periods (frames).
    pub period_spread_frames: f64,
    /// Each whole cycle's own period (frames), against the next cycle.
    pub cycle_periods: Vec<f64>,
    /// Whole periods in the track.
    pub periods_seen: usize,
    /// The normalised mismatch at the period (0: a perfect repeat, 1: none).
    pub mismatch: f64,
    /// Advance per period down the ramp (cm).
    pub advance_down: f64,
    /// Advance per period across the ramp (cm).
    pub advance_across: f64,
    /// The normalised mismatch at every shift tried (shift in frames, mismatch).
    pub mismatch_curve: Vec<[f64; 2]>,
}

/// The track at the fractional index `x` (linear between frames).
fn at(v: &[f64], x: f64) -> f64 {
    let i = (x.floor() as usize).min(v.len() - 2);
    let s = x - i as f64;
    v[i] + s * (v[i + 1] - v[i])
}

/// E(τ) over the index range `[from, to)` of starting points, normalised by `scale`.
fn mismatch(track: &CleanTrack, tau: f64, from: usize, to: usize, scale: f64) -> (f64, f64, f64) {
    let n = track.down.len();
    let last = ((n - 1) as f64 - tau).floor() as usize;
    let to = to.min(last + 1);
    if to <= from + 1 {
        return (f64::INFINITY, 0.0, 0.0);
    }
    let count = (to - from) as f64;
    let (mut sd, mut sa) = (0.0, 0.0);
    let diffs: Vec<(f64, f64)> = (from..to)
        .map(|i| {
            let x = i as f64 + tau;
            let d = at(&track.down, x) - track.down[i];
            let a = at(&track.across, x) - track.across[i];
            sd += d;
            sa += a;
            (d, a)
        })
        .collect();
    let (md, ma) = (sd / count, sa / count);
    let e = diffs
        .iter()
        .map(|(d, a)| (d - md).powi(2) + (a - ma).powi(2))
        .sum::<f64>()
        / count;
    (e / scale, md, ma)
}

/// Finds the track's period (see the module doc) between `min_frames` and half the track.
///
/// # Example
/// ```
/// use rollphase_core::analysis::tracking::{CleanTrack, find_period};
/// // A body rolling 0.5 cm a frame whose speed and sideways wobble repeat every 37.5 frames.
/// let frames: Vec<f64> = (0..400).map(f64::from).collect();
/// let w = std::f64::consts::TAU / 37.5;
/// let down = frames.iter().map(|f| 0.5 * f + 2.0 * (w * f).sin()).collect();
/// let across = frames.iter().map(|f| 0.01 * f + (w * f).cos()).collect();
/// let track = CleanTrack { frames: frames.clone(), down, across, warnings: vec![] };
/// let fit = find_period(&track, 5.0)?;
/// assert!((fit.period_frames - 37.5).abs() < 0.05, "{}", fit.period_frames);
/// assert!((fit.advance_down - 18.75).abs() < 0.05);
/// assert_eq!(fit.periods_seen, 10);
/// # Ok::<(), rollphase_core::analysis::tracking::TrackError>(())
/// ```
pub fn find_period(track: &CleanTrack, min_frames: f64) -> Result<PeriodFit, TrackError> {
    let n = track.down.len();
    let max_tau = (n - 1) / 2;
    let min_tau = min_frames.max(2.0).ceil() as usize;
    if n < 8 || max_tau < min_tau + 2 {
        return Err(TrackError::TooShort {
            usable: n,
            what: "in the steady stretch".into(),
            needed: 2 * (min_tau + 2) + 1,
        });
    }
    // The detrended variance: the scale of "unrelated points".
    let idx: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let detrended_var = |v: &[f64]| {
        let b = slope(&idx, v);
        let mean = v.iter().sum::<f64>() / n as f64;
        let mid = (n - 1) as f64 / 2.0;
        v.iter()
            .enumerate()
            .map(|(i, y)| (y - mean - b * (i as f64 - mid)).powi(2))
            .sum::<f64>()
            / n as f64
    };
    let scale = 2.0 * (detrended_var(&track.down) + detrended_var(&track.across));
    let extent = track
        .down
        .iter()
        .chain(&track.across)
        .fold(0.0f64, |m, v| m.max(v.abs()));
    // Round-off alone (1e-16 of the positions) can look periodic: below 1e-9 nothing varies.
    if scale <= (1e-9 * extent).powi(2) {
        return Err(TrackError::Damaged(
            "the track is a straight line at constant speed: nothing repeats that could give a \
             period"
                .into(),
        ));
    }
    // Quarter-frame shifts (linear interpolation between frames): a period need not be a whole
    // number of frames, and a half-frame offset alone would hide a true period behind its double.
    let curve: Vec<[f64; 2]> = (4 * min_tau..=4 * max_tau)
        .map(|q| {
            let t = q as f64 / 4.0;
            [t, mismatch(track, t, 0, n, scale).0]
        })
        .collect();
    // Small shifts match because the track has not moved on yet: only dips after the mismatch
    // has first risen out of that region count.
    let rise = curve
        .iter()
        .position(|c| c[1] >= curve[0][1] + RISE)
        .unwrap_or(curve.len());
    let best = curve[rise.min(curve.len())..]
        .iter()
        .map(|c| c[1])
        .fold(f64::INFINITY, f64::min);
    // Each dip's lowest point: the dips are the runs of shifts below best + RISE/2 (so the
    // noise's wiggles on a dip's flank are not dips of their own).
    let level = best + RISE / 2.0;
    let mut minima: Vec<usize> = Vec::new();
    let mut k = rise;
    while k < curve.len() {
        if curve[k][1] < level {
            let run_end = (k..curve.len())
                .find(|&j| curve[j][1] >= level)
                .unwrap_or(curve.len());
            let low = (k..run_end)
                .min_by(|&a, &b| curve[a][1].total_cmp(&curve[b][1]))
                .unwrap_or(k);
            // A dip that runs into the end of the range may be cut off: its lowest point must
            // be inside it.
            if low > 0 && low + 1 < curve.len() {
                minima.push(low);
            }
            k = run_end;
        } else {
            k += 1;
        }
    }
    let Some(&k) = minima
        .iter()
        .find(|&&k| curve[k][1] <= MULTIPLE_TOLERANCE * best + MULTIPLE_SLACK)
    else {
        let k = curve
            .iter()
            .position(|c| c[1] == best)
            .unwrap_or(curve.len() - 1);
        return Err(TrackError::NoPeriod {
            best_frames: curve[k][0],
            mismatch: best,
            limit: MAX_MISMATCH,
        });
    };
    let (e0, e1, e2) = (curve[k - 1][1], curve[k][1], curve[k + 1][1]);
    let denominator = e0 - 2.0 * e1 + e2;
    let shift = if denominator > 0.0 {
        (0.5 * (e0 - e2) / denominator).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    let tau = curve[k][0] + 0.25 * shift;
    let (m, advance_down, advance_across) = mismatch(track, tau, 0, n, scale);
    if m > MAX_MISMATCH {
        return Err(TrackError::NoPeriod {
            best_frames: tau,
            mismatch: m,
            limit: MAX_MISMATCH,
        });
    }
    let periods_seen = ((n - 1) as f64 / tau).floor() as usize;
    if periods_seen < 2 {
        return Err(TrackError::TooShort {
            usable: n,
            what: format!("a period of {tau:.1} frames"),
            needed: (2.0 * tau).ceil() as usize + 1,
        });
    }
    let cycle_periods = cycle_periods(track, tau, periods_seen, scale);
    let (spread, error) = if cycle_periods.len() >= 2 {
        let k = cycle_periods.len() as f64;
        let mean = cycle_periods.iter().sum::<f64>() / k;
        let var = cycle_periods
            .iter()
            .map(|p| (p - mean).powi(2))
            .sum::<f64>()
            / (k - 1.0);
        (var.sqrt(), var.sqrt() / k.sqrt())
    } else {
        (f64::NAN, f64::NAN)
    };
    Ok(PeriodFit {
        period_frames: tau,
        period_error_frames: error,
        period_spread_frames: spread,
        cycle_periods,
        periods_seen,
        mismatch: m,
        advance_down,
        advance_across,
        mismatch_curve: curve,
    })
}

/// Each whole cycle's own period (frames): the best shift within 20 % of `tau` of its window
/// against the next, refined by a parabola.
fn cycle_periods(track: &CleanTrack, tau: f64, periods_seen: usize, scale: f64) -> Vec<f64> {
    let window = tau.round() as usize;
    (0..periods_seen.saturating_sub(1))
        .filter_map(|c| {
            let from = (c as f64 * tau).round() as usize;
            let to = from + window;
            let lo = (tau * 0.8).floor() as usize;
            let hi = (tau * 1.2).ceil() as usize;
            let e: Vec<(f64, f64)> = (lo..=hi)
                .map(|t| (t as f64, mismatch(track, t as f64, from, to, scale).0))
                .filter(|p| p.1.is_finite())
                .collect();
            let j = (1..e.len().saturating_sub(1)).min_by(|&a, &b| e[a].1.total_cmp(&e[b].1))?;
            let (a, b, d) = (e[j - 1].1, e[j].1, e[j + 1].1);
            let den = a - 2.0 * b + d;
            let s = if den > 0.0 {
                (0.5 * (a - d) / den).clamp(-0.5, 0.5)
            } else {
                0.0
            };
            Some(e[j].0 + s)
        })
        .collect()
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

/// Folds points (frame, down, across) into local coordinates: period k starts at
/// `start_frame` + k·τ and is shifted back by k times the advance, from the track's position at
/// `start_frame` (`origin`), so that every period lies on the first (the paper's Fig. 5c).
/// Points before `start_frame` are left out.
///
/// # Example
/// ```
/// use rollphase_core::analysis::tracking::fold;
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
