//! A general parameter scan of 3D rolling: bodies × α × m/m0 × initial orientations ×
//! integrators, each run released from rest and followed until its fate is known
//! ([`settle_checked`]: it halts, closes a cycle, or is still undecided at `t_max`; a fate found
//! with a setting coarser than the reference is re-decided by the reference, so a scan's
//! answers do not depend on the integrator picked for speed). `rollphase
//! sweep SPEC.toml` reads a spec into a [`Scan`], shards it and writes one CSV row per run;
//! a library caller builds the [`Scan`] directly and calls [`Scan::run_all`].
//!
//! Runs are numbered body-major, integrator fastest ([`Scan::point`]), so run k is the same
//! run whatever the shard or thread count.

use crate::dynamics::validity::ContactReport;
use rayon::prelude::*;

use crate::analysis::orbits::sphere_orbits::{AnswerCheck, Settle, Settlement, settle_checked};
use crate::analysis::studies::sphere::{cruises, random_orientation};
use crate::analysis::verdict::Fate;
use crate::dynamics::{ModelError, Ramp};
use crate::geometry::Sphere;
use crate::integrate::{IntegrateError, Method};

/// The grid of a scan.
#[derive(Debug, Clone)]
pub struct Scan {
    /// The bodies (strictly convex).
    pub bodies: Vec<Sphere>,
    /// Ramp angles α (rad).
    pub alphas: Vec<f64>,
    /// Mass ratios m/m0 (0: viscous).
    pub masses: Vec<f64>,
    /// Orientations per (body, α, m/m0): orientation o is
    /// [`random_orientation`]`(body, orientation_seed, o)`, the one the figures use.
    pub orientations: usize,
    /// The seed of the orientations.
    pub orientation_seed: u64,
    /// The integrators each run is repeated with.
    pub methods: Vec<Method>,
    /// When a run's fate is decided.
    pub settle: Settle,
}

/// Where run k sits in the grid: an index into each axis of its [`Scan`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ScanPoint {
    /// Into [`Scan::bodies`].
    pub body: usize,
    /// Into [`Scan::alphas`].
    pub alpha: usize,
    /// Into [`Scan::masses`].
    pub mass: usize,
    /// The orientation.
    pub orientation: usize,
    /// Into [`Scan::methods`].
    pub method: usize,
}

/// One run's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanRun {
    /// Its fate (the reference integrator's: see [`ScanRun::check`]).
    pub fate: Settlement,
    /// Whether the run's own integrator gave the same fate.
    pub check: AnswerCheck,
    /// Right-hand-side evaluations it took.
    pub rhs_evals: u64,
    /// The contact force along it: whether the body stays on the ramp and the friction it
    /// needs ([`Settled::contact`](crate::analysis::orbits::sphere_orbits::Settled)).
    pub contact: ContactReport,
}

impl ScanRun {
    /// Cruises: closed a cycle on the ramp ([`cruises`]); an undecided run is not counted.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::studies::sweep::ScanRun;
    /// use rollphase_core::analysis::orbits::sphere_orbits::{AnswerCheck, Settlement};
    /// use rollphase_core::dynamics::{ContactForce, validity::{ContactLimits, ContactWatch}};
    /// let contact = ContactWatch::new(ContactLimits::default(), 0.0, ContactForce::viscous(0.1)).report();
    /// let run = ScanRun { fate: Settlement::Halts { t: 3.0 }, check: AnswerCheck::Reference, rhs_evals: 10, contact };
    /// assert!(!run.cruises());
    /// ```
    pub fn cruises(&self) -> bool {
        // A body that left the ramp does not roll on it.
        !self.left_model() && cruises(&self.fate)
    }

    /// Whether the body left the ramp (or slipped) during the run: then no period, rest or
    /// cruising is claimed for the model's motion past it.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::studies::sweep::ScanRun;
    /// use rollphase_core::analysis::orbits::sphere_orbits::{AnswerCheck, Settlement};
    /// use rollphase_core::dynamics::{ContactForce, validity::{ContactLimits, ContactWatch}};
    /// let mut contact = ContactWatch::new(ContactLimits::default(), 0.0, ContactForce::viscous(0.1)).report();
    /// let run = |contact| ScanRun { fate: Settlement::Halts { t: 3.0 }, check: AnswerCheck::Reference, rhs_evals: 10, contact };
    /// assert!(!run(contact).left_model());
    /// contact.lift_off_t = Some(2.0);
    /// assert!(run(contact).left_model());
    /// ```
    pub fn left_model(&self) -> bool {
        !self.contact.violations().is_empty()
    }

