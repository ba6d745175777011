//! A measured track beside the model's prediction for the same body: the mass ratio m/m0 and the
//! time unit t0 found together, so that the model's period in seconds is the measured one, and
//! the SI's speed estimate beside them as a check.
//!
//! With the driving force the weight (F = mg), the paper's units give m/m0 = m F⟨r⟩³/γ² and
//! t0 = γ/(F⟨r⟩), so m/m0 = ⟨r⟩/(g t0²): one number fixes the other. The model's period
//! T(m/m0) (in t0) times t0 must be the measured period T_s, so
//! m/m0 = ⟨r⟩ T(m/m0)² / (g T_s²), solved by iteration from the viscous model's T (T depends
//! weakly on m/m0, so it converges in a few steps, each a
//! [`predict`](crate::analysis::experiment::prediction::predict)). Below
//! [`VISCOUS_BELOW`] the viscous model is used: the inertial correction to the period there is
//! ≈ 0.03 m/m0 (`simulate`'s module doc), under 0.3 %.
//!
//! The SI's estimate (§2H) balances the drag's dissipation γω² with gravity's work: with
//! ω ≈ v/⟨r⟩, m/m0 ≈ v²/(g⟨r⟩ sin²α). The main text's v²/(g⟨r⟩ sin α) is a typo: only the SI's
//! form gives the paper's own 0.025 (v = 1 cm/s) and 2.5 (v = 10 cm/s) at ⟨r⟩ = 1 cm,
//! sin α = 0.2, g = 10 m/s². It ignores the body's shape and is reported as a check, with the
//! period in seconds it implies.

use serde::Serialize;
use thiserror::Error;

use std::sync::atomic::AtomicBool;

use super::Folded;
use crate::analysis::experiment::prediction::{
    PredictOptions, PredictedOrbit, Prediction, predict_until,
};
use crate::analysis::studies::sphere::StudyError;
use crate::geometry::Body;

/// Where the predicted orbit sits on a folded track ([`align_with_track`]), with how well it
/// fits there: the phase and the sign across are where the fit is best, and are drawn so, but the
/// sign across is a finding only where [`Self::handedness_shown`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrackAlignment {
    /// The path sample of the predicted orbit at which the folded track's periods begin: where
    /// its down-ramp path fits the track best (least squares with a free offset).
    pub phase: usize,
    /// Whether the orbit is drawn mirrored across the ramp: the sign of its across path that
    /// leaves the smaller residual at `phase` (the body's handedness, or the camera's, is not
    /// fixed by the period and advance alone).
    pub mirrored_across: bool,
    /// Whether the track shows which way round it runs: the drawn sign's across path explains
    /// at least [`HANDEDNESS_EXPLAINED`] of the folded track's across variance, and
    /// [`HANDEDNESS_MARGIN`] more than the other sign's. Otherwise either way round fits about
    /// as well (or neither does), and `mirrored_across` is only how the orbit is drawn.
    pub handedness_shown: bool,
    /// The share of the folded track's down variance the orbit's down path explains at
    /// `phase` (1 − residual/variance; 1 a perfect fit, ≤ 0 no better than a constant).
    pub down_explained: f64,
    /// The share of its across variance each sign explains at `phase`: the drawn one, then the
    /// other.
    pub across_explained: [f64; 2],
}

/// The least share of the track's across variance the drawn sign must explain for the track to
/// show its handedness ([`TrackAlignment::handedness_shown`]).
pub const HANDEDNESS_EXPLAINED: f64 = 0.5;
/// … and by how much more than the other sign.
pub const HANDEDNESS_MARGIN: f64 = 0.25;

