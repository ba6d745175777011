//! Halting loops of viscous 3D rolling and their stability (SI §2D–2E).
//!
//! The body can rest on contact point u iff Q(u) = |∇_s ln r| = tan α (r parallel to F), so the
//! rest states are the level sets Q = tan α (marching squares on a (θ, φ) grid), each a loop of
//! rest orientations in SO(3). At every loop point the rest orientation is built (the body put on
//! u, then turned about the ramp normal until r points along F), and the viscous flow
//! q̇ = ½ω(q)q is linearised there: μ̇ = Jμ with J = ∂ω/∂μ for small rotations exp(μ)q (central
//! differences). One eigenvalue of J is ≈ 0, along the loop of rest states; the point is stable
//! when the other two have negative real parts. The classification is checked by simulation:
//! sampled points, perturbed by a small rotation, must come back to rest (stable) or roll away
//! (unstable).
//!
//! Note: the SI argues that a spin on the spot always grows, since d|μ|²/dt > 0 along μ ∥ n. That
//! shows μ·Jμ > 0 for one direction, which for a non-normal J does not imply an unstable
//! eigenvalue. Stable rest points exist, and viscous runs do halt (the cruising fraction).
//!
//! Data only: `rollphase figure sphere-halting` draws it.

use glam::{DMat3, DQuat, DVec3};
use rayon::prelude::*;

use crate::analysis::studies::sphere::StudyError;
use crate::dynamics::sphere3d::DOWN;
use crate::dynamics::{Ramp, SphereViscous};
use crate::geometry::Sphere;
use crate::geometry::sphere::direction;
use crate::integrate::run::{Flow, Run};
use crate::integrate::{IntegrateError, Method};
use crate::numeric::contour::level_set;

/// The rest quality Q(u) = |∇_s ln r| sampled on a (θ, φ) grid: θ ∈ [0, π], φ ∈ [−π, π].
#[derive(Debug, Clone, PartialEq)]
pub struct QualityGrid {
    /// Polar angles, rows of `q`.
    pub thetas: Vec<f64>,
    /// Azimuths, columns of `q`.
    pub phis: Vec<f64>,
    /// Q at (θ_i, φ_j).
    pub q: Vec<Vec<f64>>,
}

impl QualityGrid {
    /// Q of `body` on an `n_theta` × `n_phi` grid (each at least 2).
    ///
    /// # Example
    ///
    /// ```
    /// use rollphase_core::analysis::rest::halting::QualityGrid;
    /// use rollphase_core::geometry::Sphere;
    ///
    /// let grid = QualityGrid::new(&Sphere::perfect(), 5, 9);
    /// // A perfect sphere rests nowhere on a slope: Q = 0 everywhere.
    /// assert!(grid.q.iter().flatten().all(|q| q.abs() < 1e-12));
    /// ```
    pub fn new(body: &Sphere, n_theta: usize, n_phi: usize) -> Self {
        let (nt, np) = (n_theta.max(2), n_phi.max(2));
        let thetas: Vec<f64> = (0..nt)
            .map(|i| std::f64::consts::PI * i as f64 / (nt - 1) as f64)
            .collect();
        let phis: Vec<f64> = (0..np)
            .map(|j| -std::f64::consts::PI + std::f64::consts::TAU * j as f64 / (np - 1) as f64)
            .collect();
        let q = thetas
            .iter()
            .map(|&t| {
                phis.iter()
                    .map(|&p| body.surface(direction(t, p)).quality())
                    .collect()
            })
            .collect();
        Self { thetas, phis, q }
    }
}

/// One segment of a halting loop, ends in (φ, θ), and whether its midpoint is a stable rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestSegment {
    /// One end (φ, θ).
    pub from: (f64, f64),
    /// The other end (φ, θ).
    pub to: (f64, f64),
    /// Whether the rest orientation at the segment's midpoint is linearly stable.
    pub stable: bool,
}

impl RestSegment {
    /// The midpoint's contact direction (θ, φ averaged over the two ends).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::rest::halting::RestSegment;
    /// let s = RestSegment { from: (0.0, 1.0), to: (0.2, 1.2), stable: true };
    /// let u = s.midpoint();
    /// assert!((u.z - 1.1f64.cos()).abs() < 1e-15);
    /// ```
    pub fn midpoint(&self) -> DVec3 {
        let ((p0, t0), (p1, t1)) = (self.from, self.to);
        direction(0.5 * (t0 + t1), 0.5 * (p0 + p1))
    }
}

