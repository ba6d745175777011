//! The viscous Poincaré map on ∂Ω of the SO(3) ball and its field (paper Fig. 3, SI §2G): one
//! step of the map from a boundary point ([`poincare_step`]), the first crossing of ∂Ω of any 3D
//! run ([`first_crossing`]), and the field V = P(p) − p on a lattice of ∂Ω ([`poincare_field`]),
//! integrated on its upper half and completed by antipodal symmetry. The crossings' geometry
//! (antipodes identified) is [`super::sphere_orbits`]'s; this file owns the map's field, which
//! the field figure, the app's field view and the orbit searches' seeds draw on.

use glam::{DQuat, DVec3};

use super::sphere_orbits::nearest_sign;
use crate::analysis::verdict::REST_THRESHOLD;
use crate::dynamics::{Ramp, RollingModel, SphereViscous};
use crate::geometry::Sphere;
use crate::integrate::events::{Direction, crossings_in_last_step};
use crate::integrate::lie::quat_at;
use crate::integrate::run::{Flow, Run};
use crate::integrate::{IntegrateError, Method};

/// One step of the viscous Poincaré map from the boundary point `p` (q = (0, p)): the next
/// crossing's point (sign nearest p) and the time taken, or `None` if the body halts first.
///
/// ```
/// use rollphase_core::analysis::orbits::poincare_field::poincare_step;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DVec3;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let (p, t) = poincare_step(&s, &Ramp::new(0.15, 0.0)?, DVec3::Z, 400.0, 1e-10)?
///     .expect("above α* it crosses ∂Ω again");
/// assert!(p.dot(DVec3::Z) >= 0.0, "the sign nearest the start");
/// assert!(t > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn poincare_step(
    body: &Sphere,
    ramp: &Ramp,
    p: DVec3,
    t_max: f64,
    rtol: f64,
) -> Result<Option<(DVec3, f64)>, IntegrateError> {
    let m = SphereViscous::new(body, ramp);
    let q0 = DQuat::from_xyzw(p.x, p.y, p.z, 0.0);
    let found = first_crossing(&m, SphereViscous::initial_state(q0), t_max, rtol, |y| {
        m.observe(y).omega.length()
    })?;
    Ok(found.map(|(t, y)| {
        let q = quat_at(&y, 0);
        (nearest_sign(p, DVec3::new(q.x, q.y, q.z).normalize()), t)
    }))
}

/// The first crossing of ∂Ω (q_w = 0, state slot 0) after t = 0 from `y0`: its time and state,
/// or `None` if `omega` (the caller's distance from rest: |ω| in the viscous model, where ω is
/// the ramp's torque over γ) falls below the verdict's [`REST_THRESHOLD`] first (the body
/// halts) or `t_max` passes.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::poincare_field::first_crossing;
/// use rollphase_core::dynamics::{Ramp, SphereViscous};
/// use rollphase_core::geometry::Sphere;
/// use rollphase_core::glam::DQuat;
/// // The unit ball turns at sin α: from q = 1 it reaches ∂Ω (a half turn) at t = π / sin α.
/// let ball = Sphere::perfect();
/// let model = SphereViscous::new(&ball, &Ramp::new(0.3, 0.0)?);
/// let y0 = SphereViscous::initial_state(DQuat::IDENTITY);
/// let (t, _) = first_crossing(&model, y0, 100.0, 1e-12, |_| 1.0)?.unwrap();
/// assert!((t - std::f64::consts::PI / 0.3f64.sin()).abs() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn first_crossing<const N: usize, S: RollingModel<N>>(
    sys: &S,
    y0: [f64; N],
    t_max: f64,
    rtol: f64,
    omega: impl Fn(&[f64; N]) -> f64,
) -> Result<Option<(f64, [f64; N])>, IntegrateError> {
    let mut run = Run::new(sys, 0.0, y0, Method::dop853(rtol))?;
    let mut times = Vec::new();
    let mut found = None;
    run.until::<IntegrateError>(t_max, u64::MAX, |st| {
        crossings_in_last_step(
            st,
            &|_t, y: &[f64; N]| sys.section(y),
            Direction::Both,
            &mut times,
        );
        if let Some(&t) = times.first() {
            found = Some((t, st.dense(t)));
            return Ok(Flow::Stop);
        }
        Ok(if omega(st.y()) < REST_THRESHOLD {
            Flow::Stop
        } else {
            Flow::Continue
        })
    })?;
    Ok(found)
}

