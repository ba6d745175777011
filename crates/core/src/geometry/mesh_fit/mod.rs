//! A body fitted to a triangle mesh: the radius about the volume centroid (the model measures r
//! from the centre of mass; uniform density assumed) least-squares fitted by real spherical
//! harmonics (3D), or an extruded cylinder's cross-section fitted by a Fourier series (2D), with
//! the fit's residuals, the l = 1 part left (how far the centroid is from the centre the fit
//! sees), the scale ⟨r⟩ in mm, and every way a mesh can fail to be such a body named.
//!
//! Written here rather than with a mesh-processing crate because what is needed is specific and
//! small: the checks are solid angles about the centroid (a closed surface seen from a point
//! inside covers 4π exactly once iff every ray from it meets the surface once, so the sum and
//! the sign of each triangle's solid angle tell open, inside-out and not-star-shaped apart in
//! one streaming pass with no edge map), and the fit needs only a sum per direction cell. So a
//! mesh of any size costs a few passes over its file and memory for 18,432 cells.
//!
//! 3D: pass 1 sums signed tetrahedra (volume, centroid, the orientation) and the area-weighted
//! normal tensor (whose eigenvectors hold an extrusion's axis); pass 2 gives each triangle's
//! solid angle Ω about the centroid, summed into equal-area cells (96 bands in cos θ × 192 in
//! φ), each cell keeping the exact surface point seen nearest its centre (large facets are cut
//! into pieces for this, so a long side is sampled along its length); the fit solves the normal
//! equations of those points, weighted by their cells' solid angle, for every degree at once
//! (leading blocks of one Gram matrix);
//! pass 3 measures the fitted body against every triangle (rms, Ω-weighted) and every vertex
//! (max). 2D: the mesh is sliced at mid-length across its axis; the slice's oriented segments
//! give the section's area centroid and r(θ) at 4,096 angles, fitted by a discrete Fourier
//! series (exact least squares on equally spaced angles).

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use serde::Serialize;

use super::facets::{MAX_PRINTED_CORNERS, PrintedSection, SectionHull, section_hull};
use super::mesh_read::{MeshError, MeshFormat, MeshSource};
use super::{Body, DiskMode, MAX_SPHERE_L, ShapeFile, SphereCoeff};

mod errors;
mod section;
mod sphere;

pub use errors::{ALPHA_DRAWS, BLOCK_EDGES, MAX_ALPHA_BIAS, MIN_BLOCKS_PER_COEFFICIENT};

pub use sphere::real_harmonics;

/// How a mesh is read into a body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// 2 (an extruded cylinder's cross-section) or 3; `None`: 2 when the mesh is an extrusion
    /// (every face a side parallel to one axis or a cap across it), else 3.
    pub dim: Option<u32>,
    /// The highest degree L (3D, 2..=12) or mode M (2D, 2..=64); `None`: [`AUTO_RULE`].
    pub modes: Option<u32>,
    /// 2D: the cylinder's axis, θ running counter-clockwise seen from its + end (so −axis
    /// gives the mirror image); `None`: found from the mesh, its largest component positive.
    pub axis: Option<DVec3>,
    /// Millimetres per mesh unit (1: STL, OBJ and PLY from CAD and printers are in mm).
    pub mm_per_unit: f64,
    /// 2D: treat the section's flat facets as an export's tessellation of a round body (a
    /// turned or cast part), and keep no [`super::facets::PrintedSection`] in the shape file
    /// (the body then rolls on its smooth fit, not on the print's outline). 3D: compute no
    /// `solid_hull` and give no facet warning.
    pub ignore_facets: bool,
    /// Compute the errors of ⟨r⟩ and α* ([`BLOCK_EDGES`], [`ALPHA_DRAWS`]); `false` leaves them
    /// `None`. The α* bootstrap is [`ALPHA_DRAWS`] α* searches, most of a fit's time at high
    /// degrees: a caller that reads only the fit itself (a coat's refit, a sweep of test
    /// meshes) skips it.
    pub errors: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            dim: None,
            modes: None,
            axis: None,
            mm_per_unit: 1.0,
            ignore_facets: false,
            errors: true,
        }
    }
}

/// The rule by which the degree is chosen when none is given.
pub const AUTO_RULE: &str = "the smallest degree whose rms residual is within 10 % of the best \
                             fit's (degree 8 in 3D, mode 24 in 2D) or under 5e-5 of ⟨r⟩";
