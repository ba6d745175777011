//! The tube of SI Fig. S3 (§2G): trajectories in SO(3) of a perfect sphere that pass through one
//! contact point. The sphere is put on the ramp touching body point u₀ and spun on the spot by
//! s ∈ [0, 2π) (the ring of all orientations sharing that contact); from each, it rolls straight
//! down, q(t) = R_y(t sin α) q₀, closing after T = 2π/sin α. Points are the vector part of ±q
//! (q_w ≥ 0) in the unit ball. One trajectory is also integrated with DOP853 and compared with
//! the closed form, so the figure checks the viscous model against an exact solution.
//!
//! Data only: `rollphase figure sphere-tube` draws it.

use glam::{DQuat, DVec3};

use crate::analysis::orbits::sphere_orbits::ball_point;
use crate::analysis::studies::sphere::StudyError;
use crate::dynamics::sphere3d::orientation_touching;
use crate::dynamics::{Ramp, SphereViscous};
use crate::geometry::Sphere;
use crate::geometry::sphere::direction;
use crate::integrate::run::{Flow, Run};
use crate::integrate::{IntegrateError, Method};

/// Points on the ring of orientations touching u₀ (its resolution in the figure).
pub const RING_POINTS: usize = 720;

/// One rolling trajectory of the tube.
#[derive(Debug, Clone, PartialEq)]
pub struct TubeTrajectory {
    /// The start's spin s about the ramp normal (rad).
    pub spin: f64,
    /// Sample times, 0 to the period inclusive.
    pub t: Vec<f64>,
    /// The ball point at each time.
    pub ball: Vec<DVec3>,
}

/// The tube through one contact point, and how exactly its orbits close.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactTube {
    /// Ramp angle α (rad).
    pub alpha: f64,
    /// The shared contact point (θ, φ) on the body.
    pub contact: [f64; 2],
    /// The period 2π/sin α.
    pub period: f64,
    /// The trajectories, spins 2πj/n for j = 0..n.
    pub trajectories: Vec<TubeTrajectory>,
    /// The ring of orientations touching u₀ ([`RING_POINTS`] + 1 points, closed).
    pub ring: Vec<DVec3>,
    /// Largest |q(T) ∓ q(0)| over the trajectories (closed orbits: ~1e-16).
    pub closure_error: f64,
    /// Largest difference between DOP853 (rtol 1e-12) and the closed form over one period,
    /// for the start with spin 1 rad.
    pub integration_error: f64,
}

/// The tube at ramp angle `alpha` through body point `contact` = (θ, φ): `trajectories`
/// closed-form orbits sampled at `samples` + 1 times over one period.
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::studies::contact_tube::contact_tube;
///
/// let tube = contact_tube(0.3, [1.0, 0.5], 8, 100).unwrap();
/// assert_eq!(tube.trajectories.len(), 8);
/// assert!((tube.period - std::f64::consts::TAU / 0.3_f64.sin()).abs() < 1e-12);
/// // The orbits close, and DOP853 follows the closed form.
/// assert!(tube.closure_error < 1e-12 && tube.integration_error < 1e-8);
/// ```
pub fn contact_tube(
    alpha: f64,
    contact: [f64; 2],
    trajectories: usize,
    samples: usize,
) -> Result<ContactTube, StudyError> {
    // Checked before any work: α as the model checks it (1e-9 ≤ α < π/2, finite).
    let ramp = Ramp::new(alpha, 0.0)?;
    if trajectories == 0 || samples == 0 {
        return Err(StudyError::BadArgument(format!(
            "the tube needs at least one trajectory and one sample (got {trajectories} and \
             {samples})"
        )));
    }
    if !contact.iter().all(|c| c.is_finite()) {
        return Err(StudyError::BadArgument(format!(
            "contact point {contact:?} is not finite"
        )));
    }
    let body = Sphere::perfect();
    let u0 = direction(contact[0], contact[1]);
    let period = std::f64::consts::TAU / alpha.sin();
    let q_at = |q0: DQuat, t: f64| DQuat::from_rotation_y(t * alpha.sin()) * q0;
    let ring = (0..=RING_POINTS)
        .map(|k| {
            ball_point(orientation_touching(
                &body,
                u0,
                std::f64::consts::TAU * k as f64 / RING_POINTS as f64,
            ))
        })
        .collect();
    let mut closure_error: f64 = 0.0;
    let paths = (0..trajectories)
        .map(|j| {
            let spin = std::f64::consts::TAU * j as f64 / trajectories as f64;
            let q0 = orientation_touching(&body, u0, spin);
            let t: Vec<f64> = (0..=samples)
                .map(|k| period * k as f64 / samples as f64)
                .collect();
            let ball = t.iter().map(|&t| ball_point(q_at(q0, t))).collect();
            let end = q_at(q0, period);
            closure_error = closure_error.max((end - q0).length().min((end + q0).length()));
            TubeTrajectory { spin, t, ball }
        })
        .collect();
    let q0 = orientation_touching(&body, u0, 1.0);
    let model = SphereViscous::new(&body, &ramp);
    let mut run = Run::new(
        &model,
        0.0,
        SphereViscous::initial_state(q0),
        Method::dop853(1e-12),
    )?;
    let mut integration_error: f64 = 0.0;
    run.until::<IntegrateError>(period, u64::MAX, |st| {
        let y = st.y();
        let q = DQuat::from_xyzw(y[1], y[2], y[3], y[0]);
        let exact = q_at(q0, st.t());
        integration_error = integration_error.max((q - exact).length().min((q + exact).length()));
        Ok(Flow::Continue)
    })?;
    Ok(ContactTube {
        alpha,
        contact,
        period,
        trajectories: paths,
        ring,
        closure_error,
        integration_error,
    })
}

