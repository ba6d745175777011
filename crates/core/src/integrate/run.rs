//! The one stepping loop: a [`Run`] owns the stepper of one trajectory, and [`Run::until`] steps
//! it towards a time, handing each accepted step to an observer. Every analysis, `simulate`, the
//! app's live run and Python step a model here and nowhere else (DynamicalSystems.jl builds its
//! analyses on one trajectory integrator in the same way).
//!
//! Observers see the stepper after each step, its interpolant covering the last step, and may
//! end the run ([`Flow::Stop`]) or fail it; they never move it: what they read (dense output,
//! the state) does not change the steps taken, so a run that records, watches the contact force
//! or looks for section crossings is bit-identical to one that does not. The parts observers are
//! made of are here ([`Samples`]: states at given times from the dense output) and beside it:
//! section crossings in [`super::events`], the contact-force watch in
//! [`crate::dynamics::validity`], the rest test in [`crate::analysis::verdict`].

use std::sync::atomic::{AtomicU64, Ordering};

use super::{Advance, IntegrateError, Method, OdeSystem, Stats, Stepper, stepper};

/// Runs started in this process (every [`Run`] counts once): how many trajectories a command
/// integrates, for `bench speed` (a relaxed counter: it never orders or moves a run).
static RUNS_STARTED: AtomicU64 = AtomicU64::new(0);

/// How many [`Run`]s this process has started so far.
///
/// # Example
/// ```
/// use rollphase_core::integrate::run::{Run, runs_started};
/// use rollphase_core::integrate::{Method, OdeSystem};
/// struct Still;
/// impl OdeSystem<1> for Still {
///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
///         [0.0]
///     }
/// }
/// let before = runs_started();
/// let _run = Run::new(&Still, 0.0, [1.0], Method::dop853(1e-9))?;
/// assert!(runs_started() > before);
/// # Ok::<(), rollphase_core::integrate::IntegrateError>(())
/// ```
pub fn runs_started() -> u64 {
    RUNS_STARTED.load(Ordering::Relaxed)
}

/// What an observer tells the run after a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Take the next step.
    Continue,
    /// End the run here (the observer has what it needs).
    Stop,
}

/// One trajectory being stepped: the stepper for its method, from its start.
pub struct Run<'a, const N: usize> {
    stepper: Box<dyn Advance<N> + 'a>,
}

impl<'a, const N: usize> Run<'a, N> {
    /// A run of `system` from (t0, y0) with `method` (checked: a bad tolerance or step, or a
    /// non-finite start, is an error before any step).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Decay;
    /// impl OdeSystem<1> for Decay {
    ///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
    ///         [-y[0]]
    ///     }
    /// }
    /// let mut run = Run::new(&Decay, 0.0, [1.0], Method::dop853(1e-12))?;
    /// run.until::<IntegrateError>(1.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// assert!((run.y()[0] - (-1.0f64).exp()).abs() < 1e-11);
    /// assert!(Run::new(&Decay, 0.0, [f64::NAN], Method::dop853(1e-12)).is_err());
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn new<S: OdeSystem<N>>(
        system: &'a S,
        t0: f64,
        y0: [f64; N],
        method: Method,
    ) -> Result<Self, IntegrateError> {
        let stepper = stepper(system, t0, y0, method)?;
        RUNS_STARTED.fetch_add(1, Ordering::Relaxed);
        Ok(Run { stepper })
    }