/// Residuals under this fraction of ⟨r⟩ are below any printer's or scanner's resolution (half a
/// micrometre on a 10 mm body): no reason to go to a higher degree.
pub const AUTO_FLOOR: f64 = 5e-5;
/// Highest degree tried by the 3D rule.
pub const AUTO_MAX_3D: u32 = 8;
/// Highest mode tried by the 2D rule.
pub const AUTO_MAX_2D: u32 = 24;
/// Largest 2D mode accepted by `--modes`.
pub const MAX_FIT_DISK_L: u32 = 64;
pub use super::facets::FACET_TOLERANCE;
/// Angles r(θ) is sampled at in 2D.
const SECTION_SAMPLES: usize = 4096;
/// Cells in cos θ and in φ of the 3D fit.
const BANDS: usize = 96;
const SECTORS: usize = 192;
/// A surface's solid angles about the centroid must add to 4π within this fraction.
const COVERAGE_TOL: f64 = 1e-6;
/// Triangles facing the centroid (a fold) are an error above this fraction of the sphere, and
/// slivers to be warned of below it.
const FOLD_TOL: f64 = 1e-5;
/// A face counts as a side (cap) of an extrusion when |n · axis| is below this (above 1 − this).
const EXTRUSION_TOL: f64 = 0.02;

/// The rms residual of one degree's fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DegreeResidual {
    /// The degree L (3D) or highest mode M (2D).
    pub modes: u32,
    /// The rms residual relative to ⟨r⟩ (on the direction cells in 3D, on the samples in 2D).
    pub rms: f64,
}

/// What the fit found, for people (`shape --from-mesh` prints it) and scripts (JSON).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitReport {
    /// The mesh file.
    pub file: String,
    /// STL, OBJ or PLY.
    pub format: String,
    /// Triangles read.
    pub triangles: usize,
    /// 2 or 3.
    pub dimension: u32,
    /// The degree L (3D) or highest mode M (2D) of the body written.
    pub modes: u32,
    /// Why that degree: "given" or the rule.
    pub modes_rule: String,
    /// ⟨r⟩ in mm: the mean radius about the centroid over directions.
    pub scale_mm: f64,
    /// The standard error of `scale_mm` (mm) from the mesh's scatter about the fit (a scan's
    /// noise, a print's roughness), its correlation between neighbouring triangles included
    /// (`errors`: blocks [`BLOCK_EDGES`] edges a side); `None` where the mesh makes fewer than
    /// [`MIN_BLOCKS_PER_COEFFICIENT`] blocks a coefficient fitted (a coarse mesh's large
    /// triangles are facets, not noise). It leaves out the facets (see the hulls) and any error
    /// in millimetres per mesh unit.
    pub scale_mm_error: Option<f64>,
    /// The volume (3D, mm³) or the section's area (2D, mm²).
    pub size_mm: f64,
    /// The centroid in the mesh's coordinates (mesh units).
    pub centroid: [f64; 3],
    /// 2D: the cylinder's axis (unit, in the mesh's coordinates); θ runs from the first
    /// in-plane axis towards the second, seen from the axis's + end.
    pub axis: Option<[f64; 3]>,
    /// 2D: the section's two in-plane axes (θ = 0 and θ = π/2).
    pub section_axes: Option<[[f64; 3]; 2]>,
    /// rms of (mesh − body) radius over the surface, relative to ⟨r⟩.
    pub rms_residual: f64,
    /// The same in mm.
    pub rms_residual_mm: f64,
    /// Largest |mesh − body| radius at a vertex (3D) or sample (2D), relative to ⟨r⟩.
    pub max_residual: f64,
    /// The same in mm.
    pub max_residual_mm: f64,
    /// Where the largest residual is (θ, φ about the centroid, or θ in the section).
    pub max_residual_at: String,
    /// Amplitude of the l = 1 part of the fit, relative to ⟨r⟩ (left out of the body: the model
    /// measures r from the centre of mass).
    pub l1_part: f64,
    /// The same in mm: about how far the fit's centre is from the centroid.
    pub l1_offset_mm: f64,
    /// The rms residual of every degree tried.
    pub degree_residuals: Vec<DegreeResidual>,
    /// Whether the fitted body is strictly convex.
    pub convex: bool,
    /// α* of the fitted body (rad), atan max |∇ ln r|.
    pub alpha_star: f64,
    /// Its standard error (rad), from the same scatter: the spread of α* over coefficient
    /// vectors drawn with the fit's covariance; `None` with `scale_mm_error`, where the bias
    /// below is over [`MAX_ALPHA_BIAS`] errors (the maximum is not resolved by the scatter), and
    /// for a coated body.
    pub alpha_star_error: Option<f64>,
    /// How far the scatter raises the fit's α* on average (rad; the maximum of a noisy slope is
    /// biased up): the surface the mesh scatters about has α* ≈ `alpha_star` − this, within
    /// `alpha_star_error`. The body written is the fit's, with `alpha_star`.
    pub alpha_star_bias: Option<f64>,
    /// The blocks of nearby samples the errors were estimated from (`None`: too few).
    pub error_blocks: Option<usize>,
    /// 2D: the section's own convex hull, its flat sides and the α* they give (what the
    /// printed prism rests up to, π/N for a regular N-gon), beside the smooth fit's
    /// `alpha_star` (its longest side in the mesh's units); a warning says when the two differ
    /// by more than [`FACET_TOLERANCE`].
    /// `None` in 3D (see `solid_hull`).
    pub mesh_hull: Option<SectionHull>,
    /// 3D: the mesh's own convex hull and the α* its facets give (what the printed polyhedron
    /// rests up to), beside the smooth fit's `alpha_star`; a warning says when the two differ by
    /// more than [`FACET_TOLERANCE`]. For a coated body, its flat faces moved out by the coat.
    /// `None` in 2D, with `ignore_facets`, or over [`MAX_HULL_VERTICES`] distinct vertices (a
    /// warning says so).
    pub solid_hull: Option<crate::geometry::solid_hull::SolidHull>,
    /// Warnings: the fit is usable, but read this.
    pub warnings: Vec<String>,
    /// The coat this body was given after the fit ([`coat`]), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coat: Option<CoatReport>,
}