/// Splits a ball-point polyline where it jumps to the antipode on ∂Ω (consecutive points more
/// than 1 apart), so a plot draws pieces instead of a chord through the ball.
///
/// # Example
///
/// ```
/// use glam::DVec3;
/// use rollphase_core::analysis::studies::contact_tube::split_at_jumps;
///
/// let path = [DVec3::new(0.9, 0.0, 0.0), DVec3::new(0.99, 0.0, 0.0), DVec3::new(-0.99, 0.0, 0.0)];
/// assert_eq!(split_at_jumps(&path).len(), 2);
/// ```
pub fn split_at_jumps(points: &[DVec3]) -> Vec<Vec<DVec3>> {
    let mut out: Vec<Vec<DVec3>> = vec![Vec::new()];
    for p in points {
        let jump = out
            .last()
            .and_then(|v| v.last())
            .is_some_and(|l| (*p - *l).length() > 1.0);
        if jump {
            out.push(Vec::new());
        }
        if let Some(v) = out.last_mut() {
            v.push(*p);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_start_of_the_tube_touches_the_ramp_at_the_contact_point() {
        let tube = contact_tube(0.3, [1.0, 0.5], 6, 40).unwrap();
        let u0 = direction(1.0, 0.5);
        let body = Sphere::perfect();
        for traj in &tube.trajectories {
            // The body point pointing down the ramp normal (−z in the lab) is u₀.
            let q0 = orientation_touching(&body, u0, traj.spin);
            assert!(
                (q0 * u0 - DVec3::NEG_Z).length() < 1e-12,
                "spin {}",
                traj.spin
            );
            assert_eq!(traj.t.len(), 41);
            assert_eq!(traj.t[40], tube.period);
            // Ball points lie in the unit ball.
            assert!(traj.ball.iter().all(|p| p.length() <= 1.0 + 1e-12));
        }
        assert_eq!(tube.ring.len(), RING_POINTS + 1);
    }

    #[test]
    fn bad_arguments_are_refused_before_any_work() {
        assert!(matches!(
            contact_tube(f64::NAN, [1.0, 0.5], 4, 10),
            Err(StudyError::Model(_))
        ));
        assert!(matches!(
            contact_tube(0.3, [1.0, 0.5], 0, 10),
            Err(StudyError::BadArgument(_))
        ));
        assert!(matches!(
            contact_tube(0.3, [f64::INFINITY, 0.5], 4, 10),
            Err(StudyError::BadArgument(_))
        ));
    }
}
