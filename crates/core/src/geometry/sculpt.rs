//! Sculpting a body by hand: a smooth bump (pulled out) or dent (pressed in) at a point of its
//! surface, mapped by least squares onto the body's own harmonics, so the result is again a body
//! of the model's family (modes l = 2 … L, L the body's degree) and every check applies to it.
//!
//! The stroke's profile is f(γ) = exp((cos γ − 1)/w²) in the angle γ from the point: a Gaussian
//! of width w near it, smooth all the way round. On
//! the sphere the least-squares fit of a function of γ alone onto the harmonics of degree ≤ L is
//! its Legendre series cut at L, and by the addition theorem P_l(u·u₀) = 4π/(2l+1) Σ_m
//! Y_lm(u) Y*_lm(u₀), so the coefficients are closed-form: ΔA_lm = l(l+1) g_l 4π/(2l+1)
//! Y*_lm(u₀). On the circle the fit is the Fourier series cut at L, cos l(θ − θ₀) folded into
//! the disk's sine form. Degrees 0 and 1 are left out, as the model's family leaves them out:
//! the mean radius stays 1 and the centre stays put, so pressing in one place lifts the rest.
//! The fit is scaled so that the surface moves by exactly the stroke's height at the point. It is
//! only as local as the body's degree allows: a stroke narrower than about π/L is drawn as
//! wide as π/L (on the paper's L = 5 body, widths 0.05 to 0.2 rad give nearly the same stroke),
//! and on a sphere a stroke wider than about 0.7 rad moves the far side by half its height or
//! more, the same way (a reviewer's measurement, 2026-12-02).
//!
//! Why our own: the fit is the closed form above (a quadrature of one profile and the
//! harmonics the body already uses), which no crate offers for these bodies.

use glam::DVec3;
use thiserror::Error;

use super::harmonics::spherical_harmonic;
use super::{Body, Disk, DiskMode, MAX_DISK_L, MAX_SPHERE_L, ShapeError, Sphere, SphereCoeff};
use crate::numeric::quadrature::gauss_legendre;

/// The narrowest stroke, in radians of the angle from its point.
pub const MIN_STROKE_WIDTH: f64 = 0.05;
/// The widest stroke (rad): wider, the profile is mostly degree 0, which the family leaves out.
pub const MAX_STROKE_WIDTH: f64 = 1.0;
/// The largest move of the surface one stroke may make, in ⟨r⟩.
pub const MAX_STROKE_HEIGHT: f64 = 0.3;
/// The degree a round body (no modes) is sculpted in: the paper's l ≤ 5.
pub const ROUND_BODY_DEGREE: u32 = 5;

/// Where a stroke lands: a body point, in the body's own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StrokePoint {
    /// A cylinder's contour at polar angle θ (rad), as `r(θ)` counts it.
    Disk {
        /// The polar angle.
        theta: f64,
    },
    /// A 3D body's surface above the direction `u` (normalised here).
    Sphere {
        /// The direction from the centre.
        u: DVec3,
    },
}

/// One stroke: how far the surface moves at the point and how wide the move is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stroke {
    /// The body point under the stroke.
    pub at: StrokePoint,
    /// The Gaussian's width w (rad), in [`MIN_STROKE_WIDTH`, `MAX_STROKE_WIDTH`].
    pub width: f64,
    /// How far the surface moves at the point, in ⟨r⟩: > 0 pulls a bump out, < 0 presses a
    /// dent in; 0 < |height| ≤ [`MAX_STROKE_HEIGHT`].
    pub height: f64,
}

/// Why a stroke was refused.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SculptError {
    /// A number of the stroke outside what is allowed.
    #[error("stroke {what} = {value} is not allowed (needs {allowed})")]
    BadStroke {
        /// "width", "height", "point".
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        allowed: String,
    },
    /// The stroke's point is of the other dimension than the body.
    #[error("a {point} stroke cannot sculpt a {body}")]
    WrongDimension {
        /// The stroke's kind.
        point: &'static str,
        /// The body's kind.
        body: &'static str,
    },
    /// The sculpted body would not be strictly convex (the model needs it): the stroke is
    /// refused and the body stays as it was.
    #[error(
        "refused: the body would not be strictly convex ({0}); try a smaller height or a wider stroke"
    )]
    NotConvex(ShapeError),
    /// A body given whole (the mode panel's values) that is not a body of the family.
    #[error("refused: {0}")]
    NotABody(ShapeError),
}