/// The phase of `orbit` (a [`PredictedOrbit`] whose path holds three repeats) at which its
/// down-ramp path best matches the folded centre track `folded` (least squares with a free
/// offset), and whether across the ramp it matches better mirrored, with how much of the
/// track's variance each explains. `cm_per_r` turns the model's lengths into the track's cm,
/// `frames_per_t0` its time into frames. An empty track, or one without variance down the ramp,
/// is placed at phase 0 with nothing shown.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::prediction::{PredictOptions, predict};
/// use rollphase_core::analysis::experiment::tracking::Folded;
/// use rollphase_core::analysis::experiment::tracking::model::align_with_track;
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let options = PredictOptions { starts: 4, ..PredictOptions::default() };
/// let orbit = predict(&body, 0.2, 0.0, &options)?.orbits.remove(0);
/// // A track that is the orbit itself, mirrored across the ramp, from sample 7 on.
/// let per = (orbit.path.len() - 1) / 3;
/// let folded: Vec<Folded> = (0..per)
///     .map(|k| {
///         let (p, p0) = (orbit.path[7 + k], orbit.path[7]);
///         Folded {
///             period: 0,
///             t_local: k as f64 * orbit.period / per as f64,
///             down_local: p[0] - p0[0],
///             across_local: -(p[1] - p0[1]),
///         }
///     })
///     .collect();
/// let a = align_with_track(&folded, &orbit, 1.0, 1.0);
/// assert_eq!((a.phase, a.mirrored_across, a.handedness_shown), (7, true, true));
/// assert!(a.down_explained > 0.999 && a.across_explained[0] > 0.999);
/// // The across motion alone, with no orbit in it: which way round is not shown.
/// let flat: Vec<Folded> = folded.iter().map(|f| Folded { across_local: 0.0, ..*f }).collect();
/// assert!(!align_with_track(&flat, &orbit, 1.0, 1.0).handedness_shown);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn align_with_track(
    folded: &[Folded],
    orbit: &PredictedOrbit,
    cm_per_r: f64,
    frames_per_t0: f64,
) -> TrackAlignment {
    let per = (orbit.path.len() - 1) / 3;
    let frames_per_sample = orbit.period * frames_per_t0 / per as f64;
    let predicted = |phase: usize, t_local: f64, k: usize| {
        let x = phase as f64 + t_local / frames_per_sample;
        let i = (x.floor().max(0.0) as usize).min(orbit.path.len() - 2);
        let s = x - i as f64;
        let p = |j: usize| orbit.path[j][k] - orbit.path[phase][k];
        cm_per_r * (p(i) + s * (p(i + 1) - p(i)))
    };
    let measured = |f: &Folded, k: usize| if k == 0 { f.down_local } else { f.across_local };
    // The residual's sum of squares about its mean (least squares with a free offset); `None`
    // for the track's own variance (a constant prediction).
    let cost = |phase: usize, k: usize, sign: Option<f64>| {
        let r: Vec<f64> = folded
            .iter()
            .map(|f| measured(f, k) - sign.map_or(0.0, |s| s * predicted(phase, f.t_local, k)))
            .collect();
        let mean = r.iter().sum::<f64>() / r.len().max(1) as f64;
        r.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
    };
    let down_costs: Vec<f64> = (0..per).map(|phase| cost(phase, 0, Some(1.0))).collect();
    let phase = (0..per)
        .min_by(|&a, &b| down_costs[a].total_cmp(&down_costs[b]))
        .unwrap_or(0);
    let explained = |residual: f64, variance: f64| {
        if variance > 0.0 && variance.is_finite() && residual.is_finite() {
            1.0 - residual / variance
        } else {
            0.0
        }
    };
    let down_explained = explained(
        down_costs.get(phase).copied().unwrap_or(0.0),
        cost(phase, 0, None),
    );
    let across_variance = cost(phase, 1, None);
    let (plain, mirrored) = (cost(phase, 1, Some(1.0)), cost(phase, 1, Some(-1.0)));
    let mirrored_across = mirrored < plain;
    let (drawn, other) = if mirrored_across {
        (mirrored, plain)
    } else {
        (plain, mirrored)
    };
    let across_explained = [
        explained(drawn, across_variance),
        explained(other, across_variance),
    ];
    TrackAlignment {
        phase,
        mirrored_across,
        handedness_shown: across_explained[0] >= HANDEDNESS_EXPLAINED
            && across_explained[0] - across_explained[1] >= HANDEDNESS_MARGIN,
        down_explained,
        across_explained,
    }
}

