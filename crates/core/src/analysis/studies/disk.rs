//! 2D analyses behind the paper's Fig. 2 and SI Fig. S2: lag times near α*, the hysteresis sweep
//! of the inertial disk, and the fixed points of its (θ, θ̇) flow.
//!
//! - **Lag time** (Fig. 2e inset, 2f): released from rest at the bottleneck θ* (where the stable
//!   and unstable rest points merged at α*), the disk needs t_lag to roll a fixed distance, here
//!   until θ − θ* = π (half a turn, "a small distance" as in the experiment). Near the
//!   saddle-node t_lag ∝ (α − α*)^(−1/2) for any mass: the time is spent creeping through the
//!   ghost of the fixed points, where θ̈ and θ̇ are both small.
//! - **Hysteresis** (Fig. 2e): α is stepped up then down with the state carried over; at each α
//!   the disk runs for a dwell time (the transient), then, if it rolls, its period T is measured
//!   by locating whole turns as events and its speed is 2π/T.
//! - **Fixed points** (SI §1D): θ̇ = 0 and r sin α − r' cos α = 0; stable where the drive
//!   decreases through zero (a restoring torque), saddles where it increases.

use rayon::prelude::*;
use serde::Serialize;

use crate::analysis::fit::{logspace, power_law};
use crate::analysis::orbits::disk_period::{inertial_disk_period, viscous_disk_period_with};
use crate::analysis::rest::critical_angle::critical_angle;
use crate::analysis::verdict::state_at_rest;
use crate::dynamics::ModelKind;
use crate::dynamics::{DiskInertial, DiskViscous, ModelError, Ramp};
use crate::geometry::{Body, Disk};
use crate::integrate::events::{Direction, crossings_in_last_step};
use crate::integrate::run::{Flow, Run, Samples};
use crate::integrate::{IntegrateError, Method, OdeSystem};

/// Time for the disk, released from rest at `theta0`, to reach θ = θ0 + `distance`; `None` if it
/// has not got there by `t_max` (it halted).
///
/// # Example
/// ```
/// use rollphase_core::analysis::studies::disk::lag_time;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Disk;
/// // The perfect disk rolls at θ̇ = sin α from the start: half a turn takes π / sin α.
/// let t = lag_time(&Disk::perfect(), &Ramp::new(0.3, 0.0)?, 0.0, std::f64::consts::PI, 1e-12, 1e3)?;
/// assert!((t.unwrap() - std::f64::consts::PI / 0.3f64.sin()).abs() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn lag_time(
    disk: &Disk,
    ramp: &Ramp,
    theta0: f64,
    distance: f64,
    rtol: f64,
    t_max: f64,
) -> Result<Option<f64>, IntegrateError> {
    let target = theta0 + distance;
    match ModelKind::for_dimension(2, ramp) {
        ModelKind::DiskViscous => {
            let m = DiskViscous::new(disk, ramp);
            first_reach(&m, [theta0, 0.0], target, rtol, t_max)
        }
        ModelKind::DiskInertial => {
            let m = DiskInertial::new(disk, ramp);
            first_reach(&m, [theta0, 0.0, 0.0, 0.0], target, rtol, t_max)
        }
        other @ (ModelKind::SphereViscous | ModelKind::SphereInertial) => other.wrong_dimension(2),
    }
}

/// The first time θ (the state's first slot) rises through `target`, run from `y0` until then
/// or `t_max`: a crossing observer on the one run loop.
fn first_reach<const N: usize, S: OdeSystem<N>>(
    model: &S,
    y0: [f64; N],
    target: f64,
    rtol: f64,
    t_max: f64,
) -> Result<Option<f64>, IntegrateError> {
    let mut run = Run::new(model, 0.0, y0, Method::dop853(rtol))?;
    let mut reached = Vec::new();
    run.until::<IntegrateError>(t_max, 50_000_000, |st| {
        crossings_in_last_step(
            st,
            &|_t, y: &[f64; N]| y[0] - target,
            Direction::Rising,
            &mut reached,
        );
        Ok(if reached.is_empty() {
            Flow::Continue
        } else {
            Flow::Stop
        })
    })?;
    Ok(reached.first().copied())
}