impl Stroke {
    /// Checks the stroke's numbers before any work.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::sculpt::{Stroke, StrokePoint};
    /// let ok = Stroke { at: StrokePoint::Disk { theta: 0.3 }, width: 0.3, height: -0.02 };
    /// assert!(ok.validate().is_ok());
    /// let e = Stroke { height: f64::NAN, ..ok }.validate().unwrap_err().to_string();
    /// assert!(e.contains("height = NaN"), "{e}");
    /// ```
    pub fn validate(&self) -> Result<(), SculptError> {
        if !(MIN_STROKE_WIDTH..=MAX_STROKE_WIDTH).contains(&self.width) {
            return Err(SculptError::BadStroke {
                what: "width",
                value: self.width,
                allowed: format!("{MIN_STROKE_WIDTH} ≤ width ≤ {MAX_STROKE_WIDTH} rad"),
            });
        }
        if !(self.height.abs() <= MAX_STROKE_HEIGHT && self.height != 0.0) {
            return Err(SculptError::BadStroke {
                what: "height",
                value: self.height,
                allowed: format!("0 < |height| ≤ {MAX_STROKE_HEIGHT} ⟨r⟩"),
            });
        }
        let finite = match self.at {
            StrokePoint::Disk { theta } => theta.is_finite().then_some(theta),
            StrokePoint::Sphere { u } => (u.is_finite() && u.length() > 1e-12).then_some(0.0),
        };
        if finite.is_none() {
            let value = match self.at {
                StrokePoint::Disk { theta } => theta,
                StrokePoint::Sphere { u } => u.length(),
            };
            return Err(SculptError::BadStroke {
                what: "point",
                value,
                allowed: "a finite angle, or a finite non-zero direction".into(),
            });
        }
        Ok(())
    }
}

/// The body after `stroke`, or why it was refused (the body unchanged). The result has the
/// body's degree (or [`ROUND_BODY_DEGREE`] for a round one), one coefficient per mode, no
/// printed section (it is no longer that print), and is strictly convex.
///
/// # Example
/// ```
/// use rollphase_core::geometry::Body;
/// use rollphase_core::geometry::sculpt::{Stroke, StrokePoint, sculpt};
/// use rollphase_core::glam::DVec3;
/// let ball = Body::random_sphere(1, 0.1, 4)?;
/// let Body::Sphere(before) = &ball else { unreachable!() };
/// let u = DVec3::new(0.0, 0.6, 0.8);
/// let stroke = Stroke { at: StrokePoint::Sphere { u }, width: 0.4, height: -0.03 };
/// let Body::Sphere(after) = sculpt(&ball, &stroke)? else { unreachable!() };
/// // Pressed in by exactly 0.03 at the point.
/// assert!((after.radius(u) - before.radius(u) + 0.03).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sculpt(body: &Body, stroke: &Stroke) -> Result<Body, SculptError> {
    stroke.validate()?;
    let sculpted = match (body, stroke.at) {
        (Body::Disk(d), StrokePoint::Disk { theta }) => {
            Body::Disk(sculpt_disk(d, theta, stroke.width, stroke.height))
        }
        (Body::Sphere(s), StrokePoint::Sphere { u }) => {
            Body::Sphere(sculpt_sphere(s, u.normalize(), stroke.width, stroke.height))
        }
        (Body::Disk(_), StrokePoint::Sphere { .. }) => {
            return Err(SculptError::WrongDimension {
                point: "3D",
                body: "cylinder",
            });
        }
        (Body::Sphere(_), StrokePoint::Disk { .. }) => {
            return Err(SculptError::WrongDimension {
                point: "2D",
                body: "3D body",
            });
        }
    };
    sculpted.check_convex().map_err(SculptError::NotConvex)?;
    Ok(sculpted)
}

/// The stroke's profile at angle `gamma` from its point: exp((cos γ − 1)/w²), a Gaussian of
/// width w near the point (cos γ − 1 ≈ −γ²/2) that is smooth all the way round. A Gaussian in γ
/// itself has a kink at the far side (γ = π), whose modes fall off only as 1/l²: on a body of
/// high degree a wide stroke then dented the far side.
fn profile(gamma: f64, width: f64) -> f64 {
    ((gamma.cos() - 1.0) / (width * width)).exp()
}