impl ModelComparison {
    /// Where this comparison's predicted orbit sits on the folded centre track `folded`
    /// ([`super::fold_centre`]) filmed at `fps` frames a second ([`align_with_track`] in the
    /// comparison's own units: its ⟨r⟩ in cm and its t0), as `rollphase track` draws the orbit
    /// over the track and Python's `compare_with_model(folded=…)` reports it.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::prediction::PredictOptions;
    /// use rollphase_core::analysis::experiment::tracking::Folded;
    /// use rollphase_core::analysis::experiment::tracking::model::{Measured, compare_with_model};
    /// use rollphase_core::geometry::Body;
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let measured = Measured { period_s: 8.0, advance_down_cm: 6.0, advance_across_cm: 0.0 };
    /// let options = PredictOptions { starts: 4, ..PredictOptions::default() };
    /// let c = compare_with_model(&body, 10.0, 0.15, &measured, Some(0.0), &options)?;
    /// // A track that is the orbit itself at 30 frames a second (in cm), from sample 5 on.
    /// let (orbit, fps) = (&c.orbit, 30.0);
    /// let per = (orbit.path.len() - 1) / 3;
    /// let frames_per_sample = orbit.period * c.t0_s * fps / per as f64;
    /// let folded: Vec<Folded> = (0..per)
    ///     .map(|k| Folded {
    ///         period: 0,
    ///         t_local: k as f64 * frames_per_sample,
    ///         down_local: (orbit.path[5 + k][0] - orbit.path[5][0]) * c.scale_mm / 10.0,
    ///         across_local: (orbit.path[5 + k][1] - orbit.path[5][1]) * c.scale_mm / 10.0,
    ///     })
    ///     .collect();
    /// let a = c.aligned_with(&folded, fps);
    /// assert_eq!((a.phase, a.mirrored_across), (5, false));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn aligned_with(&self, folded: &[Folded], fps: f64) -> TrackAlignment {
        align_with_track(folded, &self.orbit, self.scale_mm / 10.0, self.t0_s * fps)
    }
}

/// Standard gravity (m/s²).
pub const G: f64 = 9.81;
/// Below this m/m0 the viscous model stands for the inertial one.
pub const VISCOUS_BELOW: f64 = 0.1;
/// Iterations of the joint solve before it gives up.
const MAX_ITERATIONS: usize = 12;
/// The joint solve stops when m/m0 changes by less than this fraction.
const SOLVE_TOLERANCE: f64 = 1e-4;

/// What a track measured, in seconds and centimetres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Measured {
    /// The period (s).
    pub period_s: f64,
    /// Advance per period down the ramp (cm).
    pub advance_down_cm: f64,
    /// Advance per period across the ramp (cm).
    pub advance_across_cm: f64,
}

impl Measured {
    /// Mean speed down the ramp (cm/s).
    ///
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::model::Measured;
    /// let m = Measured { period_s: 5.0, advance_down_cm: 6.0, advance_across_cm: -0.4 };
    /// assert_eq!(m.speed_cm_s(), 1.2);
    /// ```
    pub fn speed_cm_s(&self) -> f64 {
        self.advance_down_cm / self.period_s
    }
}

/// Where the m/m0 the model ran at came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MassSource {
    /// Solved with t0 so that the model's period in seconds is the measured one.
    Period,
    /// Given by the user (m/m0 > 0): t0 follows from it.
    Given,
    /// The viscous model was asked for (m/m0 = 0 given): t0 is the one that makes its period in
    /// seconds the measured one, and m/m0 = ⟨r⟩/(g t0²) is what that t0 implies, so it comes
    /// from the period, not from the user.
    ViscousPeriod,
}

