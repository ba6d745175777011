//! `rollphase design`: a printable body with a chosen critical angle, window of hysteresis,
//! period doubling, drift or number of orbits, checked over the band a bench brings before it
//! is reported (`analysis::design`).

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::analysis::design;
use crate::analysis::design::{
    Band, DEFAULT_SCALE_MM, Design, DesignOptions, DesignProgress, DesignSpace, Ended,
    RampPrediction, Spelling, Target, TargetRequest, design_until, evaluate,
};
use crate::geometry::Body;
use crate::output::{self, Inputs};

/// Design a body that does what your experiment needs, and check that it still does on a bench.
///
/// Searches the model's bodies (harmonic coefficients up to --modes L, the paper's
/// normalisation) with CMA-ES for one that meets every target given:
///   --alpha-star A      α* = A rad within 1e-4 (2D or 3D): it rests on every ramp below A
///                       and rolls from any start above it
///   --hysteresis M:F    2D: at m/m0 = M a rolling cylinder keeps rolling as the ramp is
///                       lowered down to F·α* (0 < F < 1), a window you can see by hand
///   --doubling M --alpha A
///                       3D: at m/m0 = M on a ramp at A rad the attractor is period 2: every
///                       period-1 orbit the runs from rest settle on at 0.4 M has flipped (its
///                       multiplier passed −1) at M, and runs from rest there repeat after two
///                       crossings
///   --drift D --alpha A [--mass M]
///                       3D: every stable orbit the starts settle on moves D across the ramp
///                       per unit down it within 0.005 (a ball that rolls off at an angle,
///                       whichever orbit it takes), and within 0.02 over the band
///   --orbits K --alpha A [--mass M] [--share S]
///                       3D: exactly K stable orbits, each reached from at least a share S
///                       of the starts from rest (default 1/(2K)), and no start ending
///                       anywhere else (another orbit, off the ramp, undecided)
/// and the printer's constraints: strictly convex, no radius of curvature under
/// --min-radius-mm at --scale-mm millimetres per ⟨r⟩, no amplitude over --max-amplitude.
///
/// The body found is then checked by runs independent of the search, at the precise setting,
/// over a band: the ramp off by ± --alpha-band rad, m/m0 off by ± --mass-band × m/m0, and --draws
/// random print errors of up to ± --surface-mm. The report gives each target's value (fast and
/// precise), its margin over the band (≥ 0 holds), which constraints bind, whether the design
/// holds, and what the model predicts the body does on each target's ramp at the printed scale:
/// each orbit's share of the starts (with its 95 % interval), period in s (with inertia, where
/// t0 = √(⟨r⟩/(g·m/m0)); viscous times stay in t0, which depends on the liquid), advance in mm
/// and heading. A design that does not hold is still written (the best body found), and the
/// command exits with status 1 saying why.
///
/// The same --seed gives the same body on any number of threads; --budget stops the search after
/// that many seconds with the best body so far (then checked like any other).
///
/// A cylinder that rests at 10° and rolls at 11° (α* = 10.5° ± 0.5°). At 10 mm per ⟨r⟩
/// ± 0.05 mm of print moves α* by 1.2° and the design does not hold; at 40 mm it does:
///   rollphase design --dim 2 --alpha-star 0.18326 --alpha-band 0.0087 --scale-mm 40 -o cylinder.json --stl cylinder.stl
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct DesignArgs {
    /// 2 for a cylinder (its section), 3 for a sphere.
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=3))]
    pub dim: u32,
    /// Target: the critical angle α* in radians (0 < A < 1.5).
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub alpha_star: Option<f64>,
    /// Target (2D): at m/m0 = M, keeps rolling as α is lowered to F·α* (M > 0, 0 < F < 1).
    #[arg(long, value_name = "M:F")]
    pub hysteresis: Option<String>,
    /// Target (3D): at m/m0 = M and --alpha, the attractor is period 2 (every period-1 orbit
    /// has flipped).
    #[arg(
        long,
        value_name = "M",
        allow_negative_numbers = true,
        requires = "alpha"
    )]
    pub doubling: Option<f64>,
    /// Target (3D): at --alpha and --mass, every stable orbit the starts settle on moves D across
    /// the ramp per unit down it (+: to the lab's y).
    #[arg(
        long,
        value_name = "D",
        allow_negative_numbers = true,
        requires = "alpha"
    )]
    pub drift: Option<f64>,
    /// Target (3D): at --alpha and --mass, exactly K stable orbits, each reached from at least
    /// --share of the starts.
    #[arg(long, value_name = "K", requires = "alpha")]
    pub orbits: Option<usize>,
    /// The least share of the starts each of --orbits K must be reached from (default 1/(2K)).
    #[arg(
        long,
        value_name = "S",
        allow_negative_numbers = true,
        requires = "orbits"
    )]
    pub share: Option<f64>,
    /// m/m0 of a --drift or --orbits target (default 0: the viscous model).
    #[arg(long, allow_negative_numbers = true)]
    pub mass: Option<f64>,
    /// The ramp angle (rad) of a 3D target (sin α = 0.2 is α = 0.2014).
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// Highest degree L of the modes searched (2 to 8). --check-only searches nothing and
    /// checks the body at its own degree, whatever this says.
    #[arg(long, default_value_t = design::DEFAULT_MODES)]
    pub modes: u32,
    /// Millimetres per ⟨r⟩ of the printed body (the authors' prints: 10). Default: the --from
    /// body's own scale_mm where its file has one, else 10.
    #[arg(long, allow_negative_numbers = true)]
    pub scale_mm: Option<f64>,
    /// Smallest radius of curvature the printer can make, in mm (a 0.4 mm nozzle: 0.4).
    #[arg(long, default_value_t = design::DEFAULT_MIN_RADIUS_MM, allow_negative_numbers = true)]
    pub min_radius_mm: f64,
    /// Largest amplitude |a_l| (2D) or |A_lm| (3D) allowed.
    #[arg(long, default_value_t = design::DEFAULT_MAX_AMPLITUDE, allow_negative_numbers = true)]
    pub max_amplitude: f64,
    /// Start from this body (a shape file of the same dimension, degree ≤ --modes) instead of
    /// the first convex random body from --seed: the search then stays near it.
    #[arg(long, value_name = "FILE")]
    pub from: Option<PathBuf>,
    /// Seed of the start and of the search.
    #[arg(long, default_value_t = design::DEFAULT_SEED)]
    pub seed: u64,
    /// Most generations of the search.
    #[arg(long, default_value_t = design::DEFAULT_GENERATIONS)]
    pub generations: usize,
    /// Stop the search after this many seconds, with the best body so far.
    #[arg(
        long,
        value_name = "SECONDS",
        allow_negative_numbers = true,
        conflicts_with = "check_only"
    )]
    pub budget: Option<f64>,
    /// Check band: the ramp's angle off by up to this (rad).
    #[arg(long, default_value_t = design::DEFAULT_BAND.delta_alpha, allow_negative_numbers = true)]
    pub alpha_band: f64,
    /// Check band: m/m0 off by up to this fraction.
    #[arg(long, default_value_t = design::DEFAULT_BAND.mass_fraction, allow_negative_numbers = true)]
    pub mass_band: f64,
    /// Check band: print errors of up to this many mm on the surface.
    #[arg(long, default_value_t = design::DEFAULT_BAND.surface_mm, allow_negative_numbers = true)]
    pub surface_mm: f64,
    /// Check band: how many print errors are drawn.
    #[arg(long, default_value_t = design::DEFAULT_BAND.draws)]
    pub draws: usize,
    /// The designed body's shape file (with scale_mm).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write it as a watertight STL in mm, for the printer.
    #[arg(long, value_name = "FILE")]
    pub stl: Option<PathBuf>,
    /// Print the report as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Search nothing: check the --from body against the targets over the band, as a design
    /// would be checked (what `design` says of a body you already have), at its own degree
    /// (any: a fitted print's 24 modes too). -o gets the body.
    #[arg(long, requires = "from")]
    pub check_only: bool,
}

