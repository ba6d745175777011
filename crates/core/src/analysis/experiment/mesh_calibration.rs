//! How honest the mesh fit's stated errors of ⟨r⟩ and α* are: noisy meshes of known bodies
//! (3D: the paper's sphere, seed 219, σ = 0.25, degree 5, as icospheres of 1,280 to 81,920
//! triangles; 2D: the paper's disk, seed 84, σ = 0.12, five modes, extruded with 256 to 4,096
//! sides), each distinct vertex moved along its ray by Gaussian noise of a given fraction of
//! ⟨r⟩ (a scanner's noise, a print's roughness), fitted at the body's degree. The truth is the fit of the same mesh without noise: the errors
//! speak for the scatter, not for the facets, which the print's hull reports. `rollphase bench
//! calibration` prints the table; a test holds one case to the goal.

use std::collections::HashMap;

use glam::DVec3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;
use serde::Serialize;

use super::tracking::calibration::{Coverage, coverage};
use crate::geometry::Body;
use crate::geometry::mesh::{disk_mesh, sphere_mesh};
use crate::geometry::mesh_fit::{FitOptions, FitReport, fit_mesh};
use crate::geometry::mesh_read::{MeshError, MeshSource};

/// One kind of synthetic mesh.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeshCase {
    /// 3: an icosphere of the paper's sphere; 2: an extrusion of the paper's disk.
    pub dimension: u32,
    /// 3D: icosphere subdivisions (20 × 4^detail triangles); 2D: the section's sides.
    pub resolution: u32,
    /// Gaussian noise of each vertex along its ray, as a fraction of ⟨r⟩.
    pub noise: f64,
}

impl MeshCase {
    /// The mesh's triangles.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::mesh_calibration::MeshCase;
    /// let ball = MeshCase { dimension: 3, resolution: 4, noise: 0.0 };
    /// let cylinder = MeshCase { dimension: 2, resolution: 256, noise: 0.0 };
    /// assert_eq!((ball.triangles(), cylinder.triangles()), (5120, 1024));
    /// ```
    pub fn triangles(&self) -> usize {
        if self.dimension == 2 {
            4 * self.resolution as usize
        } else {
            20 * 4usize.pow(self.resolution)
        }
    }
}

const fn case(dimension: u32, resolution: u32, noise: f64) -> MeshCase {
    MeshCase {
        dimension,
        resolution,
        noise,
    }
}

/// The cases `bench calibration` runs: spheres of 1,280 to 81,920 triangles and cylinders of
/// 256 to 4,096 sides, noise 0.05 % and 0.5 % of ⟨r⟩ (5 and 50 µm on a 10 mm body).
pub const BENCH_MESH_CASES: [MeshCase; 14] = [
    case(3, 3, 5e-4),
    case(3, 3, 5e-3),
    case(3, 4, 5e-4),
    case(3, 4, 5e-3),
    case(3, 5, 5e-4),
    case(3, 5, 5e-3),
    case(3, 6, 5e-4),
    case(3, 6, 5e-3),
    case(2, 256, 5e-4),
    case(2, 256, 5e-3),
    case(2, 1024, 5e-4),
    case(2, 1024, 5e-3),
    case(2, 4096, 5e-4),
    case(2, 4096, 5e-3),
];

/// One case's calibration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshCalibration {
    /// The case.
    pub case: MeshCase,
    /// Meshes fitted.
    pub draws: usize,
    /// Fits that stated no errors (too few blocks) or failed.
    pub without_errors: usize,
    /// Fits with an error of ⟨r⟩ but none of α* (its bias over
    /// [`crate::geometry::mesh_fit::MAX_ALPHA_BIAS`] errors).
    pub alpha_without_error: usize,
    /// ⟨r⟩ (mesh units: the body's ⟨r⟩ is about 1) and its stated error.
    pub scale: Coverage,
    /// α* less its stated bias (rad), and its stated error.
    pub alpha_star: Coverage,
    /// The median stated bias of α* (rad).
    pub median_alpha_bias: f64,
}

/// The body a case of `dimension` fits: the paper's sphere (seed 219, σ = 0.25, degree 5) or
/// disk (seed 84, σ = 0.12, five modes).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::mesh_calibration::calibration_body;
/// assert_eq!(calibration_body(3).dimension(), 3);
/// assert_eq!(calibration_body(2).dimension(), 2);
/// ```
pub fn calibration_body(dimension: u32) -> Body {
    let body = if dimension == 2 {
        Body::paper_disk(84, 0.12, 5)
    } else {
        Body::paper_sphere(219, 0.25, 5)
    };
    body.expect("the paper's bodies are valid")
}

