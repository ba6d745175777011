//! Bodies: the 2D disk r(θ) and the 3D sphere r(u) with exact derivatives and curvature, the JSON
//! shape files other tools exchange with us, seeded random generators, and the convexity check
//! the contact model requires, and the meshes drawn and 3D-printed from them. Pure math: imports
//! `glam`, `serde`, `rand`, `rand_mt` only.

pub mod disk;
pub mod facets;
pub mod harmonics;
pub mod hull;
pub mod mesh;
pub mod mesh_fit;
pub(crate) mod mesh_ply;
pub mod mesh_read;
pub mod outline;
pub mod paper_bodies;
pub mod sculpt;
pub mod shape_file;
pub mod solid_hull;
pub mod sphere;

use std::f64::consts::TAU;

use crate::numeric::optimize::golden_max;
use glam::DVec3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Uniform};
use thiserror::Error;

pub use disk::{Disk, DiskMode, RadiusJet};
pub use paper_bodies::{paper_disk, paper_sphere};
pub use shape_file::{ShapeFile, ShapeLoadError};
pub use sphere::{Sphere, SphereCoeff, SurfacePoint};

/// Largest mode number accepted for a disk.
pub const MAX_DISK_L: u32 = 64;
/// Largest |amplitude| or |phase| accepted in a shape file: far beyond any convex body (whose
/// amplitudes are O(l²)), it keeps every computed quantity finite.
pub const MAX_AMPLITUDE: f64 = 1000.0;
/// Largest `scale_mm` accepted (10 m per ⟨r⟩: no printed or scanned body comes near it).
pub const MAX_SCALE_MM: f64 = 1e4;
/// Largest degree accepted for a sphere (the polynomial evaluator handles degree ≤ 15).
pub const MAX_SPHERE_L: u32 = 12;

/// A body with its dimension.
#[derive(Debug, Clone)]
pub enum Body {
    /// A cylinder's cross-section, rolling in 2D.
    Disk(Disk),
    /// A 3D body.
    Sphere(Sphere),
}

