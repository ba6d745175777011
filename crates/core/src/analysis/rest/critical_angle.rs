//! The critical angle α* = atan max Q, Q = |∇ ln r| (2D: r'/r, SI §1B; 3D: |∇_s ln r|, SI §2D),
//! and where the maximum is. Found by a dense search refined by Newton's method (2D: on Q' = 0
//! with the exact Q''; 3D: in a tangent chart), so α* is exact to round-off, not to a grid.

use glam::DVec3;
use serde::Serialize;

use crate::geometry::{
    Body, Disk, DiskMode, ShapeError, Sphere, first_convex_disk, refine_sphere, sphere,
    sphere_grid_size,
};

/// α* and its maximiser.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CriticalAngle {
    /// α* = atan Q* in radians.
    pub alpha_star: f64,
    /// Q* = max Q.
    pub q_star: f64,
    /// 2D: θ* ∈ [0, 2π). 3D: polar angle of the maximiser.
    pub theta: f64,
    /// 3D: azimuth of the maximiser; 0 in 2D.
    pub phi: f64,
    /// 3D: maximiser as a body-frame unit vector; zero in 2D.
    pub direction: [f64; 3],
    /// 2D: Q''(θ*) (< 0), which sets the prefactor of T ∝ (α − α*)^(−1/2); NaN in 3D.
    pub q_second_derivative: f64,
    /// A dented 2D body: the largest angle at which it can rest on a flat of its hull (a bridge
    /// over a dent), with the bridge's ends θ_a, θ_b; `None` for a convex body. α* is the
    /// larger of this and the curved parts' atan max Q.
    pub flat: Option<FlatRest>,
}

/// The steepest ramp on which a dented 2D body can rest on one of its hull's flats. The body
/// rests on a flat while the weight's line through the centre falls between its ends: from
/// α = atan Q(θ_a) (the line through P_a) to atan Q(θ_b) (through P_b), Q = r'/r of the curve at
/// the ends, so the flats extend the curved parts' range of rest up to their ends.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FlatRest {
    /// atan((L − foot)/height) of the bridge (rad): the weight's line through P_b.
    pub alpha: f64,
    /// Where resting on it starts: the weight's line through P_a (rad; may be negative: never).
    pub alpha_from: f64,
    /// Where the bridge leaves the curve.
    pub theta_a: f64,
    /// Where it meets it again.
    pub theta_b: f64,
    /// α* of the curved parts alone, their ends (which touch the flats) excluded.
    pub curve_alpha: f64,
}

impl Body {
    /// The critical angle α* = atan max|∇ ln r| (rad): above it no orientation can rest, so
    /// every start rolls. [`critical_angle`] also gives where the maximum is.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// assert!((body.alpha_star() - 0.1394).abs() < 1e-4);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn alpha_star(&self) -> f64 {
        critical_angle(self).alpha_star
    }
}

/// α* of a body, and where on it the maximum of |∇ ln r| is.
///
/// ```
/// use rollphase_core::analysis::critical_angle;
/// use rollphase_core::geometry::Body;
/// let ca = critical_angle(&Body::paper_disk(84, 0.12, 5)?);
/// assert!((ca.alpha_star - 0.0572145495).abs() < 1e-9);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn critical_angle(body: &Body) -> CriticalAngle {
    match body {
        Body::Disk(d) => disk_critical_angle(d),
        Body::Sphere(s) => {
            let grid = sphere::fibonacci_sphere(sphere_grid_size(s.max_degree()));
            let (u, q) = refine_sphere(|u: DVec3| s.surface(u).quality(), &grid);
            let (theta, phi) = sphere::angles(u);
            CriticalAngle {
                alpha_star: q.atan(),
                q_star: q,
                theta,
                phi,
                direction: u.to_array(),
                q_second_derivative: f64::NAN,
                flat: None,
            }
        }
    }
}

fn disk_critical_angle(d: &Disk) -> CriticalAngle {
    let n = 4096;
    let h = std::f64::consts::TAU / n as f64;
    let mut best = (0.0, f64::NEG_INFINITY);
    let hull = d.hull();
    // A printed outline's corners are far narrower than the grid: their own samples too.
    let corners = d
        .printed_outline()
        .map(|o| o.corner_samples(9))
        .unwrap_or_default();
    // A dented body rests only where it touches its hull: the dents' points never touch.
    for t in (0..n).map(|i| i as f64 * h).chain(corners) {
        if hull.bridge_at(t).is_some() {
            continue;
        }
        let q = d.jet(t).quality();
        if q > best.1 {
            best = (t, q);
        }
    }
    let mut theta = best.0;
    // Newton on Q'(θ) = 0, kept inside the bracketing grid cells.
    for _ in 0..50 {
        let j = d.jet(theta);
        let (q1, q2) = (j.quality_d1(), j.quality_d2());
        if q2 >= 0.0 {
            break;
        }
        let step = (q1 / q2).clamp(-h, h);
        theta -= step;
        if step.abs() < 1e-15 {
            break;
        }
    }
    let j = d.jet(theta);
    // (A refinement that wandered into a dent does not count.)
    let (theta, q) = if j.quality() >= best.1 && hull.bridge_at(theta).is_none() {
        (theta, j.quality())
    } else {
        best
    };
    // A curved part's ends need no candidate of their own: resting on a flat runs from the
    // weight's line through P_a (α = atan Q(θ_a)) to its line through P_b (atan Q(θ_b)), so
    // the flats below cover them.
    let curve = CriticalAngle {
        alpha_star: q.atan(),
        q_star: q,
        theta: theta.rem_euclid(std::f64::consts::TAU),
        phi: 0.0,
        direction: [0.0; 3],
        q_second_derivative: d.jet(theta).quality_d2(),
        flat: None,
    };
    let steepest = hull
        .bridges()
        .iter()
        .filter_map(|b| b.rest_angle().map(|a| (a, b)))
        .max_by(|x, y| x.0.total_cmp(&y.0));
    match steepest {
        None => curve,
        Some((alpha, b)) => {
            let flat = FlatRest {
                alpha,
                alpha_from: (-b.foot).atan2(b.height),
                theta_a: b.theta_a,
                theta_b: b.theta_b.rem_euclid(std::f64::consts::TAU),
                curve_alpha: curve.alpha_star,
            };
            if alpha > curve.alpha_star {
                // Resting on a flat: no √ law there (Q'' does not apply).
                CriticalAngle {
                    alpha_star: alpha,
                    q_star: alpha.tan(),
                    theta: b.theta_a,
                    q_second_derivative: f64::NAN,
                    flat: Some(flat),
                    ..curve
                }
            } else {
                CriticalAngle {
                    flat: Some(flat),
                    ..curve
                }
            }
        }
    }
}

