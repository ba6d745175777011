//! Linear algebra through nalgebra: the eigenvalues of a square matrix (Floquet multipliers of
//! return maps, stability of rest points).

use nalgebra::{Complex, DMatrix};

/// Eigenvalues of a square matrix, largest modulus first.
///
/// # Example
/// ```
/// use nalgebra::DMatrix;
/// use rollphase_core::numeric::linalg::eigenvalues;
/// // A rotation by 90° scaled by 2, and a lone 0.5: moduli 2, 2, 0.5.
/// let m = DMatrix::from_row_slice(3, 3, &[0.0, -2.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.5]);
/// let e = eigenvalues(&m);
/// assert!((e[0].norm() - 2.0).abs() < 1e-12 && (e[2].re - 0.5).abs() < 1e-12);
/// ```
pub fn eigenvalues(m: &DMatrix<f64>) -> Vec<Complex<f64>> {
    let mut e: Vec<Complex<f64>> = m.complex_eigenvalues().iter().copied().collect();
    e.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    e
}