/// One point of a hysteresis sweep.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SweepPoint {
    /// Ramp angle (rad).
    pub alpha: f64,
    /// true on the way up, false on the way down.
    pub ascending: bool,
    /// 2π/T from the event-located period T (0 when at rest).
    pub mean_angular_speed: f64,
    /// The period T: the time between successive whole turns of θ, located as events
    /// ([`inertial_disk_period`]); `None` at rest.
    pub period: Option<f64>,
    /// Whether three successive periods agreed to 1e-8 (false: the mean of the periods measured
    /// within the dwell, still drifting).
    pub period_converged: bool,
    /// The state (θ, θ̇) at the end of the dwell, from which T was measured: `rollphase period
    /// --theta0 θ --thetadot0 θ̇` from there gives the same T.
    pub state: [f64; 2],
}

/// Sweeps α through `alphas` (ascending then the same values descending) with the inertial
/// model, carrying (θ, θ̇) over; `dwell` time units per α let the transient die out. Where the
/// disk made at least one whole turn in the second half of the dwell, its period T is then
/// measured from the dwell's end state by locating whole turns as events (as `rollphase period`
/// does, at most 4 × `dwell` time units) and the speed is 2π/T; otherwise the speed is 0.
///
/// # Example
/// ```
/// use rollphase_core::analysis::critical_angle;
/// use rollphase_core::analysis::studies::disk::{fixed_points, hysteresis_sweep};
/// use rollphase_core::geometry::{Body, first_convex_disk};
/// // `figure disk-hysteresis --quick`'s disk and ladder: α*/2 to 1.3 α* in steps of α*/20.
/// let (disk, _) = first_convex_disk(1, 0.12, 5)?;
/// let alpha_star = critical_angle(&Body::Disk(disk.clone())).alpha_star;
/// let alphas: Vec<f64> = (0..17).map(|k| (0.5 + 0.05 * k as f64) * alpha_star).collect();
/// let rest = fixed_points(&disk, alphas[0]).into_iter().find(|p| p.stable).unwrap();
/// let sweep = hysteresis_sweep(&disk, 10.0, &alphas, [rest.theta, 0.0], 600.0, 1e-10, || {})?;
/// assert_eq!(sweep.len(), 33); // the top angle once
/// assert!(sweep[8].ascending && sweep[8].mean_angular_speed == 0.0, "at rest at 0.9 α* going up");
/// assert!(sweep[16].mean_angular_speed > 0.0, "rolling at 1.3 α*");
/// // Hysteresis: the heavy disk, once rolling, keeps rolling at 0.9 α* on the way down.
/// assert!(!sweep[24].ascending && sweep[24].mean_angular_speed > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn hysteresis_sweep(
    disk: &Disk,
    mass: f64,
    alphas: &[f64],
    start: [f64; 2],
    dwell_time: f64,
    rtol: f64,
    mut progress: impl FnMut(),
) -> Result<Vec<SweepPoint>, IntegrateError> {
    let mut state = [start[0], start[1], 0.0, 0.0];
    let mut out = Vec::new();
    let path: Vec<(f64, bool)> = alphas
        .iter()
        .map(|&a| (a, true))
        .chain(alphas.iter().rev().skip(1).map(|&a| (a, false)))
        .collect();
    for (alpha, ascending) in path {
        let ramp = Ramp::new(alpha, mass).map_err(|_| IntegrateError::BadParameter {
            name: "alpha",
            value: alpha,
            allowed: "0 < alpha < π/2",
        })?;
        let (advance, end) = dwell(disk, &ramp, [state[0], state[1]], dwell_time, rtol)?;
        state = [end[0], end[1], 0.0, 0.0];
        // Rolling means at least one whole turn in the second half of the dwell; less is a rest
        // point creeping as α changes, reported as 0.
        let measured = if advance > std::f64::consts::TAU {
            let p = inertial_disk_period(disk, &ramp, end[0], end[1], rtol, 4.0 * dwell_time)?;
            p.period.map(|t| (t, p.converged))
        } else {
            None
        };
        out.push(SweepPoint {
            alpha,
            ascending,
            mean_angular_speed: measured.map_or(0.0, |(t, _)| std::f64::consts::TAU / t),
            period: measured.map(|(t, _)| t),
            period_converged: measured.is_some_and(|(_, c)| c),
            state: end,
        });
        progress();
    }
    Ok(out)
}

