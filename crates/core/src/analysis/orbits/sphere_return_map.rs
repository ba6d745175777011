//! The return map of 3D inertial rolling on ∂Ω, its periodic orbits and their Floquet
//! multipliers (paper Fig. 4e: period doubling).
//!
//! The inertial state (q, ω) lives in SO(3) × ℝ³, six dimensions. The section is ∂Ω, q_w = 0
//! (a rotation by π), with q and −q identified: a point of the section is a boundary point p
//! (a unit vector up to sign) and ω, five dimensions. P sends (p, ω) to the next crossing of
//! q_w = 0. In a chart around a base point p₀ (gnomonic: p ∝ p₀ + s₁e₁ + s₂e₂, the sign of p
//! taken nearest p₀) P is a map of ℝ⁵, and [`crate::analysis::orbits::return_map`] finds its fixed points (the
//! period-1 orbits), their five multipliers and the masses where one passes −1.
//!
//! The period of the crossing sequence is the orbit's multiplicity: k = 1 when every crossing
//! returns to the same (p, ω), k = 2 when they alternate between two (period doubling).

use glam::{DQuat, DVec3};
use nalgebra::DVector;
use serde::Serialize;

use crate::analysis::orbits::poincare_field::{first_crossing, poincare_step};
use crate::analysis::orbits::return_map::{self, ReturnMapError};
use crate::analysis::orbits::sphere_orbits::nearest_sign;
use crate::analysis::verdict::state_at_rest;
use crate::dynamics::validity::{ContactReport, ContactWatch};
use crate::dynamics::{Ramp, RollingModel, SphereInertial, SphereViscous};
use crate::geometry::Sphere;
use crate::integrate::events::{Direction, crossings_in_last_step};
use crate::integrate::run::{Flow, Run};
use crate::integrate::{IntegrateError, Method};

/// A point of the section: where the orientation crosses ∂Ω, with the angular velocity there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SectionState {
    /// Time of the crossing.
    pub t: f64,
    /// Boundary point (unit vector; sign arbitrary).
    pub point: [f64; 3],
    /// Lab angular velocity ω.
    pub omega: [f64; 3],
}

/// Every crossing of ∂Ω of the inertial model from orientation `q0` and angular velocity
/// `omega0` up to `t_end` (DOP853 at `rtol`, crossings located on the dense output). Stops early
/// if the body comes to rest.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_return_map::inertial_crossings;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::{DQuat, DVec3};
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let ramp = Ramp::new(0.15, 6.0)?;
/// let crossings = inertial_crossings(&s, &ramp, DQuat::IDENTITY, DVec3::ZERO, 300.0, 1e-9)?;
/// assert!(crossings.len() > 3, "it rolls through ∂Ω again and again");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn inertial_crossings(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    omega0: DVec3,
    t_end: f64,
    rtol: f64,
) -> Result<Vec<SectionState>, IntegrateError> {
    inertial_crossings_until(body, ramp, q0, omega0, (t_end, t_end), rtol, |_| false).map(|r| r.0)
}

/// [`inertial_crossings`] that goes on until its fate is decided: at least `t_min`, then until
/// `decided` says so (asked at every new crossing) or the body comes to rest
/// ([`crate::analysis::verdict::at_rest`]: still, and the weight's torque zero), and at most `t_cap`
/// (`span` = (t_min, t_cap)). Returns the crossings and the time the run ended.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_return_map::inertial_crossings_until;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::{DQuat, DVec3};
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// // Decided once three crossings are in, after t = 100.
/// let (crossings, t_end) = inertial_crossings_until(&s, &Ramp::new(0.15, 1.0)?, DQuat::IDENTITY, DVec3::ZERO, (100.0, 5000.0), 1e-9, |c| c.len() >= 3)?;
/// assert!(crossings.len() >= 3 && t_end >= 100.0 && t_end < 5000.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn inertial_crossings_until(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    omega0: DVec3,
    span: (f64, f64),
    rtol: f64,
    decided: impl FnMut(&[SectionState]) -> bool,
) -> Result<(Vec<SectionState>, f64), IntegrateError> {
    inertial_run(body, ramp, q0, omega0, span, rtol, false, decided).map(|r| (r.crossings, r.t_end))
}

/// How an [`inertial_run`] ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InertialEnd {
    /// `decided` said so.
    Decided,
    /// The body came to rest ([`crate::analysis::verdict::at_rest`]).
    Rest,
    /// The normal force fell to zero: the body leaves the ramp (only when watched).
    LiftOff,
    /// It reached `t_cap`.
    Cap,
}

