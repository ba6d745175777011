//! The mesh fit's standard errors of ⟨r⟩ and α*, from the mesh's own scatter about the fit.
//!
//! A scanned mesh's vertices scatter about the body (a scanner's noise, a print's roughness),
//! and the fitted coefficients scatter with them. Their covariance is the least squares'
//! sandwich G⁻¹ (Σ_b s_b s_bᵀ) G⁻¹, summed over blocks b of nearby samples with
//! s_b = Σ_{j∈b} w_j e_j y_j (weight w, residual e, basis y at sample j). A sample's residual
//! shares its triangle's corners with its neighbours', so residuals are correlated over a few
//! edge lengths; blocks [`BLOCK_EDGES`] edges a side take that correlation in whole (the
//! cluster-robust estimator, with clusters in space, its sum scaled by B/(B − k) for the k
//! coefficients fitted from B blocks). ⟨r⟩ is linear in the coefficients. α* =
//! atan max |∇ ln r| is not: it is the maximum of a slope, and the maximum of a noisy slope is
//! biased up. So α* is drawn again for [`ALPHA_DRAWS`] coefficient vectors from the normal
//! distribution of that covariance (in antithetic pairs, x̂ ± δ, which cancel the linear part):
//! their spread is α*'s error, and their mean's excess over the fit's α* estimates how far the
//! scatter raised it (the parametric bootstrap's bias; 0.55 ms an α* on the paper's body).
//!
//! Calibrated by `bench calibration` on noisy icospheres of known bodies (the analysis layer's
//! `experiment::mesh_calibration`). What the errors leave out: a noiseless mesh's facets are
//! not noise (the print's own hull reports what they do to α*), and millimetres per mesh unit
//! are taken as exact.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use super::real_harmonics;
use crate::geometry::{Body, Disk, DiskMode, Sphere};

/// Blocks of samples are at least this many of the mesh's typical edges a side: a vertex's
/// error reaches the samples of the triangles around it, two edges across, and blocks must be
/// large against that for the sums of neighbouring blocks to be nearly independent. With 4
/// edges a side (and B/(B − 1)), the stated errors held the truth 85–94 % of the time; with 6
/// and B/(B − k), 91.5–97 % (200 meshes a case); 8 gave the same as 6 within the draws' ±2 %
/// (`bench calibration`, 2026-12-02).
pub const BLOCK_EDGES: f64 = 6.0;

/// The fewest blocks errors are stated from, per coefficient fitted: the scatter of few block
/// sums underestimates a variance, more so the more coefficients the fit has (32 blocks for
/// the 36 coefficients of degree 5 held ⟨r⟩ 75–83 % of the time). A mesh that coarse (a ball of
/// 5,120 triangles, a cylinder whose slice has under about 240 segments at mode 6) is mostly
/// facets, which the print's hull speaks for.
pub const MIN_BLOCKS_PER_COEFFICIENT: usize = 3;

/// Coefficient vectors α* is drawn again for (half of them x̂ + δ, half x̂ − δ).
pub const ALPHA_DRAWS: usize = 200;

/// The largest bias of α*, in its errors, for which an error of α* is stated. A large bias means
/// the maximum of the slope is not resolved by the mesh's scatter (several near-equal maxima,
/// or a body near round, whose α* of 0 no noisy fit reaches), and there the correction is not
/// enough: a helper's body with two symmetric maxima had a bias of 0.66 errors and its α* held
/// the truth 85.5 % of the time (2026-12-02), a round ball's 2.9 errors and almost never.
pub const MAX_ALPHA_BIAS: f64 = 0.5;

/// Standard errors of one fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct FitErrors {
    /// Of ⟨r⟩, in mesh units.
    pub(super) mean: f64,
    /// Of α* (rad), with how far the scatter raises a fit's α* on average (rad: the truth is
    /// nearer α* − this); `None` where that bias is over [`MAX_ALPHA_BIAS`] errors.
    pub(super) alpha_star: Option<(f64, f64)>,
    /// The blocks they were estimated from.
    pub(super) blocks: usize,
}

