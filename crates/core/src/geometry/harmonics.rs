//! Complex spherical harmonics Y_l^m (orthonormal, Condon–Shortley phase, θ polar, φ azimuth)
//! written as homogeneous polynomials in Cartesian (x, y, z), so that r(u) and its derivatives are
//! polynomials on the unit sphere with no singularity at the chart's poles θ = 0, π.
//!
//! On the unit sphere P_l^m(cos θ) e^{imφ} = (−1)^m (x + iy)^m P_l^{(m)}(z) for m ≥ 0 (P_l^{(m)} the
//! m-th derivative of the Legendre polynomial), and Y_l^{−m} = (−1)^m conj(Y_l^m). Each power z^k
//! of P_l^{(m)} is homogenised with (x² + y² + z²)^{(l−m−k)/2}, which is 1 on the sphere, so every
//! term has degree l; Euler's identity x·∇P = l P then gives the spherical gradient exactly.
//!
//! Why our own: sphrs overflows its factorials beyond l + |m| ≥ 21 and evaluates in (θ, φ); a
//! Cartesian form is what the contact solver needs (STACK.md).

use std::collections::BTreeMap;

/// Exponents (a, b, c) of x^a y^b z^c.
pub type Exponents = [u8; 3];

/// A complex polynomial as a map from exponents to (re, im).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ComplexPoly(pub BTreeMap<Exponents, (f64, f64)>);

impl ComplexPoly {
    fn constant(re: f64, im: f64) -> Self {
        let mut m = BTreeMap::new();
        m.insert([0, 0, 0], (re, im));
        Self(m)
    }

    fn add_term(&mut self, e: Exponents, re: f64, im: f64) {
        let entry = self.0.entry(e).or_insert((0.0, 0.0));
        entry.0 += re;
        entry.1 += im;
    }

    fn mul(&self, other: &Self) -> Self {
        let mut out = Self::default();
        for (ea, (ar, ai)) in &self.0 {
            for (eb, (br, bi)) in &other.0 {
                let e = [ea[0] + eb[0], ea[1] + eb[1], ea[2] + eb[2]];
                out.add_term(e, ar * br - ai * bi, ar * bi + ai * br);
            }
        }
        out
    }

    fn pow(&self, n: u32) -> Self {
        let mut out = Self::constant(1.0, 0.0);
        for _ in 0..n {
            out = out.mul(self);
        }
        out
    }

    /// Adds (re + i·im)·`other` to this polynomial.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::harmonics::spherical_harmonic;
    /// // Y_1^1 + conj-scaled Y_1^{−1}: 2 Re Y_1^1 = Y_1^1 − Y_1^{−1}.
    /// let mut p = spherical_harmonic(1, 1);
    /// p.add_scaled(&spherical_harmonic(1, -1), -1.0, 0.0);
    /// let (re, im) = p.eval(1.0, 0.0, 0.0);
    /// let expected = -2.0 * (3.0 / (8.0 * std::f64::consts::PI)).sqrt();
    /// assert!((re - expected).abs() < 1e-14 && im.abs() < 1e-14);
    /// ```
    pub fn add_scaled(&mut self, other: &Self, re: f64, im: f64) {
        for (e, (a, b)) in other.scale(re, im).0 {
            self.add_term(e, a, b);
        }
    }

    fn scale(&self, re: f64, im: f64) -> Self {
        Self(
            self.0
                .iter()
                .map(|(e, (a, b))| (*e, (a * re - b * im, a * im + b * re)))
                .collect(),
        )
    }

    /// Value at a point (x, y, z) as (re, im).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::harmonics::spherical_harmonic;
    /// // Y_1^0 = √(3/4π) z.
    /// let (re, im) = spherical_harmonic(1, 0).eval(0.0, 0.0, 1.0);
    /// assert!((re - (3.0 / (4.0 * std::f64::consts::PI)).sqrt()).abs() < 1e-15 && im == 0.0);
    /// ```
    pub fn eval(&self, x: f64, y: f64, z: f64) -> (f64, f64) {
        self.0.iter().fold((0.0, 0.0), |(sr, si), (e, (a, b))| {
            let m = x.powi(e[0] as i32) * y.powi(e[1] as i32) * z.powi(e[2] as i32);
            (sr + a * m, si + b * m)
        })
    }
}

