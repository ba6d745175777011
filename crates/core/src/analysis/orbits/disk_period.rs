//! The period T of a rolling disk and its order parameter 2π/T.
//!
//! Viscous (SI §1B): T = ∫₀^{2π} dθ / θ̇(θ), finite iff θ̇ > 0 everywhere, i.e. iff α > α*;
//! otherwise the disk halts at the first stable zero of θ̇. Computed by adaptive Gauss–Legendre
//! from θ* so the near-singular peak sits at the panel ends.
//!
//! Inertial: simulated with DOP853; the times where θ passes θ₀ + 2πk are located on the dense
//! output, and T is the interval between crossings once three successive intervals agree to
//! 1e-8 (the limit cycle is reached). A disk halts when it stops making revolutions and comes
//! to rest (`verdict::state_at_rest_for` at the end of the run: still, and the weight's torque
//! gone, to the resolution of the run's tolerance).

use serde::Serialize;

use crate::analysis::rest::critical_angle;
use crate::analysis::verdict::{Fate, Undecided, state_at_rest_for};
use crate::dynamics::{DiskInertial, DiskViscous, Ramp};
use crate::geometry::{Body, Disk};
use crate::integrate::run::{Flow, Run};
use crate::integrate::{IntegrateError, Method, events};
use crate::numeric::quadrature::integrate_adaptive;

/// The period of a rolling disk, or that it halts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PeriodResult {
    /// Time for θ to advance by 2π; `None` when the disk halts.
    pub period: Option<f64>,
    /// 2π/T, or 0 when the disk halts.
    pub mean_angular_speed: f64,
    /// Whether the disk comes to rest.
    pub halts: bool,
    /// Whether the period is known to 1e-9 (viscous: the quadrature's estimate and α*'s own
    /// rounding) or successive periods agreed to 1e-8 before the time limit (inertial).
    pub converged: bool,
    /// The relative error of the period (viscous: the larger of the quadrature's estimate and
    /// what α*'s rounding does to T ∝ (α − α*)^−½ this close to it).
    pub relative_error: f64,
    /// Simulated time used (0 for the quadrature).
    pub t_simulated: f64,
    /// Found by the viscous quadrature (its error is estimated), not by a run.
    pub by_quadrature: bool,
}

impl PeriodResult {
    /// Its fate in the verdict's words: periodic (a converged period: the quadrature's, or one
    /// known to its stated error up to [`MAX_VISCOUS_PERIOD_ERROR`], or three successive turns
    /// agreeing to 1e-8), halted, or undecided
    /// with what would decide it. A period still changing when the run ended (the mean of the
    /// second half) is a transient: undecided, never an answer. `alpha_above` is α − α*;
    /// `t_max` the run's length (inertial).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::orbits::disk_period::{inertial_disk_period, viscous_disk_period};
    /// use rollphase_core::analysis::verdict::{Fate, Undecided};
    /// use rollphase_core::dynamics::Ramp;
    /// use rollphase_core::geometry::Disk;
    /// let rolling = viscous_disk_period(&Disk::perfect(), &Ramp::new(0.3, 0.0)?);
    /// assert_eq!(rolling.fate(0.3, 0.0), Fate::Periodic { multiplicity: 1 });
    /// // A heavy disk still speeding up when the run ends: undecided, with the reason.
    /// let heavy = inertial_disk_period(&Disk::perfect(), &Ramp::new(0.3, 50.0)?, 0.0, 0.0, 1e-10, 30.0)?;
    /// assert!(matches!(heavy.fate(0.3, 30.0), Fate::Undecided { why: Undecided::NoRepeat { .. } | Undecided::NoTurn { .. } }));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn fate(&self, alpha_above: f64, t_max: f64) -> Fate {
        let viscous = self.by_quadrature;
        match self.period {
            _ if self.halts => Fate::Halted { t: None },
            Some(_) if self.converged => Fate::Periodic { multiplicity: 1 },
            // A quadrature known to its stated error; past MAX_VISCOUS_PERIOD_ERROR (α within
            // a few ulps of α*'s own rounding) no digit of T is known.
            Some(_) if viscous && self.relative_error <= MAX_VISCOUS_PERIOD_ERROR => {
                Fate::Periodic { multiplicity: 1 }
            }
            Some(_) if viscous => Fate::Undecided {
                why: Undecided::AtThreshold { alpha_above },
            },
            Some(t) => Fate::Undecided {
                why: Undecided::NoRepeat {
                    t_cap: t_max,
                    crossings: (self.t_simulated / t) as usize,
                    max_k: 1,
                },
            },
            None if viscous => Fate::Undecided {
                why: Undecided::AtThreshold { alpha_above },
            },
            None => Fate::Undecided {
                why: Undecided::NoTurn {
                    t_cap: t_max,
                    // Not kept by the period run.
                    angular_speed: f64::NAN,
                },
            },
        }
    }
}

