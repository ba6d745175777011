//! The bodies `design` searches and what makes one printable: harmonic coefficients up to degree
//! L in the paper's normalisation, as a flat vector of reals the optimiser moves, and the
//! constraints (convex, smallest radius of curvature in mm, an amplitude bound) checked on the
//! body that vector makes.
//!
//! 2D: for l = 2…L the pair (a_l cos lθ_l, a_l sin lθ_l) of the mode a_l/l² sin(l(θ − θ_l)).
//! 3D: for l = 2…L, Re A_l0, then Re A_lm and Im A_lm for m = 1…l, of
//! r = 1 + Re Σ A_lm/(l(l+1)) Y_lm: with the real part taken, the orders m ≥ 0 span every real
//! surface of degree l, so (L + 1)² − 4 numbers describe each body once.

use glam::DVec3;
use serde::Serialize;

use crate::geometry::sphere::fibonacci_sphere;
use crate::geometry::{
    Body, Disk, DiskMode, Sphere, SphereCoeff, refine_1d, refine_sphere, sphere_grid_size,
};

/// Highest degree `design` offers: the issue's L ≤ 8 (3D: 77 numbers).
pub const MAX_DESIGN_MODES: u32 = 8;

/// Which bodies are searched: the dimension and the highest degree L.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct DesignSpace {
    /// 2 (a cylinder's section) or 3 (a sphere).
    pub dimension: u32,
    /// The highest degree l of the modes.
    pub modes: u32,
}

impl DesignSpace {
    /// The space a body lies in: its dimension and its degree (2 at least), with no limit on
    /// the degree (a check's, not a search's).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::DesignSpace;
    /// use rollphase_core::geometry::Body;
    /// let body = Body::paper_disk(3, 0.08, 10)?;
    /// assert_eq!(DesignSpace::of(&body), DesignSpace { dimension: 2, modes: 10 });
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of(body: &Body) -> DesignSpace {
        let degree = match body {
            Body::Disk(d) => d.modes().iter().map(|m| m.l).max().unwrap_or(0),
            Body::Sphere(s) => s.max_degree(),
        };
        DesignSpace {
            dimension: body.dimension(),
            modes: degree.max(2),
        }
    }

    /// How many numbers describe a body: 2(L − 1) in 2D, (L + 1)² − 4 in 3D.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::DesignSpace;
    /// assert_eq!(DesignSpace { dimension: 2, modes: 5 }.len(), 8);
    /// assert_eq!(DesignSpace { dimension: 3, modes: 8 }.len(), 77);
    /// ```
    pub fn len(&self) -> usize {
        let l = self.modes as usize;
        if self.dimension == 2 {
            2 * (l - 1)
        } else {
            (l + 1) * (l + 1) - 4
        }
    }

    /// Never empty (L ≥ 2); here for clippy's `len` rule.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::DesignSpace;
    /// assert!(!DesignSpace { dimension: 3, modes: 2 }.is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The body a vector describes (one coefficient per mode, in the order of the module doc).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::DesignSpace;
    /// use rollphase_core::geometry::Body;
    /// let space = DesignSpace { dimension: 2, modes: 3 };
    /// // a_2 = 0.4 at θ_2 = 0: r = 1 + 0.1 sin 2θ.
    /// let Body::Disk(d) = space.body(&[0.4, 0.0, 0.0, 0.0]) else { unreachable!() };
    /// assert!((d.jet(std::f64::consts::FRAC_PI_4).r - 1.1).abs() < 1e-15);
    /// ```
    pub fn body(&self, x: &[f64]) -> Body {
        if self.dimension == 2 {
            let modes = (2..=self.modes)
                .zip(x.chunks_exact(2))
                .filter(|(_, p)| p[0] != 0.0 || p[1] != 0.0)
                .map(|(l, p)| DiskMode {
                    l,
                    a: p[0].hypot(p[1]),
                    phase: p[1].atan2(p[0]) / l as f64,
                })
                .collect();
            return Body::Disk(Disk::new(modes));
        }
        let mut coeffs = Vec::with_capacity(self.len());
        let mut k = 0;
        for l in 2..=self.modes {
            for m in 0..=l as i32 {
                let (re, im) = if m == 0 {
                    (x[k], 0.0)
                } else {
                    (x[k], x[k + 1])
                };
                k += if m == 0 { 1 } else { 2 };
                if re != 0.0 || im != 0.0 {
                    coeffs.push(SphereCoeff { l, m, re, im });
                }
            }
        }
        Body::Sphere(Sphere::new(coeffs))
    }