/// Legendre coefficients g_l (l = 0 … `degree`) of f(γ) on the sphere:
/// g_l = (2l+1)/2 ∫₀^π f(γ) P_l(cos γ) sin γ dγ, by 256-point Gauss–Legendre in γ (the
/// integrand is smooth in γ, not in cos γ at γ = π).
fn legendre_coefficients(f: impl Fn(f64) -> f64, degree: usize) -> Vec<f64> {
    let (nodes, weights) = gauss_legendre(256);
    let half_pi = 0.5 * std::f64::consts::PI;
    let mut g = vec![0.0; degree + 1];
    for (x, w) in nodes.iter().zip(&weights) {
        let gamma = half_pi * (x + 1.0);
        let (s, c) = gamma.sin_cos();
        let weight = w * half_pi * f(gamma) * s;
        let (mut p0, mut p1) = (1.0, c);
        for (l, gl) in g.iter_mut().enumerate() {
            let p = if l == 0 { p0 } else { p1 };
            *gl += weight * p;
            if l >= 1 {
                let p2 = ((2 * l + 1) as f64 * c * p1 - l as f64 * p0) / (l + 1) as f64;
                p0 = p1;
                p1 = p2;
            }
        }
    }
    g.iter()
        .enumerate()
        .map(|(l, gl)| (2 * l + 1) as f64 / 2.0 * gl)
        .collect()
}

/// Fourier cosine coefficients c_l (l = 0 … `degree`) of f(φ) on the circle, f even:
/// c_l = (1/π) ∫_{−π}^{π} f(φ) cos lφ dφ (c₀ halved), by the 4096-point trapezoid rule
/// (spectrally accurate for a smooth periodic integrand).
fn cosine_coefficients(f: impl Fn(f64) -> f64, degree: usize) -> Vec<f64> {
    let n = 4096;
    let h = std::f64::consts::TAU / n as f64;
    let mut c = vec![0.0; degree + 1];
    for i in 0..n {
        let phi = -std::f64::consts::PI + i as f64 * h;
        let v = f(phi) * h / std::f64::consts::PI;
        for (l, cl) in c.iter_mut().enumerate() {
            *cl += v * (l as f64 * phi).cos();
        }
    }
    c[0] *= 0.5;
    c
}

/// The degree a body is sculpted in.
fn sculpt_degree(body_degree: u32, max: u32) -> u32 {
    if body_degree < 2 {
        ROUND_BODY_DEGREE
    } else {
        body_degree.min(max)
    }
}

fn sculpt_sphere(s: &Sphere, u0: DVec3, width: f64, height: f64) -> Sphere {
    let degree = sculpt_degree(s.max_degree(), MAX_SPHERE_L);
    let g = legendre_coefficients(|gamma| profile(gamma, width), degree as usize);
    // The cut series' value at the point: Σ_{l≥2} g_l P_l(1).
    let peak: f64 = g[2..].iter().sum();
    let scale = height / peak;
    let mut coeffs: Vec<SphereCoeff> = Vec::new();
    let mut add =
        |l: u32, m: i32, re: f64, im: f64| match coeffs.iter_mut().find(|c| c.l == l && c.m == m) {
            Some(c) => {
                c.re += re;
                c.im += im;
            }
            None => coeffs.push(SphereCoeff { l, m, re, im }),
        };
    for c in s.coeffs() {
        add(c.l, c.m, c.re, c.im);
    }
    for l in 2..=degree {
        let k = (l * (l + 1)) as f64 * scale * g[l as usize] * 4.0 * std::f64::consts::PI
            / (2 * l + 1) as f64;
        for m in -(l as i32)..=l as i32 {
            let (yr, yi) = spherical_harmonic(l, m).eval(u0.x, u0.y, u0.z);
            // The conjugate of Y_lm(u₀).
            add(l, m, k * yr, -k * yi);
        }
    }
    Sphere::new(coeffs)
}

