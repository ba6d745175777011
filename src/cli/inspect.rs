//! `rollphase inspect`: convexity, curvature range and the critical angle of a body.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use serde::Serialize;

use crate::analysis::critical_angle;
use crate::geometry::Body;

/// Report a body's convexity, curvature range and critical angle α*.
///
/// α* = atan max |∇ ln r|: below it the body can rest on the ramp (2D: it must halt; 3D: some
/// orientations halt), above it no rest point exists. Curvature is κ in 2D and the Gaussian
/// curvature K in 3D; convexity needs κ > 0 (2D) or both principal curvatures > 0 (3D).
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct InspectArgs {
    /// Shape file (JSON).
    pub file: PathBuf,
    /// Print JSON (keys convex, curvature_min, curvature_max, alpha_star, …).
    #[arg(long)]
    pub json: bool,
}

/// What `inspect --json` prints.
#[derive(Debug, Serialize)]
pub struct Inspection {
    /// 2 or 3.
    pub dimension: u32,
    /// Strictly convex (required by the rolling models).
    pub convex: bool,
    /// Minimum of κ (2D) or Gaussian curvature K (3D).
    pub curvature_min: f64,
    /// Maximum of κ (2D) or K (3D).
    pub curvature_max: f64,
    /// Which quantity decides convexity.
    pub convexity_measure: &'static str,
    /// Its minimum.
    pub convexity_min: f64,
    /// Where.
    pub convexity_place: String,
    /// α* in radians.
    pub alpha_star: f64,
    /// α* in degrees.
    pub alpha_star_deg: f64,
    /// A cylinder's α* turned end for end (rad): set on the ramp the other way round, it rolls
    /// with its section mirrored, and rests up to this angle that way; `null` for a sphere.
    pub alpha_star_turned: Option<f64>,
    /// max |∇ ln r| = tan α*.
    pub q_star: f64,
    /// Maximiser: θ* (2D) or polar angle θ (3D).
    pub theta_star: f64,
    /// Maximiser azimuth φ (3D; 0 in 2D).
    pub phi_star: f64,
    /// Maximiser as a body-frame unit vector (3D; zeros in 2D).
    pub direction_star: [f64; 3],
    /// A 2D body that is not convex: the flats of its convex hull it rolls on, over its dents.
    pub hull_flats: Vec<crate::geometry::hull::Bridge>,
    /// A body fitted to a faceted print (its shape file keeps the print's section, which it
    /// rolls on, corners rounded): the section's flat sides and the angle they hold it up to
    /// with sharp corners; `null` otherwise.
    pub printed_section: Option<crate::geometry::facets::SectionHull>,
    /// Such a body's smooth fit (its modes alone): its α* (rad); `null` otherwise.
    pub smooth_fit_alpha_star: Option<f64>,
    /// A 2D body that is not convex: the steepest ramp it can rest on a flat at, and α* of its
    /// curved parts alone (α* is the larger).
    pub flat_rest: Option<crate::analysis::rest::critical_angle::FlatRest>,
}

/// Computes the inspection of a body.
pub fn inspect(body: &Body) -> Inspection {
    let c = body.curvature();
    let a = critical_angle(body);
    Inspection {
        dimension: body.dimension(),
        convex: c.convex,
        curvature_min: c.curvature_min,
        curvature_max: c.curvature_max,
        convexity_measure: c.convexity_measure,
        convexity_min: c.convexity_min,
        convexity_place: c.convexity_place,
        alpha_star: a.alpha_star,
        alpha_star_deg: a.alpha_star.to_degrees(),
        alpha_star_turned: match body {
            Body::Disk(d) => Some(critical_angle(&Body::Disk(d.turned())).alpha_star),
            Body::Sphere(_) => None,
        },
        q_star: a.q_star,
        theta_star: a.theta,
        phi_star: a.phi,
        direction_star: a.direction,
        hull_flats: match body {
            Body::Disk(d) => d.hull().bridges().to_vec(),
            Body::Sphere(_) => Vec::new(),
        },
        printed_section: match body {
            Body::Disk(d) => d.printed_section().and_then(|p| p.hull().ok()),
            Body::Sphere(_) => None,
        },
        smooth_fit_alpha_star: match body {
            Body::Disk(d) if d.printed_section().is_some() => {
                Some(critical_angle(&Body::Disk(d.smooth_fit())).alpha_star)
            }
            _ => None,
        },
        flat_rest: a.flat,
    }
}

/// Runs `inspect`.
pub fn run(a: InspectArgs) -> Result<()> {
    let body = super::load_body(&a.file)?;
    let r = inspect(&body);
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&r)?)?;
        return Ok(());
    }
    let what = if r.dimension == 2 {
        "disk (2D)"
    } else {
        "sphere (3D)"
    };
    let curv = if r.dimension == 2 {
        "curvature κ"
    } else {
        "Gaussian curvature K"
    };
    outln!("{}: {what}", a.file.display())?;
    outln!(
        "  convex:          {}{}",
        if r.convex { "yes" } else { "NO" },
        if r.convex {
            String::new()
        } else {
            format!(
                " ({} {:.6} at {})",
                r.convexity_measure, r.convexity_min, r.convexity_place
            )
        }
    )?;
    outln!("  {curv}: {:.6} … {:.6}", r.curvature_min, r.curvature_max)?;
    outln!(
        "  critical angle:  α* = {:.10} rad = {:.6}°  (max |∇ ln r| = {:.10})",
        r.alpha_star,
        r.alpha_star_deg,
        r.q_star
    )?;
    if let Some(f) = r.flat_rest {
        outln!(
            "  on its hull:     not convex, so it rolls on its convex hull: {} flat(s) over \
             dent(s), the deepest {:.4}",
            r.hull_flats.len(),
            r.hull_flats.iter().map(|b| b.depth).fold(0.0, f64::max)
        )?;
        outln!(
            "                   the curved parts rest up to α = {:.10}; the steepest flat \
             (θ = {:.6} … {:.6}) holds it while the weight's line falls between its ends, from α = \
             {:.10} up to {:.10}: α* is the larger",
            f.curve_alpha,
            f.theta_a,
            f.theta_b,
            f.alpha_from,
            f.alpha
        )?;
    }
    if let (Some(p), Some(fit)) = (r.printed_section, r.smooth_fit_alpha_star) {
        outln!(
            "  as printed:      {} flat sides (sharp corners: α* = {:.10} rad = {:.6}°), which \
             every command rolls on with its corners rounded to {} ⟨r⟩ (the α* above); the \
             smooth fit of its modes has α* = {:.10} rad = {:.6}°",
            p.sides,
            p.alpha_star,
            p.alpha_star.to_degrees(),
            crate::geometry::outline::CORNER_RADIUS,
            fit,
            fit.to_degrees()
        )?;
    }
    if let Some(turned) = r.alpha_star_turned {
        outln!(
            "  turned end for end: α* = {:.10} rad = {:.6}°  (the cylinder set on the ramp the \
             other way round rolls with its section mirrored)",
            turned,
            turned.to_degrees()
        )?;
    }
    if r.dimension == 2 {
        outln!("  maximiser:       θ* = {:.10}", r.theta_star)?;
    } else {
        let d = r.direction_star;
        outln!(
            "  maximiser:       θ = {:.10}, φ = {:.10}  (u = [{:.6}, {:.6}, {:.6}])",
            r.theta_star,
            r.phi_star,
            d[0],
            d[1],
            d[2]
        )?;
    }
    Ok(())
}