/// A mesh of `body` at `case.resolution` (an icosphere, or an extrusion of length 2 along y),
/// each distinct vertex moved along its ray from the axis or centre by `case.noise` ⟨r⟩ times
/// a standard normal drawn from `seed` (noise 0: the exact vertices). Vertices at one place
/// move together, so the mesh stays closed and an extrusion stays one.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::mesh_calibration::{
///     MeshCase, calibration_body, noisy_mesh,
/// };
/// let case = MeshCase { dimension: 3, resolution: 3, noise: 1e-3 };
/// assert_eq!(noisy_mesh(&calibration_body(3), &case, 1)?.triangles(), 1280);
/// # Ok::<(), rollphase_core::geometry::mesh_read::MeshError>(())
/// ```
pub fn noisy_mesh(body: &Body, case: &MeshCase, seed: u64) -> Result<MeshSource, MeshError> {
    let mesh = match body {
        Body::Sphere(s) => sphere_mesh(s, case.resolution),
        Body::Disk(d) => disk_mesh(d, case.resolution as usize, 2.0),
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, 1.0).expect("a unit normal");
    let mut moved: HashMap<[u32; 3], DVec3> = HashMap::new();
    let mut vertex = |p: [f32; 3]| -> DVec3 {
        let key = match body {
            Body::Sphere(_) => p.map(f32::to_bits),
            // An extrusion's rings repeat at both ends and in the caps: one draw a place.
            Body::Disk(_) => [p[0].to_bits(), 0, p[2].to_bits()],
        };
        let q = DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
        // The point's place along an extrusion's axis is its own; the move across it is shared
        // by the rings at both ends and the caps.
        let along = match body {
            Body::Sphere(_) => DVec3::ZERO,
            Body::Disk(_) => DVec3::new(0.0, q.y, 0.0),
        };
        along
            + *moved.entry(key).or_insert_with(|| {
                let (u, radius) = match body {
                    Body::Sphere(s) => {
                        let u = q.normalize();
                        (u, s.radius(u))
                    }
                    Body::Disk(d) => {
                        let across = DVec3::new(q.x, 0.0, q.z);
                        if across.length() == 0.0 {
                            // A cap's centre, on the axis.
                            return DVec3::ZERO;
                        }
                        (across.normalize(), d.jet(q.z.atan2(q.x)).r)
                    }
                };
                (radius + case.noise * normal.sample(&mut rng)) * u
            })
    };
    let triangles: Vec<[DVec3; 3]> = mesh
        .indices
        .iter()
        .map(|t| t.map(|i| vertex(mesh.positions[i as usize])))
        .collect();
    MeshSource::made(
        &format!(
            "a {}D mesh of {} triangles with noise {}",
            case.dimension,
            case.triangles(),
            case.noise
        ),
        triangles,
    )
}

fn fit(source: &MeshSource, dimension: u32, modes: u32) -> Result<FitReport, MeshError> {
    let options = FitOptions {
        dim: Some(dimension),
        modes: Some(modes),
        // The extrusion's axis, θ from x towards z seen from −y, as `disk_mesh` writes it.
        axis: (dimension == 2).then_some(-DVec3::Y),
        ignore_facets: true,
        ..FitOptions::default()
    };
    Ok(fit_mesh(source, &options, &|_, _, _| {})?.report)
}

/// Fits `draws` noisy meshes of `case` (seeds `seed`, `seed + 1`, …, in parallel, the same answer
/// on every run) and measures how often the stated ±1.96-error intervals of ⟨r⟩ and α* hold the
/// noiseless mesh's fit.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::mesh_calibration::{MeshCase, calibrate_mesh_case};
/// // A cylinder of 256 sides (1,024 triangles) with 0.5 % noise.
/// let c = calibrate_mesh_case(&MeshCase { dimension: 2, resolution: 256, noise: 5e-3 }, 8, 1)?;
/// assert_eq!((c.draws, c.without_errors), (8, 0));
/// assert!(c.scale.median_error > 0.0 && c.alpha_star.median_error > 0.0);
/// # Ok::<(), rollphase_core::geometry::mesh_read::MeshError>(())
/// ```
pub fn calibrate_mesh_case(
    case: &MeshCase,
    draws: usize,
    seed: u64,
) -> Result<MeshCalibration, MeshError> {
    let body = calibration_body(case.dimension);
    let modes = 5;
    let truth = fit(
        &noisy_mesh(
            &body,
            &MeshCase {
                noise: 0.0,
                ..*case
            },
            0,
        )?,
        case.dimension,
        modes,
    )?;
    let fits: Vec<Option<FitReport>> = (0..draws as u64)
        .into_par_iter()
        .map(|k| {
            noisy_mesh(&body, case, seed.wrapping_add(k))
                .and_then(|mesh| fit(&mesh, case.dimension, modes))
                .ok()
        })
        .collect();
    let with_errors: Vec<&FitReport> = fits
        .iter()
        .flatten()
        .filter(|r| r.scale_mm_error.is_some())
        .collect();
    let triples = |pick: &dyn Fn(&FitReport) -> (f64, Option<f64>), truth: f64| {
        with_errors
            .iter()
            .filter_map(|r| {
                let (value, error) = pick(r);
                error.map(|e| (value, e, truth))
            })
            .collect::<Vec<_>>()
    };
    let mut biases: Vec<f64> = with_errors
        .iter()
        .filter_map(|r| r.alpha_star_bias)
        .collect();
    biases.sort_by(f64::total_cmp);
    Ok(MeshCalibration {
        median_alpha_bias: biases.get(biases.len() / 2).copied().unwrap_or(f64::NAN),
        case: *case,
        draws,
        without_errors: draws - with_errors.len(),
        alpha_without_error: with_errors
            .iter()
            .filter(|r| r.alpha_star_error.is_none())
            .count(),
        scale: coverage(&triples(
            &|r| (r.scale_mm, r.scale_mm_error),
            truth.scale_mm,
        )),
        // The interval stated for the surface's α*: the fit's, less the bias its scatter adds.
        alpha_star: coverage(&triples(
            &|r| {
                (
                    r.alpha_star - r.alpha_star_bias.unwrap_or(0.0),
                    r.alpha_star_error,
                )
            },
            truth.alpha_star,
        )),
    })
}
