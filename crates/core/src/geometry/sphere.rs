//! The 3D body: r(u) = 1 + Re Σ_{l≥2} Σ_m A_lm/(l(l+1)) Y_l^m(u) on the unit sphere (SI §2F), its
//! surface p(u) = r(u) u, outward normal, shape operator (Weingarten map), Gaussian curvature,
//! the quality factor Q = |∇_s ln r| (SI §2D), and the support point: the surface point whose
//! outward normal is a given direction, which is where the body touches a plane.
//!
//! Everything is computed in Cartesian form. r − 1 is one polynomial f(x, y, z) that equals the
//! sum of solid harmonics on the unit sphere ([`SpherePoly`]: z² eliminated, so one short loop
//! serves all degrees). From its jet at u, with P = I − u uᵀ and f_n = u·∇f, the sphere's own
//! derivatives follow, whatever the extension: ∇_s r = P ∇f and the covariant Hessian
//! Hess_s r = P H_f P − f_n P. The body is the zero set of F(x) = |x| − R(x) with R(x) =
//! r(x/|x|), the degree-0 extension, whose Hessian at u is H_R = Hess_s r − ∇_s r uᵀ − u ∇_s rᵀ
//! (Euler: H_R u = −∇R). At p = r u: ∇F = u − ∇_s r / r and H_F = (I − u uᵀ)/r − H_R(u)/r². The
//! shape operator is S = P H_F P / |∇F| on the tangent plane (P the projector onto it). No
//! (θ, φ) chart is involved, so the poles are ordinary points.

use glam::{DMat3, DVec3};

use super::harmonics::{ComplexPoly, SpherePoly, spherical_harmonic};

/// One spherical-harmonic coefficient A_lm = re + i·im.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereCoeff {
    /// Degree l ≥ 2.
    pub l: u32,
    /// Order −l ≤ m ≤ l.
    pub m: i32,
    /// Real part of A_lm.
    pub re: f64,
    /// Imaginary part of A_lm.
    pub im: f64,
}

/// Local geometry of the surface at the point above the unit direction u.
#[derive(Debug, Clone, Copy)]
pub struct SurfacePoint {
    /// Direction from the centre (unit).
    pub u: DVec3,
    /// Radius r(u).
    pub r: f64,
    /// Surface point p = r u (body frame).
    pub p: DVec3,
    /// Spherical gradient ∇_s r (tangent to the unit sphere at u).
    pub grad_s: DVec3,
    /// Outward unit normal.
    pub normal: DVec3,
    /// An orthonormal basis (e1, e2) of the tangent plane (`normal.any_orthonormal_pair()`).
    pub tangent: (DVec3, DVec3),
    /// The shape operator dn/dp in that basis, [[a, b], [b, c]] stored as [a, b, c].
    pub shape_in_tangent: [f64; 3],
}