/// Why a still-rolling inertial disk may be undecided at a coarse tolerance: its turns are
/// called periodic when three agree to 1e-8, which a run at `rtol` above 1e-9 cannot show (at
/// rtol 1e-6 every inertial case was undecided). Names the setting, as `flag`, that decides it;
/// empty otherwise.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::disk_period::coarse_rtol_hint;
/// use rollphase_core::analysis::verdict::Undecided;
/// let why = Undecided::NoRepeat { t_cap: 5000.0, crossings: 235, max_k: 1 };
/// assert!(coarse_rtol_hint(&why, 1e-6, "--rtol").contains("--rtol 1e-10"));
/// assert!(coarse_rtol_hint(&why, 1e-10, "--rtol").is_empty());
/// ```
pub fn coarse_rtol_hint(why: &Undecided, rtol: f64, flag: &str) -> String {
    if matches!(why, Undecided::NoRepeat { .. }) && rtol > 1e-9 {
        format!(
            " (at {flag} {rtol:e} successive turns cannot agree to the 1e-8 a period needs: \
             {flag} 1e-10, the default, would decide it)"
        )
    } else {
        String::new()
    }
}

/// Viscous period by quadrature (SI eq. for T). Halts iff tan α ≤ Q* = tan α*.
///
/// ```
/// use rollphase_core::analysis::viscous_disk_period;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Disk;
/// // A perfect disk rolls at 2π/T = sin α.
/// let p = viscous_disk_period(&Disk::perfect(), &Ramp::new(0.3, 0.0)?);
/// assert!((p.mean_angular_speed - 0.3f64.sin()).abs() < 1e-12);
/// # Ok::<(), rollphase_core::dynamics::ModelError>(())
/// ```
pub fn viscous_disk_period(disk: &Disk, ramp: &Ramp) -> PeriodResult {
    let ca = critical_angle::critical_angle(&Body::Disk(disk.clone()));
    viscous_disk_period_with(disk, ramp, &ca)
}

/// [`viscous_disk_period`] with the disk's critical angle already known (`ca` must be this
/// disk's): a sweep over α finds α* once instead of at every α.
///
/// # Example
/// ```
/// use rollphase_core::analysis::critical_angle;
/// use rollphase_core::analysis::orbits::disk_period::{viscous_disk_period, viscous_disk_period_with};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_disk(84, 0.12, 5)?;
/// let ca = critical_angle(&body);
/// let Body::Disk(disk) = &body else { unreachable!() };
/// // A sweep over α finds α* once; each period is the same as computing it afresh.
/// for alpha in [1.05, 1.2, 1.5].map(|f| f * ca.alpha_star) {
///     let ramp = Ramp::new(alpha, 0.0)?;
///     assert_eq!(viscous_disk_period_with(disk, &ramp, &ca).period, viscous_disk_period(disk, &ramp).period);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn viscous_disk_period_with(
    disk: &Disk,
    ramp: &Ramp,
    ca: &critical_angle::CriticalAngle,
) -> PeriodResult {
    if ramp.alpha_rad <= ca.alpha_star {
        return PeriodResult {
            period: None,
            mean_angular_speed: 0.0,
            halts: true,
            converged: true,
            relative_error: 0.0,
            t_simulated: 0.0,
            by_quadrature: true,
        };
    }
    let model = DiskViscous::new(disk, ramp);
    let f = |t: f64| 1.0 / model.theta_dot(t);
    // Within 1e-8 of α* the integrand carries ~1e-8 relative rounding noise, so a tighter
    // tolerance only spends the budget; 1e-11 is reached everywhere else in ~1e4 evaluations.
    let q = match curved_parts(disk) {
        None => {
            let start = ca.theta;
            integrate_adaptive(&f, start, start + std::f64::consts::TAU, 1e-11, 200_000)
        }
        // On its hull (a dented body, or a print's outline) the body crosses each flat in no
        // time (it tips), so a turn takes the curved parts' time; each is a panel of its own,
        // its ends (where the peak of 1/θ̇ sits near α*) at panel ends.
        // The evaluation budget is the turn's, shared by its parts: a 512-sided print has 512
        // corners, each near-singular just above α*.
        Some(parts) => parts.iter().fold(
            crate::numeric::quadrature::Quadrature {
                value: 0.0,
                error: 0.0,
                evals: 0,
            },
            |sum, &(a, b)| {
                let budget = (200_000 / parts.len() as u64).max(2_000);
                let q = integrate_adaptive(&f, a, b, 1e-11, budget);
                crate::numeric::quadrature::Quadrature {
                    value: sum.value + q.value,
                    error: sum.error + q.error,
                    evals: sum.evals + q.evals,
                }
            },
        ),
    };
    let t = q.value;
    if !(t.is_finite() && t > 0.0 && q.error.is_finite()) {
        // So close to α* that 1/θ̇ overflows at θ*: no finite period can be computed.
        return PeriodResult {
            period: None,
            mean_angular_speed: 0.0,
            halts: false,
            converged: false,
            relative_error: f64::NAN,
            t_simulated: 0.0,
            by_quadrature: true,
        };
    }
    // α* is a maximum found to a few ulps, so α − α* carries that much absolute error, of which
    // T ∝ (α − α*)^−½ takes half, relatively. Measured on the seed-1 disk (α* = 0.0382): T·√Δ
    // strays from its law by 9e-4 at Δ = 1e-14, 0.9 % at 1e-15 and 8.5 % at 1e-16, an error of
    // Δ of 1.7e-17 (2.5 ulps), while the quadrature's own estimate said 5e-5 … 4e-3.
    let delta = ramp.alpha_rad - ca.alpha_star;
    let alpha_star_rounding = ALPHA_STAR_ROUNDING * ca.alpha_star.abs() * f64::EPSILON;
    let relative_error = (q.error / t).max(0.5 * alpha_star_rounding / delta);
    PeriodResult {
        period: Some(t),
        mean_angular_speed: std::f64::consts::TAU / t,
        halts: false,
        converged: relative_error <= 1e-9,
        relative_error,
        t_simulated: 0.0,
        by_quadrature: true,
    }
}