    /// The vector of a body of this dimension, or `None` when it has a mode above L (or is of
    /// the other dimension). A sphere's coefficient of order −m is folded onto +m
    /// (Y_l,−m = (−1)^m conj Y_lm, so Re A Y_l,−m = Re (−1)^m conj(A) Y_lm).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::DesignSpace;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::glam::DVec3;
    /// let paper = Body::paper_sphere(219, 0.25, 5)?;
    /// let space = DesignSpace { dimension: 3, modes: 5 };
    /// let again = space.body(&space.vector(&paper).unwrap());
    /// let u = DVec3::new(0.3, -0.4, 0.5).normalize();
    /// let (Body::Sphere(a), Body::Sphere(b)) = (&paper, &again) else { unreachable!() };
    /// assert!((a.radius(u) - b.radius(u)).abs() < 1e-14);
    /// assert!(DesignSpace { dimension: 3, modes: 4 }.vector(&paper).is_none());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn vector(&self, body: &Body) -> Option<Vec<f64>> {
        let mut x = vec![0.0; self.len()];
        match body {
            Body::Disk(d) if self.dimension == 2 => {
                for m in d.modes() {
                    if m.l > self.modes {
                        return None;
                    }
                    let k = 2 * (m.l as usize - 2);
                    let (s, c) = (m.l as f64 * m.phase).sin_cos();
                    x[k] += m.a * c;
                    x[k + 1] += m.a * s;
                }
            }
            Body::Sphere(s) if self.dimension == 3 => {
                for c in s.coeffs() {
                    if c.l > self.modes {
                        return None;
                    }
                    let (m, sign) = (c.m.unsigned_abs(), if c.m % 2 == 0 { 1.0 } else { -1.0 });
                    let (re, im) = if c.m >= 0 {
                        (c.re, c.im)
                    } else {
                        (sign * c.re, -sign * c.im)
                    };
                    let k = self.offset(c.l, m);
                    x[k] += re;
                    if m > 0 {
                        x[k + 1] += im;
                    }
                }
            }
            _ => return None,
        }
        Some(x)
    }

    /// Where coefficient (l, m ≥ 0) of a sphere starts in the vector.
    fn offset(&self, l: u32, m: u32) -> usize {
        // Degrees 2…l−1 take (l'+1)² − 4 − … numbers in all: l² − 4 before degree l.
        let before = (l * l - 4) as usize;
        before + if m == 0 { 0 } else { 2 * m as usize - 1 }
    }

    /// The same vector in a space of higher degree (zeros above L), for adding print errors of
    /// finer modes than the design has.
    pub(crate) fn embed(&self, x: &[f64], wider: &DesignSpace) -> Vec<f64> {
        let mut y = vec![0.0; wider.len()];
        if self.dimension == 2 {
            y[..x.len()].copy_from_slice(x);
        } else {
            let mut k = 0;
            for l in 2..=self.modes {
                for m in 0..=l {
                    let n = if m == 0 { 1 } else { 2 };
                    let j = wider.offset(l, m);
                    y[j..j + n].copy_from_slice(&x[k..k + n]);
                    k += n;
                }
            }
        }
        y
    }

    /// The largest |a_l| (2D) or |A_lm| (3D) of a vector: what `--max-amplitude` bounds.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::DesignSpace;
    /// let space = DesignSpace { dimension: 2, modes: 3 };
    /// assert_eq!(space.largest_amplitude(&[0.3, 0.4, 0.0, -0.2]), 0.5);
    /// ```
    pub fn largest_amplitude(&self, x: &[f64]) -> f64 {
        let mut largest: f64 = 0.0;
        if self.dimension == 2 {
            for p in x.chunks_exact(2) {
                largest = largest.max(p[0].hypot(p[1]));
            }
        } else {
            for l in 2..=self.modes {
                for m in 0..=l {
                    let k = self.offset(l, m);
                    let a = if m == 0 {
                        x[k].abs()
                    } else {
                        x[k].hypot(x[k + 1])
                    };
                    largest = largest.max(a);
                }
            }
        }
        largest
    }
}