impl SurfacePoint {
    /// An orthonormal basis (e1, e2) of the tangent plane.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::glam::DVec3;
    /// let p = random_sphere(1, 0.2, 4)?.surface(DVec3::new(0.3, -0.2, 0.9));
    /// let (e1, e2) = p.tangent_basis();
    /// assert!(e1.dot(p.normal).abs() < 1e-14 && e2.dot(p.normal).abs() < 1e-14 && e1.dot(e2).abs() < 1e-14);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn tangent_basis(&self) -> (DVec3, DVec3) {
        self.tangent
    }

    /// The shape operator in the tangent basis, [[a, b], [b, c]], with the basis.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::DVec3;
    /// // On the unit sphere the shape operator is the identity: a = c = 1, b = 0.
    /// let (a, b, c, _, _) = Sphere::perfect().surface(DVec3::Y).shape_2x2();
    /// assert!((a - 1.0).abs() < 1e-14 && b.abs() < 1e-14 && (c - 1.0).abs() < 1e-14);
    /// ```
    pub fn shape_2x2(&self) -> (f64, f64, f64, DVec3, DVec3) {
        let [a, b, c] = self.shape_in_tangent;
        let (e1, e2) = self.tangent;
        (a, b, c, e1, e2)
    }

    /// The shape operator as a 3×3 map (acts on tangent vectors; zero along the normal).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::glam::DVec3;
    /// let p = random_sphere(2, 0.2, 4)?.surface(DVec3::new(1.0, 0.5, -0.3));
    /// let s = p.shape_matrix();
    /// assert!((s * p.normal).length() < 1e-12, "zero along the normal");
    /// // Symmetric: ⟨S e1, e2⟩ = ⟨e1, S e2⟩.
    /// let (e1, e2) = p.tangent_basis();
    /// assert!(((s * e1).dot(e2) - e1.dot(s * e2)).abs() < 1e-12);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn shape_matrix(&self) -> DMat3 {
        let [a, b, c] = self.shape_in_tangent;
        let (e1, e2) = self.tangent;
        a * outer(e1, e1) + b * (outer(e1, e2) + outer(e2, e1)) + c * outer(e2, e2)
    }

    /// Gaussian curvature K = det S.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::DVec3;
    /// assert!((Sphere::perfect().surface(DVec3::Z).gaussian_curvature() - 1.0).abs() < 1e-14);
    /// ```
    pub fn gaussian_curvature(&self) -> f64 {
        let (a, b, c, _, _) = self.shape_2x2();
        a * c - b * b
    }

    /// Principal curvatures (k_min, k_max).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::glam::DVec3;
    /// let p = random_sphere(3, 0.2, 4)?.surface(DVec3::new(0.2, 0.7, 0.1));
    /// let (k_min, k_max) = p.principal_curvatures();
    /// assert!(k_min <= k_max && (k_min * k_max - p.gaussian_curvature()).abs() < 1e-12);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn principal_curvatures(&self) -> (f64, f64) {
        let (a, b, c, _, _) = self.shape_2x2();
        let mean = 0.5 * (a + c);
        let disc = (0.25 * (a - c) * (a - c) + b * b).sqrt();
        (mean - disc, mean + disc)
    }

    /// Q = |∇_s ln r| = |∇_s r| / r; the body can rest on this point iff Q ≥ tan α.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Sphere, random_sphere};
    /// use rollphase_core::glam::DVec3;
    /// assert_eq!(Sphere::perfect().surface(DVec3::X).quality(), 0.0);
    /// let p = random_sphere(1, 0.25, 5)?.surface(DVec3::new(0.1, 0.2, 0.9));
    /// assert!((p.quality() - p.grad_s.length() / p.r).abs() < 1e-15);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn quality(&self) -> f64 {
        self.grad_s.length() / self.r
    }

    /// Solves S v = w for a tangent vector w (the shape operator is invertible on a strictly
    /// convex body); returns a tangent vector.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::glam::DVec3;
    /// let p = random_sphere(1, 0.1, 3)?.surface(DVec3::new(0.4, -0.1, 0.8));
    /// let (e1, e2) = p.tangent_basis();
    /// let w = 0.3 * e1 - 0.7 * e2;
    /// assert!((p.shape_matrix() * p.solve_shape(w) - w).length() < 1e-12);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn solve_shape(&self, w: DVec3) -> DVec3 {
        let (a, b, c, e1, e2) = self.shape_2x2();
        let (w1, w2) = (w.dot(e1), w.dot(e2));
        let det = a * c - b * b;
        let x1 = (c * w1 - b * w2) / det;
        let x2 = (a * w2 - b * w1) / det;
        x1 * e1 + x2 * e2
    }
}

/// A star-shaped 3D body with ⟨r⟩ = 1.
#[derive(Debug, Clone)]
pub struct Sphere {
    coeffs: Vec<SphereCoeff>,
    /// r − 1 on the unit sphere.
    poly: SpherePoly,
}

/// Why the support point could not be found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupportFailure {
    /// Remaining |n − d| when Newton stopped.
    pub residual: f64,
}