/// What is wrong with a shape.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ShapeError {
    /// A mode number out of range.
    #[error(
        "{what} l = {l} is not allowed (needs {min} ≤ l ≤ {max}; l = 0 and 1 would change the mean radius or move the centre)"
    )]
    BadDegree {
        /// "disk mode", "sphere coefficient", …
        what: &'static str,
        /// The degree given.
        l: u32,
        /// The lowest allowed.
        min: u32,
        /// The highest allowed.
        max: u32,
    },
    /// An order out of range.
    #[error("sphere coefficient l = {l}, m = {m} is not allowed (needs −l ≤ m ≤ l)")]
    BadOrder {
        /// The degree.
        l: u32,
        /// The order given.
        m: i32,
    },
    /// The same mode given twice.
    #[error("{what} appears twice; give each mode once")]
    Duplicate {
        /// Which mode.
        what: String,
    },
    /// A shape file's `printed_section` that is not a polygon around the centroid.
    #[error("{0}")]
    PrintedSection(String),
    /// A `scale_mm` that is not a size.
    #[error("scale_mm = {0} is not allowed (needs 0 < scale_mm ≤ 10000, millimetres per ⟨r⟩)")]
    BadScale(f64),
    /// A NaN, infinite or absurdly large number.
    #[error("{field} = {value} is not allowed (needs a finite number with |value| ≤ 1000)")]
    NonFinite {
        /// Which number.
        field: String,
        /// Its value.
        value: f64,
    },
    /// r(u) ≤ 0 somewhere: the coefficients do not describe a star-shaped body.
    #[error(
        "shape is not star-shaped: r = {value:.6} at {place} (needs r > 0 everywhere; the amplitudes are far too large)"
    )]
    NotStarShaped {
        /// The radius found there.
        value: f64,
        /// Where.
        place: String,
    },
    /// The body is not strictly convex.
    #[error(
        "shape is not convex: {measure} {value:.6} at {place} (needs > 0); the contact model needs \
         a strictly convex body: lower the amplitudes (σ) or use fewer modes{}",
        if *measure == "curvature" {
            " (`rollphase simulate`, and `period` and `predict` without inertia, roll a 2D \
             body like this on its convex hull)"
        } else {
            ""
        }
    )]
    NotConvex {
        /// "curvature" (2D) or "Gaussian curvature" (3D).
        measure: &'static str,
        /// Its value at the worst place.
        value: f64,
        /// Where.
        place: String,
    },
    /// No strictly convex body among the seeds tried ([`first_convex_disk`],
    /// [`first_convex_sphere`]).
    #[error(
        "no convex {what} among {tried} seeds from {from}{parameters}{}",
        if *tried < 1000 { " (the seeds end at 18446744073709551615; start lower)" } else { "" }
    )]
    NoConvexSeed {
        /// "disk" or "sphere".
        what: &'static str,
        /// The first seed tried.
        from: u64,
        /// How many were tried: 1000, or fewer where the seeds run out at `u64::MAX`.
        tried: u64,
        /// The generator's parameters, as " (σ = …, M = …)", or empty.
        parameters: String,
    },
    /// Fewer bodies than asked in an α* band ([`crate::analysis::rest::critical_angle::paper_spheres_with_alpha_star`]).
    #[error("fewer than {n} convex bodies with {from} ≤ α* < {below} among 100 000 seeds")]
    TooFewBodies {
        /// How many were asked for.
        n: usize,
        /// The band's lower end.
        from: f64,
        /// The band's upper end (excluded).
        below: f64,
    },
    /// A generator parameter out of range.
    #[error("{name} = {value} is not allowed (needs {allowed})")]
    BadParameter {
        /// Which parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}

/// The typed constructors, as the paper names its bodies.
impl Body {
    /// The paper authors' 3D body for numpy seed `seed` (their public code, bit for bit), with
    /// amplitudes A_lm ~ N(0, σ) for 2 ≤ l ≤ `modes`. The paper's own body is
    /// `Body::paper_sphere(219, 0.25, 5)` (α* = 0.1394). A seed must fit numpy's 32 bits.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// assert_eq!(body.dimension(), 3);
    /// assert!(body.is_convex());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn paper_sphere(seed: u64, sigma: f64, modes: u32) -> Result<Self, ShapeError> {
        Body::Sphere(paper_sphere(numpy_seed(seed)?, sigma, modes)?).checked_as_a_shape_file()
    }

    /// The paper authors' 2D body (a cylinder's section) for numpy seed `seed`, with
    /// a_l ~ N(0, σ) for 2 ≤ l ≤ `modes` (the paper: σ = 0.08, M = 10 viscous; 0.12, 5 inertial).
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// assert_eq!(disk.dimension(), 2);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn paper_disk(seed: u64, sigma: f64, modes: u32) -> Result<Self, ShapeError> {
        Body::Disk(paper_disk(numpy_seed(seed)?, sigma, modes)?).checked_as_a_shape_file()
    }

    /// A random 3D body from rollphase's own generator (ChaCha, seeded): any u64 seed.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let body = Body::random_sphere(1, 0.25, 5)?;
    /// assert_eq!(body.dimension(), 3);
    /// // Amplitudes so large that r < 0 somewhere are no body: refused, as a shape file would be.
    /// assert!(Body::random_sphere(1, 5.0, 5).is_err());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn random_sphere(seed: u64, sigma: f64, modes: u32) -> Result<Self, ShapeError> {
        Body::Sphere(random_sphere(seed, sigma, modes)?).checked_as_a_shape_file()
    }

    /// A random 2D body from rollphase's own generator: any u64 seed.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let disk = Body::random_disk(3, 0.08, 10)?;
    /// assert_eq!(disk.dimension(), 2);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn random_disk(seed: u64, sigma: f64, modes: u32) -> Result<Self, ShapeError> {
        Body::Disk(random_disk(seed, sigma, modes)?).checked_as_a_shape_file()
    }

    /// The body, checked as [`Body::from_shape`] checks a shape file (star-shaped, amplitudes
    /// in range), so a generated body is one that its written shape file loads back as.
    fn checked_as_a_shape_file(self) -> Result<Self, ShapeError> {
        Body::from_shape(&self.to_shape())
    }

    /// Reads, parses and validates a shape file (JSON; the schema is in [`ShapeFile`]). Files
    /// over 1 MiB are refused after reading that much.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/shapes/paper-sphere.json");
    /// let body = Body::from_file(path.as_ref())?;
    /// assert_eq!(body.dimension(), 3);
    /// # Ok::<(), rollphase_core::geometry::ShapeLoadError>(())
    /// ```
    pub fn from_file(path: &std::path::Path) -> Result<Self, ShapeLoadError> {
        ShapeFile::load(path)
    }

    /// Whether the body is strictly convex, as every model needs ([`Body::check_convex`] says
    /// where it is not).
    ///
    /// # Example
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    ///
    /// assert!(Body::paper_sphere(219, 0.25, 5)?.is_convex());
    /// // Strong modes dent the outline: not every random disk is convex.
    /// assert!(!Body::random_disk(3, 2.0, 5)?.is_convex());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn is_convex(&self) -> bool {
        self.check_convex().is_ok()
    }
}