/// A run of [`inertial_run`].
#[derive(Debug, Clone)]
pub struct InertialRun {
    /// Every crossing of ∂Ω.
    pub crossings: Vec<SectionState>,
    /// When it ended.
    pub t_end: f64,
    /// Why.
    pub end: InertialEnd,
    /// |ω| at the end.
    pub angular_speed: f64,
    /// The contact force along the run, when watched.
    pub contact: Option<ContactReport>,
}

/// [`inertial_crossings_until`] with its end told apart, and, if `watch_contact`, the contact
/// force followed along the run ([`ContactWatch`], an observer: the trajectory is the same
/// with or without it) and the run stopped where the body would leave the ramp.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_return_map::{InertialEnd, inertial_run};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::{DQuat, DVec3};
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// // A very heavy body above α* is still at first, but it is speeding up, not at rest.
/// let run = inertial_run(&s, &Ramp::new(0.3, 1e10)?, DQuat::IDENTITY, DVec3::ZERO, (10.0, 100.0), 1e-9, true, |_| false)?;
/// assert_eq!(run.end, InertialEnd::Cap);
/// assert!(run.contact.is_some_and(|c| c.min_normal_force > 0.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn inertial_run(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    omega0: DVec3,
    (t_min, t_cap): (f64, f64),
    rtol: f64,
    watch_contact: bool,
    mut decided: impl FnMut(&[SectionState]) -> bool,
) -> Result<InertialRun, IntegrateError> {
    let model = SphereInertial::new(body, ramp);
    let y0 = SphereInertial::initial_state(q0, omega0);
    let mut run = Run::new(&model, 0.0, y0, Method::dop853(rtol))?;
    let mut watch =
        watch_contact.then(|| ContactWatch::lift_off_only(0.0, model.contact_force(&y0)));
    let mut times = Vec::new();
    let mut out = Vec::new();
    let mut end = InertialEnd::Cap;
    run.until::<IntegrateError>(t_cap, u64::MAX, |st| {
        if let Some(w) = watch.as_mut() {
            let at = (st.t(), *st.y());
            w.step_along(st, at, |y| model.contact_force(y));
            if w.report().lift_off_t.is_some() {
                end = InertialEnd::LiftOff;
                return Ok(Flow::Stop);
            }
        }
        times.clear();
        crossings_in_last_step(
            st,
            &|_t, y: &[f64; 10]| model.section(y),
            Direction::Both,
            &mut times,
        );
        for &t in &times {
            let y = st.dense(t);
            out.push(SectionState {
                t,
                point: DVec3::new(y[1], y[2], y[3]).normalize().to_array(),
                omega: [y[4], y[5], y[6]],
            });
        }
        if st.t() > 1.0 && state_at_rest(&model, st.y()) {
            end = InertialEnd::Rest;
            return Ok(Flow::Stop);
        }
        if st.t() >= t_min && !times.is_empty() && decided(&out) {
            end = InertialEnd::Decided;
            return Ok(Flow::Stop);
        }
        Ok(Flow::Continue)
    })?;
    let y = run.y();
    Ok(InertialRun {
        crossings: out,
        t_end: run.t(),
        end,
        angular_speed: DVec3::new(y[4], y[5], y[6]).length(),
        contact: watch.map(|w| w.report()),
    })
}

/// One application of P: from boundary point `p` with angular velocity `omega` to the next
/// crossing (sign of the point raw), with the time taken; `None` if the body halts or does not
/// return by `t_max`.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_return_map::next_crossing;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DVec3;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let ramp = Ramp::new(0.15, 2.0)?;
/// let (p, _omega, t) = next_crossing(&s, &ramp, DVec3::X, DVec3::ZERO, 400.0, 1e-9)?
///     .expect("it comes back to ∂Ω");
/// assert!((p.length() - 1.0).abs() < 1e-12 && t > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn next_crossing(
    body: &Sphere,
    ramp: &Ramp,
    p: DVec3,
    omega: DVec3,
    t_max: f64,
    rtol: f64,
) -> Result<Option<(DVec3, DVec3, f64)>, IntegrateError> {
    let model = SphereInertial::new(body, ramp);
    let q0 = DQuat::from_xyzw(p.x, p.y, p.z, 0.0);
    let found = first_crossing(
        &model,
        SphereInertial::initial_state(q0, omega),
        t_max,
        rtol,
        |y| DVec3::new(y[4], y[5], y[6]).length(),
    )?;
    Ok(found.map(|(t, y)| {
        (
            DVec3::new(y[1], y[2], y[3]).normalize(),
            DVec3::new(y[4], y[5], y[6]),
            t,
        )
    }))
}

/// Gnomonic chart of ∂Ω (antipodes identified) around `base`.
#[derive(Debug, Clone, Copy)]
pub struct SectionChart {
    base: DVec3,
    e1: DVec3,
    e2: DVec3,
}

