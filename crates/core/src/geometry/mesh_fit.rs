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

use super::facets::{SectionHull, section_hull};
use super::mesh_read::{MeshError, MeshFormat, MeshSource};
use super::{Body, DiskMode, MAX_SPHERE_L, ShapeFile, SphereCoeff};

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
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            dim: None,
            modes: None,
            axis: None,
            mm_per_unit: 1.0,
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
/// How far (rad) the mesh hull's α* and the fit's may differ before the fit warns: 0.1°, the
/// resolution of a digital inclinometer setting a ramp, so a smaller difference cannot be seen
/// in an experiment.
pub const FACET_TOLERANCE: f64 = 0.1 * PI / 180.0;
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
    /// 2D: the section's own convex hull, its flat sides and the α* they give (what the
    /// printed prism rests up to, π/N for a regular N-gon), beside the smooth fit's
    /// `alpha_star`; a warning says when the two differ by more than [`FACET_TOLERANCE`].
    /// `None` in 3D, where the mesh's hull is not computed yet.
    pub mesh_hull: Option<SectionHull>,
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
        None => find_extrusion_axis(source, &totals, progress)?,
    };
    let dim = options
        .dim
        .unwrap_or(if extrusion.is_some() { 2 } else { 3 });
    let (body, shape, mut report) = if dim == 2 {
        let Some(axis) = extrusion else {
            return Err(shape_error(
                source,
                "is not an extruded cylinder: no axis has every face either a side along it or \
                 a cap across it; give the axis (--axis X,Y,Z) if it is a cylinder with rough \
                 ends, or fit it in 3D (--dim 3)"
                    .to_string(),
            ));
        };
        if options.axis.is_some() {
            check_given_axis(source, &totals, axis, progress)?;
        }
        fit_section(source, &totals, axis, orientation, options, progress)?
    } else {
        fit_sphere(source, &totals, orientation, options, progress)?
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
/// side (normal across it) or a cap (normal along it), up to 0.1 % of the area; `None` if no
/// eigenvector is.
fn find_extrusion_axis(
    source: &MeshSource,
    totals: &Totals,
    progress: Progress,
) -> Result<Option<DVec3>, MeshError> {
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
    let total = source.triangles();
    source.for_each(|i, [a, b, c]| {
        tick(progress, "finding the axis", i, total);
        let n = (b - a).cross(c - a);
        let len = n.length();
        if len > 0.0 {
            for (k, e) in candidates.iter().enumerate() {
                let along = (n.dot(*e) / len).abs();
                if along > EXTRUSION_TOL && along < 1.0 - EXTRUSION_TOL {
                    oblique[k] += 0.5 * len;
                }
            }
        }
        Ok(())
    })?;
    let best = (0..3)
        .min_by(|&i, &j| oblique[i].total_cmp(&oblique[j]))
        .unwrap_or(0);
    if oblique[best] > 1e-3 * totals.area {
        return Ok(None);
    }
    Ok(Some(canonical_axis(candidates[best])))
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
                Some(a) => format!(
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
fn section_basis(axis: DVec3) -> (DVec3, DVec3) {
    let world = [DVec3::X, DVec3::Y, DVec3::Z];
    let w = world
        .into_iter()
        .min_by(|p, q| p.dot(axis).abs().total_cmp(&q.dot(axis).abs()))
        .unwrap_or(DVec3::X);
    let e1 = (w - w.dot(axis) * axis).normalize();
    (e1, axis.cross(e1))
}

fn cross2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[expect(
    clippy::too_many_lines,
    reason = "one pass that slices the mesh, then the section's checks, samples, Fourier fit, \
              degree rule and report, which share a dozen local quantities"
)]
fn fit_section(
    source: &MeshSource,
    totals: &Totals,
    axis: DVec3,
    orientation: f64,
    options: &FitOptions,
    progress: Progress,
) -> Result<(Body, ShapeFile, FitReport), MeshError> {
    let (e1, e2) = section_basis(axis);
    let c3 = totals.centroid;
    // The slice through the centroid: for a uniform extrusion its area centroid is the
    // centroid's projection, and it is as far from both caps as the mesh allows.
    let mut segments: Vec<([f64; 2], [f64; 2])> = Vec::new();
    let total = source.triangles();
    source.for_each(|i, t| {
        tick(progress, "slicing", i, total);
        let d = t.map(|p| (p - c3).dot(axis));
        let above = d.map(|h| h >= 0.0);
        if above.iter().all(|&x| x) || above.iter().all(|&x| !x) {
            return Ok(());
        }
        let mut points = Vec::with_capacity(2);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            if above[i] != above[j] {
                // From the edge's lexicographically smaller end, so that the two triangles
                // sharing the edge (which list it in opposite orders) get the same bits: a point
                // that differs in its last bit between its two segments can fall on either side
                // of a sample ray, counted twice or not at all.
                let (i, j) = if t[i].to_array() < t[j].to_array() {
                    (i, j)
                } else {
                    (j, i)
                };
                let p = t[i] + (t[j] - t[i]) * (d[i] / (d[i] - d[j]));
                let q = p - c3;
                points.push([q.dot(e1), q.dot(e2)]);
            }
        }
        if points.len() != 2 {
            return Ok(());
        }
        let n = orientation * (t[1] - t[0]).cross(t[2] - t[0]);
        let n2 = [n.dot(e1), n.dot(e2)];
        let (p, q) = (points[0], points[1]);
        // Outward normal of the edge p → q of a counter-clockwise boundary is (dy, −dx).
        let out = [q[1] - p[1], -(q[0] - p[0])];
        if out[0] * n2[0] + out[1] * n2[1] >= 0.0 {
            segments.push((p, q));
        } else {
            segments.push((q, p));
        }
        Ok(())
    })?;
    progress("slicing", total, total);
    if segments.len() < 3 {
        return Err(shape_error(
            source,
            format!(
                "the slice across the axis {:?} through the centroid meets {} edges: the mesh is \
                 not a closed cylinder along that axis",
                axis.to_array(),
                segments.len()
            ),
        ));
    }
    // Area and area centroid by Green's theorem (needs no ordering of the segments).
    let (mut area2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for (p, q) in &segments {
        let w = cross2(*p, *q);
        area2 += w;
        cx += (p[0] + q[0]) * w;
        cy += (p[1] + q[1]) * w;
    }
    let area = area2 / 2.0;
    if area <= 0.0 {
        return Err(shape_error(
            source,
            "the section's boundary encloses no area: the mesh is open or wound inconsistently"
                .into(),
        ));
    }
    let centre = [cx / (3.0 * area2), cy / (3.0 * area2)];
    let rel: Vec<([f64; 2], [f64; 2])> = segments
        .iter()
        .map(|(p, q)| {
            (
                [p[0] - centre[0], p[1] - centre[1]],
                [q[0] - centre[0], q[1] - centre[1]],
            )
        })
        .collect();
    // r(θ) at equally spaced angles; each ray from the centre must meet the boundary once.
    let n = SECTION_SAMPLES;
    let step = TAU / n as f64;
    let mut radius = vec![0.0f64; n];
    let mut hits = vec![0i32; n];
    let mut folds = vec![0u32; n];
    for (p, q) in &rel {
        let swept = cross2(*p, *q).atan2(p[0] * q[0] + p[1] * q[1]);
        // Each segment takes the sample rays in [start, end) counter-clockwise, with both ends'
        // angles from the points themselves: a vertex shared by two segments has one angle, so
        // a ray through it goes to exactly one of them (start + sweep, rounded differently, put
        // rays through the vertices of OpenSCAD's cylinders in both or neither).
        let (start, end) = if swept >= 0.0 { (p, q) } else { (q, p) };
        let (from, to) = (start[1].atan2(start[0]), end[1].atan2(end[0]));
        let first = (from / step).ceil() as i64;
        let mut last = (to / step).ceil() as i64;
        if last < first {
            if from - to > std::f64::consts::PI {
                // Across the cut at ±π.
                last += n as i64;
            } else {
                // A sliver whose end angle rounded below its start: it meets no ray.
                last = first;
            }
        }
        let dq = [q[0] - p[0], q[1] - p[1]];
        for k in first..last {
            let th = k as f64 * step;
            let u = [th.cos(), th.sin()];
            let den = cross2(u, dq);
            if den == 0.0 {
                continue;
            }
            let r = cross2(*p, dq) / den;
            let idx = k.rem_euclid(n as i64) as usize;
            if swept >= 0.0 {
                hits[idx] += 1;
                radius[idx] = r;
            } else {
                hits[idx] -= 1;
                folds[idx] += 1;
            }
        }
    }
    if let Some(k) = (0..n).find(|&k| folds[k] > 0 || hits[k] > 1) {
        return Err(shape_error(
            source,
            format!(
                "the section is not star-shaped about its centroid: the ray at θ = {:.4} meets \
                 its boundary more than once; the models need r(θ) single-valued",
                k as f64 * step
            ),
        ));
    }
    if let Some(k) = (0..n).find(|&k| hits[k] != 1) {
        return Err(shape_error(
            source,
            format!(
                "the section is open: the ray at θ = {:.4} from its centroid meets no boundary \
                 (a hole in the side wall)",
                k as f64 * step
            ),
        ));
    }
    let mean = radius.iter().sum::<f64>() / n as f64;
    // Fourier coefficients of r/⟨r⟩ − 1: cos (b) and sin (c) parts, l = 1 … top; the rest of
    // the variance (Parseval) is what a fit to degree M leaves.
    let top = (MAX_FIT_DISK_L as usize).max(options.modes.unwrap_or(0) as usize);
    let variance = radius.iter().map(|r| (r / mean - 1.0).powi(2)).sum::<f64>() / n as f64;
    let mut b = vec![0.0; top + 1];
    let mut c = vec![0.0; top + 1];
    for (l, (bl, cl)) in b.iter_mut().zip(c.iter_mut()).enumerate().skip(1) {
        let (mut sb, mut sc) = (0.0, 0.0);
        for (k, r) in radius.iter().enumerate() {
            let a = (l * k % n) as f64 * step;
            sb += r * a.cos();
            sc += r * a.sin();
        }
        *bl = 2.0 * sb / (n as f64 * mean);
        *cl = 2.0 * sc / (n as f64 * mean);
    }
    let tail = |from: usize| -> f64 {
        let kept: f64 = (1..from).map(|l| (b[l] * b[l] + c[l] * c[l]) / 2.0).sum();
        (variance - kept).max(0.0).sqrt()
    };
    let tried = options.modes.unwrap_or(AUTO_MAX_2D);
    let degree_residuals: Vec<DegreeResidual> = (2..=tried.max(AUTO_MAX_2D))
        .map(|m| DegreeResidual {
            modes: m,
            rms: tail(m as usize + 1),
        })
        .collect();
    let (modes, rule) = match options.modes {
        Some(m) => (m, "given".to_string()),
        None => (
            choose(&degree_residuals, AUTO_MAX_2D),
            AUTO_RULE.to_string(),
        ),
    };
    let disk_modes: Vec<DiskMode> = (2..=modes as usize)
        .map(|l| {
            let lf = l as f64;
            DiskMode {
                l: l as u32,
                a: lf * lf * b[l].hypot(c[l]),
                phase: (-b[l]).atan2(c[l]) / lf,
            }
        })
        .collect();
    let scale_mm = mean * options.mm_per_unit;
    let shape = ShapeFile::Disk {
        modes: disk_modes,
        scale_mm: Some(scale_mm),
    };
    let body = Body::from_shape(&shape).map_err(|e| shape_error(source, e.to_string()))?;
    let Body::Disk(disk) = &body else {
        unreachable!("a disk shape file gives a disk")
    };
    let (mut sum2, mut worst, mut worst_at) = (0.0, 0.0f64, 0.0);
    for (k, r) in radius.iter().enumerate() {
        let th = k as f64 * step;
        let e = r / mean - disk.jet(th).r;
        sum2 += e * e;
        if e.abs() > worst {
            (worst, worst_at) = (e.abs(), th);
        }
    }
    let rms = (sum2 / n as f64).sqrt();
    let l1 = b[1].hypot(c[1]);
    let mut warnings = Vec::new();
    let convex = body.check_convex().is_ok();
    if !convex {
        let dents = disk.hull().bridges().len();
        warnings.push(format!(
            "the fitted section is not convex ({dents} dent(s)); `simulate` rolls it on its \
             convex hull, the other commands refuse it"
        ));
    }
    let alpha_star = body.alpha_star();
    let corners: Vec<[f64; 2]> = rel.iter().flat_map(|(p, q)| [*p, *q]).collect();
    let mesh_hull = section_hull(&corners);
    if let Some(hull) = mesh_hull.filter(|h| (h.alpha_star - alpha_star).abs() > FACET_TOLERANCE) {
        warnings.push(format!(
            "the section's hull has {} flat sides, on which the printed body rests up to α = \
             {:.4} rad ({:.2}°), but the smooth fit's α* is {alpha_star:.4} rad ({:.2}°): the \
             fit does not see the facets, so `period`, `predict` and `simulate` speak for the \
             smooth body, not the print (a printer reproduces facets wider than its nozzle; \
             these are {:.2} mm at most)",
            hull.sides,
            hull.alpha_star,
            hull.alpha_star.to_degrees(),
            alpha_star.to_degrees(),
            hull.longest_side * scale_mm,
        ));
    }
    let report = FitReport {
        file: source.path().display().to_string(),
        format: format_name(source.format()),
        triangles: source.triangles(),
        dimension: 2,
        modes,
        modes_rule: rule,
        scale_mm,
        size_mm: area * options.mm_per_unit.powi(2),
        centroid: (c3 + centre[0] * e1 + centre[1] * e2).to_array(),
        axis: Some(axis.to_array()),
        section_axes: Some([e1.to_array(), e2.to_array()]),
        rms_residual: rms,
        rms_residual_mm: rms * scale_mm,
        max_residual: worst,
        max_residual_mm: worst * scale_mm,
        max_residual_at: format!("θ = {worst_at:.4}"),
        l1_part: l1,
        l1_offset_mm: l1 * scale_mm,
        degree_residuals,
        convex,
        alpha_star,
        mesh_hull,
        warnings,
        coat: None,
    };
    Ok((body, shape, report))
}

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

/// One direction cell: the solid angle the surface covers in it, and one exact point of the
/// surface there (the piece seen nearest the cell's centre). Points rather than averages keep
/// the least squares consistent: a band-limited body is fitted exactly, where a cell's mean
/// radius assigned to its mean direction is off by the radius's curvature times the cell's
/// size squared (2e-5 of ⟨r⟩ on the paper's body, measured).
#[derive(Debug, Clone, Copy)]
struct Cell {
    weight: f64,
    /// 1 − cos(angle to the cell's centre) of the point kept.
    distance: f64,
    direction: DVec3,
    radius: f64,
}

impl Default for Cell {
    fn default() -> Self {
        Cell {
            weight: 0.0,
            distance: f64::INFINITY,
            direction: DVec3::Z,
            radius: 0.0,
        }
    }
}

fn cell_of(u: DVec3) -> usize {
    let band = (((u.z + 1.0) / 2.0 * BANDS as f64) as usize).min(BANDS - 1);
    let phi = u.y.atan2(u.x).rem_euclid(TAU);
    let sector = ((phi / TAU * SECTORS as f64) as usize).min(SECTORS - 1);
    band * SECTORS + sector
}

fn cell_centre(index: usize) -> DVec3 {
    let (band, sector) = (index / SECTORS, index % SECTORS);
    let z = (band as f64 + 0.5) / BANDS as f64 * 2.0 - 1.0;
    let phi = (sector as f64 + 0.5) / SECTORS as f64 * TAU;
    let s = (1.0 - z * z).sqrt();
    DVec3::new(s * phi.cos(), s * phi.sin(), z)
}

/// A triangle seen from the centroid across more than this angle (rad) is cut into four by its
/// edges' midpoints, and so on, so that a long facet (a cylinder's side) is sampled along its
/// length and not only at its centre: about two cells' width.
const PIECE_ANGLE: f64 = 0.05;

/// Calls `f` on the pieces of the flat triangle `t` (about the centroid, the origin), each seen
/// across at most [`PIECE_ANGLE`] (or cut 10 times).
fn pieces(t: [DVec3; 3], f: &mut impl FnMut([DVec3; 3])) {
    fn cut(t: [DVec3; 3], depth: u32, f: &mut impl FnMut([DVec3; 3])) {
        let u = t.map(|p| p.normalize_or_zero());
        let widest = u[0]
            .angle_between(u[1])
            .max(u[1].angle_between(u[2]))
            .max(u[2].angle_between(u[0]));
        if depth >= 10 || widest.is_nan() || widest <= PIECE_ANGLE {
            f(t);
            return;
        }
        let [a, b, c] = t;
        let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
        for piece in [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]] {
            cut(piece, depth + 1, f);
        }
    }
    cut(t, 0, f);
}

/// Solid angle of the triangle (a, b, c) seen from the origin, signed by its winding
/// (Van Oosterom and Strackee, 1983).
fn solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}

fn angles_text(u: DVec3) -> String {
    let (theta, phi) = super::sphere::angles(u);
    format!("θ = {theta:.4}, φ = {phi:.4}")
}

#[expect(
    clippy::too_many_lines,
    reason = "the coverage pass, its three failure modes, the least-squares fit over all degrees \
              and the residual pass share the cells and the centroid; split, they would pass a \
              dozen values between them"
)]
fn fit_sphere(
    source: &MeshSource,
    totals: &Totals,
    orientation: f64,
    options: &FitOptions,
    progress: Progress,
) -> Result<(Body, ShapeFile, FitReport), MeshError> {
    let c = totals.centroid;
    let mut cells = vec![Cell::default(); BANDS * SECTORS];
    let centres: Vec<DVec3> = (0..BANDS * SECTORS).map(cell_centre).collect();
    let (mut covered, mut negative, mut folded) = (0.0, 0.0, 0usize);
    let mut worst_fold: Option<(f64, usize, DVec3)> = None;
    let total = source.triangles();
    source.for_each(|i, t| {
        tick(progress, "measuring", i, total);
        let [a, b, d] = t.map(|p| p - c);
        let omega = orientation * solid_angle(a, b, d);
        covered += omega;
        let mid = (a + b + d).normalize_or_zero();
        if omega < 0.0 {
            negative -= omega;
            folded += 1;
            if worst_fold.is_none_or(|w| -omega > w.0) {
                worst_fold = Some((-omega, i, mid));
            }
        }
        if omega > 0.0 {
            let normal = (b - a).cross(d - a);
            let plane = normal.dot(a);
            pieces([a, b, d], &mut |[p, q, r]| {
                let mid = (p + q + r).normalize_or_zero();
                let along = normal.dot(mid);
                if along != 0.0 && mid != DVec3::ZERO {
                    let w = orientation * solid_angle(p, q, r);
                    let k = cell_of(mid);
                    let distance = 1.0 - mid.dot(centres[k]);
                    let cell = &mut cells[k];
                    cell.weight += w;
                    if distance < cell.distance {
                        cell.distance = distance;
                        cell.direction = mid;
                        cell.radius = plane / along;
                    }
                }
            });
        }
        Ok(())
    })?;
    progress("measuring", total, total);
    let sphere_area = 4.0 * PI;
    if (covered - sphere_area).abs() > COVERAGE_TOL * sphere_area {
        // The cell whose coverage is furthest from once names the place.
        let cell_area = sphere_area / (BANDS * SECTORS) as f64;
        let (k, _) = cells
            .iter()
            .enumerate()
            .map(|(k, cell)| (k, (cell.weight / cell_area - 1.0).abs()))
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap_or((0, 0.0));
        let what = match Topology::of(source)?.trouble() {
            Some(trouble) => trouble,
            None if covered < sphere_area => "the mesh is open (a hole)".to_string(),
            None => "triangles overlap (duplicated faces, or a second shell)".to_string(),
        };
        return Err(shape_error(
            source,
            format!(
                "seen from its centroid the surface covers {:.6} of the sphere's 4π, not exactly \
                 once: {what}, near {}",
                covered / sphere_area,
                angles_text(cell_centre(k))
            ),
        ));
    }
    let mut warnings = Vec::new();
    if let Some((_, index, at)) = worst_fold
        && negative > FOLD_TOL * sphere_area
    {
        return Err(shape_error(
            source,
            format!(
                "the mesh is not star-shaped about its centroid: a ray from it meets the surface \
                 more than once near {} (triangle {index} faces the centroid; {:.3e} of the \
                 sphere is folded over); the models need r(θ, φ) single-valued",
                angles_text(at),
                negative / sphere_area
            ),
        ));
    }
    if let Some((_, index, at)) = worst_fold
        && negative > 0.0
    {
        warnings.push(format!(
            "{folded} triangle(s) face the centroid, covering {:.1e} of the sphere (slivers, the \
             largest triangle {index} near {}); left out of the fit",
            negative / sphere_area,
            angles_text(at)
        ));
    }
    // The least-squares fit on the cells, every degree from one Gram matrix.
    let samples: Vec<(DVec3, f64, f64)> = cells
        .iter()
        .filter(|cell| cell.weight > 0.0 && cell.distance.is_finite())
        .map(|cell| (cell.direction, cell.radius, cell.weight))
        .collect();
    let top = options.modes.unwrap_or(AUTO_MAX_3D).max(AUTO_MAX_3D);
    let basis = ((top + 1) * (top + 1)) as usize;
    let (gram, rhs, r2) = samples
        .par_chunks(512)
        .map(|chunk| {
            let mut g = vec![0.0; basis * basis];
            let mut h = vec![0.0; basis];
            let mut r2 = 0.0;
            let mut y = vec![0.0; basis];
            for &(u, r, w) in chunk {
                real_harmonics(top, u, &mut y);
                for i in 0..basis {
                    let wy = w * y[i];
                    h[i] += wy * r;
                    for j in i..basis {
                        g[i * basis + j] += wy * y[j];
                    }
                }
                r2 += w * r * r;
            }
            (g, h, r2)
        })
        // Summed in chunk order, not as rayon's work-stealing tree would: the same bits on
        // every run and thread count.
        .collect::<Vec<_>>()
        .into_iter()
        .fold(
            (vec![0.0; basis * basis], vec![0.0; basis], 0.0),
            |mut x, y| {
                x.0.iter_mut().zip(&y.0).for_each(|(a, b)| *a += b);
                x.1.iter_mut().zip(&y.1).for_each(|(a, b)| *a += b);
                (x.0, x.1, x.2 + y.2)
            },
        );
    let weight: f64 = samples.iter().map(|s| s.2).sum();
    let solve = |l: u32| -> Option<(Vec<f64>, f64)> {
        let k = ((l + 1) * (l + 1)) as usize;
        let g = DMatrix::from_fn(k, k, |i, j| gram[i.min(j) * basis + i.max(j)]);
        let h = DVector::from_fn(k, |i, _| rhs[i]);
        let x = g.clone().cholesky()?.solve(&h);
        // Σ w (r − yᵀx)² = Σ w r² − 2 xᵀh + xᵀ G x.
        let sq = r2 - 2.0 * x.dot(&h) + x.dot(&(&g * &x));
        Some((x.iter().copied().collect(), sq.max(0.0)))
    };
    let mut fits = Vec::new();
    for l in 2..=top {
        let Some((x, sq)) = solve(l) else {
            return Err(shape_error(
                source,
                format!(
                    "the directions the mesh covers do not determine a degree-{l} fit (too few \
                     triangles for that degree); give a lower --modes"
                ),
            ));
        };
        fits.push((l, x, sq));
    }
    let mean = fits[0].1[0] * (0.25 / PI).sqrt();
    let degree_residuals: Vec<DegreeResidual> = fits
        .iter()
        .map(|(l, _, sq)| DegreeResidual {
            modes: *l,
            rms: (sq / weight).sqrt() / mean,
        })
        .collect();
    let (modes, rule) = match options.modes {
        Some(m) => (m, "given".to_string()),
        None => (
            choose(&degree_residuals, AUTO_MAX_3D),
            AUTO_RULE.to_string(),
        ),
    };
    let x = &fits[(modes - 2) as usize].1;
    let mean = x[0] * (0.25 / PI).sqrt();
    let l1 = (x[1] * x[1] + x[2] * x[2] + x[3] * x[3]).sqrt() * (0.75 / PI).sqrt() / mean;
    let coeffs = sphere_coeffs(x, modes, mean);
    let scale_mm = mean * options.mm_per_unit;
    let shape = ShapeFile::Sphere {
        coeffs,
        scale_mm: Some(scale_mm),
    };
    let body = Body::from_shape(&shape).map_err(|e| shape_error(source, e.to_string()))?;
    let Body::Sphere(sphere) = &body else {
        unreachable!("a sphere shape file gives a sphere")
    };
    // The body against every triangle (along the ray through its centre) and every vertex.
    let mut chunk: Vec<[DVec3; 3]> = Vec::with_capacity(1 << 16);
    let (mut sum2, mut sum_w, mut worst, mut worst_at) = (0.0, 0.0, 0.0f64, DVec3::Z);
    let mut measure = |chunk: &mut Vec<[DVec3; 3]>| {
        let (s2, sw, w, at) = chunk
            .par_iter()
            .map(|t| {
                let [a, b, d] = t.map(|p| p - c);
                let omega = orientation * solid_angle(a, b, d);
                let normal = (b - a).cross(d - a);
                let plane = normal.dot(a);
                let (mut s2, mut sw) = (0.0, 0.0);
                if omega > 0.0 {
                    pieces([a, b, d], &mut |[p, q, r]| {
                        let mid = (p + q + r).normalize_or_zero();
                        let along = normal.dot(mid);
                        if along != 0.0 && mid != DVec3::ZERO {
                            let w = orientation * solid_angle(p, q, r);
                            let e = plane / along / mean - sphere.radius(mid);
                            s2 += w * e * e;
                            sw += w;
                        }
                    });
                }
                let (mut w, mut at) = (0.0f64, DVec3::Z);
                for p in [a, b, d] {
                    let len = p.length();
                    let e = (len / mean - sphere.radius(p / len)).abs();
                    if e > w {
                        (w, at) = (e, p / len);
                    }
                }
                (s2, sw, w, at)
            })
            // In triangle order (see the Gram matrix above).
            .collect::<Vec<_>>()
            .into_iter()
            .fold((0.0, 0.0, 0.0, DVec3::Z), |x, y| {
                let (w, at) = if y.2 > x.2 { (y.2, y.3) } else { (x.2, x.3) };
                (x.0 + y.0, x.1 + y.1, w, at)
            });
        sum2 += s2;
        sum_w += sw;
        if w > worst {
            (worst, worst_at) = (w, at);
        }
        chunk.clear();
    };
    source.for_each(|i, t| {
        tick(progress, "measuring the fit", i, total);
        chunk.push(t);
        if chunk.len() == chunk.capacity() {
            measure(&mut chunk);
        }
        Ok(())
    })?;
    measure(&mut chunk);
    progress("measuring the fit", total, total);
    let rms = (sum2 / sum_w).sqrt();
    let convex = body.check_convex();
    if let Err(e) = &convex {
        // In a mesh user's words: the generator's advice (lower σ, fewer modes) is not theirs.
        let what = match e {
            crate::geometry::ShapeError::NotConvex {
                measure,
                value,
                place,
            } => format!(
                "it is not convex ({measure} {value:.6} at {place}; the contact model needs a \
                 strictly convex body, and a dent in the printed body itself cannot roll as the \
                 model assumes)"
            ),
            other => other.to_string(),
        };
        return Err(shape_error(
            source,
            format!(
                "the degree-{modes} fit cannot be rolled: {what}. A lower --modes smooths it (the \
                 rms residual of each degree: {})",
                degree_residuals
                    .iter()
                    .map(|d| format!("L = {}: {:.2e}", d.modes, d.rms))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    let report = FitReport {
        file: source.path().display().to_string(),
        format: format_name(source.format()),
        triangles: total,
        dimension: 3,
        modes,
        modes_rule: rule,
        scale_mm,
        size_mm: totals.volume.abs() * options.mm_per_unit.powi(3),
        centroid: c.to_array(),
        axis: None,
        section_axes: None,
        rms_residual: rms,
        rms_residual_mm: rms * scale_mm,
        max_residual: worst,
        max_residual_mm: worst * scale_mm,
        max_residual_at: angles_text(worst_at),
        l1_part: l1,
        l1_offset_mm: l1 * scale_mm,
        degree_residuals,
        convex: true,
        alpha_star: body.alpha_star(),
        mesh_hull: None,
        warnings,
        coat: None,
    };
    Ok((body, shape, report))
}

/// The shape file's coefficients A_lm (m ≥ 0) of the real-basis fit `x` (mesh units), up to
/// degree `modes`, relative to ⟨r⟩ = `mean`. The file's r = 1 + Re Σ A_lm Y_lm/(l(l+1)) and
/// Re(A Y_lm) = re Re Y − im Im Y, against the basis √2 Re Y_lm (m > 0), √2 Im Y_l|m| (m < 0).
fn sphere_coeffs(x: &[f64], modes: u32, mean: f64) -> Vec<SphereCoeff> {
    let mut out = Vec::new();
    for l in 2..=modes {
        let ll = (l * (l + 1)) as f64;
        let base = (l * l + l) as i64;
        for m in 0..=l as i32 {
            let (re, im) = if m == 0 {
                (ll * x[base as usize] / mean, 0.0)
            } else {
                let cos_part = x[(base + m as i64) as usize] / mean;
                let sin_part = x[(base - m as i64) as usize] / mean;
                (
                    ll * std::f64::consts::SQRT_2 * cos_part,
                    -ll * std::f64::consts::SQRT_2 * sin_part,
                )
            };
            out.push(SphereCoeff { l, m, re, im });
        }
    }
    out
}

/// The orthonormal real spherical harmonics up to degree `top` at the unit vector `u`, into
/// `out[l² + l + m]`: Y_l0, √2 Re Y_lm for m > 0, √2 Im Y_l|m| for m < 0, with Y_lm the complex
/// harmonics of [`super::harmonics::spherical_harmonic`] (Condon–Shortley phase). By the
/// recurrence in z for P_l^m / sin^m θ, times (x + iy)^m: O(L²) a point, no trigonometry.
///
/// # Example
/// ```
/// use rollphase_core::geometry::harmonics::spherical_harmonic;
/// use rollphase_core::geometry::mesh_fit::real_harmonics;
/// use rollphase_core::glam::DVec3;
/// let u = DVec3::new(0.3, -0.5, 0.8).normalize();
/// let mut y = vec![0.0; 16];
/// real_harmonics(3, u, &mut y);
/// let (re, im) = spherical_harmonic(3, 2).eval(u.x, u.y, u.z);
/// assert!((y[9 + 3 + 2] - std::f64::consts::SQRT_2 * re).abs() < 1e-14);
/// assert!((y[9 + 3 - 2] - std::f64::consts::SQRT_2 * im).abs() < 1e-14);
/// ```
pub fn real_harmonics(top: u32, u: DVec3, out: &mut [f64]) {
    let top = top as usize;
    debug_assert!(out.len() >= (top + 1) * (top + 1));
    let (mut cr, mut ci) = (1.0, 0.0); // (x + iy)^m
    let mut pmm = 1.0; // P̃_m^m = (−1)^m (2m − 1)!!
    for m in 0..=top {
        if m > 0 {
            (cr, ci) = (cr * u.x - ci * u.y, cr * u.y + ci * u.x);
            pmm *= -((2 * m - 1) as f64);
        }
        let (mut p_prev, mut p) = (0.0, pmm);
        for l in m..=top {
            if l == m + 1 {
                (p_prev, p) = (p, u.z * (2 * m + 1) as f64 * pmm);
            } else if l > m + 1 {
                let next =
                    ((2 * l - 1) as f64 * u.z * p - (l + m - 1) as f64 * p_prev) / (l - m) as f64;
                (p_prev, p) = (p, next);
            }
            let norm = ((2 * l + 1) as f64 / (4.0 * PI) * factorial_ratio(l, m)).sqrt();
            let centre = l * l + l;
            if m == 0 {
                out[centre] = norm * p;
            } else {
                let k = std::f64::consts::SQRT_2 * norm * p;
                out[centre + m] = k * cr;
                out[centre - m] = k * ci;
            }
        }
    }
}

/// (l − m)! / (l + m)!.
fn factorial_ratio(l: usize, m: usize) -> f64 {
    ((l - m + 1)..=(l + m)).fold(1.0, |acc, k| acc / k as f64)
}