    /// The run `detached` was put down from ([`Self::detach`]), taken up again on `system`: it
    /// continues bit for bit as if it had never stopped (the same steps, the same interpolant
    /// of the last step). `None` when `detached` is of another state size. Not a new run: it
    /// does not count in [`runs_started`].
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Decay;
    /// impl OdeSystem<1> for Decay {
    ///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
    ///         [-y[0]]
    ///     }
    /// }
    /// // One run to t = 3 against one put down after every step and taken up again.
    /// let mut whole = Run::new(&Decay, 0.0, [1.0], Method::dop853(1e-9))?;
    /// whole.until::<IntegrateError>(3.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// let mut put_down = Run::new(&Decay, 0.0, [1.0], Method::dop853(1e-9))?.detach();
    /// while put_down.t() < 3.0 {
    ///     let mut run = Run::resume(&Decay, &put_down).unwrap();
    ///     run.until::<IntegrateError>(3.0, u64::MAX, |_| Ok(Flow::Stop))?;
    ///     put_down = run.detach();
    /// }
    /// let last = Run::resume(&Decay, &put_down).unwrap();
    /// assert_eq!((last.t(), last.y()), (whole.t(), whole.y()));
    /// assert_eq!(last.stats(), whole.stats());
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn resume<S: OdeSystem<N>>(system: &'a S, detached: &super::Detached) -> Option<Self> {
        Some(Run {
            stepper: super::attach(system, detached)?,
        })
    }

    /// Puts the run down ([`super::Detached`]), to be taken up again by [`Self::resume`].
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Line;
    /// impl OdeSystem<1> for Line {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [1.0]
    ///     }
    /// }
    /// let mut run = Run::new(&Line, 0.0, [0.0], Method::dop853(1e-9))?;
    /// run.until::<IntegrateError>(2.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// let again = Run::resume(&Line, &run.detach()).unwrap();
    /// assert_eq!((again.t(), again.y(), again.stats()), (run.t(), run.y(), run.stats()));
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn detach(&self) -> super::Detached {
        self.stepper.detach()
    }

    /// The state at `t` within the last step, from its interpolant (`t` in
    /// [[`Self::t_prev`], [`Self::t`]]); at the start, before any step, the start.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Line;
    /// impl OdeSystem<1> for Line {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [2.0]
    ///     }
    /// }
    /// let mut run = Run::new(&Line, 0.0, [0.0], Method::Rk4 { dt: 0.5 })?;
    /// assert_eq!(run.dense(0.3), [0.0]);
    /// run.until::<IntegrateError>(1.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// assert_eq!(run.t_prev(), 0.5);
    /// assert!((run.dense(0.75)[0] - 1.5).abs() < 1e-15);
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn dense(&mut self, t: f64) -> [f64; N] {
        if self.stepper.stats().steps == 0 {
            return *self.stepper.y();
        }
        self.stepper.dense(t)
    }

    /// Where the last step began (see [`Self::dense`]'s example).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Still;
    /// impl OdeSystem<1> for Still {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [0.0]
    ///     }
    /// }
    /// let mut run = Run::new(&Still, 0.0, [1.0], Method::Rk4 { dt: 0.25 })?;
    /// run.until::<IntegrateError>(1.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// assert_eq!((run.t_prev(), run.t()), (0.75, 1.0));
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn t_prev(&self) -> f64 {
        self.stepper.t_prev()
    }

    /// Steps towards `t_end` (never past it) within `max_steps` more accepted steps (`u64::MAX`:
    /// no bound beyond the method's own), calling `observe` after each step. Returns
    /// [`Flow::Stop`] if the observer ended the run, [`Flow::Continue`] if it reached `t_end`.
    /// More steps than allowed is [`IntegrateError::TooManySteps`], never a silent stop.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Decay;
    /// impl OdeSystem<1> for Decay {
    ///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
    ///         [-y[0]]
    ///     }
    /// }
    /// // Stop once y has halved: near t = ln 2, at the end of the step that got there.
    /// let mut run = Run::new(&Decay, 0.0, [1.0], Method::Rk4 { dt: 0.01 })?;
    /// let flow = run.until::<IntegrateError>(10.0, u64::MAX, |st| {
    ///     Ok(if st.y()[0] <= 0.5 { Flow::Stop } else { Flow::Continue })
    /// })?;
    /// assert_eq!(flow, Flow::Stop);
    /// assert!((run.t() - 2f64.ln()).abs() < 0.01);
    /// // A budget of 3 steps to t = 1 is an error.
    /// let mut short = Run::new(&Decay, 0.0, [1.0], Method::Rk4 { dt: 0.1 })?;
    /// let e = short.until::<IntegrateError>(1.0, 3, |_| Ok(Flow::Continue));
    /// assert!(matches!(e, Err(IntegrateError::TooManySteps { .. })));
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn until<E: From<IntegrateError>>(
        &mut self,
        t_end: f64,
        max_steps: u64,
        observe: impl FnMut(&mut dyn Stepper<N>) -> Result<Flow, E>,
    ) -> Result<Flow, E> {
        drive(self.stepper.as_mut(), t_end, max_steps, observe)
    }