/// A typical edge of a closed mesh of `triangles` triangles, as the angle it subtends from the
/// centroid: the side of an equilateral triangle of solid angle 4π/`triangles`.
pub(super) fn edge_angle(triangles: usize) -> f64 {
    (4.0 * (4.0 * PI / triangles.max(1) as f64) / 3f64.sqrt()).sqrt()
}

/// The standard errors of a 3D fit: `samples` (direction, radius, weight) fitted by the real
/// harmonics up to degree `modes` with coefficients `x`, on a mesh of `triangles` triangles;
/// `body_of` builds the body from a coefficient vector. `None` with too few blocks
/// ([`MIN_BLOCKS_PER_COEFFICIENT`]), or a singular fit.
pub(super) fn sphere_errors(
    samples: &[(DVec3, f64, f64)],
    x: &[f64],
    modes: u32,
    triangles: usize,
    body_of: impl Fn(&[f64]) -> Sphere,
) -> Option<FitErrors> {
    let k = ((modes + 1) * (modes + 1)) as usize;
    let side = BLOCK_EDGES * edge_angle(triangles);
    // Equal-area blocks, `bands` in cos θ by twice as many in φ: each 2π/bands² of the sphere.
    let bands = ((TAU.sqrt() / side).floor() as usize).clamp(1, super::BANDS);
    let sectors = 2 * bands;
    let mut gram = DMatrix::<f64>::zeros(k, k);
    let mut sums = vec![DVector::<f64>::zeros(k); bands * sectors];
    let mut y = vec![0.0; k];
    for &(u, r, w) in samples {
        real_harmonics(modes, u, &mut y);
        let e = r - y.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
        let band = (((u.z + 1.0) / 2.0 * bands as f64) as usize).min(bands - 1);
        let phi = u.y.atan2(u.x).rem_euclid(TAU);
        let sector = ((phi / TAU * sectors as f64) as usize).min(sectors - 1);
        let s = &mut sums[band * sectors + sector];
        for i in 0..k {
            s[i] += w * e * y[i];
            for j in i..k {
                gram[(i, j)] += w * y[i] * y[j];
            }
        }
    }
    for i in 0..k {
        for j in 0..i {
            gram[(i, j)] = gram[(j, i)];
        }
    }
    let inverse = gram.cholesky()?.inverse();
    let covariance = cluster_sandwich(&inverse, &sums)?;
    let y00 = (0.25 / PI).sqrt();
    let alpha = |xs: &[f64]| Body::Sphere(body_of(xs)).alpha_star();
    Some(FitErrors {
        mean: covariance.0[(0, 0)].max(0.0).sqrt() * y00,
        alpha_star: drawn_alpha(x, &covariance.0, alpha),
        blocks: covariance.1,
    })
}

/// The standard errors of a 2D fit: `radius` sampled at `n` equally spaced θ, its mean and
/// Fourier parts `b`, `c` (relative to the mean, index l), fitted up to mode `modes`; the
/// section has `sides` boundary segments. `None` with too few blocks.
pub(super) fn section_errors(
    radius: &[f64],
    (mean, b, c): (f64, &[f64], &[f64]),
    modes: usize,
    sides: usize,
) -> Option<FitErrors> {
    let n = radius.len();
    let step = TAU / n as f64;
    // Parameters (mean, B_1 … B_M, C_1 … C_M), B_l = mean b_l: each linear in the samples,
    // sample k's part being (1, 2 cos lθ_k, 2 sin lθ_k)/n.
    let k = 1 + 2 * modes;
    let block = ((BLOCK_EDGES * n as f64 / sides.max(1) as f64).ceil() as usize).max(1);
    let mut sums = vec![DVector::<f64>::zeros(k); n.div_ceil(block)];
    for (j, r) in radius.iter().enumerate() {
        let t = j as f64 * step;
        let fit = mean
            * (1.0
                + (1..=modes)
                    .map(|l| b[l] * (l as f64 * t).cos() + c[l] * (l as f64 * t).sin())
                    .sum::<f64>());
        let e = r - fit;
        let s = &mut sums[j / block];
        s[0] += e / n as f64;
        for l in 1..=modes {
            let lt = l as f64 * t;
            s[l] += 2.0 * e * lt.cos() / n as f64;
            s[modes + l] += 2.0 * e * lt.sin() / n as f64;
        }
    }
    let identity = DMatrix::<f64>::identity(k, k);
    let (covariance, blocks) = cluster_sandwich(&identity, &sums)?;
    // The body of a parameter vector: modes 2 … M relative to its mean, as the fit builds it.
    let alpha = |p: &[f64]| {
        let modes = (2..=modes)
            .map(|l| {
                let (bl, cl) = (p[l] / p[0], p[modes + l] / p[0]);
                let lf = l as f64;
                DiskMode {
                    l: l as u32,
                    a: lf * lf * bl.hypot(cl),
                    phase: (-bl).atan2(cl) / lf,
                }
            })
            .collect();
        Body::Disk(Disk::new(modes)).alpha_star()
    };
    let fitted: Vec<f64> = std::iter::once(mean)
        .chain((1..=modes).map(|l| mean * b[l]))
        .chain((1..=modes).map(|l| mean * c[l]))
        .collect();
    Some(FitErrors {
        mean: covariance[(0, 0)].max(0.0).sqrt(),
        alpha_star: drawn_alpha(&fitted, &covariance, alpha),
        blocks,
    })
}