/// The measurement against the model's prediction for the same body.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelComparison {
    /// α (rad).
    pub alpha: f64,
    /// ⟨r⟩ of the body (mm).
    pub scale_mm: f64,
    /// m/m0 the model ran at (0: the viscous model).
    pub mass_ratio_model: f64,
    /// m/m0 solved with t0 (or given): ⟨r⟩/(g t0²).
    pub mass_ratio: f64,
    /// Where `mass_ratio` came from.
    pub mass_ratio_from: MassSource,
    /// The time unit t0 = γ/(F⟨r⟩) (s).
    pub t0_s: f64,
    /// The SI's speed estimate v²/(g⟨r⟩ sin²α) (§2H).
    pub mass_ratio_from_speed: f64,
    /// The t0 the speed estimate implies, √(⟨r⟩/(g·m/m0)) (s).
    pub t0_from_speed_s: f64,
    /// The period (s) the model gives at the speed estimate's m/m0 and t0.
    pub period_from_speed_s: f64,
    /// The predicted orbit nearest in advance down the ramp: its period (t0).
    pub predicted_period_t0: f64,
    /// … in seconds (t0 × period; the measured period when m/m0 was solved for).
    pub predicted_period_s: f64,
    /// Its advance down the ramp per period (cm).
    pub predicted_advance_down_cm: f64,
    /// Its advance across the ramp per period (cm).
    pub predicted_advance_across_cm: f64,
    /// Its mean speed down the ramp (cm/s).
    pub predicted_speed_cm_s: f64,
    /// (measured − predicted)/predicted: advance down the ramp.
    pub advance_down_difference: f64,
    /// (measured − predicted)/predicted: period (s).
    pub period_difference: f64,
    /// (measured − predicted)/predicted: speed down the ramp.
    pub speed_difference: f64,
    /// 1, or 2 for a doubled orbit (its period and advance are per repeat).
    pub repeat: usize,
    /// Fraction of the model's starts that settle on this orbit.
    pub orbit_fraction: f64,
    /// All the predicted orbits: advance down the ramp (cm) and period (t0).
    pub orbits: Vec<[f64; 2]>,
    /// Joint-solve iterations (each a prediction; 0 when m/m0 was given).
    pub iterations: usize,
    /// d ln(m/m0) / d ln T_s: how the solved m/m0 moves with the measured period (−2 in the
    /// viscous model, −2/(1 − f′) with inertia, f′ the joint solve's own contraction, read from
    /// its last steps); t0's is −½ of it. `None` where m/m0 was given (the period does not
    /// move it) or the solve's steps do not tell.
    pub period_sensitivity: Option<f64>,
    /// The standard error of m/m0 from the measured period's alone
    /// ([`ModelComparison::with_period_error`]); ⟨r⟩'s, g's and α's are not in it.
    pub mass_ratio_error: Option<f64>,
    /// The standard error of t0 (s) from the measured period's alone, likewise.
    pub t0_error_s: Option<f64>,
    /// The orbit compared, with its path (⟨r⟩) for drawing.
    #[serde(skip)]
    pub orbit: PredictedOrbit,
}

/// Why the comparison could not be made.
#[derive(Debug, Error)]
pub enum CompareError {
    /// A bad setting.
    #[error("{0}")]
    BadArgument(String),
    /// The prediction failed.
    #[error(transparent)]
    Study(#[from] StudyError),
    /// The model has the body come to rest.
    #[error(
        "the model predicts no periodic motion for this body at α = {alpha} (m/m0 = \
         {mass_ratio}): it comes to rest, while the track rolls"
    )]
    NoOrbit {
        /// α (rad).
        alpha: f64,
        /// m/m0.
        mass_ratio: f64,
    },
    /// The joint solve for m/m0 and t0 did not settle.
    #[error(
        "m/m0 and t0 could not be found together: after {iterations} predictions m/m0 still \
         moves ({last:?}); give --mass to compare at a chosen m/m0"
    )]
    NotSettled {
        /// Predictions made.
        iterations: usize,
        /// The last values of m/m0.
        last: Vec<f64>,
    },
}

impl ModelComparison {
    /// The comparison with the errors of m/m0 and t0 that the measured period's error
    /// `period_error_s` (s, on `period_s`) gives through [`ModelComparison::period_sensitivity`]
    /// (none where that is `None`, or the error is not a positive number).
    ///
    /// ```
    /// use rollphase_core::analysis::experiment::prediction::{PredictOptions, predict};
    /// use rollphase_core::analysis::experiment::tracking::model::{Measured, compare_with_model};
    /// use rollphase_core::geometry::Body;
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let options = PredictOptions { starts: 4, ..PredictOptions::default() };
    /// let orbit = predict(&body, 0.15, 0.0, &options)?.orbits[0].clone();
    /// let measured = Measured {
    ///     period_s: orbit.period * 0.2,
    ///     advance_down_cm: orbit.advance_down,
    ///     advance_across_cm: orbit.advance_across,
    /// };
    /// // Viscous: m/m0 ∝ 1/T_s², t0 ∝ T_s, so a 1 % period error is 2 % and 1 %.
    /// let c = compare_with_model(&body, 10.0, 0.15, &measured, None, &options)?
    ///     .with_period_error(measured.period_s, 0.01 * measured.period_s);
    /// assert!((c.mass_ratio_error.unwrap() / c.mass_ratio - 0.02).abs() < 1e-12);
    /// assert!((c.t0_error_s.unwrap() / c.t0_s - 0.01).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn with_period_error(mut self, period_s: f64, period_error_s: f64) -> Self {
        let relative = period_error_s / period_s;
        let ok = relative.is_finite() && relative > 0.0;
        let s = self.period_sensitivity.filter(|_| ok);
        self.mass_ratio_error = s.map(|s| (s * relative * self.mass_ratio).abs());
        self.t0_error_s = s.map(|s| (0.5 * s * relative * self.t0_s).abs());
        self
    }
}