impl Sphere {
    /// A body from validated coefficients (see [`crate::geometry::Body::from_shape`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Sphere, SphereCoeff};
    /// use rollphase_core::glam::DVec3;
    /// // r = 1 + Re A_20 Y_20 / 6 with A_20 = 0.6: longer along z than across.
    /// let s = Sphere::new(vec![SphereCoeff { l: 2, m: 0, re: 0.6, im: 0.0 }]);
    /// assert!(s.radius(DVec3::Z) > 1.0 && s.radius(DVec3::X) < 1.0);
    /// ```
    pub fn new(coeffs: Vec<SphereCoeff>) -> Self {
        let mut sum = ComplexPoly::default();
        for c in &coeffs {
            let s = 1.0 / (c.l * (c.l + 1)) as f64;
            sum.add_scaled(&spherical_harmonic(c.l, c.m), c.re * s, c.im * s);
        }
        let poly = SpherePoly::real_part_on_sphere(&sum);
        Self { coeffs, poly }
    }

    /// The perfect unit sphere.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::DVec3;
    /// let s = Sphere::perfect();
    /// assert_eq!((s.max_degree(), s.radius(DVec3::new(1.0, 2.0, 3.0).normalize())), (0, 1.0));
    /// ```
    pub fn perfect() -> Self {
        Self::new(Vec::new())
    }