/// A body fitted to a mesh: its shape file (with `scale_mm`) and the report.
#[derive(Debug, Clone)]
pub struct MeshFit {
    /// The body.
    pub body: Body,
    /// Its shape file, `scale_mm` set.
    pub shape: ShapeFile,
    /// How good the fit is, and where it is not.
    pub report: FitReport,
}

/// What a coat of uniform thickness did to a fitted body (`shape --from-mesh --coat-mm`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoatReport {
    /// The coat's thickness (mm).
    pub coat_mm: f64,
    /// ⟨r⟩ of the body before and after (mm).
    pub scale_mm_before: f64,
    /// ⟨r⟩ after the coat (mm).
    pub scale_mm_after: f64,
    /// α* before the coat (rad).
    pub alpha_star_before: f64,
    /// α* after the coat (rad): a coat rounds the body, so α* falls.
    pub alpha_star_after: f64,
}

/// Most distinct vertices a 3D mesh's hull is computed from: `bench mesh` measured a fit of
/// 163,842 vertices at 1.7 s and 213 MB with it, where a finer mesh is streamed in about 22 MB
/// (2026-11-28). Facets of a mesh that fine tip a ball by about half a degree or less (a UV
/// sphere of 200,000 vertices: 0.43°).
pub const MAX_HULL_VERTICES: usize = 200_000;

/// Thickest coat accepted, as a fraction of ⟨r⟩.
pub const MAX_COAT: f64 = 0.5;