/// Runs the inertial disk from (θ, θ̇) = `state` on `ramp` for `duration`; returns how far θ
/// advanced over the second half, and the end state.
///
/// # Example
/// ```
/// use rollphase_core::analysis::studies::disk::dwell;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Disk;
/// // The perfect disk at terminal speed: θ advances sin α · T/2 over the second half.
/// let (advance, end) = dwell(&Disk::perfect(), &Ramp::new(0.3, 2.0)?, [0.0, 0.3f64.sin()], 10.0, 1e-12)?;
/// assert!((advance - 5.0 * 0.3f64.sin()).abs() < 1e-9 && (end[1] - 0.3f64.sin()).abs() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn dwell(
    disk: &Disk,
    ramp: &Ramp,
    state: [f64; 2],
    duration: f64,
    rtol: f64,
) -> Result<(f64, [f64; 2]), IntegrateError> {
    let model = DiskInertial::new(disk, ramp);
    let mut run = Run::new(
        &model,
        0.0,
        [state[0], state[1], 0.0, 0.0],
        Method::dop853(rtol),
    )?;
    let mut theta_half = state[0];
    run.until::<IntegrateError>(duration, u64::MAX, |st| {
        if st.t_prev() < 0.5 * duration && st.t() >= 0.5 * duration {
            theta_half = st.dense(0.5 * duration)[0];
        }
        Ok(Flow::Continue)
    })?;
    let y = *run.y();
    Ok((y[0] - theta_half, [y[0], y[1]]))
}

/// A rest point of the (θ, θ̇) flow.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FixedPoint {
    /// Contact angle in [0, 2π).
    pub theta: f64,
    /// Stable (restoring drive) or a saddle.
    pub stable: bool,
}

/// Zeros of r sin α − r' cos α on [0, 2π), located by sign changes on a fine grid and Brent.
///
/// # Example
/// ```
/// use rollphase_core::analysis::studies::disk::fixed_points;
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_disk(84, 0.12, 5)?;
/// let alpha_star = body.alpha_star();
/// let Body::Disk(disk) = body else { unreachable!() };
/// // Below α* rest points come in stable/saddle pairs; above it there are none.
/// let below = fixed_points(&disk, 0.5 * alpha_star);
/// assert!(!below.is_empty() && below.len() % 2 == 0);
/// assert_eq!(below.iter().filter(|p| p.stable).count(), below.len() / 2);
/// assert!(fixed_points(&disk, 1.1 * alpha_star).is_empty());
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn fixed_points(disk: &Disk, alpha: f64) -> Vec<FixedPoint> {
    let (sa, ca) = alpha.sin_cos();
    let drive = |t: f64| {
        let j = disk.jet(t);
        j.r * sa - j.r1 * ca
    };
    let n = 4096;
    let h = std::f64::consts::TAU / n as f64;
    let mut out = Vec::new();
    for i in 0..n {
        let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
        let (fa, fb) = (drive(a), drive(b));
        if (fa < 0.0 && fb >= 0.0) || (fa > 0.0 && fb <= 0.0) {
            let t = crate::numeric::roots::brent(drive, a, b, fa, fb, 1e-14);
            out.push(FixedPoint {
                theta: t.rem_euclid(std::f64::consts::TAU),
                stable: fa > 0.0,
            });
        }
    }
    out
}

/// Whether a viscous disk released at θ₀ makes a whole turn (cruises) before halting
/// (`verdict::state_at_rest`), DOP853 at rtol 1e-10 up to t = 10⁶: the 2D side of the cruising fraction
/// (paper Fig. 3b).
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::studies::disk::disk_cruises;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// let disk = Body::paper_disk(1, 0.25, 5)?;
/// let alpha_star = disk.alpha_star();
/// let Body::Disk(disk) = disk else { unreachable!() };
/// // In 2D the fate does not depend on the start: halts below α*, cruises above.
/// assert!(!disk_cruises(&disk, &Ramp::new(0.9 * alpha_star, 0.0)?, 0.0)?);
/// assert!(disk_cruises(&disk, &Ramp::new(1.1 * alpha_star, 0.0)?, 0.0)?);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn disk_cruises(disk: &Disk, ramp: &Ramp, theta0: f64) -> Result<bool, IntegrateError> {
    let m = DiskViscous::new(disk, ramp);
    let mut run = Run::new(&m, 0.0, [theta0, 0.0], Method::dop853(1e-10))?;
    let mut cruises = false;
    run.until::<IntegrateError>(1e6, u64::MAX, |st| {
        cruises = st.y()[0] - theta0 > std::f64::consts::TAU;
        Ok(if cruises || state_at_rest(&m, st.y()) {
            Flow::Stop
        } else {
            Flow::Continue
        })
    })?;
    Ok(cruises)
}