    /// The largest degree l among the coefficients (0 for the perfect sphere).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
    /// assert_eq!(s.max_degree(), 5);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn max_degree(&self) -> u32 {
        self.coeffs.iter().map(|c| c.l).max().unwrap_or(0)
    }

    /// The coefficients.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Sphere, SphereCoeff};
    /// let c = SphereCoeff { l: 3, m: -2, re: 0.1, im: 0.2 };
    /// assert_eq!(Sphere::new(vec![c]).coeffs()[0].l, 3);
    /// ```
    pub fn coeffs(&self) -> &[SphereCoeff] {
        &self.coeffs
    }

    /// r(u) for a unit vector u.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::glam::DVec3;
    /// let s = random_sphere(5, 0.25, 5)?;
    /// let u = DVec3::new(1.0, 1.0, 0.0).normalize();
    /// assert_eq!(s.radius(u), s.surface(u).r);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn radius(&self, u: DVec3) -> f64 {
        1.0 + self.poly.value(u.x, u.y, u.z)
    }

    /// r(θ, φ) with θ polar and φ azimuth.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::geometry::sphere::direction;
    /// let s = random_sphere(5, 0.25, 5)?;
    /// assert!((s.radius_at(1.0, 2.0) - s.radius(direction(1.0, 2.0))).abs() < 1e-14);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn radius_at(&self, theta: f64, phi: f64) -> f64 {
        self.radius(direction(theta, phi))
    }

    /// Full local geometry above the direction `u` (normalised here).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::glam::DVec3;
    /// let p = random_sphere(4, 0.2, 4)?.surface(DVec3::new(0.0, 3.0, 4.0)); // normalised here
    /// assert!((p.u - DVec3::new(0.0, 0.6, 0.8)).length() < 1e-15);
    /// assert!((p.p - p.r * p.u).length() < 1e-15 && (p.normal.length() - 1.0).abs() < 1e-14);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn surface(&self, u: DVec3) -> SurfacePoint {
        let u = u.normalize();
        let j = self.poly.jet(u.x, u.y, u.z);
        let r = 1.0 + j.value;
        let grad_poly = DVec3::from_array(j.grad);
        let f_n = u.dot(grad_poly);
        let grad = grad_poly - f_n * u;
        // ∇F at p = r u (degree-0 scaling: ∇R(p) = ∇R(u)/r, H_R(p) = H_R(u)/r²).
        let grad_f = u - grad / r;
        let gn = grad_f.length();
        let normal = grad_f / gn;
        let (e1, e2) = normal.any_orthonormal_pair();
        // S = P H_F P / |∇F| needs only e_iᵀ H_F e_j, and with t_i = (I − u uᵀ) e_i:
        // e_iᵀ H_R e_j = t_iᵀ H_f t_j − f_n t_i·t_j − (g·e_i)(u·e_j) − (u·e_i)(g·e_j),
        // e_iᵀ H_F e_j = t_i·t_j / r − e_iᵀ H_R e_j / r². Two matrix-vector products in all.
        let hess_poly = DMat3::from_cols_array_2d(&j.hess);
        let (u1, u2) = (u.dot(e1), u.dot(e2));
        let (g1, g2) = (grad.dot(e1), grad.dot(e2));
        let (t1, t2) = (e1 - u1 * u, e2 - u2 * u);
        let (h_t1, h_t2) = (hess_poly * t1, hess_poly * t2);
        let h_f = |tt: f64, tht: f64, gu: f64| (tt / r - (tht - f_n * tt - gu) / (r * r)) / gn;
        let a = h_f(t1.dot(t1), t1.dot(h_t1), 2.0 * g1 * u1);
        let b = h_f(
            t1.dot(t2),
            0.5 * (t1.dot(h_t2) + t2.dot(h_t1)),
            g1 * u2 + u1 * g2,
        );
        let c = h_f(t2.dot(t2), t2.dot(h_t2), 2.0 * g2 * u2);
        SurfacePoint {
            u,
            r,
            p: r * u,
            grad_s: grad,
            normal,
            tangent: (e1, e2),
            shape_in_tangent: [a, b, c],
        }
    }

    /// The surface point whose outward normal is the unit vector `d`: the point of contact with
    /// a plane whose inward normal is −d. Newton's method on the Gauss map from `guess`
    /// (use `d` when nothing better is known): solve S δp = d − (d·n)n in the tangent plane, move
    /// along the ray through p + δp, repeat. Quadratic convergence; 2–3 iterations from the
    /// previous contact during a simulation. Unique on a strictly convex body.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::glam::DVec3;
    /// let s = random_sphere(1, 0.2, 4)?;
    /// let d = DVec3::new(0.3, -0.5, -0.8).normalize();
    /// let contact = s.support_point(d, d).unwrap();
    /// assert!((contact.normal - d).length() < 1e-12);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn support_point(&self, d: DVec3, guess: DVec3) -> Result<SurfacePoint, SupportFailure> {
        self.support_point_from(d, self.surface(guess))
    }

    /// [`Sphere::support_point`] starting from a surface point already evaluated (the previous
    /// contact during a run): its geometry gives the first Newton step for free, which saves one
    /// of the three or four surface evaluations a warm-started solve needs.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::random_sphere;
    /// use rollphase_core::glam::DVec3;
    /// let s = random_sphere(1, 0.2, 4)?;
    /// let (d0, d1) = (DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.05, 0.0, -1.0).normalize());
    /// // The previous contact warm-starts the next one, as during a run.
    /// let previous = s.support_point(d0, d0).unwrap();
    /// let next = s.support_point_from(d1, previous).unwrap();
    /// assert!((next.normal - d1).length() < 1e-12);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn support_point_from(
        &self,
        d: DVec3,
        start: SurfacePoint,
    ) -> Result<SurfacePoint, SupportFailure> {
        let mut sp = start;
        let mut last = f64::INFINITY;
        for _ in 0..60 {
            let residual = (sp.normal - d).length();
            if residual <= 2e-15 || (residual <= 1e-12 && residual >= 0.5 * last) {
                return Ok(sp);
            }
            last = residual;
            let w = d - d.dot(sp.normal) * sp.normal;
            let (a, b, c, e1, e2) = sp.shape_2x2();
            let det = a * c - b * b;
            let mut step = if det > 1e-12 && a > 0.0 {
                let (w1, w2) = (w.dot(e1), w.dot(e2));
                ((c * w1 - b * w2) / det) * e1 + ((a * w2 - b * w1) / det) * e2
            } else {
                // Not locally convex here: fall back to a gradient step toward d.
                w * sp.r
            };
            if d.dot(sp.normal) < 0.0 {
                // Far on the wrong side: jump toward the direction itself.
                step = d * sp.r - sp.p;
            }
            let len = step.length();
            if len > 0.5 {
                step *= 0.5 / len;
            }
            sp = self.surface(sp.p + step);
        }
        let residual = (sp.normal - d).length();
        if residual <= 1e-10 {
            Ok(sp)
        } else {
            Err(SupportFailure { residual })
        }
    }
}

