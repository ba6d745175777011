//! `rollphase shape`: a seeded random body, or a body fitted to a mesh, written as a shape file.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::Args;

use crate::geometry::{Body, paper_disk, paper_sphere, random_disk, random_sphere};

/// Generate a random body and write its shape file.
///
/// 2D (a cylinder's cross-section): r(θ) = 1 + Σ_{l=2..M} A_l/l² sin(l(θ − θ_l)),
/// A_l ~ N(0, σ), θ_l ~ U[0, 2π). The paper uses σ = 0.08, M = 10 (viscous) and σ = 0.12, M = 5
/// (inertial). 3D: r = 1 + Re Σ_{l=2..L} Σ_m A_lm/(l(l+1)) Y_l^m, A_lm = a·e^{imP} with
/// a ~ N(0, σ), P ~ U[0, 2π); the paper uses σ = 0.25, L = 5. The same seed always gives the
/// same body. A body that is not strictly convex is refused (try another seed or a smaller σ).
///
/// --paper-seed N instead reproduces the paper authors' own bodies bit for bit (their code draws
/// with numpy: np.random.seed(N), all amplitudes, then all phases). The body of the paper's
/// Figs. 3–4 is
///   rollphase shape --dim 3 --paper-seed 219 --sigma 0.25 --modes 5 -o paper-sphere.json
/// (bundled as assets/shapes/paper-sphere.json).
///
/// --from-mesh FILE instead fits a body to a printed or scanned object (STL binary or ASCII, OBJ,
/// PLY; in mm unless --mm-per-unit says otherwise). 3D: the radius about the volume centroid
/// (the model measures r from the centre of mass; uniform density assumed) least-squares fitted
/// by real spherical harmonics. 2D (an extruded cylinder, found from the mesh or --dim 2): the
/// cross-section through the centroid fitted by a Fourier series. The degree is --modes, or the
/// smallest whose rms residual is within 10 % of the best fit's (L = 8 in 3D, M = 24 in 2D) or under
/// 5e-5 of ⟨r⟩.
/// The fit's report (residuals in mm and relative to ⟨r⟩, the l = 1 part left out, ⟨r⟩ in mm,
/// convexity, α*) goes to standard error, and as JSON to --report; the shape file keeps ⟨r⟩ as
/// "scale_mm", so `predict` can answer in mm. For example:
///   rollphase shape --from-mesh printed-sphere.stl -o printed-sphere.json
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct ShapeArgs {
    /// 2 for a disk (cylinder), 3 for a sphere.
    /// With --from-mesh: found from the mesh (2 when it is an extrusion) unless given.
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=3), required_unless_present = "from_mesh")]
    pub dim: Option<u32>,
    /// Random seed (rollphase's own generator).
    #[arg(
        long,
        required_unless_present_any = ["paper_seed", "from_mesh"],
        conflicts_with_all = ["paper_seed", "from_mesh"]
    )]
    pub seed: Option<u64>,
    /// numpy seed (0..=4294967295) of the paper authors' generator: the same body as their code.
    #[arg(long, conflicts_with = "from_mesh")]
    pub paper_seed: Option<u32>,
    /// Standard deviation σ of the amplitudes [default: 0.08 in 2D, 0.25 in 3D].
    #[arg(long, allow_negative_numbers = true, conflicts_with = "from_mesh")]
    pub sigma: Option<f64>,
    /// Fit the body to this mesh (.stl, .obj, .ply) instead of drawing one.
    #[arg(long, value_name = "FILE")]
    pub from_mesh: Option<PathBuf>,
    /// With --from-mesh: millimetres per mesh unit (1 for files in mm, 10 for cm, 25.4 for inches).
    #[arg(
        long,
        default_value_t = 1.0,
        requires = "from_mesh",
        allow_negative_numbers = true
    )]
    pub mm_per_unit: f64,
    /// With --from-mesh --dim 2: the cylinder's axis as X,Y,Z (found from the mesh if not given).
    #[arg(long, requires = "from_mesh", allow_hyphen_values = true)]
    pub axis: Option<String>,
    /// With --from-mesh: coat the fitted body with this many mm of uniform thickness (the
    /// rubber of the viscous experiments) and fit the coated surface again; the report gives
    /// ⟨r⟩ and α* before and after, and the shape file is the coated body's.
    #[arg(
        long,
        requires = "from_mesh",
        value_name = "MM",
        allow_negative_numbers = true
    )]
    pub coat_mm: Option<f64>,
    /// With --from-mesh --dim 2: the section's flat facets are an export's tessellation of a
    /// round body (a turned or cast part), not flats of the print. Without it the shape file
    /// keeps the section's hull as `printed_section`, and every command rolls the body on it
    /// (its sides flat, its corners rounded to 0.001 ⟨r⟩) rather than on the smooth fit. In 3D
    /// it skips the mesh's own hull (the α* its facets give) and its warning.
    #[arg(long, requires = "from_mesh")]
    pub ignore_facets: bool,
    /// With --from-mesh: write the fit's report as JSON here (residuals, ⟨r⟩ in mm, α*, …).
    #[arg(long, requires = "from_mesh", value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Highest degree l of the modes: M in 2D (2..=64), L in 3D (2..=12) [default: 10 in 2D, 5
    /// in 3D]. The paper authors' 2D generator counts modes instead: their get_r(seed,
    /// num_modes, std) covers l = 2 … num_modes + 1, so their num_modes = 8 is --modes 9 here.
    /// In 3D their L is this L (seed 219, l ≤ 5: --modes 5).
    #[arg(long)]
    pub modes: Option<u32>,
    /// Output file [default: standard output].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// Runs `shape`.