fn factorial(n: u32) -> f64 {
    (1..=n).map(f64::from).product()
}

fn binomial(n: u32, k: u32) -> f64 {
    factorial(n) / (factorial(k) * factorial(n - k))
}

/// Coefficients c_k of z^k in the m-th derivative of the Legendre polynomial P_l.
fn legendre_derivative(l: u32, m: u32) -> Vec<f64> {
    let mut c = vec![0.0; l as usize + 1];
    // Rodrigues: P_l(z) = 2^{−l} Σ_k (−1)^k C(l,k) C(2l−2k, l) z^{l−2k}
    for k in 0..=l / 2 {
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        c[(l - 2 * k) as usize] +=
            sign * binomial(l, k) * binomial(2 * l - 2 * k, l) / 2f64.powi(l as i32);
    }
    for _ in 0..m {
        let mut d = vec![0.0; c.len()];
        for p in 1..c.len() {
            d[p - 1] = c[p] * p as f64;
        }
        c = d;
    }
    c
}

/// Y_l^m as a homogeneous complex polynomial of degree l (exact on the unit sphere).
///
/// # Example
/// ```
/// use rollphase_core::geometry::harmonics::spherical_harmonic;
/// use rollphase_core::geometry::sphere::fibonacci_sphere;
/// // Orthonormal on the sphere: the mean of |Y_3^2|² over nearly uniform points is 1/4π.
/// let y = spherical_harmonic(3, 2);
/// let points = fibonacci_sphere(20_000);
/// let mean: f64 = points.iter().map(|u| {
///     let (re, im) = y.eval(u.x, u.y, u.z);
///     re * re + im * im
/// }).sum::<f64>() / points.len() as f64;
/// assert!((mean * 4.0 * std::f64::consts::PI - 1.0).abs() < 1e-3);
/// ```
pub fn spherical_harmonic(l: u32, m: i32) -> ComplexPoly {
    let k = m.unsigned_abs();
    assert!(k <= l, "|m| ≤ l is checked by the shape validator");
    let norm = ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI) * factorial(l - k)
        / factorial(l + k))
    .sqrt();
    // (x ± iy)^k
    let mut xy = ComplexPoly::default();
    xy.add_term([1, 0, 0], 1.0, 0.0);
    xy.add_term([0, 1, 0], 0.0, if m >= 0 { 1.0 } else { -1.0 });
    let xy_k = xy.pow(k);
    // Homogenised P_l^{(k)}(z)
    let mut r2 = ComplexPoly::default();
    r2.add_term([2, 0, 0], 1.0, 0.0);
    r2.add_term([0, 2, 0], 1.0, 0.0);
    r2.add_term([0, 0, 2], 1.0, 0.0);
    let mut pz = ComplexPoly::default();
    let deg = l - k;
    for (p, c) in legendre_derivative(l, k).iter().enumerate() {
        if *c == 0.0 {
            continue;
        }
        let mut zp = ComplexPoly::default();
        zp.add_term([0, 0, p as u8], *c, 0.0);
        let fill = (deg - p as u32) / 2;
        for (e, (a, b)) in zp.mul(&r2.pow(fill)).0 {
            pz.add_term(e, a, b);
        }
    }
    // m ≥ 0: N (−1)^m (x+iy)^m P^{(m)}; m < 0: (−1)^k conj(Y_l^k) = N (x−iy)^k P^{(k)}.
    let sign = if m >= 0 && k % 2 == 1 { -1.0 } else { 1.0 };
    xy_k.mul(&pz).scale(sign * norm, 0.0)
}

/// Value, gradient and Hessian of a polynomial at one point.
#[derive(Debug, Clone, Copy, Default)]
pub struct PolyJet {
    /// f(x)
    pub value: f64,
    /// ∇f(x)
    pub grad: [f64; 3],
    /// Hessian of f, row-major (symmetric).
    pub hess: [[f64; 3]; 3],
}

/// Largest degree a [`SpherePoly`] may have.
pub const MAX_SPHERE_POLY_DEGREE: usize = 15;