/// Unit vector for polar angle θ and azimuth φ.
///
/// # Example
/// ```
/// use rollphase_core::geometry::sphere::direction;
/// use rollphase_core::glam::DVec3;
/// assert!((direction(std::f64::consts::FRAC_PI_2, 0.0) - DVec3::X).length() < 1e-15);
/// assert_eq!(direction(0.0, 1.0).z, 1.0);
/// ```
pub fn direction(theta: f64, phi: f64) -> DVec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    DVec3::new(st * cp, st * sp, ct)
}

/// (θ, φ) of a unit vector, θ ∈ [0, π], φ ∈ (−π, π].
///
/// # Example
/// ```
/// use rollphase_core::geometry::sphere::{angles, direction};
/// let (theta, phi) = angles(direction(0.8, -2.5));
/// assert!((theta - 0.8).abs() < 1e-14 && (phi + 2.5).abs() < 1e-14);
/// ```
pub fn angles(u: DVec3) -> (f64, f64) {
    let u = u.normalize();
    (u.z.clamp(-1.0, 1.0).acos(), u.y.atan2(u.x))
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// `n` nearly uniform unit vectors (Fibonacci lattice), deterministic.
///
/// # Example
/// ```
/// use rollphase_core::geometry::sphere::fibonacci_sphere;
/// let points = fibonacci_sphere(1000);
/// assert!(points.iter().all(|u| (u.length() - 1.0).abs() < 1e-14));
/// // Nearly uniform: the mean is near the centre.
/// let mean = points.iter().sum::<rollphase_core::glam::DVec3>() / 1000.0;
/// assert!(mean.length() < 1e-2);
/// ```
pub fn fibonacci_sphere(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let rho = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            DVec3::new(rho * phi.cos(), rho * phi.sin(), z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lumpy() -> Sphere {
        Sphere::new(vec![
            SphereCoeff {
                l: 2,
                m: 0,
                re: 0.3,
                im: 0.0,
            },
            SphereCoeff {
                l: 2,
                m: 1,
                re: 0.1,
                im: -0.2,
            },
            SphereCoeff {
                l: 3,
                m: -2,
                re: 0.2,
                im: 0.1,
            },
            SphereCoeff {
                l: 5,
                m: 4,
                re: -0.25,
                im: 0.05,
            },
        ])
    }

    #[test]
    fn unit_sphere_geometry() {
        let s = Sphere::perfect();
        let sp = s.surface(DVec3::new(0.3, -0.4, 0.8));
        assert!((sp.r - 1.0).abs() < 1e-15);
        assert!((sp.normal - sp.u).length() < 1e-15);
        assert!((sp.gaussian_curvature() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn normal_matches_finite_differences_of_the_surface() {
        let s = lumpy();
        for u in fibonacci_sphere(40) {
            let sp = s.surface(u);
            let (e1, e2) = u.any_orthonormal_pair();
            let h = 1e-6;
            let p = |v: DVec3| {
                let v = v.normalize();
                s.radius(v) * v
            };
            let t1 = (p(u + h * e1) - p(u - h * e1)) / (2.0 * h);
            let t2 = (p(u + h * e2) - p(u - h * e2)) / (2.0 * h);
            let n = t1.cross(t2).normalize();
            assert!((n - sp.normal).length() < 1e-8, "{n} vs {}", sp.normal);
        }
    }

    #[test]
    fn shape_operator_matches_finite_differences_of_the_normal() {
        let s = lumpy();
        for u in fibonacci_sphere(30) {
            let sp = s.surface(u);
            let (e1, _) = sp.tangent_basis();
            // move along the surface in tangent direction e1
            let h = 1e-6;
            let pa = sp.p + h * e1;
            let pb = sp.p - h * e1;
            let na = s.surface(pa).normal;
            let nb = s.surface(pb).normal;
            let dn = (na - nb) / (2.0 * h);
            let expected = sp.shape_matrix() * e1;
            assert!((dn - expected).length() < 1e-6, "{dn} vs {expected}");
        }
    }

    #[test]
    fn support_point_has_the_requested_normal() {
        let s = lumpy();
        for d in fibonacci_sphere(200) {
            let sp = s.support_point(d, d).expect("converges");
            assert!((sp.normal - d).length() < 1e-13);
        }
    }
}
