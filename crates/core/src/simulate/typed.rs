//! The typed face of a run, in the paper's words: choose a [`Model`] (viscous, or inertial with
//! its m/m0), describe the run with a [`Simulation`], and get back a [`Trajectory`] whose
//! columns have names (t, q, contact, ω, centre of mass for a sphere; θ, θ̇, ψ, x, y for a disk)
//! and the run's [`Summary`]; or hand each [`Sample`] to a closure as it is computed
//! ([`simulate_streaming`]).
//!
//! It is a thin layer over [`super::run`], which the command line uses: the same body, start,
//! model and integrator give the same numbers, to the last digit, as `rollphase simulate`.

use glam::{DQuat, DVec3};

use std::sync::atomic::AtomicBool;

use super::{ContactLimits, InitialState, RunError, RunSpec, Summary, run, run_until};
use crate::dynamics::sphere3d::orientation_touching;
use crate::dynamics::{ContactForce, DragLaw, Ramp};
use crate::geometry::Body;
use crate::geometry::sphere::direction;
use crate::integrate::Method;

/// Which of the paper's limits the body rolls in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Model {
    /// No inertia: θ̇ from the torque balance (2D), ω = −r×F/γ (3D).
    Viscous,
    /// With inertia: m/m0 > 0 (a finite, positive mass ratio).
    Inertial {
        /// m/m0.
        mass_ratio: f64,
    },
}

impl Model {
    /// The command line's `--mass` convention: 0 is [`Model::Viscous`], anything else
    /// [`Model::Inertial`] (checked when the run starts).
    ///
    /// ```
    /// use rollphase_core::simulate::Model;
    /// assert_eq!(Model::from_mass_ratio(0.0), Model::Viscous);
    /// assert_eq!(Model::from_mass_ratio(6.0), Model::Inertial { mass_ratio: 6.0 });
    /// ```
    pub fn from_mass_ratio(mass_ratio: f64) -> Self {
        if !crate::dynamics::models::asks_for_inertia(mass_ratio) {
            Model::Viscous
        } else {
            Model::Inertial { mass_ratio }
        }
    }

    /// m/m0: 0 for [`Model::Viscous`].
    ///
    /// # Example
    /// ```
    /// use rollphase_core::simulate::Model;
    /// assert_eq!(Model::Viscous.mass_ratio(), 0.0);
    /// assert_eq!(Model::Inertial { mass_ratio: 6.0 }.mass_ratio(), 6.0);
    /// ```
    pub fn mass_ratio(self) -> f64 {
        match self {
            Model::Viscous => 0.0,
            Model::Inertial { mass_ratio } => mass_ratio,
        }
    }
}

impl InitialState {
    /// The command line's default start, released from rest: a sphere with its south pole (the
    /// body point in direction −z) touching the ramp, a disk at contact angle θ = 0.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::InitialState;
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// assert!(matches!(InitialState::at_rest(&body), InitialState::Sphere { .. }));
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn at_rest(body: &Body) -> Self {
        match body {
            Body::Disk(_) => InitialState::Disk {
                theta0: 0.0,
                theta_dot0: 0.0,
            },
            Body::Sphere(sphere) => InitialState::Sphere {
                q0: orientation_touching(sphere, DVec3::NEG_Z, 0.0),
                omega0: DVec3::ZERO,
            },
        }
    }

    /// A sphere released from rest with its body point at polar angle `theta`, azimuth `phi`
    /// touching the ramp (the shortest rotation that puts it there), then turned by `spin`
    /// radians about the ramp's normal: the command line's `--contact θ,φ --spin s`. `None`
    /// for a disk, or for angles that are not finite.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::InitialState;
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// assert!(InitialState::touching(&body, 1.0, 2.0, 0.5).is_some());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn touching(body: &Body, theta: f64, phi: f64, spin: f64) -> Option<Self> {
        let Body::Sphere(sphere) = body else {
            return None;
        };
        if !(theta.is_finite() && phi.is_finite() && spin.is_finite()) {
            return None;
        }
        Some(InitialState::Sphere {
            q0: orientation_touching(sphere, direction(theta, phi), spin),
            omega0: DVec3::ZERO,
        })
    }
}

/// Everything a run needs besides the body. [`Simulation::new`] gives the command line's
/// defaults; the builder methods change one thing each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Simulation {
    /// Ramp angle α (rad), 1e-9 ≤ α < π/2.
    pub alpha: f64,
    /// Viscous or inertial.
    pub model: Model,
    /// Rotational drag γ in units of γ0 (1 by default; 0 only for inertial runs).
    pub drag: f64,
    /// How the drag grows with the speed (linear by default; [`crate::dynamics::drag`]).
    pub drag_law: DragLaw,
    /// Where it starts; `None`: [`InitialState::at_rest`], the command line's default.
    pub initial: Option<InitialState>,
    /// The integrator (DOP853 at rtol 1e-10 by default).
    pub method: Method,
    /// The run goes from t = 0 to this.
    pub t_end: f64,
    /// Equally spaced samples from t = 0 to `t_end` inclusive (1001 by default).
    pub samples: usize,
    /// Step budget (10⁸ by default): the run stops with an error beyond it.
    pub max_steps: u64,
    /// The surface the run is checked against, and what a lift-off or slip does (by default:
    /// lift-off checked, slip not, a violation reported in the summary).
    pub limits: ContactLimits,
}