/// The inertial disk's path in the (θ, θ̇) plane from `start` = (θ, θ̇) to `t_end`: `samples` + 1
/// evenly spaced points (θ wrapped to [0, 2π), dense output of DOP853 at rtol 1e-10), and
/// whether it rolls on: not at rest (`verdict::state_at_rest`) within ten times `t_end`. SI Fig. S2's trajectories.
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::studies::disk::phase_path;
/// use rollphase_core::dynamics::{DiskInertial, Ramp};
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_disk(1, 0.12, 5)?;
/// let alpha_star = body.alpha_star();
/// let Body::Disk(disk) = body else { unreachable!() };
/// // Above α* there is no fixed point: the disk keeps rolling.
/// let model = DiskInertial::new(&disk, &Ramp::new(1.2 * alpha_star, 10.0)?);
/// let (points, rolls) = phase_path(&model, [std::f64::consts::FRAC_PI_2, 0.04], 300.0, 1000)?;
/// assert_eq!(points.len(), 1001);
/// assert!(rolls && points.iter().all(|p| (0.0..std::f64::consts::TAU).contains(&p[0])));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn phase_path(
    model: &DiskInertial,
    start: [f64; 2],
    t_end: f64,
    samples: usize,
) -> Result<(Vec<[f64; 2]>, bool), IntegrateError> {
    let mut run = Run::new(
        model,
        0.0,
        [start[0], start[1], 0.0, 0.0],
        Method::dop853(1e-10),
    )?;
    let times: Vec<f64> = (0..=samples)
        .map(|k| t_end * k as f64 / samples as f64)
        .collect();
    let mut points = Vec::with_capacity(samples + 1);
    let mut sampled = Samples::new(&times);
    let mut point = |_: f64, y: &[f64; 4]| {
        points.push([y[0].rem_euclid(std::f64::consts::TAU), y[1]]);
    };
    sampled.take_at_start(&run, &mut point);
    run.until::<IntegrateError>(t_end, u64::MAX, |st| {
        sampled.take(st, &mut point);
        Ok(Flow::Continue)
    })?;
    // Whether it rolls on: the run goes on past the path drawn, up to ten times its length,
    // until the verdict's rest. A disk settling into a rest point's well still swings at the
    // path's end (at m/m0 = 10 and 0.3 α*, |θ̇| ~ 1e-6 at t = 300); a cut of |θ̇| < 1e-6 there
    // was a second rest rule.
    let mut rests = state_at_rest(model, run.y());
    if !rests {
        run.until::<IntegrateError>(10.0 * t_end, u64::MAX, |st| {
            rests = state_at_rest(model, st.y());
            Ok(if rests { Flow::Stop } else { Flow::Continue })
        })?;
    }
    Ok((points, !rests))
}

/// Why the return transition α** could not be located.
#[derive(Debug, thiserror::Error)]
pub enum ReturnTransitionError {
    /// The descending sweep never rolled, so there is no rolling state to lower α from.
    #[error("never rolled on the way down")]
    NeverRolledDown,
    /// A bad α or m/m0 along the way.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An integration failed.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
}

/// Where the inertial disk stops rolling on the way down ([`return_transition`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReturnTransition {
    /// α**, the midpoint of the final bisection bracket.
    pub alpha_return: f64,
    /// The lowest α found rolling (the bracket's top).
    pub lowest_rolling: f64,
    /// The rolling state (θ, θ̇) there, to continue from.
    pub state: [f64; 2],
}

/// Whether the disk, started from `state` at `alpha`, still rolls after `duration` (at least one
/// more turn in the second half); the end state.
///
/// # Example
/// ```
/// use rollphase_core::analysis::studies::disk::still_rolls;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Disk;
/// let (rolls, _) = still_rolls(&Disk::perfect(), &Ramp::new(0.3, 2.0)?, [0.0, 0.0], 100.0, 1e-10)?;
/// assert!(rolls, "a perfect disk never stops");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn still_rolls(
    disk: &Disk,
    ramp: &Ramp,
    state: [f64; 2],
    duration: f64,
    rtol: f64,
) -> Result<(bool, [f64; 2]), IntegrateError> {
    let (advance, end) = dwell(disk, ramp, state, duration, rtol)?;
    Ok((advance > std::f64::consts::TAU, end))
}