/// A step of the joint solve over this fraction of m/m0 is read for its secant: ten times the
/// solve's own tolerance ([`SOLVE_TOLERANCE`]), since nearer steps differ by the predictions'
/// noise as much as by the map.
const SECANT_STEP: f64 = 10.0 * SOLVE_TOLERANCE;

/// d ln(m/m0)/d ln T_s of the joint solve m = f(m) = ⟨r⟩T(m)²/(g T_s²): at its fixed point
/// dm = f′dm − 2(m/T_s)dT_s, so −2/(1 − f′). f′ is a secant of the solve's own values (each the
/// map of the one before: (m₂ − m₁)/(m₁ − m₀) = (f(m₁) − f(m₀))/(m₁ − m₀)), the last whose
/// first step is over [`SECANT_STEP`] of m/m0; 0 where no step
/// is (the map barely depends on m/m0), and `None` where f′ ≥ 0.9 (a slow solve: the period
/// then hardly fixes m/m0).
fn solved_sensitivity(history: &[f64], inertial: bool) -> Option<f64> {
    let last = history.last().copied().unwrap_or(0.0).abs();
    let slope = if inertial {
        history
            .windows(3)
            .rev()
            .find(|w| (w[1] - w[0]).abs() > SECANT_STEP * last)
            .map_or(0.0, |w| (w[2] - w[1]) / (w[1] - w[0]))
    } else {
        0.0
    };
    (slope < 0.9).then(|| -2.0 / (1.0 - slope))
}

/// The SI's estimate (§2H): m/m0 ≈ v²/(g⟨r⟩ sin²α), v in m/s, ⟨r⟩ in m.
///
/// ```
/// use rollphase_core::analysis::experiment::tracking::model::mass_ratio_from_speed;
/// // The paper's own numbers: ⟨r⟩ = 1 cm, g = 10, sin α = 0.2.
/// let alpha = 0.2f64.asin();
/// let viscous = mass_ratio_from_speed(0.01, 0.01, alpha, 10.0);
/// let inertial = mass_ratio_from_speed(0.1, 0.01, alpha, 10.0);
/// assert!((viscous - 0.025).abs() < 1e-12 && (inertial - 2.5).abs() < 1e-12);
/// ```
pub fn mass_ratio_from_speed(speed_m_s: f64, radius_m: f64, alpha: f64, g: f64) -> f64 {
    speed_m_s.powi(2) / (g * radius_m * alpha.sin().powi(2))
}

/// The time unit for m/m0 when the driving force is the weight: t0 = √(⟨r⟩/(g·m/m0)) (s).
///
/// ```
/// use rollphase_core::analysis::experiment::tracking::model::t0_for_mass_ratio;
/// // The uncoated print: m/m0 = 2.5 at ⟨r⟩ = 1 cm gives t0 ≈ 20 ms.
/// let t0 = t0_for_mass_ratio(2.5, 0.01, 9.81);
/// assert!((t0 - 0.020_19).abs() < 1e-5);
/// ```
pub fn t0_for_mass_ratio(mass_ratio: f64, radius_m: f64, g: f64) -> f64 {
    (radius_m / (g * mass_ratio)).sqrt()
}

/// The orbit of `p` nearest the measured advance down the ramp (`cm` per ⟨r⟩).
fn nearest(p: &Prediction, measured: &Measured, cm: f64) -> Option<PredictedOrbit> {
    p.orbits
        .iter()
        .min_by(|x, y| {
            (x.advance_down * cm - measured.advance_down_cm)
                .abs()
                .total_cmp(&(y.advance_down * cm - measured.advance_down_cm).abs())
        })
        .cloned()
}