/// numpy's seeds are 32-bit.
fn numpy_seed(seed: u64) -> Result<u32, ShapeError> {
    u32::try_from(seed).map_err(|_| ShapeError::BadParameter {
        name: "paper seed",
        value: seed as f64,
        allowed: "0 ≤ seed ≤ 4294967295, numpy's 32-bit seeds",
    })
}

impl Body {
    /// Builds a body from a parsed shape file, checking ranges and finiteness (not convexity).
    ///
    /// # Example
    ///
    /// ```
    /// use rollphase_core::geometry::{Body, ShapeFile};
    ///
    /// let disk = Body::paper_disk(1, 0.25, 5)?;
    /// let file: ShapeFile = disk.to_shape();
    /// assert_eq!(Body::from_shape(&file)?.alpha_star(), disk.alpha_star());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn from_shape(file: &ShapeFile) -> Result<Self, ShapeError> {
        if let Some(scale) = file.scale_mm()
            && !(scale.is_finite() && scale > 0.0 && scale <= MAX_SCALE_MM)
        {
            return Err(ShapeError::BadScale(scale));
        }
        match file {
            ShapeFile::Disk {
                modes,
                printed_section,
                ..
            } => {
                let mut seen = std::collections::BTreeSet::new();
                for (i, m) in modes.iter().enumerate() {
                    if !(2..=MAX_DISK_L).contains(&m.l) {
                        return Err(ShapeError::BadDegree {
                            what: "disk mode",
                            l: m.l,
                            min: 2,
                            max: MAX_DISK_L,
                        });
                    }
                    for (name, v) in [("a", m.a), ("phase", m.phase)] {
                        if !v.is_finite() || v.abs() > MAX_AMPLITUDE {
                            return Err(ShapeError::NonFinite {
                                field: format!("modes[{i}].{name}"),
                                value: v,
                            });
                        }
                    }
                    if !seen.insert(m.l) {
                        return Err(ShapeError::Duplicate {
                            what: format!("disk mode l = {}", m.l),
                        });
                    }
                }
                // The modes are checked as the smooth body they describe; the print's section
                // is attached after.
                let disk = Disk::new(modes.clone());
                // Σ|a_l|/l² < 1 guarantees r > 0; otherwise look for the smallest radius.
                if modes
                    .iter()
                    .map(|m| m.a.abs() / (m.l * m.l) as f64)
                    .sum::<f64>()
                    >= 1.0
                {
                    let (t, neg_r) = refine_1d(|t| -disk.jet(t).r, DISK_GRID);
                    if -neg_r <= 0.0 {
                        return Err(ShapeError::NotStarShaped {
                            value: -neg_r,
                            place: format!("θ = {:.4}", t.rem_euclid(TAU)),
                        });
                    }
                }
                if let Some(section) = printed_section {
                    let smooth_hull = facets::PrintedSection::hull_mean_radius(|t| disk.jet(t).r);
                    section
                        .check_for_shape_file(smooth_hull)
                        .map_err(ShapeError::PrintedSection)?;
                }
                Ok(Body::Disk(
                    disk.with_printed_section(printed_section.clone()),
                ))
            }
            ShapeFile::Sphere { coeffs, .. } => {
                let mut seen = std::collections::BTreeSet::new();
                for (i, c) in coeffs.iter().enumerate() {
                    if !(2..=MAX_SPHERE_L).contains(&c.l) {
                        return Err(ShapeError::BadDegree {
                            what: "sphere coefficient",
                            l: c.l,
                            min: 2,
                            max: MAX_SPHERE_L,
                        });
                    }
                    if c.m.unsigned_abs() > c.l {
                        return Err(ShapeError::BadOrder { l: c.l, m: c.m });
                    }
                    for (name, v) in [("re", c.re), ("im", c.im)] {
                        if !v.is_finite() || v.abs() > MAX_AMPLITUDE {
                            return Err(ShapeError::NonFinite {
                                field: format!("coeffs[{i}].{name}"),
                                value: v,
                            });
                        }
                    }
                    if !seen.insert((c.l, c.m)) {
                        return Err(ShapeError::Duplicate {
                            what: format!("sphere coefficient l = {}, m = {}", c.l, c.m),
                        });
                    }
                }
                let sphere = Sphere::new(coeffs.clone());
                // |Y_l^m| ≤ √((2l+1)/4π), so this sum < 1 guarantees r > 0.
                let bound: f64 = coeffs
                    .iter()
                    .map(|c| {
                        let l = c.l as f64;
                        c.re.hypot(c.im) * ((2.0 * l + 1.0) / (4.0 * std::f64::consts::PI)).sqrt()
                            / (l * (l + 1.0))
                    })
                    .sum();
                if bound >= 1.0 {
                    let grid = sphere::fibonacci_sphere(sphere_grid_size(sphere.max_degree()));
                    let (u, neg_r) = refine_sphere(|u| -sphere.radius(u), &grid);
                    if -neg_r <= 0.0 {
                        let (theta, phi) = sphere::angles(u);
                        return Err(ShapeError::NotStarShaped {
                            value: -neg_r,
                            place: format!("θ = {theta:.4}, φ = {phi:.4}"),
                        });
                    }
                }
                Ok(Body::Sphere(sphere))
            }
        }
    }

    /// The shape file describing this body.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// let body = Body::paper_disk(84, 0.12, 5)?;
    /// let again = Body::from_shape(&body.to_shape())?;
    /// assert_eq!(again.alpha_star(), body.alpha_star());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn to_shape(&self) -> ShapeFile {
        match self {
            Body::Disk(d) => ShapeFile::Disk {
                modes: d.modes().to_vec(),
                scale_mm: None,
                printed_section: d.printed_section().cloned(),
            },
            Body::Sphere(s) => ShapeFile::Sphere {
                coeffs: s.coeffs().to_vec(),
                scale_mm: None,
            },
        }
    }

    /// 2 or 3.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// assert_eq!(Body::random_disk(1, 0.1, 5)?.dimension(), 2);
    /// assert_eq!(Body::random_sphere(1, 0.1, 5)?.dimension(), 3);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn dimension(&self) -> u32 {
        match self {
            Body::Disk(_) => 2,
            Body::Sphere(_) => 3,
        }
    }

    /// Curvature extremes and the convexity verdict (see `curvature_report`).
    ///
    /// # Example
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    ///
    /// // The unit circle has curvature 1 everywhere.
    /// let report = Body::random_disk(1, 0.0, 5)?.curvature();
    /// assert!((report.curvature_min - 1.0).abs() < 1e-9 && (report.curvature_max - 1.0).abs() < 1e-9);
    /// assert!(report.convex);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn curvature(&self) -> CurvatureReport {
        curvature_report(self)
    }

    /// [`Body::curvature`] searched from a grid of `grid_size` points (the disk's θ grid or the
    /// sphere's Fibonacci lattice) instead of the default size: for checking the default
    /// against a denser search.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// // A denser search agrees with the default one on the extremes.
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let (default, dense) = (body.curvature(), body.curvature_on_grid(20_000));
    /// assert!((default.curvature_min - dense.curvature_min).abs() < 1e-9);
    /// assert_eq!(default.convex, dense.convex);
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn curvature_on_grid(&self, grid_size: usize) -> CurvatureReport {
        curvature_report_on(self, grid_size.max(8))
    }

    /// Whether `simulate` can roll the body: a strictly convex one, or a 2D body that is not
    /// convex but rolls on its convex hull (issue 34: across a dent on the bridge that spans it)
    /// and whose hull's curved parts are strictly convex. A 3D body must be convex.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// // The authors' printed σ = 0.5 cylinder has two dents: it rolls on its hull.
    /// let printed = Body::paper_disk(219, 0.5, 9)?;
    /// assert!(printed.check_convex().is_err() && printed.check_rollable().is_ok());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn check_rollable(&self) -> Result<(), ShapeError> {
        let Err(e) = self.check_convex() else {
            return Ok(());
        };
        let Body::Disk(d) = self else {
            return Err(e);
        };
        // A dented disk rolls on its hull: its curved parts must be strictly convex.
        let hull = d.hull();
        let n = DISK_GRID;
        // A printed outline's corners are far narrower than the grid: their own samples too.
        let corners = d
            .printed_outline()
            .map(|o| o.corner_samples(9))
            .unwrap_or_default();
        let worst = (0..n)
            .map(|i| i as f64 * std::f64::consts::TAU / n as f64)
            .chain(corners)
            .filter(|t| hull.bridge_at(*t).is_none())
            .map(|t| (d.jet(t).convexity(), t))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match worst {
            Some((c, _)) if c > 0.0 && !hull.bridges().is_empty() => Ok(()),
            Some((c, t)) => Err(ShapeError::NotConvex {
                measure: "curvature on the convex hull",
                value: c,
                place: format!("θ = {t:.6}"),
            }),
            None => Err(e),
        }
    }

    /// Returns an error naming the worst point unless the body is strictly convex.
    ///
    /// ```
    /// use rollphase_core::geometry::Body;
    /// assert!(Body::paper_sphere(219, 0.25, 5)?.check_convex().is_ok());
    /// // Large amplitudes dent the body: the error says where.
    /// let dented = Body::random_disk(1, 3.0, 10)?;
    /// assert!(dented.check_convex().is_err());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn check_convex(&self) -> Result<(), ShapeError> {
        // The convexity measure alone: the same search and verdict as `curvature()`'s, without
        // the curvature extremes a check does not need (half a run's set-up time).
        let rep = curvature_search(self, default_grid(self), Search::Convexity);
        if rep.convex {
            Ok(())
        } else {
            Err(ShapeError::NotConvex {
                measure: rep.convexity_measure,
                value: rep.convexity_min,
                place: rep.convexity_place,
            })
        }
    }
}