/// `base` with all its mode amplitudes scaled by one factor, found by bisection, so that its α*
/// equals `target` (convexity not checked).
///
/// # Example
/// ```
/// use rollphase_core::analysis::rest::critical_angle::disk_with_alpha_star;
/// use rollphase_core::geometry::{Body, Disk, DiskMode};
/// let base = Disk::new(vec![DiskMode { l: 3, a: 0.2, phase: 0.4 }]);
/// let tuned = disk_with_alpha_star(&base, 0.1);
/// assert!((Body::Disk(tuned).alpha_star() - 0.1).abs() < 1e-9);
/// ```
pub fn disk_with_alpha_star(base: &Disk, target: f64) -> Disk {
    let scaled = |s: f64| {
        Disk::new(
            base.modes()
                .iter()
                .map(|m| DiskMode { a: m.a * s, ..*m })
                .collect(),
        )
    };
    let a_of = |s: f64| critical_angle(&Body::Disk(scaled(s))).alpha_star;
    let (mut lo, mut hi) = (0.0, 1.0);
    while a_of(hi) < target {
        hi *= 2.0;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if a_of(mid) < target {
            lo = mid
        } else {
            hi = mid
        }
    }
    scaled(0.5 * (lo + hi))
}

/// A strictly convex disk with α* = `target`, to compare a sphere with: the modes l = 2, 3 of
/// the first convex random disk from `seed` (σ = 0.08) rescaled ([`disk_with_alpha_star`]), or,
/// if that is not convex, the single mode r = 1 + (a/4) sin 2θ, whose
/// Q* = (a/2)/√(1 − a²/16) is inverted exactly.
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::rest::critical_angle::convex_disk_with_alpha_star;
/// use rollphase_core::geometry::Body;
/// let disk = Body::Disk(convex_disk_with_alpha_star(1, 0.14)?);
/// assert!((disk.alpha_star() - 0.14).abs() < 1e-9 && disk.is_convex());
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn convex_disk_with_alpha_star(seed: u64, target: f64) -> Result<Disk, ShapeError> {
    let base = first_convex_disk(seed, 0.08, 3)?.0;
    let d = disk_with_alpha_star(&base, target);
    if Body::Disk(d.clone()).check_convex().is_ok() {
        return Ok(d);
    }
    let q = target.tan();
    let a = 2.0 * q / (1.0 + q * q / 4.0).sqrt();
    let d = Disk::new(vec![DiskMode {
        l: 2,
        a,
        phase: 0.0,
    }]);
    Body::Disk(d.clone()).check_convex()?;
    Ok(d)
}

/// The first `n` of the paper authors' 3D bodies (σ = 0.25, l ≤ 5; numpy seeds 0, 1, 2, …) that
/// are strictly convex with `from` ≤ α* < `below`, with their seeds: the other bodies of the
/// cross-body statistics. Seeds are tried 64 at a time in parallel, up to 100 000.
///
/// # Example
///
/// ```
/// use rollphase_core::analysis::rest::critical_angle::paper_spheres_with_alpha_star;
/// use rollphase_core::geometry::Body;
/// let bodies = paper_spheres_with_alpha_star(2, 0.13, 0.15)?;
/// assert_eq!(bodies.len(), 2);
/// for (_, sphere) in bodies {
///     let alpha_star = Body::Sphere(sphere).alpha_star();
///     assert!((0.13..0.15).contains(&alpha_star));
/// }
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn paper_spheres_with_alpha_star(
    n: usize,
    from: f64,
    below: f64,
) -> Result<Vec<(u32, Sphere)>, ShapeError> {
    use rayon::prelude::*;
    let mut found = Vec::new();
    let chunk = 64u32;
    let mut next_seed = 0u32;
    while found.len() < n {
        let batch: Vec<Result<Option<(u32, Sphere)>, ShapeError>> = (0..chunk)
            .into_par_iter()
            .with_max_len(1)
            .map(|i| {
                let seed = next_seed + i;
                let b = crate::geometry::paper_sphere(seed, 0.25, 5)?;
                let body = Body::Sphere(b);
                if body.check_convex().is_err() {
                    return Ok(None);
                }
                let a = critical_angle(&body).alpha_star;
                let Body::Sphere(b) = body else {
                    unreachable!("built as a sphere above")
                };
                if a < from || a >= below {
                    return Ok(None);
                }
                Ok(Some((seed, b)))
            })
            .collect();
        for r in batch {
            if let Some(x) = r? {
                found.push(x);
            }
        }
        next_seed += chunk;
        if next_seed > 100_000 {
            return Err(ShapeError::TooFewBodies { n, from, below });
        }
    }
    found.truncate(n);
    Ok(found)
}
