//! Event location on dense output: the times where a scalar function g(t, y(t)) changes sign.
//!
//! After each accepted step g is evaluated at the step's end and at interior points of the
//! interpolant (so that a double crossing inside one step is not missed), and each bracketed
//! root is refined with Brent's method on t ↦ g(t, dense(t)) to a time tolerance of
//! 1e-13·max(1, |t|). The error of a located event is therefore the interpolant's error, not the
//! step length.

use super::run::{Flow, Run};
use super::{IntegrateError, Stepper};
use crate::numeric::roots::brent;

/// Which sign changes count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// g goes from negative to positive.
    Rising,
    /// g goes from positive to negative.
    Falling,
    /// Either.
    Both,
}

/// Interior probes per step in addition to the end point.
const PROBES: usize = 3;

/// Finds the crossings of `g` in the step just taken by `stepper` (from `t_prev` to `t`), in
/// time order, appending their times to `out`.
///
/// # Example
/// ```
/// use rollphase_core::integrate::events::{Direction, crossings_in_last_step};
/// use rollphase_core::integrate::run::{Flow, Run};
/// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
/// // The oscillator y'' = −y from (0, 1): y = sin t rises through 0 at t = 2π.
/// struct Oscillator;
/// impl OdeSystem<2> for Oscillator {
///     fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
///         [y[1], -y[0]]
///     }
/// }
/// let mut run = Run::new(&Oscillator, 0.0, [0.0, 1.0], Method::dop853(1e-12))?;
/// let mut rising = Vec::new();
/// run.until::<IntegrateError>(7.0, u64::MAX, |st| {
///     crossings_in_last_step(st, &|_t, y: &[f64; 2]| y[0], Direction::Rising, &mut rising);
///     Ok(Flow::Continue)
/// })?;
/// assert_eq!(rising.len(), 1);
/// assert!((rising[0] - std::f64::consts::TAU).abs() < 1e-10);
/// # Ok::<(), rollphase_core::integrate::IntegrateError>(())
/// ```
pub fn crossings_in_last_step<const N: usize>(
    stepper: &mut dyn Stepper<N>,
    g: &impl Fn(f64, &[f64; N]) -> f64,
    direction: Direction,
    out: &mut Vec<f64>,
) {
    let t0 = stepper.t_prev();
    let t1 = stepper.t();
    if t1 <= t0 {
        return;
    }
    let mut ta = t0;
    let mut ga = g(t0, stepper.y_prev());
    for j in 1..=PROBES + 1 {
        let tb = if j == PROBES + 1 {
            t1
        } else {
            t0 + (t1 - t0) * j as f64 / (PROBES + 1) as f64
        };
        let gb = if j == PROBES + 1 {
            g(t1, stepper.y())
        } else {
            let y = stepper.dense(tb);
            g(tb, &y)
        };
        let rising = ga < 0.0 && gb >= 0.0;
        let falling = ga > 0.0 && gb <= 0.0;
        let wanted = match direction {
            Direction::Rising => rising,
            Direction::Falling => falling,
            Direction::Both => rising || falling,
        };
        if wanted {
            let root = brent(
                |t| {
                    let y = stepper.dense(t);
                    g(t, &y)
                },
                ta,
                tb,
                ga,
                gb,
                1e-13 * tb.abs().max(1.0),
            );
            out.push(root);
        }
        ta = tb;
        ga = gb;
    }
}

/// Times in the last step where state component `slot` rises through `*next_target`, then
/// `*next_target + step`, …: used to time whole turns of an angle (θ passing θ₀ + 2πk).
/// Advances `*next_target` past every crossing found.
///
/// # Example
/// ```
/// use rollphase_core::integrate::events::turns_in_last_step;
/// use rollphase_core::integrate::run::{Flow, Run};
/// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
/// // θ' = 1: whole turns at t = 2π, 4π.
/// struct Spin;
/// impl OdeSystem<1> for Spin {
///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
///         [1.0]
///     }
/// }
/// let tau = std::f64::consts::TAU;
/// let mut run = Run::new(&Spin, 0.0, [0.0], Method::dop853(1e-12))?;
/// let (mut next, mut turns) = (tau, Vec::new());
/// run.until::<IntegrateError>(13.0, u64::MAX, |st| {
///     turns_in_last_step(st, 0, &mut next, tau, &mut turns);
///     Ok(Flow::Continue)
/// })?;
/// assert_eq!(turns.len(), 2);
/// assert!((turns[1] - 2.0 * tau).abs() < 1e-9 && (next - 3.0 * tau).abs() < 1e-12);
/// # Ok::<(), rollphase_core::integrate::IntegrateError>(())
/// ```
pub fn turns_in_last_step<const N: usize>(
    stepper: &mut dyn Stepper<N>,
    slot: usize,
    next_target: &mut f64,
    step: f64,
    out: &mut Vec<f64>,
) {
    while stepper.y()[slot] >= *next_target {
        let target = *next_target;
        let mut found = Vec::new();
        crossings_in_last_step(
            stepper,
            &|_t, y: &[f64; N]| y[slot] - target,
            Direction::Rising,
            &mut found,
        );
        // A crossing exactly at the step's start belongs to the previous step's bracket; fall
        // back to the step end only if the locator saw none (a tangency at the target).
        out.push(found.last().copied().unwrap_or(stepper.t()));
        *next_target += step;
    }
}

/// Steps `run` until `t_end` or until `stop(events_so_far)` says so, collecting crossings.
///
/// # Example
/// ```
/// use rollphase_core::integrate::events::{Direction, integrate_collecting};
/// use rollphase_core::integrate::run::Run;
/// use rollphase_core::integrate::{Method, OdeSystem};
/// struct Oscillator;
/// impl OdeSystem<2> for Oscillator {
///     fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
///         [y[1], -y[0]]
///     }
/// }
/// // Zeros of sin t in either direction, stopping at the third: π, 2π, 3π.
/// let mut run = Run::new(&Oscillator, 0.0, [0.0, 1.0], Method::dop853(1e-12))?;
/// let zeros = integrate_collecting(&mut run, 100.0, 100_000, &|_t, y: &[f64; 2]| y[0], Direction::Both, |e| e.len() >= 3)?;
/// assert_eq!(zeros.len(), 3);
/// assert!((zeros[2] - 3.0 * std::f64::consts::PI).abs() < 1e-10 && run.t() < 100.0);
/// # Ok::<(), rollphase_core::integrate::IntegrateError>(())
/// ```
pub fn integrate_collecting<const N: usize>(
    run: &mut Run<'_, N>,
    t_end: f64,
    max_steps: u64,
    g: &impl Fn(f64, &[f64; N]) -> f64,
    direction: Direction,
    mut stop: impl FnMut(&[f64]) -> bool,
) -> Result<Vec<f64>, IntegrateError> {
    let mut events = Vec::new();
    run.until::<IntegrateError>(t_end, max_steps, |st| {
        let before = events.len();
        crossings_in_last_step(st, g, direction, &mut events);
        Ok(if events.len() > before && stop(&events) {
            Flow::Stop
        } else {
            Flow::Continue
        })
    })?;
    Ok(events)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_cubic_root() {
        let f = |x: f64| x * x * x - 2.0;
        let r = brent(f, 0.0, 2.0, f(0.0), f(2.0), 1e-15);
        assert!((r - 2f64.cbrt()).abs() < 1e-14, "{r}");
    }
}