/// The halting loops at one α, classified, with the classification checked by simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct HaltingLoops {
    /// Ramp angle α (rad).
    pub alpha: f64,
    /// The loops' segments, in marching-squares order.
    pub segments: Vec<RestSegment>,
    /// Perturbed stable points that came back to rest nearby, and how many were tried (≤ 4).
    pub stable_confirmed: [usize; 2],
    /// Perturbed unstable points that left, and how many were tried (≤ 4).
    pub unstable_confirmed: [usize; 2],
}

impl HaltingLoops {
    /// Fraction of segments classified stable (0 when there are none).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::rest::halting::{HaltingLoops, RestSegment};
    /// let seg = |stable| RestSegment { from: (0.0, 1.0), to: (0.1, 1.0), stable };
    /// let loops = HaltingLoops { alpha: 0.1, segments: vec![seg(true), seg(false), seg(true), seg(true)], stable_confirmed: [0, 0], unstable_confirmed: [0, 0] };
    /// assert_eq!(loops.stable_fraction(), 0.75);
    /// ```
    pub fn stable_fraction(&self) -> f64 {
        let stable = self.segments.iter().filter(|s| s.stable).count();
        stable as f64 / self.segments.len().max(1) as f64
    }
}

/// The halting loops Q = tan α of `body` on `grid`, each segment classified by the eigenvalues
/// of the linearised viscous flow (in parallel; `on_segment(total)` is called as each of the
/// `total` segments is done, for a progress bar), then up to four segments of each kind checked by a perturbed viscous run.
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::rest::halting::{QualityGrid, halting_loops};
/// use rollphase_core::geometry::Body;
///
/// let paper = Body::paper_sphere(219, 0.25, 5).unwrap();
/// let alpha_star = paper.alpha_star();
/// let Body::Sphere(body) = paper else { unreachable!() };
/// let grid = QualityGrid::new(&body, 31, 61);
/// let loops = halting_loops(&body, &grid, 0.9 * alpha_star, &|_| {}).unwrap();
/// assert!(!loops.segments.is_empty());
/// // The loops hold both stable and unstable rest points.
/// assert!(loops.stable_fraction() > 0.0 && loops.stable_fraction() < 1.0);
/// // Up to four of each kind were checked by a perturbed run.
/// assert!(loops.stable_confirmed[1] <= 4 && loops.stable_confirmed[0] <= loops.stable_confirmed[1]);
/// ```
pub fn halting_loops(
    body: &Sphere,
    grid: &QualityGrid,
    alpha: f64,
    on_segment: &(dyn Fn(usize) + Sync),
) -> Result<HaltingLoops, StudyError> {
    let ramp = Ramp::new(alpha, 0.0)?;
    let ends = level_set(&grid.q, &grid.thetas, &grid.phis, alpha.tan());
    let stable: Vec<bool> = (0..ends.len())
        .into_par_iter()
        .with_max_len(1)
        .map(|k| {
            let ((p0, t0), (p1, t1)) = ends[k];
            let u = direction(0.5 * (t0 + t1), 0.5 * (p0 + p1));
            let model = SphereViscous::new(body, &ramp);
            let stable = is_stable_rest(rest_jacobian(&model, rest_orientation(body, u)));
            on_segment(ends.len());
            stable
        })
        .collect();
    let segments: Vec<RestSegment> = ends
        .iter()
        .zip(&stable)
        .map(|(&(from, to), &stable)| RestSegment { from, to, stable })
        .collect();
    let model = SphereViscous::new(body, &ramp);
    let check = |want: bool| -> Result<[usize; 2], IntegrateError> {
        let idx: Vec<usize> = (0..segments.len())
            .filter(|&k| segments[k].stable == want)
            .collect();
        let picks: Vec<usize> = idx
            .iter()
            .step_by((idx.len() / 4).max(1))
            .take(4)
            .copied()
            .collect();
        let mut agreed = 0;
        for &k in &picks {
            let q = rest_orientation(body, segments[k].midpoint());
            let kicked = DQuat::from_scaled_axis(DVec3::new(1e-4, -2e-4, 1.5e-4)) * q;
            if returns_to_rest(&model, kicked, q, 400.0)? == want {
                agreed += 1;
            }
        }
        Ok([agreed, picks.len()])
    };
    let stable_confirmed = check(true)?;
    let unstable_confirmed = check(false)?;
    Ok(HaltingLoops {
        alpha,
        segments,
        stable_confirmed,
        unstable_confirmed,
    })
}