/// Curvature extremes of a body, found on a dense grid and refined locally.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvatureReport {
    /// Strictly convex everywhere.
    pub convex: bool,
    /// Minimum of κ (2D) or of the Gaussian curvature K (3D).
    pub curvature_min: f64,
    /// Maximum of κ (2D) or of K (3D).
    pub curvature_max: f64,
    /// The quantity whose sign decides convexity: κ (2D) or the smaller principal curvature (3D).
    pub convexity_measure: &'static str,
    /// Its minimum.
    pub convexity_min: f64,
    /// Where that minimum is, as text (θ, or θ/φ and the unit vector).
    pub convexity_place: String,
}

/// Dense-grid size for the disk's curvature and α* searches.
const DISK_GRID: usize = 4096;

/// Grid size for a global search over a sphere of largest degree `max_degree`: 100 L² points
/// (at least 800), a spacing of about 0.35/L rad, so ≥ 18 points per wavelength of the highest
/// harmonic and ≥ 9 for the products of two that curvature contains. The grid only has to land in
/// the basin of each candidate extremum; Newton refinement then finds it to round-off.
/// The unit tests check the verdicts and extremes against a 20 000-point grid on a few hundred
/// random bodies at the edge of convexity. A 2500-point grid for L = 5 costs about 0.3 ms.
///
/// # Example
/// ```
/// use rollphase_core::geometry::sphere_grid_size;
/// // Finer bodies need finer grids.
/// assert!(sphere_grid_size(5) >= sphere_grid_size(2));
/// ```
pub fn sphere_grid_size(max_degree: u32) -> usize {
    (100 * (max_degree as usize).pow(2)).clamp(800, 20_000)
}