/// A real polynomial on the unit sphere written as Σ_b y^b (A_b(x) + z B_b(x)): every z² of the
/// homogeneous solid harmonics replaced by 1 − x² − y², which is exact on the sphere. All degrees
/// of a body then share one polynomial with (L+1)(L+2)/2 coefficient pairs (21 for L = 5,
/// against 52 homogeneous monomials in four separate sums), evaluated with its first and second
/// derivatives by nested Horner schemes (in x inside, in y outside): about six multiply-adds per
/// pair and no power tables. This is what makes the contact solve cheap.
///
/// This form is a different extension off the sphere than the homogeneous one, so callers must
/// use only what the restriction to the sphere determines: the value, and the tangential
/// gradient and covariant Hessian built from the jet (see [`super::sphere`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SpherePoly {
    degree: usize,
    /// Row b holds A_b's coefficients for x^0..x^(L−b), then B_b's for the same powers.
    rows: Vec<Vec<f64>>,
}

/// p(x), p′(x) and p″(x)/2 of Σ_a c_a x^a by Horner's scheme.
#[inline(always)]
fn horner2(coeffs: &[f64], x: f64) -> (f64, f64, f64) {
    let (mut p, mut d1, mut d2) = (0.0, 0.0, 0.0);
    for &c in coeffs.iter().rev() {
        d2 = d2 * x + d1;
        d1 = d1 * x + p;
        p = p * x + c;
    }
    (p, d1, d2)
}

impl SpherePoly {
    /// Re of the complex polynomial `poly`, reduced on the sphere. Degrees above
    /// [`MAX_SPHERE_POLY_DEGREE`] are refused by the shape validator before this is reached.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::harmonics::{SpherePoly, spherical_harmonic};
    /// // Re Y_2^0 = √(5/16π)(3z² − 1), here with z² written as 1 − x² − y².
    /// let p = SpherePoly::real_part_on_sphere(&spherical_harmonic(2, 0));
    /// let z: f64 = 0.6;
    /// let exact = (5.0 / (16.0 * std::f64::consts::PI)).sqrt() * (3.0 * z * z - 1.0);
    /// assert!((p.value(0.8, 0.0, z) - exact).abs() < 1e-14);
    /// ```
    pub fn real_part_on_sphere(poly: &ComplexPoly) -> Self {
        let mut acc: BTreeMap<(u8, u8, bool), f64> = BTreeMap::new();
        let mut degree = 0;
        for (&[a, b, c], &(re, _)) in &poly.0 {
            if re == 0.0 {
                continue;
            }
            degree = degree.max(usize::from(a + b + c));
            // z^c = z^(c mod 2) (1 − x² − y²)^k, k = c div 2, by the trinomial theorem.
            let (k, odd) = (u32::from(c / 2), c % 2 == 1);
            for j in 0..=k {
                for m in 0..=k - j {
                    let i = k - j - m;
                    let multinomial = factorial(k) / (factorial(i) * factorial(j) * factorial(m));
                    let sign = if (j + m) % 2 == 0 { 1.0 } else { -1.0 };
                    let key = (a + 2 * j as u8, b + 2 * m as u8, odd);
                    *acc.entry(key).or_insert(0.0) += re * multinomial * sign;
                }
            }
        }
        assert!(
            degree <= MAX_SPHERE_POLY_DEGREE,
            "degree {degree} exceeds the supported {MAX_SPHERE_POLY_DEGREE}"
        );
        let mut rows: Vec<Vec<f64>> = (0..=degree)
            .map(|b| vec![0.0; 2 * (degree - b + 1)])
            .collect();
        for ((a, b, odd), c) in acc {
            let (a, b) = (usize::from(a), usize::from(b));
            let width = degree - b + 1;
            rows[b][a + if odd { width } else { 0 }] = c;
        }
        Self { degree, rows }
    }

    /// Value at a point.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::harmonics::{SpherePoly, spherical_harmonic};
    /// let poly = spherical_harmonic(4, 3);
    /// let p = SpherePoly::real_part_on_sphere(&poly);
    /// let u = rollphase_core::glam::DVec3::new(0.2, -0.5, 0.7).normalize();
    /// assert!((p.value(u.x, u.y, u.z) - poly.eval(u.x, u.y, u.z).0).abs() < 1e-14);
    /// ```
    pub fn value(&self, x: f64, y: f64, z: f64) -> f64 {
        self.rows.iter().rev().fold(0.0, |acc, row| {
            let (a, b) = row.split_at(row.len() / 2);
            let horner = |c: &[f64]| c.iter().rev().fold(0.0, |p, &c| p * x + c);
            acc * y + horner(a) + z * horner(b)
        })
    }