/// Rest orientation on contact direction u: put u on the ramp, then turn about +z until the lab
/// contact vector's horizontal part points downhill (+x), i.e. r ∥ F when Q(u) = tan α.
///
/// # Example
///
/// ```
/// use glam::DVec3;
/// use rollphase_core::analysis::rest::halting::rest_orientation;
/// use rollphase_core::geometry::Sphere;
///
/// // The unit sphere on its south pole: already at rest, no turn needed.
/// let q = rest_orientation(&Sphere::perfect(), DVec3::NEG_Z);
/// assert!((q * DVec3::NEG_Z - DVec3::NEG_Z).length() < 1e-12);
/// ```
pub fn rest_orientation(body: &Sphere, u: DVec3) -> DQuat {
    let sp = body.surface(u);
    let tilt = DQuat::from_rotation_arc(sp.normal, DOWN);
    let r = tilt * sp.p;
    (DQuat::from_rotation_z(-r.y.atan2(r.x)) * tilt).normalize()
}

/// J = ∂ω/∂μ at q for the viscous model, μ the small rotation exp(μ)q (central differences,
/// ε = 1e-6).
///
/// # Example
/// ```
/// use rollphase_core::analysis::rest::halting::{QualityGrid, halting_loops, is_stable_rest, rest_jacobian, rest_orientation};
/// use rollphase_core::dynamics::{Ramp, SphereViscous};
/// use rollphase_core::geometry::Body;
/// let paper = Body::paper_sphere(219, 0.25, 5)?;
/// let alpha = 0.9 * paper.alpha_star();
/// let Body::Sphere(body) = paper else { unreachable!() };
/// let loops = halting_loops(&body, &QualityGrid::new(&body, 31, 61), alpha, &|_| {})?;
/// // The classification of every segment is the sign of this Jacobian's eigenvalues.
/// let model = SphereViscous::new(&body, &Ramp::new(alpha, 0.0)?);
/// for s in &loops.segments {
///     let j = rest_jacobian(&model, rest_orientation(&body, s.midpoint()));
///     assert_eq!(is_stable_rest(j), s.stable);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn rest_jacobian(model: &SphereViscous, q: DQuat) -> DMat3 {
    let eps = 1e-6;
    let omega = |q: DQuat| model.observe(&SphereViscous::initial_state(q)).omega;
    let cols: Vec<DVec3> = [DVec3::X, DVec3::Y, DVec3::Z]
        .iter()
        .map(|e| {
            let plus = omega(DQuat::from_scaled_axis(*e * eps) * q);
            let minus = omega(DQuat::from_scaled_axis(-*e * eps) * q);
            (plus - minus) / (2.0 * eps)
        })
        .collect();
    DMat3::from_cols(cols[0], cols[1], cols[2])
}

/// Real parts of the eigenvalues of a 3×3 matrix (nalgebra's Schur decomposition).
///
/// # Example
///
/// ```
/// use glam::{DMat3, DVec3};
/// use rollphase_core::analysis::rest::halting::eigen_real_parts;
///
/// let mut e = eigen_real_parts(DMat3::from_diagonal(DVec3::new(-2.0, 0.0, 3.0)));
/// e.sort_by(f64::total_cmp);
/// assert!((e[0] + 2.0).abs() < 1e-12 && e[1].abs() < 1e-12 && (e[2] - 3.0).abs() < 1e-12);
/// ```
pub fn eigen_real_parts(m: DMat3) -> [f64; 3] {
    let cols = m.to_cols_array();
    let e = crate::numeric::linalg::eigenvalues(&nalgebra::DMatrix::from_column_slice(3, 3, &cols));
    [e[0].re, e[1].re, e[2].re]
}

