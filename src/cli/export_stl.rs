//! `rollphase export-stl`: a body as a watertight binary STL mesh in millimetres, to 3D-print
//! and roll as the paper's authors did.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::geometry::Body;

/// Write a body as a watertight STL mesh in millimetres, for 3D printing.
///
/// The mean radius ⟨r⟩ = 1 becomes --radius-mm. A 3D body is an icosphere mapped through r(u);
/// a 2D body is extruded into a cylinder --length-mm long with flat ends.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct ExportStlArgs {
    /// Shape file (JSON).
    pub file: PathBuf,
    /// Output STL file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Mean radius in millimetres.
    #[arg(long, default_value_t = 25.0, allow_negative_numbers = true)]
    pub radius_mm: f64,
    /// Cylinder length in millimetres (2D bodies) [default: 2 × radius].
    #[arg(long, allow_negative_numbers = true)]
    pub length_mm: Option<f64>,
    /// Mesh resolution: icosphere subdivisions (3D: 20·4^n triangles) or at least 2^n·16
    /// segments (2D: more where the printed polygon's flats would raise α* by over 0.05°).
    #[arg(long, default_value_t = 6)]
    pub detail: u32,
}

/// Runs `export-stl`.
pub fn run(a: ExportStlArgs) -> Result<()> {
    // Below a micrometre the vertices, written as 32-bit floats, collapse onto each other.
    if !(a.radius_mm.is_finite() && (1e-3..=10_000.0).contains(&a.radius_mm)) {
        bail!(
            "--radius-mm {} is not allowed (needs 0.001 ≤ radius ≤ 10000 mm)",
            super::short(a.radius_mm)
        );
    }
    let length = a.length_mm.unwrap_or(2.0 * a.radius_mm);
    if !(length.is_finite() && (1e-3..=100_000.0).contains(&length)) {
        bail!(
            "--length-mm {} is not allowed (needs 0.001 ≤ length ≤ 100000 mm)",
            super::short(length)
        );
    }
    if !(1..=8).contains(&a.detail) {
        bail!(
            "--detail {} is not allowed (needs 1 ≤ detail ≤ 8)",
            a.detail
        );
    }
    let body = super::load_body(&a.file)?;
    if a.length_mm.is_some() && matches!(body, Body::Sphere(_)) {
        bail!(
            "--length-mm is for a 2D body's cylinder; {} is a 3D sphere (its size is --radius-mm)",
            a.file.display()
        );
    }
    // A dented cylinder or a print's outline rolls on its hull: it is printed as it is.
    body.check_rollable()
        .with_context(|| format!("{} cannot roll as a rigid body", a.file.display()))?;
    let mesh = crate::geometry::mesh::print_mesh(&body, a.detail, length / a.radius_mm);
    let open = mesh.open_edges();
    if open != 0 {
        bail!("internal error: the mesh has {open} open edges; please report this shape file");
    }
    let mut file =
        crate::output::OutputFile::create(&a.output, &crate::output::Inputs::of([&a.file]))?;
    let name = a
        .file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("body");
    let name = match &body {
        Body::Disk(_) => format!("{name} {}", crate::geometry::mesh::DISK_AXIS_TAG),
        Body::Sphere(_) => name.to_string(),
    };
    mesh.write_stl(&mut file, a.radius_mm, &name)
        .with_context(|| format!("cannot write {}", a.output.display()))?;
    file.commit()?;
    let volume_cm3 = mesh.volume() * a.radius_mm.powi(3) / 1000.0;
    let status = format!(
        "wrote {} ({} triangles, watertight, volume {volume_cm3:.2} cm³ at ⟨r⟩ = {} mm)",
        a.output.display(),
        mesh.indices.len(),
        a.radius_mm
    );
    let facets = match &body {
        Body::Sphere(_) => printed_facets_note(&mesh, body.alpha_star(), a.detail),
        Body::Disk(_) => None,
    };
    // Standard output carries the STL itself: nothing else may follow it there.
    if crate::output::is_standard_output(&a.output) {
        eprintln!("{status}");
    } else {
        outln!("{status}")?;
    }
    if let Some(note) = facets {
        eprintln!("note: {note}");
    }
    Ok(())
}

/// What a sphere's icosphere does to the print: a polyhedron rests on its facets up to the
/// α* of its own hull, above the body's (`alpha_star`), by about the facets' size over the
/// radius; each level of `detail` halves that. `None` where the excess is within 0.1°.
pub fn printed_facets_note(
    mesh: &crate::geometry::mesh::TriMesh,
    alpha_star: f64,
    detail: u32,
) -> Option<String> {
    let hull = mesh.printed_hull()?;
    let excess = hull.alpha_star - alpha_star;
    (excess > crate::geometry::facets::FACET_TOLERANCE).then(|| {
        format!(
            "printed as written, this mesh's facets hold the ball up to α = {:.4} rad ({:.2}°), \
             {:.2}° above the body's α* = {:.4} rad; each step of --detail halves that (detail \
             {detail} now; 8 gives about {:.2}°, a 65 MB STL), and a print's layers and a \
             coat round the facets part of the way",
            hull.alpha_star,
            hull.alpha_star.to_degrees(),
            excess.to_degrees(),
            alpha_star,
            (excess / f64::from(1u32 << (8u32.saturating_sub(detail)))).to_degrees()
        )
    })
}