    /// The run's fate ([`Settlement::fate`]), the contact force's verdict first: a body that
    /// left the ramp is [`Fate::LeftModel`] (the model's motion past a lift-off is not one the
    /// body can make, so no period or rest is claimed for it). Its [`Fate::name`] is the word
    /// the sweep CSV writes.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::studies::sweep::ScanRun;
    /// use rollphase_core::analysis::orbits::sphere_orbits::{AnswerCheck, Settle, Settlement};
    /// use rollphase_core::dynamics::{ContactForce, validity::{ContactLimits, ContactWatch}};
    /// let mut contact = ContactWatch::new(ContactLimits::default(), 0.0, ContactForce::viscous(0.1)).report();
    /// let fate = Settlement::Periodic { period: 40.0, k: 1, point: [1.0, 0.0, 0.0], t: 400.0 };
    /// let run = ScanRun { fate: fate.clone(), check: AnswerCheck::Reference, rhs_evals: 10, contact };
    /// assert_eq!(run.fate(&Settle::default()).name(), "periodic");
    /// contact.lift_off_t = Some(4.5);
    /// let lifted = ScanRun { fate, check: AnswerCheck::Reference, rhs_evals: 10, contact };
    /// assert_eq!(lifted.fate(&Settle::default()).name(), "left_model");
    /// ```
    pub fn fate(&self, settle: &Settle) -> Fate {
        match self.contact.violations().first() {
            Some(&violation) => Fate::LeftModel { violation },
            None => self.fate.fate(settle),
        }
    }
}

/// The counts of a scan's fates.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ScanTally {
    /// Runs counted.
    pub runs: usize,
    /// Runs that came to rest.
    pub halts: usize,
    /// Runs that closed a cycle.
    pub periodic: usize,
    /// Runs neither at t_max.
    pub undecided: usize,
    /// Runs whose body left the ramp (counted here and in no other fate).
    pub left_model: usize,
    /// Runs that cruise (closed a cycle on the ramp: the periodic ones).
    pub cruising: usize,
    /// Runs whose own integrator's fate the reference corrected.
    pub corrected: usize,
    /// Right-hand-side evaluations, all runs.
    pub rhs_evals: u64,
}

impl ScanTally {
    /// Counts one more run.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::studies::sweep::{ScanRun, ScanTally};
    /// use rollphase_core::analysis::orbits::sphere_orbits::{AnswerCheck, Settlement};
    /// let mut tally = ScanTally::default();
    /// let check = AnswerCheck::Corrected { fast: Settlement::Halts { t: 4.0 } };
    /// # use rollphase_core::dynamics::{ContactForce, validity::{ContactLimits, ContactWatch}};
    /// # let contact = ContactWatch::new(ContactLimits::default(), 0.0, ContactForce::viscous(0.1)).report();
    /// tally.add(&ScanRun { fate: Settlement::Undecided { omega_end: 0.1 }, check, rhs_evals: 40, contact });
    /// tally.add(&ScanRun { fate: Settlement::Halts { t: 9.0 }, check: AnswerCheck::Confirmed, rhs_evals: 2, contact });
    /// assert_eq!((tally.runs, tally.undecided, tally.halts, tally.cruising), (2, 1, 1, 0));
    /// assert_eq!((tally.rhs_evals, tally.corrected), (42, 1));
    /// ```
    pub fn add(&mut self, r: &ScanRun) {
        self.runs += 1;
        let count = match r.fate {
            _ if r.left_model() => &mut self.left_model,
            Settlement::Halts { .. } => &mut self.halts,
            Settlement::Periodic { .. } => &mut self.periodic,
            Settlement::Undecided { .. } => &mut self.undecided,
        };
        *count += 1;
        self.cruising += usize::from(r.cruises());
        self.corrected += usize::from(matches!(r.check, AnswerCheck::Corrected { .. }));
        self.rhs_evals += r.rhs_evals;
    }
}

/// Why a scan could not run.
#[derive(Debug, thiserror::Error)]
pub enum ScanError {
    /// An axis is empty.
    #[error(
        "the scan has no runs: every axis (bodies, alphas, masses, orientations, methods) needs a value"
    )]
    Empty,
    /// A bad α or m/m0.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An integration failed.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
}