fn sculpt_disk(d: &Disk, theta0: f64, width: f64, height: f64) -> Disk {
    let max_l = d.modes().iter().map(|m| m.l).max().unwrap_or(0);
    let degree = sculpt_degree(max_l, MAX_DISK_L);
    let c = cosine_coefficients(|phi| profile(phi, width), degree as usize);
    let peak: f64 = c[2..].iter().sum();
    let scale = height / peak;
    // Each mode as S sin lθ + C cos lθ of the radius (a_l/l² sin l(θ − θ_l) expanded).
    let mut sc = vec![(0.0, 0.0); degree as usize + 1];
    let mut kept: Vec<DiskMode> = Vec::new();
    for m in d.modes() {
        if m.l > degree {
            kept.push(*m);
            continue;
        }
        let r = m.a / (m.l * m.l) as f64;
        let lp = m.l as f64 * m.phase;
        let e = &mut sc[m.l as usize];
        e.0 += r * lp.cos();
        e.1 -= r * lp.sin();
    }
    for l in 2..=degree as usize {
        let k = scale * c[l];
        let lt = l as f64 * theta0;
        sc[l].0 += k * lt.sin();
        sc[l].1 += k * lt.cos();
    }
    let mut modes: Vec<DiskMode> = (2..=degree)
        .filter_map(|l| {
            let (s, c) = sc[l as usize];
            let r = s.hypot(c);
            (r > 0.0).then(|| DiskMode {
                l,
                a: r * (l * l) as f64,
                phase: (-c).atan2(s) / l as f64,
            })
        })
        .collect();
    modes.extend(kept);
    Disk::new(modes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::sphere::fibonacci_sphere;
    use std::f64::consts::PI;

    #[test]
    fn the_coefficients_of_a_harmonic_profile_are_that_harmonic() {
        // P_3(cos γ) has Legendre coefficients δ_l3; cos 4φ has Fourier coefficients δ_l4.
        let p3 = |g: f64| {
            let x = g.cos();
            0.5 * (5.0 * x * x * x - 3.0 * x)
        };
        let g = legendre_coefficients(p3, 6);
        for (l, gl) in g.iter().enumerate() {
            let want = if l == 3 { 1.0 } else { 0.0 };
            assert!((gl - want).abs() < 1e-13, "g_{l} = {gl}");
        }
        let c = cosine_coefficients(|p: f64| (4.0 * p).cos(), 6);
        for (l, cl) in c.iter().enumerate() {
            let want = if l == 4 { 1.0 } else { 0.0 };
            assert!((cl - want).abs() < 1e-13, "c_{l} = {cl}");
        }
    }

    fn sphere() -> Body {
        Body::random_sphere(3, 0.1, 5).unwrap()
    }

    #[test]
    fn a_sphere_stroke_moves_the_point_by_its_height_keeps_the_mean_and_is_round_about_it() {
        let body = sphere();
        let Body::Sphere(before) = &body else {
            unreachable!()
        };
        let u0 = DVec3::new(0.3, -0.5, 0.8).normalize();
        let stroke = Stroke {
            at: StrokePoint::Sphere { u: u0 },
            width: 0.35,
            height: 0.04,
        };
        let Body::Sphere(after) = sculpt(&body, &stroke).unwrap() else {
            unreachable!()
        };
        let dr = |u: DVec3| after.radius(u) - before.radius(u);
        assert!((dr(u0) - 0.04).abs() < 1e-12, "{}", dr(u0));
        // The mean radius over the sphere is unchanged (no degree 0): a nearly uniform grid's
        // mean of Δr is 0 to its quadrature error.
        let grid = fibonacci_sphere(20_000);
        let mean = grid.iter().map(|&u| dr(u)).sum::<f64>() / grid.len() as f64;
        assert!(mean.abs() < 1e-5, "mean Δr = {mean}");
        // Δr depends on the angle from u₀ alone: the same at points turned about u₀.
        let side = u0.any_orthonormal_vector();
        let q = glam::DQuat::from_axis_angle(u0, 1.1);
        for gamma in [0.2, 0.7, 1.5, 2.8] {
            let p = glam::DQuat::from_axis_angle(side, gamma) * u0;
            assert!((dr(p) - dr(q * p)).abs() < 1e-12, "γ = {gamma}");
        }
        // Highest at the point, and each coefficient given once.
        assert!(grid.iter().all(|&u| dr(u) <= 0.04 + 1e-12));
        let mut keys: Vec<(u32, i32)> = after.coeffs().iter().map(|c| (c.l, c.m)).collect();
        keys.sort_unstable();
        keys.dedup();
        assert_eq!(keys.len(), after.coeffs().len());
        assert_eq!(after.max_degree(), 5);
    }

    #[test]
    fn a_disk_stroke_moves_the_point_by_its_height_and_is_even_about_it() {
        let body = Body::random_disk(2, 0.1, 6).unwrap();
        let Body::Disk(before) = &body else {
            unreachable!()
        };
        let t0 = 2.2;
        let stroke = Stroke {
            at: StrokePoint::Disk { theta: t0 },
            width: 0.3,
            height: -0.05,
        };
        let Body::Disk(after) = sculpt(&body, &stroke).unwrap() else {
            unreachable!()
        };
        let dr = |t: f64| after.jet(t).r - before.jet(t).r;
        assert!((dr(t0) + 0.05).abs() < 1e-12, "{}", dr(t0));
        for d in [0.1, 0.5, 1.3, 3.0] {
            assert!((dr(t0 + d) - dr(t0 - d)).abs() < 1e-12, "±{d}");
        }
        let n = 4096;
        let mean = (0..n)
            .map(|i| dr(i as f64 * 2.0 * PI / n as f64))
            .sum::<f64>()
            / n as f64;
        assert!(mean.abs() < 1e-13, "mean Δr = {mean}");
        assert!(after.modes().iter().all(|m| (2..=6).contains(&m.l)));
        assert_eq!(after.modes().len(), 5);
    }

    #[test]
    fn a_stroke_and_its_opposite_give_the_body_back() {
        let body = Body::random_disk(2, 0.1, 6).unwrap();
        let at = StrokePoint::Disk { theta: 1.0 };
        let push = Stroke {
            at,
            width: 0.5,
            height: 0.03,
        };
        let back = sculpt(
            &sculpt(&body, &push).unwrap(),
            &Stroke {
                height: -0.03,
                ..push
            },
        )
        .unwrap();
        let (Body::Disk(a), Body::Disk(b)) = (&body, &back) else {
            unreachable!()
        };
        for i in 0..100 {
            let t = i as f64 * 0.0628;
            assert!((a.jet(t).r - b.jet(t).r).abs() < 1e-14);
        }
    }

    #[test]
    fn a_deep_narrow_dent_is_refused_with_why_and_bad_numbers_by_name() {
        let body = sphere();
        let dent = Stroke {
            at: StrokePoint::Sphere { u: DVec3::Z },
            width: 0.15,
            height: -0.3,
        };
        let e = sculpt(&body, &dent).unwrap_err();
        assert!(matches!(e, SculptError::NotConvex(_)), "{e}");
        assert!(e.to_string().contains("strictly convex"), "{e}");
        for (width, height, what) in [
            (0.0, 0.1, "width"),
            (f64::NAN, 0.1, "width"),
            (2.0, 0.1, "width"),
            (0.3, 0.0, "height"),
            (0.3, f64::INFINITY, "height"),
            (0.3, -0.31, "height"),
        ] {
            let e = sculpt(
                &body,
                &Stroke {
                    width,
                    height,
                    ..dent
                },
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains(&format!("stroke {what} = ")), "{e}");
        }
        let nowhere = Stroke {
            at: StrokePoint::Sphere { u: DVec3::ZERO },
            width: 0.3,
            height: 0.01,
        };
        assert!(
            sculpt(&body, &nowhere)
                .unwrap_err()
                .to_string()
                .contains("point")
        );
        let flat = Stroke {
            at: StrokePoint::Disk { theta: 0.0 },
            width: 0.3,
            height: 0.01,
        };
        assert!(matches!(
            sculpt(&body, &flat),
            Err(SculptError::WrongDimension { .. })
        ));
    }

    #[test]
    fn a_round_body_is_sculpted_in_the_papers_degree() {
        let ball = Body::Sphere(Sphere::new(Vec::new()));
        let stroke = Stroke {
            at: StrokePoint::Sphere { u: DVec3::X },
            width: 0.5,
            height: 0.02,
        };
        let Body::Sphere(s) = sculpt(&ball, &stroke).unwrap() else {
            unreachable!()
        };
        assert_eq!(s.max_degree(), ROUND_BODY_DEGREE);
        assert!((s.radius(DVec3::X) - 1.02).abs() < 1e-12);
    }
}