/// α*'s spread and bias over [`ALPHA_DRAWS`] parameter vectors x̂ ± δ, δ normal with
/// `covariance` (its square root by eigenvalues: a covariance is only semi-definite), drawn
/// from a fixed seed so a fit gives the same bits on every run; `None` where the bias is over
/// [`MAX_ALPHA_BIAS`] errors.
fn drawn_alpha(
    fitted: &[f64],
    covariance: &DMatrix<f64>,
    alpha: impl Fn(&[f64]) -> f64,
) -> Option<(f64, f64)> {
    let eigen = covariance.clone().symmetric_eigen();
    let root =
        &eigen.eigenvectors * DMatrix::from_diagonal(&eigen.eigenvalues.map(|v| v.max(0.0).sqrt()));
    let mut rng = ChaCha8Rng::seed_from_u64(0x6d65_7368);
    let normal = Normal::new(0.0, 1.0).expect("a unit normal");
    let k = fitted.len();
    let centre = alpha(fitted);
    let mut drawn = Vec::with_capacity(ALPHA_DRAWS);
    for _ in 0..ALPHA_DRAWS / 2 {
        let z = DVector::from_fn(k, |_, _| normal.sample(&mut rng));
        let delta = &root * z;
        for sign in [1.0, -1.0] {
            let p: Vec<f64> = fitted
                .iter()
                .zip(delta.iter())
                .map(|(a, d)| a + sign * d)
                .collect();
            drawn.push(alpha(&p));
        }
    }
    let n = drawn.len() as f64;
    let average = drawn.iter().sum::<f64>() / n;
    let spread = (drawn.iter().map(|a| (a - average).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let bias = average - centre;
    (bias.abs() <= MAX_ALPHA_BIAS * spread).then_some((spread, bias))
}

/// G⁻¹ (Σ_b s_b s_bᵀ) G⁻¹ × B/(B − k) over the B blocks that hold samples, with that B;
/// `None` under [`MIN_BLOCKS_PER_COEFFICIENT`] blocks a coefficient. Terms between neighbouring
/// blocks (Bartlett's weights, as spatial HAC estimators add) were tried and made the errors
/// smaller, not larger (coverage 88–96 % against 91.5–97 %): the residuals' block sums add to
/// exactly zero (the normal equations), so their cross products lean negative.
fn cluster_sandwich(
    inverse: &DMatrix<f64>,
    sums: &[DVector<f64>],
) -> Option<(DMatrix<f64>, usize)> {
    let k = inverse.nrows();
    let mut meat = DMatrix::<f64>::zeros(k, k);
    let mut blocks = 0;
    for s in sums.iter().filter(|s| s.iter().any(|v| *v != 0.0)) {
        meat += s * s.transpose();
        blocks += 1;
    }
    if blocks < MIN_BLOCKS_PER_COEFFICIENT * k {
        return None;
    }
    // The k coefficients fitted use up k of the blocks' degrees of freedom.
    meat *= blocks as f64 / (blocks - k) as f64;
    Some((inverse * meat * inverse, blocks))
}
