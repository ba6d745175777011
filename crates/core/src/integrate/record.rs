//! Recording the states a run evaluates, so a right-hand side can be timed on exactly the
//! sequence a real run feeds it (`bench speed`, `benches/core.rs`). Repeating one state would
//! let a model's warm-started inner solvers (the 3D contact Newton) converge in one iteration
//! and flatter the figure several times over.

use std::cell::RefCell;

use super::run::{Flow, drive};
use super::{IntegrateError, Method, OdeSystem, stepper};

/// Wraps a system and keeps every state its right-hand side is called with.
pub struct Recorder<'a, S, const N: usize> {
    system: &'a S,
    states: RefCell<Vec<[f64; N]>>,
}

impl<S: OdeSystem<N>, const N: usize> OdeSystem<N> for Recorder<'_, S, N> {
    fn rhs(&self, t: f64, y: &[f64; N]) -> [f64; N] {
        self.states.borrow_mut().push(*y);
        self.system.rhs(t, y)
    }

    fn quaternion_slot(&self) -> Option<usize> {
        self.system.quaternion_slot()
    }
}

/// The states, in order, at which a run of `method` from (0, `y0`) to `t_end` evaluates the
/// right-hand side of `system`.
///
/// # Example
/// ```
/// use rollphase_core::integrate::record::recorded_states;
/// use rollphase_core::integrate::{Method, OdeSystem};
/// struct Decay;
/// impl OdeSystem<1> for Decay {
///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
///         [-y[0]]
///     }
/// }
/// // RK4 evaluates four times a step: 10 steps, 40 states (plus its step-doubling checks).
/// let states = recorded_states(&Decay, [1.0], 1.0, Method::Rk4 { dt: 0.1 })?;
/// assert!(states.len() >= 40 && states[0] == [1.0]);
/// # Ok::<(), rollphase_core::integrate::IntegrateError>(())
/// ```
pub fn recorded_states<S: OdeSystem<N>, const N: usize>(
    system: &S,
    y0: [f64; N],
    t_end: f64,
    method: Method,
) -> Result<Vec<[f64; N]>, IntegrateError> {
    let recorder = Recorder {
        system,
        states: RefCell::new(Vec::new()),
    };
    {
        // The run's own stepper and loop, but not a `Run`: a recording is not a trajectory a
        // command integrates, so it stays out of `runs_started`.
        let mut st = stepper(&recorder, 0.0, y0, method)?;
        drive::<N, IntegrateError>(&mut *st, t_end, u64::MAX, |_| Ok(Flow::Continue))?;
    }
    Ok(recorder.states.into_inner())
}

/// Evaluates the right-hand side at each state in order; returns a sum of the results so that
/// the work cannot be optimised away.
///
/// # Example
/// ```
/// use rollphase_core::integrate::OdeSystem;
/// use rollphase_core::integrate::record::replay;
/// struct Decay;
/// impl OdeSystem<1> for Decay {
///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
///         [-y[0]]
///     }
/// }
/// assert_eq!(replay(&Decay, &[[1.0], [2.0]]), -3.0);
/// ```
pub fn replay<S: OdeSystem<N>, const N: usize>(system: &S, states: &[[f64; N]]) -> f64 {
    states.iter().map(|y| system.rhs(0.0, y)[0]).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Decay;
    impl OdeSystem<1> for Decay {
        fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
            [-y[0]]
        }
    }

    #[test]
    fn records_every_evaluation_of_a_run() {
        let states = recorded_states(&Decay, [1.0], 1.0, Method::Rk4 { dt: 0.25 }).expect("runs");
        // The stepper's first evaluation at y0 (kept for dense output), four RK4 steps of four
        // stages each, and the first step's check by step doubling (two half steps: 3 + 1 + 3).
        assert_eq!(states.len(), 1 + 4 * 4 + 7);
        assert_eq!(states[0], [1.0]);
        assert!(states.iter().all(|y| y[0] > 0.0 && y[0] <= 1.0));
        let sum = replay(&Decay, &states);
        assert!((sum + states.iter().map(|y| y[0]).sum::<f64>()).abs() < 1e-15);
    }
}