/// The model's period (t0) and orbit at `mass_ratio` (viscous below [`VISCOUS_BELOW`]).
fn model_at(
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    (measured, cm): (&Measured, f64),
    options: &PredictOptions,
    stop: &AtomicBool,
) -> Result<(Prediction, PredictedOrbit, f64), CompareError> {
    let run_at = if mass_ratio < VISCOUS_BELOW {
        0.0
    } else {
        mass_ratio
    };
    let p = predict_until(body, alpha, run_at, options, stop)?;
    let orbit = nearest(&p, measured, cm).ok_or(CompareError::NoOrbit {
        alpha,
        mass_ratio: run_at,
    })?;
    Ok((p, orbit, run_at))
}

/// Compares `measured` with the model for `body` (⟨r⟩ = `scale_mm`) at α: m/m0 and t0 solved
/// together (or m/m0 given), the orbit nearest in advance, and the SI's estimate beside them.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::prediction::{PredictOptions, predict};
/// use rollphase_core::analysis::experiment::tracking::model::{Measured, compare_with_model};
/// use rollphase_core::geometry::Body;
/// // The paper's sphere at ⟨r⟩ = 1 cm, filmed on its own viscous orbit with t0 = 0.2 s.
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let options = PredictOptions { starts: 4, ..PredictOptions::default() };
/// let orbit = predict(&body, 0.15, 0.0, &options)?.orbits[0].clone();
/// let measured = Measured {
///     period_s: orbit.period * 0.2,
///     advance_down_cm: orbit.advance_down,
///     advance_across_cm: orbit.advance_across,
/// };
/// let c = compare_with_model(&body, 10.0, 0.15, &measured, None, &options)?;
/// assert!((c.t0_s - 0.2).abs() < 1e-9);
/// assert!((c.mass_ratio - 0.01 / (9.81 * 0.04)).abs() < 1e-9); // m/m0 = ⟨r⟩/(g t0²)
/// assert_eq!(c.mass_ratio_model, 0.0); // viscous
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// Non-finite or non-positive measurements, an α or m/m0 the model refuses, a body that comes
/// to rest, or a joint solve that does not settle.
pub fn compare_with_model(
    body: &Body,
    scale_mm: f64,
    alpha: f64,
    measured: &Measured,
    mass_ratio: Option<f64>,
    options: &PredictOptions,
) -> Result<ModelComparison, CompareError> {
    compare_with_model_until(
        body,
        scale_mm,
        alpha,
        measured,
        mass_ratio,
        options,
        &AtomicBool::new(false),
    )
}