impl Scan {
    /// Runs in the scan.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::studies::sweep::Scan;
    /// # use rollphase_core::analysis::orbits::sphere_orbits::Settle;
    /// # use rollphase_core::integrate::Method;
    /// # let sphere = rollphase_core::geometry::random_sphere(1, 0.1, 3)?;
    /// let scan = Scan {
    ///     bodies: vec![sphere],
    ///     alphas: vec![0.3, 0.4],
    ///     masses: vec![0.0, 1.0, 6.0],
    ///     orientations: 5,
    ///     orientation_seed: 1,
    ///     methods: vec![Method::dop853(1e-9)],
    ///     settle: Settle::default(),
    /// };
    /// assert_eq!(scan.runs(), 30);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn runs(&self) -> usize {
        self.bodies.len()
            * self.alphas.len()
            * self.masses.len()
            * self.orientations
            * self.methods.len()
    }

    /// Run k's place in the grid: body-major, method fastest.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::studies::sweep::{Scan, ScanPoint};
    /// # use rollphase_core::analysis::orbits::sphere_orbits::Settle;
    /// # use rollphase_core::integrate::Method;
    /// # let sphere = rollphase_core::geometry::random_sphere(1, 0.1, 3)?;
    /// let scan = Scan {
    ///     bodies: vec![sphere],
    ///     alphas: vec![0.3, 0.4],
    ///     masses: vec![0.0, 1.0],
    ///     orientations: 3,
    ///     orientation_seed: 1,
    ///     methods: vec![Method::dop853(1e-9), Method::Rk4 { dt: 0.01 }],
    ///     settle: Settle::default(),
    /// };
    /// let p = scan.point(7);
    /// assert_eq!((p.alpha, p.mass, p.orientation, p.method), (0, 1, 0, 1));
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn point(&self, k: usize) -> ScanPoint {
        let sizes = [
            self.bodies.len(),
            self.alphas.len(),
            self.masses.len(),
            self.orientations,
            self.methods.len(),
        ];
        let mut out = [0; 5];
        let mut rest = k;
        for d in (0..5).rev() {
            out[d] = rest % sizes[d];
            rest /= sizes[d];
        }
        let [body, alpha, mass, orientation, method] = out;
        ScanPoint {
            body,
            alpha,
            mass,
            orientation,
            method,
        }
    }

    /// Run k: released from rest at its orientation and followed until its fate is decided.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::studies::sweep::Scan;
    /// # use rollphase_core::analysis::orbits::sphere_orbits::{Settlement, Settle};
    /// # use rollphase_core::integrate::Method;
    /// use rollphase_core::geometry::Body;
    /// let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
    /// let scan = Scan {
    ///     bodies: vec![body],
    ///     alphas: vec![0.05],
    ///     masses: vec![0.0],
    ///     orientations: 1,
    ///     orientation_seed: 1,
    ///     methods: vec![Method::dop853(1e-9)],
    ///     settle: Settle { t_max: 2000.0, ..Settle::default() },
    /// };
    /// // Far below α* = 0.139 the paper's body halts from any orientation.
    /// assert!(matches!(scan.run(0)?.fate, Settlement::Halts { .. }));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn run(&self, k: usize) -> Result<ScanRun, ScanError> {
        let p = self.point(k);
        let body = &self.bodies[p.body];
        let ramp = Ramp::new(self.alphas[p.alpha], self.masses[p.mass])?;
        let q0 = random_orientation(body, self.orientation_seed, p.orientation);
        let run = settle_checked(body, &ramp, q0, &self.settle, self.methods[p.method])?;
        Ok(ScanRun {
            fate: run.fate,
            check: run.check,
            rhs_evals: run.stats.rhs_evals,
            contact: run.contact,
        })
    }

    /// Checks, before any run, that the scan has runs and that every (α, m/m0) is a ramp. (A
    /// fixed step too long for a body's drag relaxation is caught by the step's own error
    /// check during the run; `rollphase sweep` also refuses it before the first run, through
    /// `simulate::choose_model`.)
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::studies::sweep::{Scan, ScanError};
    /// # use rollphase_core::analysis::orbits::sphere_orbits::Settle;
    /// # use rollphase_core::integrate::Method;
    /// # let sphere = rollphase_core::geometry::random_sphere(1, 0.1, 3)?;
    /// let scan = Scan {
    ///     bodies: vec![sphere],
    ///     alphas: vec![2.0], // more than π/2
    ///     masses: vec![0.0],
    ///     orientations: 1,
    ///     orientation_seed: 1,
    ///     methods: vec![Method::dop853(1e-9)],
    ///     settle: Settle::default(),
    /// };
    /// assert!(matches!(scan.check(), Err(ScanError::Model(_))));
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn check(&self) -> Result<(), ScanError> {
        if self.runs() == 0 {
            return Err(ScanError::Empty);
        }
        for &alpha in &self.alphas {
            for &mass in &self.masses {
                Ramp::new(alpha, mass)?;
            }
        }
        Ok(())
    }

    /// Every run, in parallel (one task per run: their costs differ by orders of magnitude),
    /// in run order, with their tally; [`Scan::check`]ed first. Holds every result: a scan of
    /// millions of runs streams them with [`Scan::run`] instead, as `rollphase sweep` does.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::studies::sweep::Scan;
    /// # use rollphase_core::analysis::orbits::sphere_orbits::Settle;
    /// # use rollphase_core::integrate::Method;
    /// use rollphase_core::geometry::Body;
    /// let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
    /// let scan = Scan {
    ///     bodies: vec![body],
    ///     alphas: vec![0.05, 0.3],
    ///     masses: vec![0.0],
    ///     orientations: 2,
    ///     orientation_seed: 1,
    ///     methods: vec![Method::dop853(1e-9)],
    ///     settle: Settle { t_max: 2000.0, ..Settle::default() },
    /// };
    /// let (runs, tally) = scan.run_all()?;
    /// assert_eq!(runs.len(), 4);
    /// // Halts below α* = 0.139, rolls on far above it.
    /// assert_eq!((tally.halts, tally.cruising), (2, 2));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn run_all(&self) -> Result<(Vec<ScanRun>, ScanTally), ScanError> {
        self.check()?;
        let runs: Vec<ScanRun> = (0..self.runs())
            .into_par_iter()
            .with_max_len(1)
            .map(|k| self.run(k))
            .collect::<Result<_, _>>()?;
        let mut tally = ScanTally::default();
        for r in &runs {
            tally.add(r);
        }
        Ok((runs, tally))
    }
}