/// The fitted body coated with `coat_mm` of uniform thickness: its own surface (a level-6
/// icosphere of 81,920 triangles in 3D, a 4096-gon extrusion in 2D, at its scale in mm) moved
/// out by `coat_mm` along the surface normals, and fitted again to the same degree about its
/// own centroid. The viscous experiments coat the printed sphere with rubber; the coated body is
/// the one that rolls.
///
/// # Example
/// ```
/// use rollphase_core::geometry::mesh::sphere_mesh;
/// use rollphase_core::geometry::mesh_fit::{FitOptions, coat, fit_mesh};
/// use rollphase_core::geometry::mesh_read::MeshSource;
/// use rollphase_core::geometry::sphere::Sphere;
/// // A round ball of 10 mm coated with 0.5 mm: a round ball of 10.5 mm.
/// let mesh = sphere_mesh(&Sphere::perfect(), 4);
/// let triangles = mesh.indices.iter().map(|t| t.map(|i| {
///     let p = mesh.positions[i as usize];
///     rollphase_core::glam::DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64) * 10.0
/// })).collect();
/// let fit = fit_mesh(&MeshSource::made("ball", triangles)?, &FitOptions::default(), &|_, _, _| {})?;
/// let (coated, report) = coat(&fit, 0.5, &|_, _, _| {})?;
/// assert!((report.scale_mm_after - report.scale_mm_before - 0.5).abs() < 1e-3);
/// assert!((coated.report.scale_mm - report.scale_mm_after).abs() < 1e-12);
/// # Ok::<(), rollphase_core::geometry::mesh_read::MeshError>(())
/// ```
pub fn coat(
    fit: &MeshFit,
    coat_mm: f64,
    progress: Progress,
) -> Result<(MeshFit, CoatReport), MeshError> {
    let scale = fit.report.scale_mm;
    if !(coat_mm.is_finite() && coat_mm > 0.0 && coat_mm <= MAX_COAT * scale) {
        return Err(MeshError::Options(format!(
            "a coat of {coat_mm} mm is not allowed (needs 0 < coat ≤ {:.3} mm, half the body's \
             mean radius {scale:.3} mm)",
            MAX_COAT * scale
        )));
    }
    let as_d = |p: [f32; 3]| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
    let (mesh, options) = match &fit.body {
        Body::Sphere(s) => (
            crate::geometry::mesh::sphere_mesh(s, 6),
            FitOptions {
                dim: Some(3),
                modes: Some(fit.report.modes),
                // Its icosphere is the sampling, not facets of the print.
                ignore_facets: true,
                // The coat's errors are the fitted mesh's (below).
                errors: false,
                ..FitOptions::default()
            },
        ),
        Body::Disk(d) => (
            // Exported along y with θ from x towards z: seen from −y, θ runs as the fit's.
            crate::geometry::mesh::disk_mesh(d, 4096, 2.0),
            FitOptions {
                dim: Some(2),
                modes: Some(fit.report.modes),
                axis: Some(-DVec3::Y),
                // Its 4,096-gon is the export's sampling, not facets of the print.
                ignore_facets: true,
                errors: false,
                ..FitOptions::default()
            },
        ),
    };
    let triangles: Vec<[DVec3; 3]> = mesh
        .indices
        .iter()
        .map(|t| {
            t.map(|i| {
                let i = i as usize;
                as_d(mesh.positions[i]) * scale + as_d(mesh.normals[i]).normalize() * coat_mm
            })
        })
        .collect();
    let source = MeshSource::made(
        &format!("{} coated with {coat_mm} mm", fit.report.file),
        triangles,
    )?;
    let mut coated = fit_mesh(&source, &options, progress)?;
    let report = CoatReport {
        coat_mm,
        scale_mm_before: scale,
        scale_mm_after: coated.report.scale_mm,
        alpha_star_before: fit.report.alpha_star,
        alpha_star_after: coated.report.alpha_star,
    };
    // The coated body is reported as the original mesh's, with the coat beside it.
    coated.report.file.clone_from(&fit.report.file);
    coated.report.format.clone_from(&fit.report.format);
    coated.report.triangles = fit.report.triangles;
    coated.report.modes_rule.clone_from(&fit.report.modes_rule);
    // The coated surface is the fitted body's, in the body's frame: the mesh's axis and
    // centroid are the original's; its 4,096-gon is the sampling's, so the hull reported is the
    // print's section offset by the coat (below), if the print has one.
    // A printed ball's facets stay flat under a coat, moved out by it: its own hull's α* is
    // read again for the coated print, and the mesh's other warnings are the original's.
    let facets = "the mesh's hull has";
    let mut warnings: Vec<String> = fit
        .report
        .warnings
        .iter()
        .filter(|w| !w.starts_with(facets))
        .cloned()
        .collect();
    warnings.append(&mut coated.report.warnings);
    if let Some(hull) = &fit.report.solid_hull {
        let printed = hull.coated(coat_mm / hull.mm_per_unit);
        warnings.extend(sphere::facet_warning(
            hull,
            printed,
            coated.report.alpha_star,
            hull.mm_per_unit,
        ));
        coated.report.solid_hull = Some(crate::geometry::solid_hull::SolidHull {
            alpha_star: printed,
            ..hull.clone()
        });
    }
    coated.report.warnings = warnings;
    // The coat is taken as exact, so ⟨r⟩'s error is the fitted mesh's, carried over (the refit
    // of the coated smooth surface has no scatter of its own to measure). α*'s is not: the coat
    // changes α* and how it moves with the coefficients (a helper found the coated α* spread
    // 5.2e-4 where the uncoated error was 7.0e-4).
    coated.report.scale_mm_error = fit.report.scale_mm_error;
    coated.report.alpha_star_error = None;
    coated.report.alpha_star_bias = None;
    coated.report.error_blocks = fit.report.error_blocks;
    coated.report.axis = fit.report.axis;
    coated.report.section_axes = fit.report.section_axes;
    coated.report.centroid = fit.report.centroid;
    coated.report.mesh_hull = None;
    // The print's flats stay flats under a coat: its section, offset by the coat, in the
    // coated body's units.
    if let (Body::Disk(d), ShapeFile::Disk { modes, .. }) = (&fit.body, &coated.shape)
        && let Some(section) = d.printed_section()
    {
        let offset = section.coated(coat_mm / scale, coated.report.scale_mm / scale);
        coated.shape = ShapeFile::Disk {
            modes: modes.clone(),
            scale_mm: coated.shape.scale_mm(),
            printed_section: offset.clone(),
        };
        // The report names the coated print's flats as a fit's report names the mesh's.
        // (Its sides keep the original's lengths, in the mesh's units.)
        coated.report.mesh_hull = offset.as_ref().and_then(|s| s.hull().ok()).map(|h| {
            crate::geometry::facets::SectionHull {
                longest_side: fit.report.mesh_hull.map_or(f64::NAN, |m| m.longest_side),
                ..h
            }
        });
        if let Body::Disk(c) = &coated.body {
            coated.body = Body::Disk(c.clone().with_printed_section(offset));
        }
    }
    coated
        .report
        .warnings
        .retain(|w| !w.starts_with("the section's hull has"));
    coated.report.coat = Some(report.clone());
    Ok((coated, report))
}