    /// Value, gradient and Hessian of this polynomial (as a function on R³) at a point.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::harmonics::{SpherePoly, spherical_harmonic};
    /// let p = SpherePoly::real_part_on_sphere(&spherical_harmonic(3, 1));
    /// let (x, y, z, h) = (0.3, 0.4, 0.5, 1e-6);
    /// let jet = p.jet(x, y, z);
    /// let d_dy = (p.value(x, y + h, z) - p.value(x, y - h, z)) / (2.0 * h);
    /// assert!((jet.grad[1] - d_dy).abs() < 1e-8);
    /// assert!((jet.hess[0][1] - jet.hess[1][0]).abs() < 1e-14);
    /// ```
    pub fn jet(&self, x: f64, y: f64, z: f64) -> PolyJet {
        // Outer Horner in y over the rows; each sequence needs its value and as many
        // y-derivatives as the Hessian asks for (d2 terms are halved second derivatives).
        let (mut w, mut w_y, mut w_yy) = (0.0, 0.0, 0.0);
        let (mut wx, mut wx_y) = (0.0, 0.0);
        let mut wxx = 0.0;
        let (mut bz, mut bz_y) = (0.0, 0.0);
        let mut bzx = 0.0;
        for row in self.rows.iter().rev() {
            let (a_coeffs, b_coeffs) = row.split_at(row.len() / 2);
            let (a0, a1, a2) = horner2(a_coeffs, x);
            let (b0, b1, b2) = horner2(b_coeffs, x);
            let (s0, s1, s2) = (a0 + z * b0, a1 + z * b1, 2.0 * (a2 + z * b2));
            w_yy = w_yy * y + w_y;
            w_y = w_y * y + w;
            w = w * y + s0;
            wx_y = wx_y * y + wx;
            wx = wx * y + s1;
            wxx = wxx * y + s2;
            bz_y = bz_y * y + bz;
            bz = bz * y + b0;
            bzx = bzx * y + b1;
        }
        let (fxy, fxz, fyz) = (wx_y, bzx, bz_y);
        PolyJet {
            value: w,
            grad: [wx, w_y, bz],
            hess: [[wxx, fxy, fxz], [fxy, 2.0 * w_yy, fyz], [fxz, fyz, 0.0]],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn at(theta: f64, phi: f64) -> (f64, f64, f64) {
        (
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    /// Reference values from the closed forms in standard tables (Condon–Shortley phase).
    #[test]
    fn matches_reference_table() {
        type Closed = Box<dyn Fn(f64, f64) -> (f64, f64)>;
        let cases: Vec<(u32, i32, Closed)> = vec![
            (
                2,
                0,
                Box::new(|t: f64, _p: f64| {
                    (
                        0.25 * (5.0 / PI).sqrt() * (3.0 * t.cos().powi(2) - 1.0),
                        0.0,
                    )
                }),
            ),
            (
                2,
                1,
                Box::new(|t: f64, p: f64| {
                    let a = -0.5 * (15.0 / (2.0 * PI)).sqrt() * t.sin() * t.cos();
                    (a * p.cos(), a * p.sin())
                }),
            ),
            (
                3,
                -2,
                Box::new(|t: f64, p: f64| {
                    let a = 0.25 * (105.0 / (2.0 * PI)).sqrt() * t.sin().powi(2) * t.cos();
                    (a * (2.0 * p).cos(), -a * (2.0 * p).sin())
                }),
            ),
            (
                5,
                5,
                Box::new(|t: f64, p: f64| {
                    let a = -(3.0 / 32.0) * (77.0 / PI).sqrt() * t.sin().powi(5);
                    (a * (5.0 * p).cos(), a * (5.0 * p).sin())
                }),
            ),
            (
                4,
                -3,
                Box::new(|t: f64, p: f64| {
                    let a = 0.375 * (35.0 / PI).sqrt() * t.sin().powi(3) * t.cos();
                    (a * (-3.0 * p).cos(), a * (-3.0 * p).sin())
                }),
            ),
        ];
        for (l, m, reference) in cases {
            let poly = spherical_harmonic(l, m);
            for &(t, p) in &[(0.3, 1.1), (1.7, -2.0), (2.9, 0.4), (0.0, 0.0), (PI, 1.0)] {
                let (x, y, z) = at(t, p);
                let (re, im) = poly.eval(x, y, z);
                let (rr, ri) = reference(t, p);
                assert!(
                    (re - rr).abs() < 1e-13 && (im - ri).abs() < 1e-13,
                    "Y_{l}^{m}({t},{p}) = {re}+{im}i, table {rr}+{ri}i"
                );
            }
        }
    }

    /// The z²-reduced form agrees with the homogeneous sum on the sphere (all degrees up to 12
    /// and every order at once), and its jet with central differences off the sphere.
    #[test]
    fn sphere_reduced_form_matches_the_homogeneous_sum() {
        let mut sum = ComplexPoly::default();
        for l in 2..=12u32 {
            for m in -(l as i32)..=l as i32 {
                let (re, im) = (
                    (l as f64 * 0.37 + m as f64).sin(),
                    (m as f64 * 1.3 - 0.2).cos(),
                );
                sum.add_scaled(&spherical_harmonic(l, m), re, im);
            }
        }
        let reduced = SpherePoly::real_part_on_sphere(&sum);
        let pairs: usize = reduced.rows.iter().map(|r| r.len() / 2).sum();
        assert!(pairs < sum.0.len() / 2, "the reduction shortens the sum");
        for &(t, p) in &[
            (0.3, 1.1),
            (1.7, -2.0),
            (2.9, 0.4),
            (0.0, 0.0),
            (PI, 1.0),
            (1.2, 3.0),
        ] {
            let (x, y, z) = at(t, p);
            let exact = sum.eval(x, y, z).0;
            let got = reduced.value(x, y, z);
            assert!(
                (got - exact).abs() < 1e-11 * (1.0 + exact.abs()),
                "{got} vs {exact}"
            );
            let j = reduced.jet(x, y, z);
            assert!((j.value - got).abs() < 1e-12 * (1.0 + got.abs()));
            let h = 1e-5;
            for axis in 0..3 {
                let shifted = |s: f64| {
                    let mut v = [x, y, z];
                    v[axis] += s;
                    reduced.jet(v[0], v[1], v[2])
                };
                let (plus, minus) = (shifted(h), shifted(-h));
                let g = (plus.value - minus.value) / (2.0 * h);
                assert!((g - j.grad[axis]).abs() < 1e-6 * (1.0 + g.abs()), "∂{axis}");
                for k in 0..3 {
                    let hk = (plus.grad[k] - minus.grad[k]) / (2.0 * h);
                    assert!(
                        (hk - j.hess[axis][k]).abs() < 1e-5 * (1.0 + hk.abs()),
                        "∂{axis}∂{k}"
                    );
                }
            }
        }
    }

    #[test]
    fn orthonormal_on_the_sphere() {
        // Gauss–Legendre in cos θ × uniform in φ integrates these polynomials exactly.
        let n = 24;
        let (nodes, weights) = crate::numeric::quadrature::gauss_legendre(n);
        let pairs = [
            ((2, 1), (2, 1)),
            ((3, -2), (3, -2)),
            ((2, 1), (3, 1)),
            ((4, 0), (4, 0)),
            ((5, 3), (5, -3)),
        ];
        for ((l1, m1), (l2, m2)) in pairs {
            let (a, b) = (spherical_harmonic(l1, m1), spherical_harmonic(l2, m2));
            let (mut re, mut im) = (0.0, 0.0);
            for (ct, w) in nodes.iter().zip(&weights) {
                for k in 0..2 * n {
                    let phi = 2.0 * PI * k as f64 / (2 * n) as f64;
                    let st = (1.0 - ct * ct).sqrt();
                    let (x, y, z) = (st * phi.cos(), st * phi.sin(), *ct);
                    let (ar, ai) = a.eval(x, y, z);
                    let (br, bi) = b.eval(x, y, z);
                    // a · conj(b)
                    re += w * (2.0 * PI / (2 * n) as f64) * (ar * br + ai * bi);
                    im += w * (2.0 * PI / (2 * n) as f64) * (ai * br - ar * bi);
                }
            }
            let expect = if (l1, m1) == (l2, m2) { 1.0 } else { 0.0 };
            assert!(
                (re - expect).abs() < 1e-12 && im.abs() < 1e-12,
                "<Y{l1}{m1},Y{l2}{m2}> = {re}+{im}i"
            );
        }
    }
}