pub fn run(a: ShapeArgs) -> Result<()> {
    if let Some(mesh) = &a.from_mesh {
        return from_mesh(&a, mesh);
    }
    let dim = a.dim.unwrap_or(3);
    let (sigma, modes) = if dim == 2 {
        (a.sigma.unwrap_or(0.08), a.modes.unwrap_or(10))
    } else {
        (a.sigma.unwrap_or(0.25), a.modes.unwrap_or(5))
    };
    let (body, which) = match (a.paper_seed, a.seed) {
        (Some(n), _) if dim == 2 => (Body::Disk(paper_disk(n, sigma, modes)?), "paper seed"),
        (Some(n), _) => (Body::Sphere(paper_sphere(n, sigma, modes)?), "paper seed"),
        (None, Some(n)) if dim == 2 => (Body::Disk(random_disk(n, sigma, modes)?), "seed"),
        (None, Some(n)) => (Body::Sphere(random_sphere(n, sigma, modes)?), "seed"),
        (None, None) => bail!("give --seed N or --paper-seed N"),
    };
    if let Err(e) = body.check_rollable() {
        let n = a.paper_seed.map_or_else(|| a.seed.unwrap_or(0), u64::from);
        bail!("{which} {n} gives a body the models cannot roll: {e}");
    }
    if let (Body::Disk(d), Err(_)) = (&body, body.check_convex()) {
        let bridges = d.hull().bridges();
        let deepest = bridges.iter().map(|b| b.depth).fold(0.0, f64::max);
        eprintln!(
            "note: this body is not convex: it has {} dent(s), the deepest {deepest:.4} ⟨r⟩ under \
             the flat that spans it; `simulate`, and `period` and `predict` without inertia, \
             roll it on its convex hull (across a dent on the flat, tipping from one end to the \
             other); the figures and `design` refuse it",
            bridges.len()
        );
    }
    super::write_output(
        a.output.as_ref(),
        &(body.to_shape().to_json()? + "\n"),
        &crate::output::Inputs::none(),
    )
}

