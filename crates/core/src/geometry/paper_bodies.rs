//! The paper's own bodies, bit for bit: the authors' public code draws them with numpy's legacy
//! `RandomState`, so the same seed here gives the same coefficients as `np.random.seed(N)` there.
//!
//! - 3D (`paper_sphere`): `A = normal(0, σ, K)`, then `P = random(K)·2π`, K = (L+1)² − 4, and
//!   r = 1 + Re Σ_{l=2..L} Σ_{m=−l..l} A/(l(l+1)) Y_l^m(θ, φ + P) with the coefficients taken in
//!   that (l, m) order. Since Y_l^m(θ, φ + P) = e^{imP} Y_l^m(θ, φ), A_lm = A·e^{imP} in our
//!   schema. The paper's Figs. 3–4 body is seed 219, σ = 0.25, L = 5.
//! - 2D (`paper_disk`): the authors' `get_r(seed, num_modes = M − 1, std)`: `a = normal(0, σ,
//!   M − 1)`, then `θ = random(M − 1)·2π`, a_l = a[l − 2], θ_l = θ[l − 2].
//!
//! The generator: MT19937 seeded by `init_genrand(N)` (the `rand_mt` crate), `random` as the
//! 53-bit `genrand_res53`, and `normal` as numpy's legacy polar Box–Muller, which returns the
//! second value of each pair and keeps the first for the next call. These two numpy-specific
//! draws are written here because no crate reproduces numpy's legacy streams; they are checked
//! against numbers numpy itself produced (`tests/physics/paper_bodies.rs`, fixture and script in
//! `tests/fixtures/`).

use std::f64::consts::TAU;

use rand_mt::Mt;

use super::{Disk, DiskMode, MAX_DISK_L, MAX_SPHERE_L, ShapeError, Sphere, SphereCoeff};

/// numpy's legacy `RandomState` (the stream behind `np.random.seed`, `normal`, `random`).
#[derive(Debug, Clone)]
pub struct NumpyRandomState {
    mt: Mt,
    cached_gauss: Option<f64>,
}

impl NumpyRandomState {
    /// `np.random.seed(seed)`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::paper_bodies::NumpyRandomState;
    /// // np.random.seed(0); np.random.random() → 0.5488135039273248
    /// assert_eq!(NumpyRandomState::new(0).random(), 0.5488135039273248);
    /// ```
    pub fn new(seed: u32) -> Self {
        Self {
            mt: Mt::new(seed),
            cached_gauss: None,
        }
    }

    /// One `np.random.random()`: a uniform double in [0, 1) with 53 random bits.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::paper_bodies::NumpyRandomState;
    /// let mut rng = NumpyRandomState::new(0);
    /// let x = rng.random();
    /// assert!((0.0..1.0).contains(&x));
    /// ```
    pub fn random(&mut self) -> f64 {
        let a = (self.mt.next_u32() >> 5) as f64;
        let b = (self.mt.next_u32() >> 6) as f64;
        (a * 67_108_864.0 + b) / 9_007_199_254_740_992.0
    }

    /// One standard normal deviate, as numpy's legacy `gauss`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::paper_bodies::NumpyRandomState;
    /// // np.random.seed(0); np.random.normal() → 1.764052345967664
    /// assert!((NumpyRandomState::new(0).gauss() - 1.764052345967664).abs() < 1e-15);
    /// ```
    pub fn gauss(&mut self) -> f64 {
        if let Some(g) = self.cached_gauss.take() {
            return g;
        }
        loop {
            let x1 = 2.0 * self.random() - 1.0;
            let x2 = 2.0 * self.random() - 1.0;
            let r2 = x1 * x1 + x2 * x2;
            if r2 < 1.0 && r2 != 0.0 {
                let f = (-2.0 * r2.ln() / r2).sqrt();
                self.cached_gauss = Some(f * x1);
                return f * x2;
            }
        }
    }

    /// `np.random.normal(loc, scale, n)`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::paper_bodies::NumpyRandomState;
    /// // np.random.seed(0); np.random.normal(1.0, 0.5, 1) → [1.882026172983832]
    /// let v = NumpyRandomState::new(0).normal(1.0, 0.5, 1);
    /// assert!((v[0] - 1.882026172983832).abs() < 1e-15);
    /// ```
    pub fn normal(&mut self, loc: f64, scale: f64, n: usize) -> Vec<f64> {
        (0..n).map(|_| loc + scale * self.gauss()).collect()
    }