/// Stable when the two eigenvalues other than the one nearest 0 (along the loop of rest
/// states) have negative real parts.
///
/// # Example
/// ```
/// use rollphase_core::analysis::rest::halting::is_stable_rest;
/// use rollphase_core::glam::{DMat3, DVec3};
/// // One eigenvalue near 0 (along the loop of rest states); the others decide.
/// assert!(is_stable_rest(DMat3::from_diagonal(DVec3::new(-0.3, 1e-9, -0.1))));
/// assert!(!is_stable_rest(DMat3::from_diagonal(DVec3::new(-0.3, 1e-9, 0.1))));
/// ```
pub fn is_stable_rest(j: DMat3) -> bool {
    let mut e = eigen_real_parts(j);
    e.sort_by(|x, y| x.abs().total_cmp(&y.abs()));
    e[1] < 0.0 && e[2] < 0.0
}

/// Whether a viscous run from `q`, a small rotation away from the rest orientation `rest`, stays
/// near it: it comes to rest (the verdict's rest, [`crate::analysis::verdict::state_at_rest`])
/// within `t_max` less than 0.05 rad from `rest`. A
/// neighbour on the (neutral) loop counts as near; an unstable point is left for good, either
/// rolling away or settling on a distant stable part of the loop.
///
/// # Example
/// ```
/// use rollphase_core::analysis::rest::halting::{QualityGrid, halting_loops, rest_orientation, returns_to_rest};
/// use rollphase_core::dynamics::{Ramp, SphereViscous};
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::{DQuat, DVec3};
/// let paper = Body::paper_sphere(219, 0.25, 5)?;
/// let alpha = 0.9 * paper.alpha_star();
/// let Body::Sphere(body) = paper else { unreachable!() };
/// let loops = halting_loops(&body, &QualityGrid::new(&body, 31, 61), alpha, &|_| {})?;
/// let stable = loops.segments.iter().find(|s| s.stable).unwrap();
/// let rest = rest_orientation(&body, stable.midpoint());
/// let kicked = DQuat::from_scaled_axis(DVec3::new(1e-4, -2e-4, 1.5e-4)) * rest;
/// let model = SphereViscous::new(&body, &Ramp::new(alpha, 0.0)?);
/// assert!(returns_to_rest(&model, kicked, rest, 400.0)?);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn returns_to_rest(
    model: &SphereViscous,
    q: DQuat,
    rest: DQuat,
    t_max: f64,
) -> Result<bool, IntegrateError> {
    let mut run = Run::new(
        model,
        0.0,
        SphereViscous::initial_state(q),
        Method::dop853(1e-10),
    )?;
    let mut returned = false;
    run.until::<IntegrateError>(t_max, u64::MAX, |st| {
        let y = st.y();
        let now = DQuat::from_xyzw(y[1], y[2], y[3], y[0]).normalize();
        if 2.0 * now.dot(rest).abs().min(1.0).acos() > 0.05 {
            return Ok(Flow::Stop);
        }
        returned = crate::analysis::verdict::state_at_rest(model, y);
        Ok(if returned { Flow::Stop } else { Flow::Continue })
    })?;
    Ok(returned)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Body;

    #[test]
    fn a_perfect_sphere_has_no_halting_loop() {
        let body = Sphere::perfect();
        let grid = QualityGrid::new(&body, 19, 37);
        let loops = halting_loops(&body, &grid, 0.1, &|_| {}).unwrap();
        assert!(loops.segments.is_empty());
        assert_eq!(loops.stable_fraction(), 0.0);
        assert_eq!(loops.stable_confirmed, [0, 0]);
    }

    #[test]
    fn the_body_rests_at_the_rest_orientation_of_a_loop_point() {
        let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5).unwrap() else {
            unreachable!()
        };
        let alpha = 0.1;
        let grid = QualityGrid::new(&body, 91, 181);
        let loops = halting_loops(&body, &grid, alpha, &|_| {}).unwrap();
        assert!(loops.segments.len() > 20);
        let model = SphereViscous::new(&body, &Ramp::new(alpha, 0.0).unwrap());
        // On Q = tan α the torque of gravity about the contact vanishes: ω is zero up to the
        // grid's interpolation of the level set (compare a rolling body's |ω| ~ 0.1).
        let worst = loops
            .segments
            .iter()
            .map(|s| {
                let q = rest_orientation(&body, s.midpoint());
                model
                    .observe(&SphereViscous::initial_state(q))
                    .omega
                    .length()
            })
            .fold(0.0, f64::max);
        assert!(worst < 1e-3, "|ω| at rest orientations up to {worst}");
    }
}