/// The error of a computed α*, in units of |α*| ε (the spacing of doubles there, about): the
/// maximum of Q(θ) is found to 2.5 of them on the seed-1 disk; 4 states it with room.
const ALPHA_STAR_ROUNDING: f64 = 4.0;

/// The largest relative error at which a viscous period is still stated (with that error):
/// within a few ulps of α* the period is known to no useful digit, and is undecided.
pub const MAX_VISCOUS_PERIOD_ERROR: f64 = 1e-2;

/// The curved parts of a disk that rolls on its hull, as (start, end) contact angles over one
/// turn: the gaps between its bridges; `None` for a convex disk.
pub(crate) fn curved_parts(disk: &Disk) -> Option<Vec<(f64, f64)>> {
    let bridges = disk.hull().bridges();
    let n = bridges.len();
    (n > 0).then(|| {
        (0..n)
            .map(|k| {
                let end = bridges[k].theta_b;
                let next = bridges[(k + 1) % n].theta_a;
                (end, end + (next - end).rem_euclid(std::f64::consts::TAU))
            })
            .collect()
    })
}

/// Why the inertial period of `disk` is not computed, when it rolls on its hull (a dent's
/// bridges or a print's flat sides): each flat ends in an impact, which only the run loop
/// ([`crate::simulate::run`]) follows, while this period steps the smooth equations alone.
/// `None` for a convex disk.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::disk_period::inertial_on_hull;
/// use rollphase_core::geometry::{Body, Disk};
/// assert!(inertial_on_hull(&Disk::perfect()).is_none());
/// let Body::Disk(dented) = Body::paper_disk(219, 0.5, 9)? else { unreachable!() };
/// assert!(inertial_on_hull(&dented).unwrap().contains("simulate"));
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn inertial_on_hull(disk: &Disk) -> Option<String> {
    let flats = disk.hull().bridges().len();
    (flats > 0).then(|| {
        format!(
            "this body rolls on its convex hull ({flats} flat side(s): {}), and with inertia each \
             flat ends in an impact that the period's turn-by-turn run does not follow; the \
             viscous period (m/m0 = 0) is computed exactly, and `rollphase simulate --mass M` \
             runs the inertial model with its impacts",
            if disk.printed_outline().is_some() {
                "the print's sides"
            } else {
                "bridges over its dents"
            }
        )
    })
}