/// One arrow of the Poincaré field on ∂Ω: from a boundary point to the next crossing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldArrow {
    /// Start on ∂Ω (unit vector).
    pub start: DVec3,
    /// The next crossing (sign nearest `start`), or `None` if the body halted first.
    pub end: Option<DVec3>,
    /// Time to the next crossing (0 if halted).
    pub time: f64,
}

/// The Poincaré field V = P(p) − p of the viscous model on a Fibonacci lattice of `n` points
/// of ∂Ω. Only the upper half (p_z ≥ 0) is integrated, in parallel: V(−p) = −V(p) because q
/// and −q are the same orientation. `tick` is called once per integrated start (progress).
/// The result is in lattice order whatever the thread count.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::poincare_field::poincare_field;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let field = poincare_field(&s, &Ramp::new(0.15, 0.0)?, 40, 400.0, 1e-9, &|| {})?;
/// assert_eq!(field.len(), 40);
/// // Above α* = 0.139 no start halts: every arrow has an end.
/// assert!(field.iter().all(|a| a.end.is_some() && a.time > 0.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn poincare_field(
    body: &Sphere,
    ramp: &Ramp,
    n: usize,
    t_max: f64,
    rtol: f64,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<FieldArrow>, IntegrateError> {
    use rayon::prelude::*;
    let upper = field_lattice(n);
    let images: Vec<Option<(DVec3, f64)>> = upper
        .par_iter()
        .map(|&p| {
            let r = poincare_step(body, ramp, p, t_max, rtol);
            tick();
            r
        })
        .collect::<Result<_, _>>()?;
    Ok(field_from_images(&upper, &images))
}

/// The starts of [`poincare_field`] that are integrated: the lattice points with p_z ≥ 0.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::poincare_field::field_lattice;
/// let upper = field_lattice(100);
/// assert!(upper.iter().all(|p| p.z >= 0.0) && upper.len() <= 100);
/// ```
pub fn field_lattice(n: usize) -> Vec<DVec3> {
    crate::geometry::sphere::fibonacci_sphere(n)
        .into_iter()
        .filter(|p| p.z >= 0.0)
        .collect()
}

/// The whole field from the images of the [`field_lattice`] starts (next crossing and time, or
/// `None` for a halt): each arrow and, for p_z > 0, its antipode.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::poincare_field::field_from_images;
/// use rollphase_core::glam::DVec3;
/// // One integrated start above the equator gives its arrow and the antipode's, reversed.
/// let arrows = field_from_images(&[DVec3::Z], &[Some((DVec3::X, 2.0))]);
/// assert_eq!(arrows.len(), 2);
/// assert_eq!((arrows[1].start, arrows[1].end), (-DVec3::Z, Some(-DVec3::X)));
/// ```
pub fn field_from_images(upper: &[DVec3], images: &[Option<(DVec3, f64)>]) -> Vec<FieldArrow> {
    let mut field = Vec::with_capacity(2 * upper.len());
    for (&p, &r) in upper.iter().zip(images) {
        let arrow = FieldArrow {
            start: p,
            end: r.map(|(q, _)| q),
            time: r.map_or(0.0, |(_, t)| t),
        };
        field.push(arrow);
        if p.z > 0.0 {
            field.push(FieldArrow {
                start: -p,
                end: arrow.end.map(|q| -q),
                time: arrow.time,
            });
        }
    }
    field
}