    /// `np.random.random(n)`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::paper_bodies::NumpyRandomState;
    /// // np.random.seed(0); np.random.random(3) → [0.5488135, 0.71518937, 0.60276338]
    /// let v = NumpyRandomState::new(0).random_vec(3);
    /// assert!((v[1] - 0.71518937).abs() < 1e-8 && (v[2] - 0.60276338).abs() < 1e-8);
    /// ```
    pub fn random_vec(&mut self, n: usize) -> Vec<f64> {
        (0..n).map(|_| self.random()).collect()
    }
}

/// The paper's 3D body for numpy seed `seed` (see the module doc); `degree` is the largest l.
///
/// # Example
/// ```
/// use rollphase_core::geometry::{Body, paper_sphere};
/// // The body of the paper's Figs. 3–4: α* = 0.1394.
/// let body = Body::Sphere(paper_sphere(219, 0.25, 5)?);
/// assert!((body.alpha_star() - 0.1394).abs() < 1e-4);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn paper_sphere(seed: u32, sigma: f64, degree: u32) -> Result<Sphere, ShapeError> {
    super::check_sigma(sigma)?;
    if !(2..=MAX_SPHERE_L).contains(&degree) {
        return Err(ShapeError::BadParameter {
            name: "modes",
            value: degree as f64,
            allowed: "2 ≤ modes ≤ 12 (the largest degree l)",
        });
    }
    let count = ((degree + 1) * (degree + 1) - 4) as usize;
    let mut rng = NumpyRandomState::new(seed);
    let amplitudes = rng.normal(0.0, sigma, count);
    let phases: Vec<f64> = rng.random_vec(count).iter().map(|p| p * TAU).collect();
    let mut coeffs = Vec::with_capacity(count);
    let mut k = 0;
    for l in 2..=degree {
        for m in -(l as i32)..=(l as i32) {
            let (s, c) = (m as f64 * phases[k]).sin_cos();
            coeffs.push(SphereCoeff {
                l,
                m,
                re: amplitudes[k] * c,
                im: amplitudes[k] * s,
            });
            k += 1;
        }
    }
    Ok(Sphere::new(coeffs))
}

/// The paper's 2D body for numpy seed `seed` (see the module doc); `modes` is the largest l = M.
///
/// # Example
/// ```
/// use rollphase_core::geometry::paper_disk;
/// // M = 5: modes l = 2..5, as the authors' get_r(seed, 4, σ) draws them.
/// let disk = paper_disk(1, 0.2, 5)?;
/// assert_eq!(disk.modes().iter().map(|m| m.l).collect::<Vec<_>>(), [2, 3, 4, 5]);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn paper_disk(seed: u32, sigma: f64, modes: u32) -> Result<Disk, ShapeError> {
    super::check_sigma(sigma)?;
    if !(2..=MAX_DISK_L).contains(&modes) {
        return Err(ShapeError::BadParameter {
            name: "modes",
            value: modes as f64,
            allowed: "2 ≤ modes ≤ 64",
        });
    }
    let count = (modes - 1) as usize;
    let mut rng = NumpyRandomState::new(seed);
    let amplitudes = rng.normal(0.0, sigma, count);
    let phases = rng.random_vec(count);
    let ms = (0..count)
        .map(|i| DiskMode {
            l: i as u32 + 2,
            a: amplitudes[i],
            phase: phases[i] * TAU,
        })
        .collect();
    Ok(Disk::new(ms))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mt19937_reference_output() {
        // The reference implementation's first outputs for init_genrand(5489).
        let mut mt = Mt::new(5489);
        assert_eq!(mt.next_u32(), 3_499_211_612);
        assert_eq!(mt.next_u32(), 581_869_302);
    }

    #[test]
    fn gauss_returns_the_cached_partner_second() {
        let mut a = NumpyRandomState::new(1);
        let mut b = NumpyRandomState::new(1);
        let first = a.gauss();
        let second = a.gauss();
        // The pair comes from one polar draw: second² + first² = f²(x1² + x2²) = −2 ln r2.
        let (x1, x2) = loop {
            let x1 = 2.0 * b.random() - 1.0;
            let x2 = 2.0 * b.random() - 1.0;
            if x1 * x1 + x2 * x2 < 1.0 {
                break (x1, x2);
            }
        };
        assert!((first / second - x2 / x1).abs() < 1e-12);
    }
}