impl Simulation {
    /// A viscous run at α from rest to `t_end`, with the command line's defaults.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{Model, Simulation, simulate};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let sim = Simulation::new(0.15, 100.0).model(Model::Inertial { mass_ratio: 6.0 });
    /// let (trajectory, summary) = simulate(&body, &sim)?;
    /// assert_eq!(trajectory.len(), 1001);
    /// assert_eq!(summary.model.to_string(), "sphere-inertial");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(alpha: f64, t_end: f64) -> Self {
        Simulation {
            alpha,
            model: Model::Viscous,
            drag: 1.0,
            drag_law: DragLaw::LINEAR,
            initial: None,
            method: Method::dop853(1e-10),
            t_end,
            samples: 1001,
            max_steps: 100_000_000,
            limits: ContactLimits::default(),
        }
    }

    /// With this model.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{Model, Simulation};
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// let spec = Simulation::new(0.1, 10.0).model(Model::Inertial { mass_ratio: 2.0 }).spec(&body)?;
    /// assert_eq!(spec.ramp.mass_ratio, 2.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn model(self, model: Model) -> Self {
        Simulation { model, ..self }
    }

    /// From this start.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, Simulation};
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// let start = InitialState::Disk { theta0: 1.0, theta_dot0: 0.0 };
    /// assert_eq!(Simulation::new(0.1, 10.0).initial(start).spec(&body)?.initial, start);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn initial(self, initial: InitialState) -> Self {
        Simulation {
            initial: Some(initial),
            ..self
        }
    }

    /// With this integrator.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::integrate::Method;
    /// use rollphase_core::simulate::Simulation;
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// let spec = Simulation::new(0.1, 10.0).method(Method::Rk4 { dt: 0.01 }).spec(&body)?;
    /// assert_eq!(spec.method, Method::Rk4 { dt: 0.01 });
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn method(self, method: Method) -> Self {
        Simulation { method, ..self }
    }

    /// With this many samples.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{Simulation, simulate};
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// let (trajectory, _) = simulate(&body, &Simulation::new(0.1, 10.0).samples(11))?;
    /// assert_eq!(trajectory.t(), &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn samples(self, samples: usize) -> Self {
        Simulation { samples, ..self }
    }

    /// With this drag γ/γ0.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::Simulation;
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// assert_eq!(Simulation::new(0.1, 10.0).drag(2.0).spec(&body)?.ramp.drag, 2.0);
    /// // A viscous run needs drag.
    /// assert!(Simulation::new(0.1, 10.0).drag(0.0).spec(&body).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn drag(self, drag: f64) -> Self {
        Simulation { drag, ..self }
    }

    /// With this drag law.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::DragLaw;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::Simulation;
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// let spec = Simulation::new(0.1, 10.0).drag_law(DragLaw::LINEAR).spec(&body)?;
    /// assert!(spec.ramp.drag_law.is_linear());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn drag_law(self, drag_law: DragLaw) -> Self {
        Simulation { drag_law, ..self }
    }

    /// With this surface: its μ, and whether a lift-off or slip stops the run.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{ContactLimits, OnViolation, RunError, Simulation, simulate};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// // The viscous body needs μ = tan α = 0.15 on this ramp: μ = 0.1 is not enough.
    /// let slippery = ContactLimits { friction: Some(0.1), on_violation: OnViolation::Stop };
    /// let e = simulate(&body, &Simulation::new(0.15, 10.0).limits(slippery));
    /// assert!(matches!(e, Err(RunError::LeftModel { .. })));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn limits(self, limits: ContactLimits) -> Self {
        Simulation { limits, ..self }
    }

    /// The [`RunSpec`] this stands for, for `body`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::Simulation;
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// let spec = Simulation::new(0.1, 10.0).spec(&body)?;
    /// assert_eq!((spec.t_end, spec.ramp.alpha_rad), (10.0, 0.1));
    /// // The run checks the rest before any work, naming the value.
    /// let e = rollphase_core::simulate::simulate(&body, &Simulation::new(0.1, f64::INFINITY));
    /// assert!(e.unwrap_err().to_string().contains("t_end = inf"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn spec(&self, body: &Body) -> Result<RunSpec, RunError> {
        // The ramp first, so a bad m/m0 gets the command line's message for `--mass`.
        let ramp = Ramp::with_drag(self.alpha, self.model.mass_ratio(), self.drag)?
            .with_drag_law(self.drag_law);
        if let Model::Inertial { mass_ratio } = self.model
            && !(mass_ratio.is_finite() && mass_ratio > 0.0)
        {
            return Err(RunError::Mismatch(format!(
                "Model::Inertial needs a finite m/m0 > 0, not {mass_ratio}; for no inertia use \
                 Model::Viscous"
            )));
        }
        Ok(RunSpec {
            ramp,
            initial: self.initial.unwrap_or_else(|| InitialState::at_rest(body)),
            method: self.method,
            t_end: self.t_end,
            samples: self.samples,
            max_steps: self.max_steps,
            limits: self.limits,
        })
    }
}