/// Progress of a fit: (what, done, total) every 65,536 triangles and at each pass's end.
pub type Progress<'a> = &'a (dyn Fn(&str, usize, usize) + Sync);

/// Fits a body to the mesh in `source`.
///
/// # Example
/// ```
/// use rollphase_core::geometry::mesh::sphere_mesh;
/// use rollphase_core::geometry::mesh_fit::{FitOptions, fit_mesh};
/// use rollphase_core::geometry::mesh_read::MeshSource;
/// use rollphase_core::geometry::Body;
/// // A body written as STL at 10 mm per ⟨r⟩ and read back: the same body, to the facets' size.
/// let Body::Sphere(s) = Body::paper_sphere(6, 0.25, 4)? else { unreachable!() };
/// let dir = std::env::temp_dir().join(format!("rp-doc-fit-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("body.stl");
/// let mut stl = Vec::new();
/// sphere_mesh(&s, 5).write_stl(&mut stl, 10.0, "body")?;
/// std::fs::write(&path, stl)?;
/// let fit = fit_mesh(&MeshSource::open(&path)?, &FitOptions::default(), &|_, _, _| {})?;
/// assert_eq!((fit.report.dimension, fit.report.modes), (3, 4));
/// assert!(fit.report.rms_residual < 1e-3 && (fit.report.scale_mm - 10.0).abs() < 0.01);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fit_mesh(
    source: &MeshSource,
    options: &FitOptions,
    progress: Progress,
) -> Result<MeshFit, MeshError> {
    if !(options.mm_per_unit.is_finite() && options.mm_per_unit > 0.0) {
        return Err(MeshError::Options(format!(
            "millimetres per mesh unit = {} is not allowed (needs a finite number > 0)",
            options.mm_per_unit
        )));
    }
    if let Some(d) = options.dim
        && !(2..=3).contains(&d)
    {
        return Err(MeshError::Options(format!(
            "dimension {d} is not allowed (2 for a cylinder, 3 for a sphere)"
        )));
    }
    if let (Some(m), dim) = (options.modes, options.dim) {
        let max = if dim == Some(2) {
            MAX_FIT_DISK_L
        } else {
            MAX_SPHERE_L
        };
        if !(2..=max).contains(&m) {
            return Err(MeshError::Options(format!(
                "modes = {m} is not allowed (needs 2 ≤ modes ≤ {max}{})",
                if dim.is_none() {
                    "; 2D fits allow up to 64 with --dim 2"
                } else {
                    ""
                }
            )));
        }
    }
    // Any finite non-zero vector is a direction, however long or short: it is scaled by its
    // largest component before it is normalised, where its length would over- or underflow.
    if let Some(a) = options.axis
        && !(a.is_finite() && a.abs().max_element() > 0.0)
    {
        return Err(MeshError::Options(format!(
            "axis {:?} is not a direction (needs a finite, non-zero vector)",
            a.to_array()
        )));
    }
    let totals = first_pass(source, progress)?;
    let scale_check = totals.bbox_max - totals.bbox_min;
    let extent = scale_check.max_element();
    if totals.volume.is_nan() || totals.volume.abs() <= 1e-9 * extent.powi(3) {
        let why = Topology::of(source)?.trouble().unwrap_or_else(|| {
            "the mesh is open, flat, or its triangles are wound inconsistently".to_string()
        });
        return Err(shape_error(
            source,
            format!(
                "the triangles enclose no volume ({:.3e} cubic units in a box {:.4} units \
                 across): {why}",
                totals.volume, extent
            ),
        ));
    }
    let mut warnings = Vec::new();
    let orientation = totals.volume.signum();
    if orientation < 0.0 {
        warnings.push(
            "the triangles are wound inside-out (their normals point into the body); read as \
             the reverse"
                .to_string(),
        );
    }
    let extrusion = match options.axis {
        Some(a) => Some((a / a.abs().max_element()).normalize()),
        None if options.dim == Some(3) => None,
        None => match find_extrusion_axis(source, &totals, progress)? {
            // rollphase's own export names its axis, whose sign the mesh cannot tell.
            Some((axis, warning)) => match source
                .stl_header()
                .as_deref()
                .and_then(crate::geometry::mesh::stl_header_axis)
                .map(|a| DVec3::from_array(a).normalize())
            {
                Some(named) if named.dot(axis).abs() > 1.0 - 1e-9 => Some(named),
                _ => {
                    warnings.extend(warning);
                    Some(axis)
                }
            },
            None => None,
        },
    };
    let dim = options
        .dim
        .unwrap_or(if extrusion.is_some() { 2 } else { 3 });
    let (body, shape, mut report) = if dim == 2 {
        let Some(axis) = extrusion else {
            return Err(shape_error(
                source,
                "is not an extruded cylinder: no axis has every face either a side along it or \
                 a cap at one of its two ends (a cap between them is a step or a notch, where \
                 the section changes); give the axis (--axis X,Y,Z) if it is a cylinder with rough \
                 ends, or fit it in 3D (--dim 3)"
                    .to_string(),
            ));
        };
        if options.axis.is_some() {
            check_given_axis(source, &totals, axis, progress)?;
        }
        section::fit_section(source, &totals, axis, orientation, options, progress)?
    } else {
        sphere::fit_sphere(source, &totals, orientation, options, progress)?
    };
    report.warnings.splice(0..0, warnings);
    Ok(MeshFit {
        body,
        shape,
        report,
    })
}