/// α** of a [`hysteresis_sweep`] over `alphas` at `mass` with `dwell_time`: bisection
/// (`iterations` halvings) between the lowest descending α that rolled and the next one below,
/// each trial run for 3 × `dwell_time` from the rolling state of the last α that still rolled.
/// `on_step` is called after each halving (a progress bar).
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::studies::disk::{fixed_points, hysteresis_sweep, return_transition};
/// use rollphase_core::geometry::{Body, first_convex_disk};
/// let (disk, _) = first_convex_disk(1, 0.12, 5)?;
/// let alpha_star = Body::Disk(disk.clone()).alpha_star();
/// // disk-hysteresis's sweep, coarser: 0.5 α* to 1.3 α* and back, m/m0 = 10, from rest.
/// let alphas: Vec<f64> = (0..9).map(|i| alpha_star * (0.5 + 0.1 * i as f64)).collect();
/// let rest = fixed_points(&disk, alphas[0]).into_iter().find(|p| p.stable).unwrap();
/// let sweep = hysteresis_sweep(&disk, 10.0, &alphas, [rest.theta, 0.0], 600.0, 1e-10, || {})?;
/// let back = return_transition(&disk, 10.0, &sweep, &alphas, 600.0, 10, 1e-10, &|| {})?;
/// // With inertia it keeps rolling below α*: hysteresis.
/// assert!(back.alpha_return < alpha_star);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn return_transition(
    disk: &Disk,
    mass: f64,
    sweep: &[SweepPoint],
    alphas: &[f64],
    dwell_time: f64,
    iterations: usize,
    rtol: f64,
    on_step: &dyn Fn(),
) -> Result<ReturnTransition, ReturnTransitionError> {
    let rolls = |alpha: f64, state: [f64; 2], duration: f64| {
        Ok::<_, ReturnTransitionError>(still_rolls(
            disk,
            &Ramp::new(alpha, mass)?,
            state,
            duration,
            rtol,
        )?)
    };
    let down: Vec<_> = sweep.iter().filter(|p| !p.ascending).collect();
    let last_rolling = down
        .iter()
        .rposition(|p| p.mean_angular_speed > 0.0)
        .ok_or(ReturnTransitionError::NeverRolledDown)?;
    let (mut hi, mut lo) = (
        down[last_rolling].alpha,
        down.get(last_rolling + 1)
            .map(|p| p.alpha)
            .unwrap_or(alphas[0]),
    );
    // The rolling state at `hi`: re-run the descent from the top with continuation.
    let mut state = [0.0, 0.05];
    for &a in alphas.iter().rev().filter(|&&a| a >= hi) {
        state = rolls(a, state, dwell_time)?.1;
    }
    for _ in 0..iterations {
        let mid = 0.5 * (lo + hi);
        let (r, end) = rolls(mid, state, 3.0 * dwell_time)?;
        if r {
            hi = mid;
            state = end;
        } else {
            lo = mid;
        }
        on_step();
    }
    Ok(ReturnTransition {
        alpha_return: 0.5 * (lo + hi),
        lowest_rolling: hi,
        state,
    })
}

/// The saddle-node prefactor T* of the viscous disk's period near α*, T ≈ T*·δα^(−1/2), from the
/// expansion Q(θ* + δθ) = Q* + ½Q''δθ²: T* = √2 · G(θ*) π / √(−Q''(θ*)), G = (r² + r'²)κ/r²
/// (γ = F = 1). The SI prints it without the √2 (it drops the ½).
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::critical_angle;
/// use rollphase_core::analysis::studies::disk::saddle_node_prefactor;
/// use rollphase_core::geometry::{Body, first_convex_disk};
/// let (disk, _) = first_convex_disk(1, 0.08, 10)?;
/// let ca = critical_angle(&Body::Disk(disk.clone()));
/// assert!(saddle_node_prefactor(&disk, ca.theta, ca.q_second_derivative) > 0.0);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn saddle_node_prefactor(disk: &Disk, theta_star: f64, q_second_derivative: f64) -> f64 {
    let j = disk.jet(theta_star);
    let g = (j.r * j.r + j.r1 * j.r1) * j.curvature() / (j.r * j.r);
    2f64.sqrt() * g * std::f64::consts::PI / (-q_second_derivative).sqrt()
}