/// One sample of a sphere's run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereSample {
    /// Time.
    pub t: f64,
    /// Orientation, the body-to-lab unit quaternion (Hamilton).
    pub q: DQuat,
    /// The contact point as a body-frame unit vector.
    pub contact: DVec3,
    /// Lab angular velocity ω.
    pub omega: DVec3,
    /// Centre of mass in the ramp frame (x downhill, z the ramp's normal).
    pub com: DVec3,
    /// The ramp's force on the body.
    pub force: ContactForce,
}

/// One sample of a disk's run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiskSample {
    /// Time.
    pub t: f64,
    /// Contact angle θ in the body.
    pub theta: f64,
    /// θ̇.
    pub theta_dot: f64,
    /// The body's rotation ψ.
    pub psi: f64,
    /// Centre of mass downhill along the ramp.
    pub x: f64,
    /// Height of the centre of mass above the ramp.
    pub y: f64,
    /// The ramp's force on the body.
    pub force: ContactForce,
}

/// One sample, of either dimension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sample {
    /// A disk's.
    Disk(DiskSample),
    /// A sphere's.
    Sphere(SphereSample),
}

/// The force columns of a run's row, from `first` on.
fn force_at(row: &[f64], first: usize) -> ContactForce {
    ContactForce {
        normal: row[first],
        friction: [row[first + 1], row[first + 2]],
    }
}

impl Sample {
    /// From a row of [`super::run`] for a disk (columns as in [`super::DISK_HEADER`]) or a
    /// sphere ([`super::SPHERE_HEADER`]).
    fn from_row(disk: bool, row: &[f64]) -> Self {
        if disk {
            Sample::Disk(DiskSample {
                t: row[0],
                theta: row[1],
                theta_dot: row[2],
                psi: row[3],
                x: row[4],
                y: row[5],
                force: force_at(row, 6),
            })
        } else {
            Sample::Sphere(SphereSample {
                t: row[0],
                q: DQuat::from_xyzw(row[2], row[3], row[4], row[1]),
                contact: DVec3::new(row[5], row[6], row[7]),
                omega: DVec3::new(row[8], row[9], row[10]),
                com: DVec3::new(row[11], row[12], row[13]),
                force: force_at(row, 14),
            })
        }
    }
}

/// A sphere's trajectory, column by column.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SphereTrajectory {
    /// Times.
    pub t: Vec<f64>,
    /// Orientations.
    pub q: Vec<DQuat>,
    /// Contact points (body frame, unit).
    pub contact: Vec<DVec3>,
    /// Lab angular velocities.
    pub omega: Vec<DVec3>,
    /// Centres of mass.
    pub com: Vec<DVec3>,
    /// The ramp's force on the body.
    pub force: Vec<ContactForce>,
}

/// A disk's trajectory, column by column.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DiskTrajectory {
    /// Times.
    pub t: Vec<f64>,
    /// Contact angles θ.
    pub theta: Vec<f64>,
    /// θ̇.
    pub theta_dot: Vec<f64>,
    /// Body rotations ψ.
    pub psi: Vec<f64>,
    /// Centre of mass downhill.
    pub x: Vec<f64>,
    /// Centre of mass height.
    pub y: Vec<f64>,
    /// The ramp's force on the body.
    pub force: Vec<ContactForce>,
}

/// A run's samples, with named columns.
#[derive(Debug, Clone, PartialEq)]
pub enum Trajectory {
    /// A disk's.
    Disk(DiskTrajectory),
    /// A sphere's.
    Sphere(SphereTrajectory),
}