fn curvature_report(body: &Body) -> CurvatureReport {
    curvature_report_on(body, default_grid(body))
}

/// The grid [`Body::curvature`] searches.
fn default_grid(body: &Body) -> usize {
    match body {
        Body::Disk(_) => DISK_GRID,
        Body::Sphere(s) => sphere_grid_size(s.max_degree()),
    }
}

/// What a curvature search finds: the convexity measure's minimum alone (all a convexity check
/// needs, and what a run's set-up pays for), or the curvature's extremes too.
#[derive(Clone, Copy, PartialEq)]
enum Search {
    Convexity,
    Full,
}

fn curvature_report_on(body: &Body, grid_size: usize) -> CurvatureReport {
    curvature_search(body, grid_size, Search::Full)
}

/// The search behind [`CurvatureReport`]; with [`Search::Convexity`] its curvature extremes are
/// NaN (not searched).
fn curvature_search(body: &Body, grid_size: usize, search: Search) -> CurvatureReport {
    let full = search == Search::Full;
    match body {
        Body::Disk(d) => {
            let kappa = |t: f64| d.jet(t).curvature();
            let (tmin, kmin) = refine_1d(|t| -kappa(t), grid_size);
            let kmax = if full {
                refine_1d(kappa, grid_size).1
            } else {
                f64::NAN
            };
            let kmin = -kmin;
            CurvatureReport {
                convex: kmin > 0.0,
                curvature_min: kmin,
                curvature_max: kmax,
                convexity_measure: "curvature",
                convexity_min: kmin,
                convexity_place: format!("θ = {:.4}", tmin.rem_euclid(TAU)),
            }
        }
        Body::Sphere(s) => {
            let pts = sphere::fibonacci_sphere(grid_size);
            let kmin_of = |u: DVec3| s.surface(u).principal_curvatures().0;
            let gauss = |u: DVec3| s.surface(u).gaussian_curvature();
            // One surface evaluation per grid point serves all three searches (the expensive
            // part: r with its first and second derivatives); only the refinements differ.
            let (mut neg_kmin, mut neg_gauss, mut gauss_values) = (
                Vec::with_capacity(pts.len()),
                Vec::with_capacity(pts.len()),
                Vec::with_capacity(pts.len()),
            );
            for &u in &pts {
                let sp = s.surface(u);
                neg_kmin.push(-sp.principal_curvatures().0);
                if full {
                    let g = sp.gaussian_curvature();
                    neg_gauss.push(-g);
                    gauss_values.push(g);
                }
            }
            let (u_min, k1) = refine_sphere_from(|u| -kmin_of(u), &pts, &neg_kmin);
            let (gmin, gmax) = if full {
                let (_, gmin) = refine_sphere_from(|u| -gauss(u), &pts, &neg_gauss);
                let (_, gmax) = refine_sphere_from(gauss, &pts, &gauss_values);
                (-gmin, gmax)
            } else {
                (f64::NAN, f64::NAN)
            };
            let (theta, phi) = sphere::angles(u_min);
            CurvatureReport {
                convex: -k1 > 0.0,
                curvature_min: gmin,
                curvature_max: gmax,
                convexity_measure: "smallest principal curvature",
                convexity_min: -k1,
                convexity_place: format!(
                    "θ = {theta:.4}, φ = {phi:.4} (u = [{:.4}, {:.4}, {:.4}])",
                    u_min.x, u_min.y, u_min.z
                ),
            }
        }
    }
}

