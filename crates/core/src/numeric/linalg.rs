//! Linear algebra through nalgebra: the eigenvalues of a square matrix (Floquet multipliers of
//! return maps, stability of rest points).

use nalgebra::{Complex, DMatrix};

/// Eigenvalues of a square matrix, largest modulus first.
pub fn eigenvalues(m: &DMatrix<f64>) -> Vec<Complex<f64>> {
    let mut e: Vec<Complex<f64>> = m.complex_eigenvalues().iter().copied().collect();
    e.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    e
}