/// What a body offers a printer, at a scale of `scale_mm` per ⟨r⟩.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Printability {
    /// Strictly convex (every model needs it).
    pub convex: bool,
    /// The smallest curvature (2D) or smaller principal curvature (3D), in 1/⟨r⟩: > 0 when convex.
    pub convexity_min: f64,
    /// The smallest radius of curvature in mm: 1/(the largest curvature) × scale.
    pub smallest_radius_mm: f64,
    /// The smallest r, in ⟨r⟩ (a star-shaped body has r > 0 everywhere).
    pub smallest_r: f64,
}

impl Printability {
    /// Measures a body: the convexity by [`Body::curvature`]'s search, the largest curvature by
    /// a grid search refined to round-off (2D: κ; 3D: the larger principal curvature).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::Printability;
    /// use rollphase_core::geometry::Body;
    /// // A round body at 10 mm per ⟨r⟩: radius of curvature 10 mm everywhere.
    /// let p = Printability::of(&Body::random_sphere(1, 0.0, 3)?, 10.0);
    /// assert!(p.convex && (p.smallest_radius_mm - 10.0).abs() < 1e-9);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn of(body: &Body, scale_mm: f64) -> Self {
        let smallest_r = smallest_r(body);
        if smallest_r <= 0.0 {
            // Not a star-shaped body: no surface to measure.
            return Printability {
                convex: false,
                convexity_min: f64::NEG_INFINITY,
                smallest_radius_mm: 0.0,
                smallest_r,
            };
        }
        let report = body.curvature();
        let kappa_max = match body {
            Body::Disk(d) => refine_1d(|t| d.jet(t).curvature(), 4096).1,
            Body::Sphere(s) => {
                let grid = fibonacci_sphere(sphere_grid_size(s.max_degree()));
                refine_sphere(|u: DVec3| s.surface(u).principal_curvatures().1, &grid).1
            }
        };
        Printability {
            convex: report.convex,
            convexity_min: report.convexity_min,
            smallest_radius_mm: if kappa_max > 0.0 {
                scale_mm / kappa_max
            } else {
                0.0
            },
            smallest_r,
        }
    }
}

/// The smallest r of a body, in ⟨r⟩, refined from a grid.
///
/// # Example
/// ```
/// use rollphase_core::analysis::design::space::smallest_r;
/// use rollphase_core::geometry::{Body, Disk, DiskMode};
/// // r = 1 + 0.1 sin 2θ is smallest, 0.9, at θ = 3π/4.
/// let d = Disk::new(vec![DiskMode { l: 2, a: 0.4, phase: 0.0 }]);
/// assert!((smallest_r(&Body::Disk(d)) - 0.9).abs() < 1e-12);
/// ```
pub fn smallest_r(body: &Body) -> f64 {
    match body {
        Body::Disk(d) => -refine_1d(|t| -d.jet(t).r, 4096).1,
        Body::Sphere(s) => {
            let grid = fibonacci_sphere(sphere_grid_size(s.max_degree()));
            -refine_sphere(|u: DVec3| -s.radius(u), &grid).1
        }
    }
}