/// Maximises a smooth 2π-periodic f: best of `n` grid points, then golden-section search on the
/// bracketing cell pair, to |Δθ| ≈ 1e-12. Returns (θ, f(θ)).
///
/// # Example
/// ```
/// use rollphase_core::geometry::refine_1d;
/// let (theta, value) = refine_1d(|t| (t - 1.0).cos(), 16);
/// assert!((theta - 1.0).abs() < 1e-7 && (value - 1.0).abs() < 1e-14);
/// ```
pub fn refine_1d(f: impl Fn(f64) -> f64, n: usize) -> (f64, f64) {
    let h = TAU / n as f64;
    let (mut best_i, mut best) = (0, f64::NEG_INFINITY);
    for i in 0..n {
        let v = f(i as f64 * h);
        if v > best {
            best = v;
            best_i = i;
        }
    }
    let t = golden_max(
        &f,
        (best_i as f64 - 1.0) * h,
        (best_i as f64 + 1.0) * h,
        1e-12,
    );
    let v = f(t);
    if v >= best {
        (t, v)
    } else {
        (best_i as f64 * h, best)
    }
}

/// Maximises a smooth f on the unit sphere: the best grid point and the best few local maxima
/// of the grid are refined by Newton's method in a tangent chart (finite-difference gradient and
/// Hessian, backtracking), which converges to the maximiser to ~1e-8 and so to the maximum value
/// to ~1e-15. Returns (u, f(u)).
///
/// # Example
/// ```
/// use rollphase_core::geometry::{refine_sphere, sphere::fibonacci_sphere};
/// use rollphase_core::glam::DVec3;
/// let target = DVec3::new(1.0, 2.0, -2.0).normalize();
/// let (u, value) = refine_sphere(|u| u.dot(target), &fibonacci_sphere(200));
/// assert!((u - target).length() < 1e-6 && (value - 1.0).abs() < 1e-12);
/// ```
pub fn refine_sphere(f: impl Fn(DVec3) -> f64, grid: &[DVec3]) -> (DVec3, f64) {
    let values: Vec<f64> = grid.iter().map(|&u| f(u)).collect();
    refine_sphere_from(f, grid, &values)
}

/// How many of the best grid values [`refine_sphere_from`] scans for separated candidates.
const CANDIDATE_POOL: usize = 400;

/// [`refine_sphere`] with f already evaluated on the grid (`values[i]` = f(`grid[i]`)), so that
/// several searches can share one pass of an expensive evaluation.
///
/// # Example
/// ```
/// use rollphase_core::geometry::{refine_sphere_from, sphere::fibonacci_sphere};
/// use rollphase_core::glam::DVec3;
/// let grid = fibonacci_sphere(200);
/// // One pass of values, two searches: the maximum of f and of −f.
/// let f = |u: DVec3| u.z + 0.5 * u.x;
/// let values: Vec<f64> = grid.iter().map(|&u| f(u)).collect();
/// let negated: Vec<f64> = values.iter().map(|v| -v).collect();
/// let (_, max) = refine_sphere_from(f, &grid, &values);
/// let (_, min) = refine_sphere_from(|u| -f(u), &grid, &negated);
/// assert!((max - 1.25f64.sqrt()).abs() < 1e-12 && (min - 1.25f64.sqrt()).abs() < 1e-12);
/// ```
pub fn refine_sphere_from(
    f: impl Fn(DVec3) -> f64,
    grid: &[DVec3],
    values: &[f64],
) -> (DVec3, f64) {
    let mut vals: Vec<(f64, usize)> = values.iter().copied().zip(0..).collect();
    // Only the top few hundred are looked at: select them, then sort just those.
    let top = CANDIDATE_POOL.min(vals.len());
    if top < vals.len() {
        vals.select_nth_unstable_by(top, |a, b| b.0.total_cmp(&a.0));
    }
    vals.truncate(top);
    vals.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut best = (grid[vals[0].1], vals[0].0);
    // Candidates: the top few grid values that are not within 0.1 rad of a better one.
    let mut starts: Vec<DVec3> = Vec::new();
    for &(_, i) in &vals {
        let u = grid[i];
        if starts.iter().all(|s| s.dot(u) < 0.995) {
            starts.push(u);
        }
        if starts.len() == 6 {
            break;
        }
    }
    for start in starts {
        let (u, v) = newton_max_on_sphere(&f, start);
        if v > best.1 {
            best = (u, v);
        }
    }
    best
}