/// Inertial period by simulation from (θ₀, θ̇₀), at most `t_max` time units: the time between
/// whole turns of θ, located as events, once three in a row agree to 1e-8 (`rollphase period
/// --mass`).
///
/// ```
/// use rollphase_core::analysis::inertial_disk_period;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// let Body::Disk(disk) = Body::paper_disk(84, 0.12, 5)? else { unreachable!() };
/// let p = inertial_disk_period(&disk, &Ramp::new(0.039, 10.0)?, 1.5707963267948966, 0.04, 1e-10, 5000.0)?;
/// assert!(!p.halts && p.converged); // the SI's "halting near 0.039" does not hold on this disk
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn inertial_disk_period(
    disk: &Disk,
    ramp: &Ramp,
    theta0: f64,
    theta_dot0: f64,
    rtol: f64,
    t_max: f64,
) -> Result<PeriodResult, IntegrateError> {
    let never = std::sync::atomic::AtomicBool::new(false);
    inertial_disk_period_until(disk, ramp, theta0, theta_dot0, rtol, t_max, &never)
        .map(|p| p.expect("never stopped"))
}

/// [`inertial_disk_period`], ending early (`Ok(None)`) once `stop` is set: a stiff run (tiny
/// m/m0) can take minutes, and a caller (Python's Ctrl-C) must be able to end it.
///
/// # Example
/// ```
/// use std::sync::atomic::AtomicBool;
/// use rollphase_core::analysis::orbits::disk_period::inertial_disk_period_until;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// let Body::Disk(disk) = Body::paper_disk(84, 0.12, 5)? else { unreachable!() };
/// let stop = AtomicBool::new(true); // already asked to stop
/// let p = inertial_disk_period_until(&disk, &Ramp::new(0.3, 1e-9)?, 0.0, 0.0, 1e-10, 5000.0, &stop)?;
/// assert!(p.is_none());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn inertial_disk_period_until(
    disk: &Disk,
    ramp: &Ramp,
    theta0: f64,
    theta_dot0: f64,
    rtol: f64,
    t_max: f64,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<Option<PeriodResult>, IntegrateError> {
    let model = DiskInertial::new(disk, ramp);
    let mut run = Run::new(
        &model,
        0.0,
        [theta0, theta_dot0, 0.0, 0.0],
        Method::dop853(rtol),
    )?;
    let mut crossings: Vec<f64> = Vec::new();
    let mut target = theta0 + std::f64::consts::TAU;
    let mut periods: Vec<f64> = Vec::new();
    let mut converged = None;
    let mut stopped = stop.load(std::sync::atomic::Ordering::Relaxed);
    if !stopped {
        run.until::<IntegrateError>(t_max, 50_000_000, |st| {
            let before = crossings.len();
            events::turns_in_last_step(st, 0, &mut target, std::f64::consts::TAU, &mut crossings);
            for i in before.max(1)..crossings.len() {
                periods.push(crossings[i] - crossings[i - 1]);
            }
            if periods.len() >= 3 {
                let n = periods.len();
                let (a, b, c) = (periods[n - 3], periods[n - 2], periods[n - 1]);
                if (a - b).abs() <= 1e-8 * c && (b - c).abs() <= 1e-8 * c {
                    converged = Some(PeriodResult {
                        period: Some(c),
                        mean_angular_speed: std::f64::consts::TAU / c,
                        halts: false,
                        converged: true,
                        relative_error: 1e-8,
                        t_simulated: st.t(),
                        by_quadrature: false,
                    });
                    return Ok(Flow::Stop);
                }
            }
            stopped = stop.load(std::sync::atomic::Ordering::Relaxed);
            Ok(if stopped { Flow::Stop } else { Flow::Continue })
        })?;
    }
    if converged.is_some() {
        return Ok(converged);
    }
    if stopped {
        return Ok(None);
    }
    // At rest by the verdict's one rule, to the resolution this run's tolerance has: still,
    // and the weight's torque gone (a very heavy disk above α* has θ̇ ≈ 0 for a long time, but
    // it is accelerating, not halted).
    let resting = state_at_rest_for(&model, run.y(), rtol);
    let last_crossing = crossings.last().copied().unwrap_or(0.0);
    let not_measured = PeriodResult {
        period: None,
        mean_angular_speed: 0.0,
        halts: resting,
        converged: resting,
        relative_error: f64::NAN,
        t_simulated: run.t(),
        by_quadrature: false,
    };
    if resting || periods.is_empty() || (run.t() - last_crossing) > 0.5 * t_max {
        return Ok(Some(not_measured));
    }
    // Still rolling but not yet periodic to 1e-8: report the mean over the second half.
    let half: Vec<f64> = periods.iter().skip(periods.len() / 2).copied().collect();
    let mean = half.iter().sum::<f64>() / half.len() as f64;
    if !(mean.is_finite() && mean > 0.0) {
        return Ok(Some(not_measured));
    }
    Ok(Some(PeriodResult {
        period: Some(mean),
        mean_angular_speed: std::f64::consts::TAU / mean,
        halts: false,
        converged: false,
        relative_error: f64::NAN,
        t_simulated: run.t(),
        by_quadrature: false,
    }))
}