    /// The current time.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Line;
    /// impl OdeSystem<1> for Line {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [1.0]
    ///     }
    /// }
    /// let mut run = Run::new(&Line, 1.0, [0.0], Method::Rk4 { dt: 0.5 })?;
    /// run.until::<IntegrateError>(3.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// assert_eq!((run.t(), run.y()[0]), (3.0, 2.0));
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn t(&self) -> f64 {
        self.stepper.t()
    }

    /// The current state.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Line;
    /// impl OdeSystem<1> for Line {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [1.0]
    ///     }
    /// }
    /// let mut run = Run::new(&Line, 1.0, [0.0], Method::Rk4 { dt: 0.5 })?;
    /// run.until::<IntegrateError>(3.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// assert_eq!((run.t(), run.y()[0]), (3.0, 2.0));
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn y(&self) -> &[f64; N] {
        self.stepper.y()
    }

    /// The work done so far.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Still;
    /// impl OdeSystem<1> for Still {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [0.0]
    ///     }
    /// }
    /// let mut run = Run::new(&Still, 0.0, [1.0], Method::Rk4 { dt: 0.25 })?;
    /// run.until::<IntegrateError>(1.0, u64::MAX, |_| Ok(Flow::Continue))?;
    /// assert_eq!(run.stats().steps, 4);
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn stats(&self) -> Stats {
        self.stepper.stats()
    }
}

/// The loop itself: every accepted step of every run in the program is taken here.
pub(super) fn drive<const N: usize, E: From<IntegrateError>>(
    stepper: &mut dyn Advance<N>,
    t_end: f64,
    max_steps: u64,
    mut observe: impl FnMut(&mut dyn Stepper<N>) -> Result<Flow, E>,
) -> Result<Flow, E> {
    let first = stepper.stats().steps;
    while stepper.t() < t_end {
        if stepper.stats().steps - first >= max_steps {
            return Err(IntegrateError::TooManySteps {
                t: stepper.t(),
                max_steps,
            }
            .into());
        }
        stepper.step(t_end)?;
        if observe(stepper)? == Flow::Stop {
            return Ok(Flow::Stop);
        }
    }
    Ok(Flow::Continue)
}

/// An observer part: the state at each of a list of times (ascending), read from the dense
/// output as the steps pass them, so samples never depend on where the steps fall.
#[derive(Debug, Clone)]
pub struct Samples<'t> {
    times: &'t [f64],
    next: usize,
}

impl<'t> Samples<'t> {
    /// Samples at `times` (ascending).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run, Samples};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem, uniform_times};
    /// struct Decay;
    /// impl OdeSystem<1> for Decay {
    ///     fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
    ///         [-y[0]]
    ///     }
    /// }
    /// let times = uniform_times(0.0, 2.0, 5);
    /// let mut samples = Samples::new(&times);
    /// let mut seen = Vec::new();
    /// let mut run = Run::new(&Decay, 0.0, [1.0], Method::dop853(1e-12))?;
    /// samples.take_at_start(&run, |t, y| seen.push((t, y[0])));
    /// run.until::<IntegrateError>(2.0, u64::MAX, |st| {
    ///     samples.take(st, |t, y| seen.push((t, y[0])));
    ///     Ok(if samples.done() { Flow::Stop } else { Flow::Continue })
    /// })?;
    /// assert_eq!(seen.len(), 5);
    /// assert!(seen.iter().all(|(t, y)| (y - (-t).exp()).abs() < 1e-11));
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn new(times: &'t [f64]) -> Self {
        Samples { times, next: 0 }
    }