impl SectionChart {
    /// The chart centred on the unit vector `base`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::orbits::sphere_return_map::SectionChart;
    /// use rollphase_core::glam::DVec3;
    /// let chart = SectionChart::new(DVec3::new(0.0, 0.0, 2.0)); // normalised here
    /// let (p, _) = chart.unpack(&chart.pack(DVec3::Z, DVec3::ZERO));
    /// assert!((p - DVec3::Z).length() < 1e-15);
    /// ```
    pub fn new(base: DVec3) -> Self {
        let base = base.normalize();
        let (e1, e2) = base.any_orthonormal_pair();
        Self { base, e1, e2 }
    }

    /// Chart coordinates (s₁, s₂, ω) → (p, ω).
    ///
    /// # Example
    /// ```
    /// use nalgebra::DVector;
    /// use rollphase_core::analysis::orbits::sphere_return_map::SectionChart;
    /// use rollphase_core::glam::DVec3;
    /// let chart = SectionChart::new(DVec3::Z);
    /// // The chart's origin is its base point.
    /// let (p, omega) = chart.unpack(&DVector::from_vec(vec![0.0, 0.0, 0.1, 0.2, 0.3]));
    /// assert_eq!((p, omega), (DVec3::Z, DVec3::new(0.1, 0.2, 0.3)));
    /// ```
    pub fn unpack(&self, x: &DVector<f64>) -> (DVec3, DVec3) {
        let p = (self.base + x[0] * self.e1 + x[1] * self.e2).normalize();
        (p, DVec3::new(x[2], x[3], x[4]))
    }

    /// (p, ω) → chart coordinates; p's sign is taken nearest the base.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::orbits::sphere_return_map::SectionChart;
    /// use rollphase_core::glam::DVec3;
    /// let chart = SectionChart::new(DVec3::X);
    /// let p = DVec3::new(-0.9, 0.3, 0.1).normalize();
    /// // The sign nearest the base is taken: −p and p pack alike.
    /// assert_eq!(chart.pack(p, DVec3::ZERO), chart.pack(-p, DVec3::ZERO));
    /// let (back, _) = chart.unpack(&chart.pack(p, DVec3::ONE));
    /// assert!((back + p).length() < 1e-14);
    /// ```
    pub fn pack(&self, p: DVec3, omega: DVec3) -> DVector<f64> {
        let p = nearest_sign(self.base, p);
        let d = p.dot(self.base);
        DVector::from_vec(vec![
            p.dot(self.e1) / d,
            p.dot(self.e2) / d,
            omega.x,
            omega.y,
            omega.z,
        ])
    }
}

/// A period-1 orbit of the inertial model: a fixed point of P.
#[derive(Debug, Clone, Serialize)]
pub struct PeriodicOrbit {
    /// m/m0.
    pub mass_ratio: f64,
    /// Its crossing point on ∂Ω (sign arbitrary).
    pub point: [f64; 3],
    /// ω at the crossing.
    pub omega: [f64; 3],
    /// Period (time between crossings).
    pub period: f64,
    /// The five Floquet multipliers (re, im), largest modulus first.
    pub multipliers: Vec<[f64; 2]>,
    /// Largest |μ|: stable below 1.
    pub max_modulus: f64,
    /// The most negative real multiplier, if any (the flip happens where it passes −1).
    pub most_negative_real: Option<f64>,
    /// Newton steps taken.
    pub newton_steps: usize,
}

/// Settings of the orbit solve.
#[derive(Debug, Clone, Copy)]
pub struct OrbitSolve {
    /// DOP853 tolerance of each map evaluation.
    pub rtol: f64,
    /// Central-difference step of DP.
    pub fd_step: f64,
    /// Newton stops at |P(x) − x| below this.
    pub tol: f64,
    /// Longest time for one return.
    pub t_max: f64,
    /// Newton steps allowed.
    pub max_newton: usize,
}

impl Default for OrbitSolve {
    fn default() -> Self {
        // The map is accurate to ~1e-9 at rtol 1e-11; a 1e-5 step keeps the truncation error of
        // the central differences (~h²) and the round-off (~1e-9/h) near 1e-4 in DP.
        Self {
            rtol: 1e-11,
            fd_step: 1e-5,
            tol: 1e-8,
            t_max: 400.0,
            max_newton: 12,
        }
    }
}