fn newton_max_on_sphere(f: &impl Fn(DVec3) -> f64, start: DVec3) -> (DVec3, f64) {
    let mut u = start;
    let mut fu = f(u);
    for _ in 0..50 {
        let (e1, e2) = u.any_orthonormal_pair();
        let at = |a: f64, b: f64| f((u + a * e1 + b * e2).normalize());
        let h = 1e-4;
        let f0 = fu;
        let (fp0, fm0, f0p, f0m) = (at(h, 0.0), at(-h, 0.0), at(0.0, h), at(0.0, -h));
        let (fpp, fpm, fmp, fmm) = (at(h, h), at(h, -h), at(-h, h), at(-h, -h));
        let g1 = (fp0 - fm0) / (2.0 * h);
        let g2 = (f0p - f0m) / (2.0 * h);
        let h11 = (fp0 - 2.0 * f0 + fm0) / (h * h);
        let h22 = (f0p - 2.0 * f0 + f0m) / (h * h);
        let h12 = (fpp - fpm - fmp + fmm) / (4.0 * h * h);
        let det = h11 * h22 - h12 * h12;
        let (mut s1, mut s2) = if h11 < 0.0 && det > 0.0 {
            (-(h22 * g1 - h12 * g2) / det, -(h11 * g2 - h12 * g1) / det)
        } else {
            // Not concave here: a gradient step.
            (g1 * 1e-2, g2 * 1e-2)
        };
        let len = (s1 * s1 + s2 * s2).sqrt();
        if len > 0.05 {
            s1 *= 0.05 / len;
            s2 *= 0.05 / len;
        }
        let mut accepted = false;
        for _ in 0..30 {
            let cand = (u + s1 * e1 + s2 * e2).normalize();
            let fc = f(cand);
            if fc >= fu {
                u = cand;
                fu = fc;
                accepted = true;
                break;
            }
            s1 *= 0.5;
            s2 *= 0.5;
        }
        if !accepted || (s1 * s1 + s2 * s2).sqrt() < 1e-11 {
            break;
        }
    }
    (u, fu)
}

/// Seeded random disk (SI §1C): A_l ~ N(0, σ), θ_l ~ U[0, 2π) for l = 2..=modes, drawn in that
/// order (A_l then θ_l for each l) from ChaCha8 seeded with `seed`.
///
/// # Example
///
/// ```
/// use rollphase_core::geometry::random_disk;
///
/// // The same seed gives the same disk on every run and machine.
/// assert_eq!(random_disk(7, 0.25, 5)?, random_disk(7, 0.25, 5)?);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn random_disk(seed: u64, sigma: f64, modes: u32) -> Result<Disk, ShapeError> {
    check_sigma(sigma)?;
    if !(2..=MAX_DISK_L).contains(&modes) {
        return Err(ShapeError::BadParameter {
            name: "modes",
            value: modes as f64,
            allowed: "2 ≤ modes ≤ 64",
        });
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, sigma).map_err(|_| bad_sigma(sigma))?;
    let phase = Uniform::new(0.0, TAU).map_err(|_| bad_sigma(sigma))?;
    let ms = (2..=modes)
        .map(|l| {
            let a = normal.sample(&mut rng);
            let p = phase.sample(&mut rng);
            DiskMode { l, a, phase: p }
        })
        .collect();
    Ok(Disk::new(ms))
}