/// The viscous disk's transition at α* measured ([`saddle_node_law`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SaddleNodeLaw {
    /// α* (rad).
    pub alpha_star: f64,
    /// β of T(δα) − T(2δα) ∝ δα^(−β) on δα = 1e-8…1e-5 (the differences cancel T's regular
    /// part; expect ½).
    pub exponent: f64,
    /// Its standard error.
    pub exponent_stderr: f64,
    /// The slope of a plain log–log fit of 2π/T on the same δα (biased by the regular part).
    pub exponent_naive: f64,
    /// T* measured: (T(1e-8) − T(1e-6)) / (1e4 − 1e3).
    pub t_star_measured: f64,
    /// T* from [`saddle_node_prefactor`].
    pub t_star_analytic: f64,
    /// (α, 2π/T) on the given α grid plus seven points just above α*, ascending.
    pub speeds: Vec<(f64, f64)>,
    /// (δα, 2π/T) at 25 δα from 1e-8 to 1e-2 above α*.
    pub near: Vec<(f64, f64)>,
}

/// Why [`saddle_node_law`] failed.
#[derive(Debug, thiserror::Error)]
pub enum SaddleNodeError {
    /// A bad α on the grid.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// Too few finite periods to fit a power law.
    #[error("no power-law fit: too few finite periods just above α*")]
    NoFit,
}

/// 2π/T of the viscous `disk` (by quadrature) over `alphas` and just above its α*, the exponent
/// of the √δα law fitted on period differences (and naively), and the prefactor T* measured and
/// analytic: one disk of paper Fig. 2d.
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::studies::disk::saddle_node_law;
/// use rollphase_core::geometry::first_convex_disk;
/// let (disk, _) = first_convex_disk(1, 0.08, 10)?;
/// let law = saddle_node_law(&disk, &[0.1, 0.3])?;
/// // The square-root law, and the prefactor with the √2 the SI drops.
/// assert!((law.exponent - 0.5).abs() < 1e-3);
/// assert!((law.t_star_measured / law.t_star_analytic - 1.0).abs() < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn saddle_node_law(disk: &Disk, alphas: &[f64]) -> Result<SaddleNodeLaw, SaddleNodeError> {
    let ca = critical_angle(&Body::Disk(disk.clone()));
    let speed = |a: f64| -> Result<f64, ModelError> {
        Ok(viscous_disk_period_with(disk, &Ramp::new(a, 0.0)?, &ca).mean_angular_speed)
    };
    let mut grid: Vec<f64> = alphas.to_vec();
    grid.extend(
        [1e-6, 1e-5, 1e-4, 4e-4, 1e-3, 2e-3, 4e-3]
            .iter()
            .map(|d| ca.alpha_star + d),
    );
    grid.sort_by(f64::total_cmp);
    let speeds = grid
        .iter()
        .map(|&a| Ok((a, speed(a)?)))
        .collect::<Result<Vec<_>, ModelError>>()?;
    let period = |da: f64| -> Result<f64, ModelError> {
        Ok(
            viscous_disk_period_with(disk, &Ramp::new(ca.alpha_star + da, 0.0)?, &ca)
                .period
                .unwrap_or(f64::NAN),
        )
    };
    let periods: Vec<(f64, f64, f64)> = logspace(1e-8, 1e-5, 7)
        .iter()
        .map(|&da| Ok((da, period(da)?, period(2.0 * da)?)))
        .collect::<Result<_, ModelError>>()?;
    let naive: Vec<(f64, f64)> = periods
        .iter()
        .map(|&(da, t, _)| (da, std::f64::consts::TAU / t))
        .collect();
    let diffs: Vec<(f64, f64)> = periods.iter().map(|&(da, t1, t2)| (da, t1 - t2)).collect();
    let fit = power_law(&diffs).ok_or(SaddleNodeError::NoFit)?;
    let naive_fit = power_law(&naive).ok_or(SaddleNodeError::NoFit)?;
    let near = logspace(1e-8, 1e-2, 25)
        .into_iter()
        .map(|da| Ok((da, speed(ca.alpha_star + da)?)))
        .collect::<Result<Vec<_>, ModelError>>()?;
    let t_star_measured = (period(1e-8)? - period(1e-6)?) / (1e4 - 1e3);
    Ok(SaddleNodeLaw {
        alpha_star: ca.alpha_star,
        exponent: -fit.slope,
        exponent_stderr: fit.slope_stderr,
        exponent_naive: naive_fit.slope,
        t_star_measured,
        t_star_analytic: saddle_node_prefactor(disk, ca.theta, ca.q_second_derivative),
        speeds,
        near,
    })
}

