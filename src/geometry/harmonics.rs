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

    fn scale(&self, re: f64, im: f64) -> Self {
        Self(
            self.0
                .iter()
                .map(|(e, (a, b))| (*e, (a * re - b * im, a * im + b * re)))
                .collect(),
        )
    }

    /// Value at a point (x, y, z) as (re, im).
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

/// A real homogeneous polynomial of one degree, flattened for fast evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct RealPoly {
    /// Degree l of every term.
    pub degree: u32,
    /// (exponents, coefficient) pairs.
    pub terms: Vec<(Exponents, f64)>,
}

/// Value, gradient and Hessian of a polynomial at one point.
#[derive(Debug, Clone, Copy, Default)]
pub struct PolyJet {
    /// P(x)
    pub value: f64,
    /// ∇P(x)
    pub grad: [f64; 3],
    /// Hessian of P, row-major.
    pub hess: [[f64; 3]; 3],
}

impl RealPoly {
    /// Re Σ_m c_m Y_l^m for the given complex coefficients of one degree l.
    pub fn real_part_of(l: u32, coeffs: &[(i32, f64, f64)]) -> Self {
        let mut acc = ComplexPoly::default();
        for &(m, re, im) in coeffs {
            for (e, (a, b)) in spherical_harmonic(l, m).scale(re, im).0 {
                acc.add_term(e, a, b);
            }
        }
        let terms = acc
            .0
            .into_iter()
            .filter(|(_, (re, _))| re.abs() > 1e-300)
            .map(|(e, (re, _))| (e, re))
            .collect();
        Self { degree: l, terms }
    }

    /// Value, gradient and Hessian at (x, y, z) given the powers `pw[axis][k]` = x_axis^k.
    pub fn jet(&self, pw: &[[f64; 16]; 3]) -> PolyJet {
        let mut j = PolyJet::default();
        for (e, c) in &self.terms {
            let [a, b, d] = [e[0] as usize, e[1] as usize, e[2] as usize];
            let (px, py, pz) = (pw[0][a], pw[1][b], pw[2][d]);
            let dp = |k: usize, axis: usize| {
                if k == 0 {
                    0.0
                } else {
                    k as f64 * pw[axis][k - 1]
                }
            };
            let ddp = |k: usize, axis: usize| {
                if k < 2 {
                    0.0
                } else {
                    (k * (k - 1)) as f64 * pw[axis][k - 2]
                }
            };
            let (dx, dy, dz) = (dp(a, 0), dp(b, 1), dp(d, 2));
            j.value += c * px * py * pz;
            j.grad[0] += c * dx * py * pz;
            j.grad[1] += c * px * dy * pz;
            j.grad[2] += c * px * py * dz;
            let hxx = c * ddp(a, 0) * py * pz;
            let hyy = c * px * ddp(b, 1) * pz;
            let hzz = c * px * py * ddp(d, 2);
            let hxy = c * dx * dy * pz;
            let hxz = c * dx * py * dz;
            let hyz = c * px * dy * dz;
            j.hess[0][0] += hxx;
            j.hess[1][1] += hyy;
            j.hess[2][2] += hzz;
            j.hess[0][1] += hxy;
            j.hess[1][0] += hxy;
            j.hess[0][2] += hxz;
            j.hess[2][0] += hxz;
            j.hess[1][2] += hyz;
            j.hess[2][1] += hyz;
        }
        j
    }
}

/// Powers x^k, y^k, z^k for k < 16 (degrees up to 15 are supported).
pub fn powers(x: f64, y: f64, z: f64) -> [[f64; 16]; 3] {
    let mut pw = [[1.0; 16]; 3];
    for (axis, v) in [x, y, z].into_iter().enumerate() {
        for k in 1..16 {
            pw[axis][k] = pw[axis][k - 1] * v;
        }
    }
    pw
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