/// [`compare_with_model`] that stops with the predictions' [`StudyError::Stopped`] once `stop`
/// is set.
///
/// ```
/// use std::sync::atomic::AtomicBool;
/// use rollphase_core::analysis::experiment::prediction::PredictOptions;
/// use rollphase_core::analysis::experiment::tracking::model::{Measured, compare_with_model_until};
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let measured = Measured { period_s: 8.0, advance_down_cm: 6.0, advance_across_cm: 0.0 };
/// let stopped = AtomicBool::new(true);
/// let options = PredictOptions::default();
/// assert!(compare_with_model_until(&body, 10.0, 0.15, &measured, None, &options, &stopped).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compare_with_model_until(
    body: &Body,
    scale_mm: f64,
    alpha: f64,
    measured: &Measured,
    mass_ratio: Option<f64>,
    options: &PredictOptions,
    stop: &AtomicBool,
) -> Result<ModelComparison, CompareError> {
    if !(measured.period_s.is_finite() && measured.period_s > 0.0) {
        return Err(CompareError::BadArgument(format!(
            "the measured period {} s is not a positive number",
            measured.period_s
        )));
    }
    if !(measured.advance_down_cm.is_finite() && measured.advance_down_cm > 0.0) {
        return Err(CompareError::BadArgument(format!(
            "the track advances {:.4} cm down the ramp per period: the model rolls downhill, so \
             a comparison needs a track that does (check the sign of --scale's down factor, SY, \
             and the --down-column)",
            measured.advance_down_cm
        )));
    }
    if !(scale_mm.is_finite() && scale_mm > 0.0) {
        return Err(CompareError::BadArgument(format!(
            "the body's scale_mm {scale_mm} is not a positive length"
        )));
    }
    let radius_m = scale_mm / 1000.0;
    let cm = scale_mm / 10.0;
    let from_speed = mass_ratio_from_speed(measured.speed_cm_s() / 100.0, radius_m, alpha, G);
    let mut iterations = 0;
    let mut sensitivity = None;
    let (prediction, orbit, model_mass, mass, t0, source) = match mass_ratio {
        Some(m) if m > 0.0 => {
            let (p, orbit, run_at) = model_at(body, alpha, m, (measured, cm), options, stop)?;
            (
                p,
                orbit,
                run_at,
                m,
                t0_for_mass_ratio(m, radius_m, G),
                MassSource::Given,
            )
        }
        Some(_) => {
            let (p, orbit, _) = model_at(body, alpha, 0.0, (measured, cm), options, stop)?;
            let t0 = measured.period_s / orbit.period;
            let implied = radius_m / (G * t0 * t0);
            sensitivity = Some(-2.0);
            (p, orbit, 0.0, implied, t0, MassSource::ViscousPeriod)
        }
        None => {
            let (mut p, mut orbit, _) = model_at(body, alpha, 0.0, (measured, cm), options, stop)?;
            let implied = |period_t0: f64| radius_m * (period_t0 / measured.period_s).powi(2) / G;
            let mut mass = implied(orbit.period);
            let mut run_at = 0.0;
            let mut history = vec![mass];
            while mass >= VISCOUS_BELOW {
                if iterations == MAX_ITERATIONS {
                    return Err(CompareError::NotSettled {
                        iterations,
                        last: history[history.len().saturating_sub(4)..].to_vec(),
                    });
                }
                iterations += 1;
                (p, orbit, run_at) = model_at(body, alpha, mass, (measured, cm), options, stop)?;
                let next = implied(orbit.period);
                history.push(next);
                let settled = ((next - mass) / mass).abs() < SOLVE_TOLERANCE;
                mass = next;
                if settled {
                    break;
                }
            }
            if mass < VISCOUS_BELOW && run_at > 0.0 {
                // The inertial model's answer fell into the viscous range: the viscous one stands.
                (p, orbit, run_at) = model_at(body, alpha, 0.0, (measured, cm), options, stop)?;
                mass = implied(orbit.period);
            }
            let t0 = measured.period_s / orbit.period;
            sensitivity = solved_sensitivity(&history, run_at > 0.0);
            (p, orbit, run_at, mass, t0, MassSource::Period)
        }
    };
    // The speed estimate's own implication: its t0 and the model's period there.
    let t0_speed = t0_for_mass_ratio(from_speed, radius_m, G);
    let speed_orbit_period =
        if from_speed < VISCOUS_BELOW && !crate::dynamics::models::asks_for_inertia(model_mass) {
            orbit.period
        } else {
            model_at(body, alpha, from_speed, (measured, cm), options, stop)?
                .1
                .period
        };
    let predicted_period_s = orbit.period * t0;
    let predicted_down = orbit.advance_down * cm;
    let predicted_speed = predicted_down / predicted_period_s;
    Ok(ModelComparison {
        alpha,
        scale_mm,
        mass_ratio_model: model_mass,
        mass_ratio: mass,
        mass_ratio_from: source,
        t0_s: t0,
        mass_ratio_from_speed: from_speed,
        t0_from_speed_s: t0_speed,
        period_from_speed_s: speed_orbit_period * t0_speed,
        predicted_period_t0: orbit.period,
        predicted_period_s,
        predicted_advance_down_cm: predicted_down,
        predicted_advance_across_cm: orbit.advance_across * cm,
        predicted_speed_cm_s: predicted_speed,
        advance_down_difference: (measured.advance_down_cm - predicted_down) / predicted_down,
        period_difference: (measured.period_s - predicted_period_s) / predicted_period_s,
        speed_difference: (measured.speed_cm_s() - predicted_speed) / predicted_speed,
        repeat: orbit.repeat,
        orbit_fraction: orbit.fraction,
        orbits: prediction
            .orbits
            .iter()
            .map(|o| [o.advance_down * cm, o.period])
            .collect(),
        iterations,
        period_sensitivity: sensitivity,
        mass_ratio_error: None,
        t0_error_s: None,
        orbit,
    })
}
