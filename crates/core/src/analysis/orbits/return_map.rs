//! Fixed points of a return (Poincaré) map, their multipliers, and flip bifurcations.
//!
//! A periodic orbit of a flow is a fixed point x* = P(x*) of its return map P on a section. The
//! multipliers μ_i (eigenvalues of DP(x*), the orbit's nontrivial Floquet multipliers) decide its
//! stability: stable while every |μ_i| < 1. A period-doubling (flip) bifurcation is where a real
//! multiplier passes through −1: the fixed point loses stability and a 2-cycle of P is born (or
//! dies).
//!
//! Here the map is any function of a vector (it may fail, e.g. when a body halts before it returns
//! to the section). Newton's method on P(x) − x finds x* with DP from central differences; the
//! eigenvalues come from nalgebra's real Schur decomposition; the flip parameter is located by
//! bisection on μ_min + 1, the most negative real multiplier plus one. Pure math: imports
//! nalgebra and thiserror only.

use crate::numeric::linalg::eigenvalues;
use nalgebra::{Complex, DMatrix, DVector};
use thiserror::Error;

/// Why no fixed point was found.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ReturnMapError {
    /// The map has no value at this point (e.g. the trajectory never came back).
    #[error("the return map is undefined at {at:?}")]
    Undefined {
        /// The point.
        at: Vec<f64>,
    },
    /// Newton stopped without reaching the tolerance.
    #[error("no fixed point: |P(x) − x| = {residual:.3e} after {iterations} Newton steps")]
    NoConvergence {
        /// Last residual.
        residual: f64,
        /// Steps taken.
        iterations: usize,
    },
    /// DP − I is singular (a multiplier is exactly 1).
    #[error("DP − I is singular at the iterate: a multiplier equals 1")]
    Singular,
}

/// A fixed point of a return map with its linearisation.
#[derive(Debug, Clone)]
pub struct FixedPoint {
    /// x* with |P(x*) − x*| ≤ the requested tolerance.
    pub point: DVector<f64>,
    /// DP(x*) by central differences.
    pub jacobian: DMatrix<f64>,
    /// Its eigenvalues, largest modulus first.
    pub multipliers: Vec<Complex<f64>>,
    /// Newton steps taken.
    pub iterations: usize,
    /// |P(x*) − x*|.
    pub residual: f64,
}

/// DP(x) by central differences with step `h` in every coordinate.
///
/// # Example
/// ```
/// use nalgebra::{DMatrix, DVector};
/// use rollphase_core::analysis::orbits::return_map::jacobian;
/// // A linear map P(x) = A x has DP = A.
/// let a = DMatrix::from_row_slice(2, 2, &[0.5, 1.0, 0.0, -0.3]);
/// let j = jacobian(&|x: &DVector<f64>| Some(&a * x), &DVector::from_vec(vec![1.0, 2.0]), 1e-6)?;
/// assert!((j - a).norm() < 1e-9);
/// # Ok::<(), rollphase_core::analysis::orbits::return_map::ReturnMapError>(())
/// ```
pub fn jacobian(
    map: &impl Fn(&DVector<f64>) -> Option<DVector<f64>>,
    x: &DVector<f64>,
    h: f64,
) -> Result<DMatrix<f64>, ReturnMapError> {
    let n = x.len();
    let mut j = DMatrix::zeros(n, n);
    for c in 0..n {
        let mut plus = x.clone();
        let mut minus = x.clone();
        plus[c] += h;
        minus[c] -= h;
        let undefined = |p: &DVector<f64>| ReturnMapError::Undefined {
            at: p.iter().copied().collect(),
        };
        let fp = map(&plus).ok_or_else(|| undefined(&plus))?;
        let fm = map(&minus).ok_or_else(|| undefined(&minus))?;
        j.set_column(c, &((fp - fm) / (2.0 * h)));
    }
    Ok(j)
}

/// The most negative real eigenvalue (imaginary part below 1e-9 of the modulus), if any is < 0.
///
/// # Example
/// ```
/// use nalgebra::Complex;
/// use rollphase_core::analysis::orbits::return_map::most_negative_real;
/// let mu = [Complex::new(0.3, 0.4), Complex::new(-1.2, 0.0), Complex::new(-0.5, 0.0)];
/// assert_eq!(most_negative_real(&mu), Some(-1.2));
/// assert_eq!(most_negative_real(&mu[..1]), None); // a complex pair is not real
/// ```
pub fn most_negative_real(multipliers: &[Complex<f64>]) -> Option<f64> {
    multipliers
        .iter()
        .filter(|m| m.im.abs() <= 1e-9 * m.norm().max(1e-300) && m.re < 0.0)
        .map(|m| m.re)
        .min_by(f64::total_cmp)
}