/// Sums of the first pass.
#[derive(Debug, Clone, Copy)]
struct Totals {
    /// Signed volume (mesh units³).
    volume: f64,
    centroid: DVec3,
    bbox_min: DVec3,
    bbox_max: DVec3,
    /// Σ area · n nᵀ over faces (the normal tensor), rows.
    normal_tensor: [[f64; 3]; 3],
    area: f64,
}

fn shape_error(source: &MeshSource, reason: String) -> MeshError {
    MeshError::Shape {
        path: source.path().to_path_buf(),
        reason,
    }
}

fn tick(progress: Progress, what: &str, i: usize, total: usize) {
    if i.is_multiple_of(65_536) {
        progress(what, i, total);
    }
}

fn first_pass(source: &MeshSource, progress: Progress) -> Result<Totals, MeshError> {
    let total = source.triangles();
    let mut origin = None;
    let (mut six_volume, mut weighted) = (0.0, DVec3::ZERO);
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let mut tensor = [[0.0; 3]; 3];
    let mut area = 0.0;
    source.for_each(|i, [a, b, c]| {
        tick(progress, "reading", i, total);
        // Tetrahedra from the first vertex rather than the origin: far fewer digits cancel.
        let o = *origin.get_or_insert(a);
        let (a0, b0, c0) = (a - o, b - o, c - o);
        let v6 = a0.dot(b0.cross(c0));
        six_volume += v6;
        weighted += v6 * (a0 + b0 + c0);
        for p in [a, b, c] {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let n = (b - a).cross(c - a);
        let len = n.length();
        if len > 0.0 {
            let n1 = n / len;
            for (r, row) in tensor.iter_mut().enumerate() {
                for (k, cell) in row.iter_mut().enumerate() {
                    *cell += 0.5 * len * n1[r] * n1[k];
                }
            }
            area += 0.5 * len;
        }
        Ok(())
    })?;
    progress("reading", total, total);
    let o = origin.unwrap_or(DVec3::ZERO);
    Ok(Totals {
        volume: six_volume / 6.0,
        centroid: o + weighted / (4.0 * six_volume),
        bbox_min: lo,
        bbox_max: hi,
        normal_tensor: tensor,
        area,
    })
}

/// The axis of an extrusion: the eigenvector of the normal tensor along which every face is a
/// side (normal across it) or a cap (normal along it) at one of the two ends, up to 0.1 % of
/// the area; `None` if no eigenvector is. A box-like mesh (a square rod, a tile) is an extrusion along two or three
/// axes: the one whose section is the roundest (the smallest ratio of its extents, so the
/// most rollable; then the longest) is taken, with a warning naming the others.
fn find_extrusion_axis(
    source: &MeshSource,
    totals: &Totals,
    progress: Progress,
) -> Result<Option<(DVec3, Option<String>)>, MeshError> {
    let t = totals.normal_tensor;
    let m = nalgebra::Matrix3::from_fn(|r, c| t[r][c]);
    let eigen = m.symmetric_eigen();
    let candidates: Vec<DVec3> = (0..3)
        .map(|k| {
            let v = eigen.eigenvectors.column(k);
            DVec3::new(v[0], v[1], v[2]).normalize()
        })
        .collect();
    let mut oblique = [0.0f64; 3];
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let total = source.triangles();
    source.for_each(|i, [a, b, c]| {
        tick(progress, "finding the axis", i, total);
        let n = (b - a).cross(c - a);
        let len = n.length();
        for (k, e) in candidates.iter().enumerate() {
            for p in [a, b, c] {
                lo[k] = lo[k].min(p.dot(*e));
                hi[k] = hi[k].max(p.dot(*e));
            }
            if len > 0.0 {
                let along = (n.dot(*e) / len).abs();
                if along > EXTRUSION_TOL && along < 1.0 - EXTRUSION_TOL {
                    oblique[k] += 0.5 * len;
                }
            }
        }
        Ok(())
    })?;
    let extent = |k: usize| hi[k] - lo[k];
    let mut extruded: Vec<usize> = (0..3)
        .filter(|&k| oblique[k] <= 1e-3 * totals.area)
        .collect();
    if !extruded.is_empty() {
        // A cap between the ends is a step or a notch: the section changes along that axis,
        // which the normals alone cannot see (a notched cube's faces all face along x, y or z).
        let mut inside = [0.0f64; 3];
        source.for_each(|i, [a, b, c]| {
            tick(progress, "checking the ends", i, total);
            let n = (b - a).cross(c - a);
            let len = n.length();
            for &k in &extruded {
                let e = candidates[k];
                if len > 0.0 && (n.dot(e) / len).abs() >= 1.0 - EXTRUSION_TOL {
                    let at = (a + b + c).dot(e) / 3.0;
                    if (at - lo[k]).min(hi[k] - at) > 1e-4 * extent(k) {
                        inside[k] += 0.5 * len;
                    }
                }
            }
            Ok(())
        })?;
        extruded.retain(|&k| inside[k] <= 1e-3 * totals.area);
    }
    // The section across axis k: its longer extent over its shorter.
    let aspect = |k: usize| {
        let (a, b) = (extent((k + 1) % 3), extent((k + 2) % 3));
        a.max(b) / a.min(b)
    };
    let roundest = |&i: &usize, &j: &usize| {
        let (ai, aj) = (aspect(i), aspect(j));
        if (ai - aj).abs() <= 1e-6 * ai.max(aj) {
            extent(j).total_cmp(&extent(i))
        } else {
            ai.total_cmp(&aj)
        }
    };
    let Some(best) = extruded.iter().copied().min_by(roundest) else {
        return Ok(None);
    };
    let axis = canonical_axis(candidates[best]);
    let warning = (extruded.len() > 1).then(|| {
        let others: Vec<String> = extruded
            .iter()
            .filter(|&&k| k != best)
            .map(|&k| format!("{:?}", canonical_axis(candidates[k]).to_array()))
            .collect();
        format!(
            "the mesh is an extrusion along {} axes (a box-like body): read along {:?}, whose \
             section ({:.4} × {:.4}) is the roundest, not along {}; give --axis X,Y,Z to roll \
             it about another",
            extruded.len(),
            axis.to_array(),
            extent((best + 1) % 3).max(extent((best + 2) % 3)),
            extent((best + 1) % 3).min(extent((best + 2) % 3)),
            others.join(" or ")
        )
    });
    Ok(Some((axis, warning)))
}

/// A given axis checked against the mesh: more of the surface must run along it (a side) than
/// be tilted to it (neither a side nor a cap), so that a cylinder with rough ends passes and a
/// sphere (whose equator alone is along any axis) or a cylinder given an axis 11° off its own
/// (whose oblique section is an ellipse) is refused, naming how much of the surface misfits
/// and the axis the mesh has, if any.
fn check_given_axis(
    source: &MeshSource,
    totals: &Totals,
    axis: DVec3,
    progress: Progress,
) -> Result<(), MeshError> {
    let (mut side, mut tilted) = (0.0, 0.0);
    let total = source.triangles();
    source.for_each(|i, [a, b, c]| {
        tick(progress, "checking the axis", i, total);
        let n = (b - a).cross(c - a);
        let len = n.length();
        if len > 0.0 {
            let along = (n.dot(axis) / len).abs();
            if along <= EXTRUSION_TOL {
                side += 0.5 * len;
            } else if along < 1.0 - EXTRUSION_TOL {
                tilted += 0.5 * len;
            }
        }
        Ok(())
    })?;
    if tilted <= side {
        return Ok(());
    }
    let own = find_extrusion_axis(source, totals, progress)?;
    Err(shape_error(
        source,
        format!(
            "is not a cylinder along the given axis {:?}: {:.1} % of its surface is tilted to it \
             (neither a side along it nor an end across it) against {:.1} % along it; {}",
            axis.to_array(),
            100.0 * tilted / totals.area,
            100.0 * side / totals.area,
            match own {
                Some((a, _)) => format!(
                    "the mesh is an extrusion along {:?} (give that axis, or leave --axis out)",
                    a.to_array()
                ),
                None => "it is no extrusion along any axis: fit it in 3D (--dim 3)".to_string(),
            }
        ),
    ))
}

/// How a mesh's triangles join, for saying why a surface does not cover the sphere once: its
/// vertices welded where their coordinates are equal (as a mesh's own vertices are in STL),
/// each edge's uses counted with their direction, the triangles joined into shells across the
/// edges they share. Built only on that error path: it holds the whole mesh.
struct Topology {
    /// Edges used by one triangle only: the rims of holes.
    boundary: usize,
    /// Edges two triangles use in the same direction: one of them is flipped.
    flipped: usize,
    /// Edges used by more than two triangles.
    nonmanifold: usize,
    /// Separate pieces of surface.
    shells: usize,
    /// Holes through a closed, consistently wound single shell (2 − χ)/2: a torus has one.
    genus: i64,
}

impl Topology {
    fn of(source: &MeshSource) -> Result<Topology, MeshError> {
        use std::collections::HashMap;
        let mut vertices: HashMap<[u64; 3], u32> = HashMap::new();
        let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(source.triangles());
        source.for_each(|_, t| {
            let ids = t.map(|p| {
                let next = vertices.len() as u32;
                *vertices
                    .entry(p.to_array().map(|c| (c + 0.0).to_bits()))
                    .or_insert(next)
            });
            if ids[0] != ids[1] && ids[1] != ids[2] && ids[2] != ids[0] {
                triangles.push(ids);
            }
            Ok(())
        })?;
        // Each undirected edge: (uses a → b, uses b → a, the first triangle using it).
        let mut edges: HashMap<(u32, u32), (u32, u32, usize)> = HashMap::new();
        let mut parent: Vec<usize> = (0..triangles.len()).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for (k, t) in triangles.iter().enumerate() {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let key = (a.min(b), a.max(b));
                let e = edges.entry(key).or_insert((0, 0, k));
                if a < b {
                    e.0 += 1;
                } else {
                    e.1 += 1;
                }
                let (x, y) = (root(&mut parent, k), root(&mut parent, e.2));
                parent[x] = y;
            }
        }
        let (mut boundary, mut flipped, mut nonmanifold) = (0, 0, 0);
        for &(forward, backward, _) in edges.values() {
            match forward + backward {
                1 => boundary += 1,
                2 if forward != 1 => flipped += 1,
                2 => {}
                _ => nonmanifold += 1,
            }
        }
        let shells = (0..triangles.len())
            .filter(|&i| root(&mut parent, i) == i)
            .count();
        let euler = vertices.len() as i64 - edges.len() as i64 + triangles.len() as i64;
        Ok(Topology {
            boundary,
            flipped,
            nonmanifold,
            shells,
            genus: (2 - euler) / 2,
        })
    }

    /// What is wrong, in a mesh user's words, if the topology shows it.
    fn trouble(&self) -> Option<String> {
        if self.boundary > 0 {
            return Some(format!(
                "the mesh is open: {} edge(s) belong to one triangle only, the rim of a hole \
                 (close it in the modelling program, or export the solid as one closed body)",
                self.boundary
            ));
        }
        if self.flipped > 0 {
            return Some(format!(
                "part of the mesh is flipped: {} edge(s) are used twice in the same direction \
                 (recompute or unify the normals in the modelling program)",
                self.flipped
            ));
        }
        if self.shells > 1 {
            return Some(format!(
                "the mesh has {} separate shells: two bodies, or a hollow one (an inner \
                 surface); a rolling body is one closed surface",
                self.shells
            ));
        }
        if self.nonmanifold > 0 {
            return Some(format!(
                "triangles overlap: {} edge(s) are shared by more than two triangles \
                 (duplicated faces, or bodies touching along an edge)",
                self.nonmanifold
            ));
        }
        if self.genus > 0 {
            return Some(format!(
                "the body has a hole through it ({} handle(s), like a ring or a torus): a ray \
                 from its centre cannot meet its surface once in every direction",
                self.genus
            ));
        }
        None
    }
}