/// The period-1 orbit near the crossing (`p`, `omega`), by Newton on the return map, with its
/// multipliers.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_return_map::{OrbitSolve, periodic_orbit};
/// use rollphase_core::analysis::studies::sphere::periodic_orbits;
/// use rollphase_core::analysis::orbits::sphere_orbits::Decide;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DVec3;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let decide = Decide { t_min: 600.0, t_cap: 6000.0, max_k: 1, tol: 1e-5 };
/// let found = &periodic_orbits(&body, 0.15, 10.0, 2, 1, &decide)?[0].orbit;
/// // Continued to m/m0 = 10.5 from the orbit at 10.
/// let Body::Sphere(s) = &body else { unreachable!() };
/// let (p, w) = (DVec3::from_array(found.point), DVec3::from_array(found.omega));
/// let next = periodic_orbit(s, &Ramp::new(0.15, 10.5)?, p, w, &OrbitSolve::default())?;
/// assert_eq!(next.multipliers.len(), 5);
/// assert!(next.max_modulus < 1.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn periodic_orbit(
    body: &Sphere,
    ramp: &Ramp,
    p: DVec3,
    omega: DVec3,
    solve: &OrbitSolve,
) -> Result<PeriodicOrbit, ReturnMapError> {
    let chart = SectionChart::new(p);
    let map = |x: &DVector<f64>| {
        let (p, w) = chart.unpack(x);
        match next_crossing(body, ramp, p, w, solve.t_max, solve.rtol) {
            Ok(Some((p1, w1, _))) => Some(chart.pack(p1, w1)),
            _ => None,
        }
    };
    let fp = return_map::find_fixed_point(
        &map,
        chart.pack(p, omega),
        solve.fd_step,
        solve.tol,
        0.2,
        solve.max_newton,
    )?;
    let (p, w) = chart.unpack(&fp.point);
    let period = match next_crossing(body, ramp, p, w, solve.t_max, solve.rtol) {
        Ok(Some((_, _, t))) => t,
        _ => {
            return Err(ReturnMapError::Undefined {
                at: fp.point.iter().copied().collect(),
            });
        }
    };
    Ok(PeriodicOrbit {
        mass_ratio: ramp.mass_ratio,
        point: p.to_array(),
        omega: w.to_array(),
        period,
        max_modulus: fp.multipliers.first().map_or(0.0, |c| c.norm()),
        most_negative_real: return_map::most_negative_real(&fp.multipliers),
        multipliers: fp.multipliers.iter().map(|c| [c.re, c.im]).collect(),
        newton_steps: fp.iterations,
    })
}

/// A period-1 orbit of the viscous model near the boundary point `p`: a fixed point of the
/// viscous Poincaré map on ∂Ω (two dimensions: the boundary point in a gnomonic chart around
/// `p`, ω following from the orientation), by Newton on the map, with its two multipliers.
/// `omega` in the result is ω at the crossing; `solve.t_max` and `solve.rtol` apply to each
/// map evaluation.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_return_map::{OrbitSolve, viscous_periodic_orbit};
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DVec3;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let guess = DVec3::new(-0.04, -0.26, -0.96); // near one of the paper's two orbits
/// let orbit = viscous_periodic_orbit(&s, &Ramp::new(0.15, 0.0)?, guess, &OrbitSolve::default())?;
/// assert_eq!(orbit.multipliers.len(), 2);
/// assert!(orbit.max_modulus < 1.0, "a stable orbit");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn viscous_periodic_orbit(
    body: &Sphere,
    ramp: &Ramp,
    p: DVec3,
    solve: &OrbitSolve,
) -> Result<PeriodicOrbit, ReturnMapError> {
    let base = p.normalize();
    let (e1, e2) = base.any_orthonormal_pair();
    let unpack = |x: &DVector<f64>| (base + x[0] * e1 + x[1] * e2).normalize();
    let pack = |p: DVec3| {
        let p = nearest_sign(base, p);
        let d = p.dot(base);
        DVector::from_vec(vec![p.dot(e1) / d, p.dot(e2) / d])
    };
    let step = |p: DVec3| {
        poincare_step(body, ramp, p, solve.t_max, solve.rtol)
            .ok()
            .flatten()
    };
    let map = |x: &DVector<f64>| step(unpack(x)).map(|(p1, _)| pack(p1));
    let fp = return_map::find_fixed_point(
        &map,
        pack(base),
        solve.fd_step,
        solve.tol,
        0.2,
        solve.max_newton,
    )?;
    let p = unpack(&fp.point);
    let Some((_, period)) = step(p) else {
        return Err(ReturnMapError::Undefined {
            at: fp.point.iter().copied().collect(),
        });
    };
    let model = SphereViscous::new(body, ramp);
    let q = DQuat::from_xyzw(p.x, p.y, p.z, 0.0);
    let omega = model.observe(&SphereViscous::initial_state(q)).omega;
    Ok(PeriodicOrbit {
        mass_ratio: 0.0,
        point: p.to_array(),
        omega: omega.to_array(),
        period,
        max_modulus: fp.multipliers.first().map_or(0.0, |c| c.norm()),
        most_negative_real: return_map::most_negative_real(&fp.multipliers),
        multipliers: fp.multipliers.iter().map(|c| [c.re, c.im]).collect(),
        newton_steps: fp.iterations,
    })
}