/// Seeded random sphere (SI §2F and the issue's generator): for l = 2..=degree and m = −l..=l in
/// that order, a ~ N(0, σ) then P ~ U[0, 2π), A_lm = a·e^{imP}; ChaCha8 seeded with `seed`.
///
/// # Example
///
/// ```
/// use glam::DVec3;
/// use rollphase_core::geometry::random_sphere;
///
/// // The same seed gives the same body on every run and machine.
/// let u = DVec3::new(0.3, -0.5, 0.8).normalize();
/// assert_eq!(random_sphere(7, 0.25, 5)?.radius(u), random_sphere(7, 0.25, 5)?.radius(u));
/// // σ must be finite and ≥ 0.
/// assert!(random_sphere(7, f64::NAN, 5).is_err());
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn random_sphere(seed: u64, sigma: f64, degree: u32) -> Result<Sphere, ShapeError> {
    check_sigma(sigma)?;
    if !(2..=MAX_SPHERE_L).contains(&degree) {
        return Err(ShapeError::BadParameter {
            name: "modes",
            value: degree as f64,
            allowed: "2 ≤ modes ≤ 12 (the largest degree l)",
        });
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, sigma).map_err(|_| bad_sigma(sigma))?;
    let phase = Uniform::new(0.0, TAU).map_err(|_| bad_sigma(sigma))?;
    let mut coeffs = Vec::new();
    for l in 2..=degree {
        for m in -(l as i32)..=(l as i32) {
            let a = normal.sample(&mut rng);
            let p = phase.sample(&mut rng);
            let (s, c) = (m as f64 * p).sin_cos();
            coeffs.push(SphereCoeff {
                l,
                m,
                re: a * c,
                im: a * s,
            });
        }
    }
    Ok(Sphere::new(coeffs))
}

fn check_sigma(sigma: f64) -> Result<(), ShapeError> {
    if sigma.is_finite() && sigma >= 0.0 {
        Ok(())
    } else {
        Err(bad_sigma(sigma))
    }
}

fn bad_sigma(sigma: f64) -> ShapeError {
    ShapeError::BadParameter {
        name: "sigma",
        value: sigma,
        allowed: "a finite number ≥ 0",
    }
}

/// The first strictly convex [`random_disk`] at seed `seed`, `seed` + 1, … (1000 tried): the
/// disk and the seed that gave it.
///
/// # Example
///
/// ```
/// use rollphase_core::geometry::{Body, first_convex_disk};
///
/// let (disk, seed) = first_convex_disk(3, 0.25, 5)?;
/// assert!(seed >= 3 && Body::Disk(disk).is_convex());
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn first_convex_disk(seed: u64, sigma: f64, modes: u32) -> Result<(Disk, u64), ShapeError> {
    match first_convex(seed, |s| Ok(Body::Disk(random_disk(s, sigma, modes)?)))? {
        Some((Body::Disk(d), s)) => Ok((d, s)),
        _ => Err(ShapeError::NoConvexSeed {
            what: "disk",
            from: seed,
            tried: seeds_tried(seed),
            parameters: format!(" (σ = {sigma}, M = {modes})"),
        }),
    }
}

/// The first strictly convex [`random_sphere`] at seed `seed`, `seed` + 1, … (1000 tried): the
/// sphere and the seed that gave it.
///
/// # Example
/// ```
/// use rollphase_core::geometry::{Body, first_convex_sphere};
/// let (sphere, seed) = first_convex_sphere(1, 0.25, 5)?;
/// assert!(seed >= 1 && Body::Sphere(sphere).is_convex());
/// // At the end of the seeds fewer are tried, and the message says how many.
/// let e = first_convex_sphere(u64::MAX - 1, 3.0, 5).unwrap_err().to_string();
/// assert!(e.contains("among 2 seeds") && e.contains("start lower"), "{e}");
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn first_convex_sphere(
    seed: u64,
    sigma: f64,
    degree: u32,
) -> Result<(Sphere, u64), ShapeError> {
    match first_convex(seed, |s| Ok(Body::Sphere(random_sphere(s, sigma, degree)?)))? {
        Some((Body::Sphere(b), s)) => Ok((b, s)),
        _ => Err(ShapeError::NoConvexSeed {
            what: "sphere",
            from: seed,
            tried: seeds_tried(seed),
            parameters: String::new(),
        }),
    }
}

/// The first strictly convex body `make(s)` for s = `seed`, `seed` + 1, … (1000 tried), with its
/// seed; `None` when none is.
/// How many seeds [`first_convex`] tries from `seed`: 1000, fewer near `u64::MAX`.
fn seeds_tried(seed: u64) -> u64 {
    seed.saturating_add(999) - seed + 1
}

fn first_convex(
    seed: u64,
    make: impl Fn(u64) -> Result<Body, ShapeError>,
) -> Result<Option<(Body, u64)>, ShapeError> {
    for s in seed..=seed.saturating_add(999) {
        let body = make(s)?;
        if body.check_convex().is_ok() {
            return Ok(Some((body, s)));
        }
    }
    Ok(None)
}