/// The targets the flags name.
fn targets(a: &DesignArgs) -> Result<Vec<Target>> {
    let mut hysteresis = None;
    if let Some(text) = &a.hysteresis {
        let (m, f) = text.split_once(':').with_context(|| {
            format!("--hysteresis {text:?} is not M:F (m/m0 and the fraction of α*, e.g. 10:0.8)")
        })?;
        let number = |s: &str, what: &str| {
            s.trim()
                .parse::<f64>()
                .with_context(|| format!("--hysteresis {text:?}: {s:?} is not a number ({what})"))
        };
        hysteresis = Some((number(m, "m/m0")?, number(f, "the fraction F of α*")?));
    }
    let request = TargetRequest {
        alpha_star: a.alpha_star,
        hysteresis,
        doubling: a.doubling,
        drift: a.drift,
        orbits: a.orbits,
        share: a.share,
        mass: a.mass,
        alpha: a.alpha,
    };
    Ok(request.targets(&Spelling {
        alpha: "--alpha",
        mass: "--mass",
        share: "--share",
        targets: "--alpha-star A, --hysteresis M:F, --doubling M --alpha A, --drift D --alpha A \
                  or --orbits K --alpha A (see --help)",
    })?)
}

/// Runs `design`.
pub fn run(a: DesignArgs) -> Result<()> {
    let (start, file_scale_mm) = match &a.from {
        Some(f) => {
            let (body, scale) = crate::geometry::ShapeFile::load_scaled(f)?;
            if let crate::geometry::Body::Disk(d) = &body {
                let fit = crate::geometry::Body::Disk(d.smooth_fit()).alpha_star();
                if let Some(gap) = d.printed_section().and_then(|p| p.facets_matter(fit)) {
                    bail!(
                        "--from {} was fitted to a print with {} flat sides that hold it up to \
                         α* = {:.5} rad, where its smooth fit has α* = {fit:.5} rad; `design` \
                         checks and changes the smooth fit, which is not the body printed. \
                         Design from a body of the model, or refit the mesh with \
                         `--ignore-facets` if its facets are only the export's tessellation of \
                         a round body",
                        f.display(),
                        gap.sides,
                        gap.print_alpha_star
                    );
                }
            }
            (Some(body), scale)
        }
        None => (None, None),
    };
    // A body checked or refined is checked at the size it will be printed: its file's scale,
    // unless --scale-mm says otherwise.
    let scale_mm = a.scale_mm.or(file_scale_mm).unwrap_or(DEFAULT_SCALE_MM);
    let options = DesignOptions {
        space: DesignSpace {
            dimension: a.dim,
            modes: a.modes,
        },
        targets: targets(&a)?,
        scale_mm,
        min_radius_mm: a.min_radius_mm,
        max_amplitude: a.max_amplitude,
        start,
        seed: a.seed,
        max_generations: a.generations,
        band: Band {
            delta_alpha: a.alpha_band,
            mass_fraction: a.mass_band,
            surface_mm: a.surface_mm,
            draws: a.draws,
            seed: a.seed,
        },
    };
    let options = if a.check_only {
        options.for_check()?
    } else {
        options.validate()?;
        options
    };
    design::check_budget(a.budget)?;
    let inputs = Inputs::of(a.from.iter());
    output::check_file(&a.output, &inputs)?;
    if let Some(stl) = &a.stl {
        output::check_distinct(&[("-o", &a.output), ("--stl", stl)])?;
        output::check_file(stl, &inputs)?;
    }
    let stop = AtomicBool::new(false);
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        indicatif::ProgressBar::new(a.generations as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "designing {bar:30} generation {pos}/{len} {msg} {elapsed}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let clock = std::time::Instant::now();
    let progress = |p: DesignProgress| {
        bar.set_position(p.generation as u64);
        bar.set_message(format!("best {:.3}", p.best));
    };
    let design = if a.check_only {
        evaluate(&options)?
    } else {
        design::with_budget(&stop, a.budget, || design_until(&options, &stop, &progress))?
    };
    bar.finish_and_clear();
    let seconds = clock.elapsed().as_secs_f64();
    let shape = design
        .body
        .to_shape()
        .with_scale_mm(Some(scale_mm))
        .to_json()?;
    // The body first, on its own: the search's result is never lost to an optional output
    // that fails (an STL onto a full disk), and the report is printed before that is tried.
    output::write_bytes(&a.output, (shape + "\n").as_bytes(), &inputs)?;
    if a.json {
        let report = serde_json::json!({
            "holds": design.holds(),
            "why_not": design.why_not(&|s| format!("--{s}")),
            "seconds": seconds,
            "scale_mm": scale_mm,
            "design": design,
        });
        outln!("{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        print_report(&design, seconds, &a)?;
    }
    if let Some(stl) = &a.stl {
        write_stl(stl, &design, (scale_mm, &a.output), &inputs)?;
    }
    if !design.holds() {
        let what = if a.check_only {
            "the body checked"
        } else {
            "the best body found"
        };
        bail!(
            "the design does not hold: {} ({what} is in {})",
            design.why_not(&|s| format!("--{s}")).join("; "),
            a.output.display()
        );
    }
    Ok(())
}

/// A doubling target's evidence: the window, the runs, the multipliers across m/m0.
fn print_doubling(e: &crate::analysis::design::targets::DoublingEvidence) -> Result<()> {
    let at = |m: Option<f64>| m.map_or("not found".into(), |m| format!("{m:.3}"));
    outln!(
        "  flip window (every orbit's multiplier below −1): m/m0 from {} to {}",
        at(e.onset_mass),
        at(e.end_mass)
    )?;
    let c = &e.runs.cycle_counts;
    outln!(
        "  runs from rest: {} repeat after 1 crossing, {} after 2, {} after 3–4, {} not \
         (at rest {}, undecided {}, left the ramp {})",
        c[0],
        c[1],
        c[2] + c[3],
        c[4],
        e.runs.at_rest,
        e.runs.undecided,
        e.runs.left_model
    )?;
    for (i, b) in e.branches.iter().enumerate() {
        let row: Vec<String> = b
            .iter()
            .step_by(4)
            .map(|s| match s.most_negative_real {
                Some(mu) => format!("{:.2}:{mu:+.3}", s.mass_ratio),
                None => format!("{:.2}:none", s.mass_ratio),
            })
            .collect();
        outln!("  orbit {i} (m/m0:μ_min): {}", row.join(" "))?;
    }
    Ok(())
}

/// What the body does on one ramp, at the printed scale.
fn print_prediction(p: &RampPrediction) -> Result<()> {
    outln!()?;
    let time = match p.t0_s {
        Some(t0) => format!("t0 = {:.2} ms", 1000.0 * t0),
        None => "viscous: times in t0, which the liquid sets (film one period to fix it)".into(),
    };
    outln!("predicted on the ramp of \"{}\":", p.why)?;
    outln!(
        "  α = {:.4} rad ({:.2}°), m/m0 = {}, ⟨r⟩ = {} mm, {time}; {} starts from rest",
        p.alpha,
        p.alpha.to_degrees(),
        p.mass_ratio,
        p.scale_mm,
        p.starts
    )?;
    outln!(
        "  {:<8} {:>6} {:>16} {:>10} {:>10} {:>11} {:>11} {:>9} {:>9}",
        "orbit",
        "repeat",
        "share (95 %)",
        "period t0",
        "period s",
        "down mm",
        "across mm",
        "heading°",
        "mm/s"
    )?;
    for (i, o) in p.orbits.iter().enumerate() {
        let secs =
            |v: Option<f64>, digits: usize| v.map_or("-".into(), |v| format!("{v:.digits$}"));
        outln!(
            "  {:<8} {:>6} {:>16} {:>10.3} {:>10} {:>11.2} {:>11.2} {:>9.2} {:>9}",
            format!("{i}{}", if o.stable { "" } else { " (not stable)" }),
            o.repeat,
            format!(
                "{}/{} ({:.2}–{:.2})",
                o.starts, p.starts, o.share_95[0], o.share_95[1]
            ),
            o.period_t0,
            secs(o.period_s, 4),
            o.advance_down_mm,
            o.advance_across_mm,
            o.heading_deg,
            secs(o.speed_mm_s, 1)
        )?;
    }
    if p.orbits.is_empty() {
        outln!("  no orbit")?;
    }
    if p.halted > 0.0 || p.elsewhere > 0.0 {
        outln!(
            "  at rest: {:.3} of the starts; on no stable orbit: {:.3}",
            p.halted,
            p.elsewhere
        )?;
    }
    Ok(())
}

/// The design as an STL for the printer, after the body and the report: a failed write names
/// where the body is. A sphere's facets are said (`export_stl::printed_facets_note`).
fn write_stl(
    stl: &std::path::Path,
    design: &Design,
    (scale_mm, output_path): (f64, &std::path::Path),
    inputs: &Inputs,
) -> Result<()> {
    // Detail 6, as `export-stl`'s default: fine enough that a printed polygon's flats do not
    // raise α* (0.05°).
    let mesh = crate::geometry::mesh::print_mesh(&design.body, 6, 2.0);
    let mut bytes = Vec::new();
    let name = match &design.body {
        Body::Disk(_) => format!("design {}", crate::geometry::mesh::DISK_AXIS_TAG),
        Body::Sphere(_) => "design".to_string(),
    };
    mesh.write_stl(&mut bytes, scale_mm, &name)?;
    output::write_bytes(stl, &bytes, inputs).with_context(|| {
        format!(
            "the STL was not written (the body is in {}, the report above)",
            output_path.display()
        )
    })?;
    if matches!(design.body, Body::Sphere(_))
        && let Some(note) =
            super::export_stl::printed_facets_note(&mesh, design.body.alpha_star(), 6)
    {
        eprintln!(
            "note: {note}; the check above is the smooth body's (`rollphase export-stl {} -o FILE.stl \
             --detail 8` writes a finer STL)",
            output_path.display()
        );
    }
    Ok(())
}

/// The report for people.
fn print_report(d: &Design, seconds: f64, a: &DesignArgs) -> Result<()> {
    let ended = match d.ended {
        Ended::Met => "targets met",
        Ended::Converged => "the search stopped improving",
        Ended::Generations => "the generations ran out",
        Ended::Stopped => "the budget ran out",
        Ended::CheckedOnly => "a given body checked, no search",
    };
    outln!(
        "design: {}D, L = {}, {} generations ({} bodies), {ended}, {seconds:.1} s",
        a.dim,
        // A check is of the body at its own degree.
        if d.ended == Ended::CheckedOnly {
            DesignSpace::of(&d.body).modes
        } else {
            a.modes
        },
        d.generations,
        d.evaluations
    )?;
    if d.ended != Ended::CheckedOnly {
        outln!("started from {}", d.start)?;
    }
    match d.alpha_star_turned {
        Some(turned) => outln!(
            "α* = {:.6} rad ({:.3}°); turned end for end {:.6} rad ({:.3}°)",
            d.alpha_star,
            d.alpha_star.to_degrees(),
            turned,
            turned.to_degrees()
        )?,
        None => outln!(
            "α* = {:.6} rad ({:.3}°)",
            d.alpha_star,
            d.alpha_star.to_degrees()
        )?,
    }
    outln!()?;
    let w = d
        .achieved
        .iter()
        .map(|t| t.target.describe().chars().count())
        .fold(6, usize::max);
    outln!(
        "{:<w$} {:>12} {:>12} {:>5} {:>12} {:>6}",
        "target",
        "fast",
        "precise",
        "met",
        "margin",
        "holds"
    )?;
    for (t, c) in d.achieved.iter().zip(
        d.check
            .targets
            .iter()
            .map(Some)
            .chain(std::iter::repeat(None)),
    ) {
        outln!(
            "{:<w$} {:>12.6} {:>12.6} {:>5} {:>12} {:>6}",
            t.target.describe(),
            t.fast,
            t.precise,
            if t.met { "yes" } else { "no" },
            c.map_or("-".into(), |c| format!("{:.6}", c.margin)),
            c.map_or("-", |c| if c.holds { "yes" } else { "no" })
        )?;
    }
    let b = &d.check.band;
    outln!(
        "band: α ± {} rad, m/m0 ± {} %, {} print errors of ± {} mm ({} convex), at the precise setting",
        b.delta_alpha,
        100.0 * b.mass_fraction,
        b.draws,
        b.surface_mm,
        d.check.convex_draws
    )?;
    for c in &d.check.targets {
        outln!(
            "  {}: nominal {:.6}, worst over {} variants {:.6}, margin {:.6} {}",
            c.target.describe(),
            c.nominal,
            c.variants,
            c.worst,
            c.margin,
            c.margin_unit
        )?;
        if let Some(e) = &c.evidence {
            print_doubling(e)?;
        }
    }
    for p in &d.predicted {
        print_prediction(p)?;
    }
    outln!()?;
    outln!(
        "{:<40} {:>12} {:>10} {:>8}",
        "constraint",
        "value",
        "bound",
        "binds"
    )?;
    for c in &d.constraints {
        outln!(
            "{:<40} {:>12.4} {:>10} {:>8}",
            c.name,
            c.value,
            c.bound,
            if c.binding { "yes" } else { "no" }
        )?;
    }
    match (d.holds(), d.check.print_failure_bound) {
        (true, Some(p)) => outln!(
            "holds: yes (over the band, and in all {} print errors drawn: a random print within \
             ± {} mm breaks it with probability under {:.1} % at 95 % confidence; more --draws \
             narrow that)",
            d.check.band.draws,
            d.check.band.surface_mm,
            100.0 * p
        )?,
        (holds, _) => outln!("holds: {}", if holds { "yes" } else { "no" })?,
    }
    Ok(())
}