    /// Calls `visit(t, y)` for each time not yet taken up to the stepper's current time: the
    /// current state at exactly that time, the dense output before it.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run, Samples};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Line;
    /// impl OdeSystem<1> for Line {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [1.0]
    ///     }
    /// }
    /// let times = [0.25, 0.5, 2.0];
    /// let mut samples = Samples::new(&times);
    /// let mut run = Run::new(&Line, 0.0, [0.0], Method::Rk4 { dt: 0.5 })?;
    /// run.until::<IntegrateError>(1.0, u64::MAX, |st| {
    ///     samples.take(st, |t, y| assert!((y[0] - t).abs() < 1e-12));
    ///     Ok(Flow::Continue)
    /// })?;
    /// // 2.0 lies beyond the run's end: not taken yet.
    /// assert!(!samples.done() && samples.taken() == 2);
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn take<const N: usize>(
        &mut self,
        st: &mut dyn Stepper<N>,
        mut visit: impl FnMut(f64, &[f64; N]),
    ) {
        while self.next < self.times.len() && self.times[self.next] <= st.t() {
            let t = self.times[self.next];
            let y = if t == st.t() { *st.y() } else { st.dense(t) };
            visit(t, &y);
            self.next += 1;
        }
    }

    /// Takes the times at the run's start (before its first step) from its state there, so a
    /// caller never reaches into the run's stepper.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Run, Samples};
    /// use rollphase_core::integrate::{Method, OdeSystem};
    /// struct Still;
    /// impl OdeSystem<1> for Still {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [0.0]
    ///     }
    /// }
    /// let run = Run::new(&Still, 0.0, [7.0], Method::Rk4 { dt: 0.1 })?;
    /// let times = [0.0, 1.0];
    /// let mut samples = Samples::new(&times);
    /// let mut seen = Vec::new();
    /// samples.take_at_start(&run, |t, y| seen.push((t, y[0])));
    /// assert_eq!((seen, samples.taken()), (vec![(0.0, 7.0)], 1));
    /// # Ok::<(), rollphase_core::integrate::IntegrateError>(())
    /// ```
    pub fn take_at_start<const N: usize>(
        &mut self,
        run: &Run<'_, N>,
        mut visit: impl FnMut(f64, &[f64; N]),
    ) {
        while self.next < self.times.len() && self.times[self.next] <= run.t() {
            visit(self.times[self.next], run.y());
            self.next += 1;
        }
    }

    /// Whether every time has been taken.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::{Flow, Run, Samples};
    /// use rollphase_core::integrate::{IntegrateError, Method, OdeSystem};
    /// struct Line;
    /// impl OdeSystem<1> for Line {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1]) -> [f64; 1] {
    ///         [1.0]
    ///     }
    /// }
    /// let times = [0.25, 0.5, 2.0];
    /// let mut samples = Samples::new(&times);
    /// let mut run = Run::new(&Line, 0.0, [0.0], Method::Rk4 { dt: 0.5 })?;
    /// run.until::<IntegrateError>(1.0, u64::MAX, |st| {
    ///     samples.take(st, |t, y| assert!((y[0] - t).abs() < 1e-12));
    ///     Ok(Flow::Continue)
    /// })?;
    /// // 2.0 lies beyond the run's end: not taken yet.
    /// assert!(!samples.done() && samples.taken() == 2);
    /// # Ok::<(), IntegrateError>(())
    /// ```
    pub fn done(&self) -> bool {
        self.next == self.times.len()
    }

    /// How many times have been taken.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::run::Samples;
    /// assert_eq!(Samples::new(&[0.0, 1.0]).taken(), 0);
    /// ```
    pub fn taken(&self) -> usize {
        self.next
    }
}