impl Trajectory {
    /// The sample times.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{Simulation, simulate};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let (trajectory, _) = simulate(&body, &Simulation::new(0.15, 2.0).samples(3))?;
    /// assert_eq!(trajectory.t(), &[0.0, 1.0, 2.0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn t(&self) -> &[f64] {
        match self {
            Trajectory::Disk(d) => &d.t,
            Trajectory::Sphere(s) => &s.t,
        }
    }

    /// The ramp's force on the body at each sample.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{Simulation, simulate};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let (trajectory, _) = simulate(&body, &Simulation::new(0.15, 2.0).samples(3))?;
    /// // Viscous: N = cos α throughout.
    /// assert!(trajectory.forces().iter().all(|f| (f.normal - 0.15f64.cos()).abs() < 1e-15));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn forces(&self) -> &[ContactForce] {
        match self {
            Trajectory::Disk(d) => &d.force,
            Trajectory::Sphere(s) => &s.force,
        }
    }

    /// The number of samples.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{Simulation, simulate};
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// let (trajectory, _) = simulate(&body, &Simulation::new(0.1, 5.0).samples(6))?;
    /// assert_eq!(trajectory.len(), 6);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn len(&self) -> usize {
        self.t().len()
    }

    /// Whether there are none.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{Simulation, simulate};
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// assert!(!simulate(&body, &Simulation::new(0.1, 5.0))?.0.is_empty());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn is_empty(&self) -> bool {
        self.t().is_empty()
    }

    fn push(&mut self, sample: Sample) {
        match (self, sample) {
            (Trajectory::Disk(d), Sample::Disk(s)) => {
                d.t.push(s.t);
                d.theta.push(s.theta);
                d.theta_dot.push(s.theta_dot);
                d.psi.push(s.psi);
                d.x.push(s.x);
                d.y.push(s.y);
                d.force.push(s.force);
            }
            (Trajectory::Sphere(d), Sample::Sphere(s)) => {
                d.t.push(s.t);
                d.q.push(s.q);
                d.contact.push(s.contact);
                d.omega.push(s.omega);
                d.com.push(s.com);
                d.force.push(s.force);
            }
            // The body fixes the dimension of every sample of a run.
            _ => unreachable!("a run's samples all have its body's dimension"),
        }
    }
}

/// Runs `sim` on `body` and returns its whole trajectory and summary.
///
/// ```
/// use rollphase_core::geometry::Body;
/// use rollphase_core::simulate::{Simulation, Trajectory, simulate};
/// let body = Body::random_sphere(1, 0.25, 5)?;
/// let sim = Simulation::new(1.5 * body.alpha_star(), 100.0).samples(101);
/// let (trajectory, summary) = simulate(&body, &sim)?;
/// let Trajectory::Sphere(path) = trajectory else { unreachable!() };
/// assert!(path.com.last().unwrap().x > 5.0, "it rolled downhill");
/// assert!(summary.max_contact_normal_error.unwrap() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn simulate(body: &Body, sim: &Simulation) -> Result<(Trajectory, Summary), RunError> {
    simulate_until(body, sim, &AtomicBool::new(false))
}

/// [`simulate`] that stops with [`RunError::Stopped`] soon after `stop` is set (from another
/// thread), as [`super::run_until`] does.
///
/// ```
/// use std::sync::atomic::AtomicBool;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::simulate::{Simulation, simulate_until};
/// let body = Body::paper_disk(84, 0.12, 5)?;
/// let (trajectory, _) = simulate_until(&body, &Simulation::new(0.1, 10.0), &AtomicBool::new(false))?;
/// assert_eq!(trajectory.len(), 1001);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn simulate_until(
    body: &Body,
    sim: &Simulation,
    stop: &AtomicBool,
) -> Result<(Trajectory, Summary), RunError> {
    let mut trajectory = match body {
        Body::Disk(_) => Trajectory::Disk(DiskTrajectory::default()),
        Body::Sphere(_) => Trajectory::Sphere(SphereTrajectory::default()),
    };
    let spec = sim.spec(body)?;
    let disk = matches!(body, Body::Disk(_));
    let summary = run_until(body, &spec, stop, |row| {
        trajectory.push(Sample::from_row(disk, row))
    })?;
    Ok((trajectory, summary))
}

/// Runs `sim` on `body`, handing each sample to `sample` as it is computed (memory stays flat
/// however many samples), and returns the summary.
///
/// ```
/// use rollphase_core::geometry::Body;
/// use rollphase_core::simulate::{Model, Sample, Simulation, simulate_streaming};
/// let body = Body::paper_disk(84, 0.12, 5)?;
/// let sim = Simulation::new(0.06, 500.0).model(Model::Inertial { mass_ratio: 10.0 });
/// let mut furthest = 0.0f64;
/// simulate_streaming(&body, &sim, |s| {
///     if let Sample::Disk(d) = s {
///         furthest = furthest.max(d.x);
///     }
/// })?;
/// assert!(furthest > 1.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn simulate_streaming(
    body: &Body,
    sim: &Simulation,
    mut sample: impl FnMut(Sample),
) -> Result<Summary, RunError> {
    let spec = sim.spec(body)?;
    let disk = matches!(body, Body::Disk(_));
    run(body, &spec, |row| sample(Sample::from_row(disk, row)))
}