/// `shape --from-mesh`: the fit, its report on standard error (or JSON to --report), the shape
/// file to -o. Every output is checked before the mesh is read.
fn from_mesh(a: &ShapeArgs, mesh: &Path) -> Result<()> {
    use crate::geometry::mesh_fit::{FitOptions, fit_mesh};
    use crate::geometry::mesh_read::MeshSource;
    use crate::output::{self, Inputs};
    let axis = match &a.axis {
        Some(text) => {
            let v = super::parse_list(text, 3, "--axis", "X,Y,Z")?;
            Some(crate::glam::DVec3::new(v[0], v[1], v[2]))
        }
        None => None,
    };
    if axis.is_some() && a.dim == Some(3) {
        bail!("--axis is the axis of a cylinder (--dim 2); a 3D fit needs none");
    }
    let options = FitOptions {
        dim: if axis.is_some() { Some(2) } else { a.dim },
        modes: a.modes,
        axis,
        mm_per_unit: a.mm_per_unit,
        ignore_facets: a.ignore_facets,
        errors: true,
    };
    if let Some(c) = a.coat_mm
        && !(c.is_finite() && c > 0.0)
    {
        bail!(
            "--coat-mm {c} is not allowed (needs a positive thickness in mm, at most half the \
             body's mean radius)"
        );
    }
    let inputs = Inputs::of([mesh]);
    let shape_out = a.output.clone().unwrap_or_else(|| PathBuf::from("-"));
    if let Some(report) = &a.report {
        output::check_distinct(&[("-o", &shape_out), ("--report", report)])?;
        output::check_file(report, &inputs)?;
    }
    output::check_file(&shape_out, &inputs)?;
    let source = MeshSource::open(mesh)?;
    let bar = if source.triangles() >= 1_000_000
        && std::io::IsTerminal::is_terminal(&std::io::stderr())
    {
        indicatif::ProgressBar::new(source.triangles() as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} triangles {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let progress = |what: &str, done: usize, _total: usize| {
        bar.set_message(what.to_string());
        bar.set_position(done as u64);
    };
    let mut fit = fit_mesh(&source, &options, &progress)?;
    if let Some(c) = a.coat_mm {
        fit = crate::geometry::mesh_fit::coat(&fit, c, &progress)?.0;
    }
    bar.finish_and_clear();
    let r = &fit.report;
    for w in &r.warnings {
        eprintln!("warning: {w}");
    }
    eprintln!("{}", report_text(r));
    let mut outputs = output::OutputSet::new();
    outputs.write(
        &shape_out,
        (fit.shape.to_json()? + "\n").as_bytes(),
        &inputs,
    )?;
    if let Some(path) = &a.report {
        let text = serde_json::to_string_pretty(r)? + "\n";
        outputs.write(path, text.as_bytes(), &inputs)?;
    }
    outputs.commit()?;
    Ok(())
}

/// `value` with `digits` decimals and its standard error where there is one, in `unit`.
fn with_error(value: f64, error: Option<f64>, digits: usize, unit: &str) -> String {
    match error {
        Some(e) => format!("{value:.digits$} ± {e:.1e} {unit}"),
        None => format!("{value:.digits$} {unit}"),
    }
}

/// The fit's report for people.
fn report_text(r: &crate::geometry::mesh_fit::FitReport) -> String {
    let mut out = format!(
        "{} ({}, {} triangles): a {} body, ⟨r⟩ = {}\n",
        r.file,
        r.format,
        r.triangles,
        if r.dimension == 2 {
            "2D (cylinder)"
        } else {
            "3D"
        },
        with_error(r.scale_mm, r.scale_mm_error, 4, "mm")
    );
    if let (Some(axis), Some([e1, _])) = (r.axis, r.section_axes) {
        out += &format!(
            "  axis ({:.4}, {:.4}, {:.4}); θ = 0 along ({:.4}, {:.4}, {:.4})\n",
            axis[0], axis[1], axis[2], e1[0], e1[1], e1[2]
        );
    }
    out += &format!(
        "  {} {} ({}): rms residual {:.4} mm ({:.3} % of ⟨r⟩), max {:.4} mm ({:.3} %) at {}\n",
        if r.dimension == 2 {
            "modes up to M ="
        } else {
            "degree L ="
        },
        r.modes,
        r.modes_rule,
        r.rms_residual_mm,
        100.0 * r.rms_residual,
        r.max_residual_mm,
        100.0 * r.max_residual,
        r.max_residual_at
    );
    out += &format!(
        "  l = 1 part left out: {:.3} % of ⟨r⟩ ({:.4} mm, the centroid's offset from the fit's centre)\n",
        100.0 * r.l1_part,
        r.l1_offset_mm
    );
    out += &format!(
        "  {}, α* = {}",
        if r.convex {
            "strictly convex"
        } else {
            "not convex"
        },
        with_error(r.alpha_star, r.alpha_star_error, 6, "rad")
    );
    if let Some(hull) = &r.mesh_hull {
        out += &format!(
            " (the fit); the mesh's own hull: {} flat sides, α* = {:.6} rad",
            hull.sides, hull.alpha_star
        );
    }
    if let Some(hull) = &r.solid_hull {
        out += &format!(
            " (the fit); the mesh's own hull: {} triangles, α* = {:.6} rad",
            hull.triangles, hull.alpha_star
        );
    }
    out += &match (r.error_blocks, r.alpha_star_error, r.alpha_star_bias) {
        (Some(blocks), Some(_), Some(bias)) => format!(
            "\n  ± one standard error, from the mesh's scatter about the fit ({blocks} blocks of \
             nearby triangles; facets are not scatter, and the hull above is what they do); the \
             scatter raises a fit's α* by {bias:.1e} rad on average, so the surface's is nearer \
             {:.6} rad",
            (r.alpha_star - bias).max(0.0)
        ),
        (Some(blocks), _, _) if r.coat.is_some() => format!(
            "\n  ⟨r⟩ ± one standard error, from the mesh's scatter about the fit ({blocks} blocks \
             of nearby triangles); α*'s error is not carried through the coat"
        ),
        (Some(blocks), _, _) => format!(
            "\n  ⟨r⟩ ± one standard error, from the mesh's scatter about the fit ({blocks} blocks \
             of nearby triangles); α* has none: the scatter raises a fit's α* by over half its \
             spread, so the slope's maximum is not resolved (several near-equal maxima, or a \
             body near round)"
        ),
        _ => "\n  no errors stated: the mesh makes fewer than 3 blocks of nearby triangles per \
              coefficient fitted (a mesh too coarse for its scatter to be told from its facets, \
              or a degree too high for it: a lower --modes may give them)"
            .to_string(),
    };
    if let Some(c) = &r.coat {
        out += &format!(
            "\n  coated with {} mm: ⟨r⟩ {:.4} → {:.4} mm ({:+.2} %), α* {:.6} → {:.6} rad ({:+.2} %); \
             the residuals above are the coated surface's against its degree-{} fit",
            c.coat_mm,
            c.scale_mm_before,
            c.scale_mm_after,
            100.0 * (c.scale_mm_after / c.scale_mm_before - 1.0),
            c.alpha_star_before,
            c.alpha_star_after,
            100.0 * (c.alpha_star_after / c.alpha_star_before - 1.0),
            r.modes
        );
    }
    out
}
