//! A disk's period as `rollphase period` and Python's `period` answer it: the model chosen as
//! `simulate` chooses it ([`choose_model`]: the viscous limit at m/m0 ≤ rtol), the viscous
//! quadrature or the inertial run ([`crate::analysis::orbits::disk_period`]), and the verdict's
//! fate, from which a period is reported only when it is periodic (a period still changing when
//! the run ends is a transient). The one home of that sequence: the surfaces parse, check the
//! start, and print around it.

use std::sync::atomic::AtomicBool;

use thiserror::Error;

use super::{RunError, choose_model};
use crate::analysis::orbits::disk_period::{
    inertial_disk_period_until, inertial_on_hull, viscous_disk_period,
};
use crate::analysis::verdict::Fate;
use crate::dynamics::{ModelKind, Ramp};
use crate::geometry::{Body, Disk};
use crate::integrate::{IntegrateError, Method};

/// Why a period cannot be asked for.
#[derive(Debug, Error)]
pub enum PeriodError {
    /// The body is a sphere: its orbits are found by simulation.
    #[error(
        "the body is a 3D sphere; a period is for disks (a sphere's orbits are found by simulation)"
    )]
    NotADisk,
    /// The model could not be chosen (bad α, m/m0, drag or integrator).
    #[error(transparent)]
    Run(#[from] RunError),
    /// An inertial period on a body that rolls on its hull (a dented body, a print's sides):
    /// the period run steps the smooth equations alone. Says what to do instead.
    #[error("{0}")]
    OnHull(String),
    /// The inertial run failed.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
}

/// The model and ramp a period is computed with, chosen before the run (a surface warns of a
/// slow stiff run between the two).
#[derive(Debug, Clone)]
pub struct PeriodPlan {
    disk: Disk,
    /// The ramp simulated (m/m0 set to 0 where the viscous limit is taken).
    pub ramp: Ramp,
    /// disk-viscous or disk-inertial.
    pub model: ModelKind,
    /// Why the model differs from the one asked for, if it does.
    pub note: Option<String>,
    /// α* of the disk (rad).
    pub alpha_star: f64,
    rtol: f64,
}

/// A disk's period, decided.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodAnswer {
    /// The run's fate: periodic, halted, or undecided with why.
    pub fate: Fate,
    /// T, the time for θ to advance 2π: only when the fate is periodic.
    pub period: Option<f64>,
    /// 2π/T when periodic, 0 when halted; `None` when undecided (neither is known).
    pub mean_angular_speed: Option<f64>,
    /// Whether the number is converged (quadrature error ≤ 1e-9, or periodic to 1e-8).
    pub converged: bool,
    /// The relative error of T (viscous: the quadrature's and α*'s rounding), else NaN.
    pub relative_error: f64,
    /// Said with a periodic T that is not known to 1e-9 (a viscous period this close to α*):
    /// how well it is known, for every surface to say beside the number.
    pub caveat: Option<String>,
}

impl PeriodPlan {
    /// The plan for `body` on `ramp`, the inertial run at DOP853 `rtol`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::period::PeriodPlan;
    /// // m/m0 = 1e-12 is below rtol: the viscous limit, said in the note.
    /// let plan = PeriodPlan::new(&Body::paper_disk(84, 0.12, 5)?, Ramp::new(0.3, 1e-12)?, 1e-10)?;
    /// assert_eq!(plan.model, ModelKind::DiskViscous);
    /// assert!(plan.note.is_some());
    /// // A tolerance that is no tolerance is refused, viscous or not.
    /// assert!(PeriodPlan::new(&Body::paper_disk(84, 0.12, 5)?, Ramp::new(0.3, 0.0)?, f64::NAN).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(body: &Body, ramp: Ramp, rtol: f64) -> Result<Self, PeriodError> {
        let Body::Disk(disk) = body else {
            return Err(PeriodError::NotADisk);
        };
        // Checked whatever the model: the viscous quadrature does not use it, but `--rtol nan`
        // was accepted there and refused with inertia (a helper found it, 2026-12-02).
        Method::dop853(rtol).validate()?;
        let choice = choose_model(body, ramp, Method::dop853(rtol))?;
        let model = ModelKind::of(body, &choice.ramp);
        if model.is_inertial()
            && let Some(why) = inertial_on_hull(disk)
        {
            return Err(PeriodError::OnHull(why));
        }
        Ok(Self {
            disk: disk.clone(),
            ramp: choice.ramp,
            model,
            note: choice.note,
            alpha_star: body.alpha_star(),
            rtol,
        })
    }

    /// The period from (θ₀, θ̇₀) (the inertial run's start; the viscous period does not depend
    /// on it), the inertial run at most `t_max` long; `Ok(None)` once `stop` is set.
    ///
    /// # Example
    /// ```
    /// use std::sync::atomic::AtomicBool;
    /// use rollphase_core::analysis::verdict::Fate;
    /// use rollphase_core::dynamics::Ramp;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::period::PeriodPlan;
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// let never = AtomicBool::new(false);
    /// let rolls = PeriodPlan::new(&disk, Ramp::new(0.3, 0.0)?, 1e-10)?.run(0.0, 0.0, 5000.0, &never)?.unwrap();
    /// assert_eq!(rolls.fate, Fate::Periodic { multiplicity: 1 });
    /// assert!(rolls.period.unwrap() > 0.0);
    /// let rests = PeriodPlan::new(&disk, Ramp::new(0.02, 0.0)?, 1e-10)?.run(0.0, 0.0, 5000.0, &never)?.unwrap();
    /// assert!(matches!(rests.fate, Fate::Halted { .. }) && rests.period.is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn run(
        &self,
        theta0: f64,
        theta_dot0: f64,
        t_max: f64,
        stop: &AtomicBool,
    ) -> Result<Option<PeriodAnswer>, PeriodError> {
        let p = if self.model.is_inertial() {
            let run = inertial_disk_period_until(
                &self.disk, &self.ramp, theta0, theta_dot0, self.rtol, t_max, stop,
            )?;
            match run {
                Some(p) => p,
                None => return Ok(None),
            }
        } else {
            viscous_disk_period(&self.disk, &self.ramp)
        };
        let fate = p.fate(self.ramp.alpha_rad - self.alpha_star, t_max);
        let period = p.period.filter(|_| matches!(fate, Fate::Periodic { .. }));
        let caveat = (period.is_some() && !p.converged).then(|| {
            format!(
                "T is known to {:.1e} of itself: this close to α* the rounding of α − α* (α* is \
                 found to a few ulps) and of 1/θ̇ limits it",
                p.relative_error
            )
        });
        Ok(Some(PeriodAnswer {
            fate,
            period,
            mean_angular_speed: match fate {
                Fate::Periodic { .. } => period.map(|_| p.mean_angular_speed),
                Fate::Halted { .. } => Some(0.0),
                _ => None,
            },
            converged: p.converged,
            relative_error: p.relative_error,
            caveat,
        }))
    }
}