/// The lag time's law at one m/m0 ([`lag_time_law`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LagLaw {
    /// m/m0 (0: viscous).
    pub mass_ratio: f64,
    /// (δα, t_lag) for each δα given.
    pub lag_times: Vec<(f64, f64)>,
    /// β of t(δα) − t(2δα) ∝ δα^(−β), fitted on the δα ≤ 1e-5 (the differences cancel t_lag's
    /// regular part; expect ½).
    pub exponent: f64,
    /// Its standard error.
    pub exponent_stderr: f64,
}

/// Why [`lag_time_law`] failed.
#[derive(Debug, thiserror::Error)]
pub enum LagLawError {
    /// A bad α or m/m0.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An integration failed.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
    /// The disk had not rolled half a turn by t = 10⁷.
    #[error("m/m0 = {mass_ratio}, δα = {delta}: the disk did not roll away")]
    NeverRolled {
        /// m/m0.
        mass_ratio: f64,
        /// δα.
        delta: f64,
    },
    /// Fewer than two δα ≤ 1e-5 to fit.
    #[error("m/m0 = {0}: no fit")]
    NoFit(f64),
}

/// Paper Fig. 2f: the lag time (released from rest at θ*, until θ − θ* = π; DOP853 at
/// rtol 1e-11) at α* + δα and α* + 2δα for every m/m0 in `masses` and δα in `deltas`, in
/// parallel (two runs per (m/m0, δα) pair; `on_run` is called after each, for a progress bar),
/// and the exponent fitted on the differences.
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::studies::disk::lag_time_law;
/// use rollphase_core::geometry::first_convex_disk;
/// let (disk, _) = first_convex_disk(1, 0.12, 5)?;
/// let laws = lag_time_law(&disk, &[0.0, 2.0], &[1e-8, 1e-7, 1e-6, 1e-5], &|| {})?;
/// // t_lag ∝ δα^(−1/2), whatever the mass: the time is spent at the saddle-node ghost.
/// for law in &laws {
///     assert!((law.exponent - 0.5).abs() < 0.01, "{law:?}");
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn lag_time_law(
    disk: &Disk,
    masses: &[f64],
    deltas: &[f64],
    on_run: &(dyn Fn() + Sync),
) -> Result<Vec<LagLaw>, LagLawError> {
    let ca = critical_angle(&Body::Disk(disk.clone()));
    // Every (mass, δα) pair and its double.
    let jobs: Vec<(f64, f64)> = masses
        .iter()
        .flat_map(|&m| deltas.iter().flat_map(move |&d| [(m, d), (m, 2.0 * d)]))
        .collect();
    // One task per run: their costs differ by orders of magnitude.
    let times: Vec<Result<f64, LagLawError>> = (0..jobs.len())
        .into_par_iter()
        .with_max_len(1)
        .map(|k| {
            let (m, d) = jobs[k];
            let ramp = Ramp::new(ca.alpha_star + d, m)?;
            let t = lag_time(disk, &ramp, ca.theta, std::f64::consts::PI, 1e-11, 1e7)?.ok_or(
                LagLawError::NeverRolled {
                    mass_ratio: m,
                    delta: d,
                },
            );
            on_run();
            t
        })
        .collect();
    let times: Vec<f64> = times.into_iter().collect::<Result<_, _>>()?;
    masses
        .iter()
        .enumerate()
        .map(|(mi, &m)| {
            let mut diffs = Vec::new();
            let mut lag_times = Vec::new();
            for (di, &d) in deltas.iter().enumerate() {
                let k = 2 * (mi * deltas.len() + di);
                let (t1, t2) = (times[k], times[k + 1]);
                lag_times.push((d, t1));
                if d <= 1e-5 {
                    diffs.push((d, t1 - t2));
                }
            }
            let fit = power_law(&diffs).ok_or(LagLawError::NoFit(m))?;
            Ok(LagLaw {
                mass_ratio: m,
                lag_times,
                exponent: -fit.slope,
                exponent_stderr: fit.slope_stderr,
            })
        })
        .collect()
}
