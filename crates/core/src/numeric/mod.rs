//! Numerical building blocks with no physics in them, used by `geometry`, `integrate` and
//! `analysis`: quadrature, golden-section maximisation, root finding, marching squares and
//! eigenvalues (nalgebra). Imports nothing else of the crate.

pub mod contour;
pub mod linalg;
pub mod optimize;
pub mod quadrature;
pub mod roots;