/// The sign convention of an axis: its largest component positive, so the same mesh always gives
/// the same section (not its mirror image).
fn canonical_axis(axis: DVec3) -> DVec3 {
    // Round-off of the eigenvector (1e-15) snapped away: an axis-aligned cylinder reports its
    // axis as (0, 0, 1), not (2e-17, 1e-15, 1).
    let a = DVec3::from_array(
        axis.normalize()
            .to_array()
            .map(|c| if c.abs() < 1e-9 { 0.0 } else { c }),
    )
    .normalize();
    let k = (0..3)
        .max_by(|&i, &j| a[i].abs().total_cmp(&a[j].abs()))
        .unwrap_or(2);
    // + 0.0 turns the −0.0 that negating a snapped zero gives into 0.0 (printed "-0.0" else).
    let a = if a[k] < 0.0 { -a } else { a };
    DVec3::from_array(a.to_array().map(|c| c + 0.0))
}

/// In-plane axes (e1, e2) with e1 × e2 = axis: e1 the world axis most across `axis`, made
/// perpendicular.
fn format_name(format: MeshFormat) -> String {
    format.to_string()
}

/// The degree the rule picks: the smallest whose residual is within 10 % of the residual at
/// `best`, or under [`AUTO_FLOOR`].
fn choose(residuals: &[DegreeResidual], best: u32) -> u32 {
    let floor = residuals
        .iter()
        .find(|d| d.modes == best)
        .map_or(0.0, |d| d.rms);
    residuals
        .iter()
        .filter(|d| d.modes <= best)
        .find(|d| d.rms <= 1.1 * floor || d.rms < AUTO_FLOOR)
        .map_or(best, |d| d.modes)
}