/// Newton's method for P(x) = x from `x0`: steps solve (DP − I) δ = −(P(x) − x), with DP from
/// central differences of step `h`, each step limited to length `max_step`. Stops when
/// |P(x) − x| ≤ `tol`, then linearises at the solution.
///
/// # Example
/// ```
/// use nalgebra::DVector;
/// use rollphase_core::analysis::orbits::return_map::find_fixed_point;
/// // P(x) = cos x has its fixed point at x = 0.739085…, with multiplier −sin x* there.
/// let map = |x: &DVector<f64>| Some(x.map(f64::cos));
/// let fp = find_fixed_point(&map, DVector::from_vec(vec![1.0]), 1e-6, 1e-12, 1.0, 20)?;
/// assert!((fp.point[0] - 0.739_085_133_215_160_6).abs() < 1e-11);
/// assert!((fp.multipliers[0].re + fp.point[0].sin()).abs() < 1e-8);
/// # Ok::<(), rollphase_core::analysis::orbits::return_map::ReturnMapError>(())
/// ```
pub fn find_fixed_point(
    map: &impl Fn(&DVector<f64>) -> Option<DVector<f64>>,
    x0: DVector<f64>,
    h: f64,
    tol: f64,
    max_step: f64,
    max_iterations: usize,
) -> Result<FixedPoint, ReturnMapError> {
    let undefined = |p: &DVector<f64>| ReturnMapError::Undefined {
        at: p.iter().copied().collect(),
    };
    let mut x = x0;
    let mut residual = f64::INFINITY;
    for iteration in 0..=max_iterations {
        let fx = map(&x).ok_or_else(|| undefined(&x))?;
        let r = &fx - &x;
        residual = r.norm();
        let j = jacobian(map, &x, h)?;
        if residual <= tol {
            let multipliers = eigenvalues(&j);
            return Ok(FixedPoint {
                point: x,
                jacobian: j,
                multipliers,
                iterations: iteration,
                residual,
            });
        }
        if iteration == max_iterations {
            break;
        }
        let n = x.len();
        let a = j - DMatrix::identity(n, n);
        let mut step = a.lu().solve(&(-r)).ok_or(ReturnMapError::Singular)?;
        let len = step.norm();
        if len > max_step {
            step *= max_step / len;
        }
        x += step;
    }
    Err(ReturnMapError::NoConvergence {
        residual,
        iterations: max_iterations,
    })
}

/// The parameter in [lo, hi] where `flip(p)` (μ_min + 1 of the orbit at p) changes sign, by
/// bisection to `tol`; `None` if it has the same sign at both ends or is undefined there.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::return_map::locate_flip;
/// // μ_min(p) = −p/2: it passes −1 at p = 2.
/// let p = locate_flip(0.0, 5.0, 1e-9, |p| Some(1.0 - p / 2.0)).unwrap();
/// assert!((p - 2.0).abs() < 1e-8);
/// assert_eq!(locate_flip(0.0, 1.0, 1e-9, |p| Some(1.0 - p / 2.0)), None);
/// ```
pub fn locate_flip(
    mut lo: f64,
    mut hi: f64,
    tol: f64,
    mut flip: impl FnMut(f64) -> Option<f64>,
) -> Option<f64> {
    let mut f_lo = flip(lo)?;
    let f_hi = flip(hi)?;
    if f_lo.signum() == f_hi.signum() {
        return None;
    }
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        let f_mid = flip(mid)?;
        if f_mid.signum() == f_lo.signum() {
            lo = mid;
            f_lo = f_mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn logistic(r: f64) -> impl Fn(&DVector<f64>) -> Option<DVector<f64>> {
        move |x: &DVector<f64>| Some(DVector::from_element(1, r * x[0] * (1.0 - x[0])))
    }

    fn flip_of_logistic(r: f64) -> Option<f64> {
        let fp = find_fixed_point(
            &logistic(r),
            DVector::from_element(1, 0.5),
            1e-6,
            1e-13,
            0.1,
            50,
        )
        .ok()?;
        Some(most_negative_real(&fp.multipliers).unwrap_or(0.0) + 1.0)
    }

    #[test]
    fn logistic_fixed_point_and_multiplier_are_exact() {
        // x* = 1 − 1/r, μ = r(1 − 2x*) = 2 − r.
        for r in [2.2, 2.9, 3.3] {
            let fp = find_fixed_point(
                &logistic(r),
                DVector::from_element(1, 0.5),
                1e-6,
                1e-14,
                0.1,
                50,
            )
            .expect("converges");
            assert!((fp.point[0] - (1.0 - 1.0 / r)).abs() < 1e-13, "r = {r}");
            assert!((fp.multipliers[0].re - (2.0 - r)).abs() < 1e-8, "r = {r}");
        }
    }

    #[test]
    fn logistic_first_flip_is_at_three() {
        let r = locate_flip(2.5, 3.4, 1e-10, flip_of_logistic).expect("a flip in [2.5, 3.4]");
        assert!((r - 3.0).abs() < 1e-7, "flip at {r}");
    }

    #[test]
    fn henon_flip_is_at_the_closed_form() {
        // Hénon x' = 1 − a x² + y, y' = b x: the fixed point's flip is at a = 3(1 − b)²/4.
        let b = 0.3;
        let flip = |a: f64| {
            let map = move |v: &DVector<f64>| {
                Some(DVector::from_vec(vec![
                    1.0 - a * v[0] * v[0] + v[1],
                    b * v[0],
                ]))
            };
            let fp = find_fixed_point(
                &map,
                DVector::from_vec(vec![0.6, 0.2]),
                1e-6,
                1e-13,
                0.1,
                50,
            )
            .ok()?;
            Some(most_negative_real(&fp.multipliers)? + 1.0)
        };
        let a = locate_flip(0.2, 0.6, 1e-10, flip).expect("a flip");
        let exact = 3.0 * (1.0 - b) * (1.0 - b) / 4.0;
        assert!((a - exact).abs() < 1e-7, "flip at {a}, exact {exact}");
    }

    #[test]
    fn eigenvalues_of_a_rotation_are_complex_and_sorted() {
        let m = DMatrix::from_row_slice(3, 3, &[0.0, -2.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.5]);
        let e = eigenvalues(&m);
        assert!((e[0].norm() - 2.0).abs() < 1e-12 && e[0].im.abs() > 1.9);
        assert!((e[2].re - 0.5).abs() < 1e-12 && e[2].im == 0.0);
        assert_eq!(most_negative_real(&e), None);
    }
}
