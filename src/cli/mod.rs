//! The command line: argument structures (clap) and one file per subcommand. Errors are
//! `anyhow` with context naming the file or flag; `main.rs` prints them and sets the exit code.

/// `println!` that returns the error (a closed pipe, a full disk) instead of panicking.
macro_rules! outln {
    () => {
        $crate::output::stdout_line("").map_err(::anyhow::Error::from)
    };
    ($($arg:tt)*) => {
        $crate::output::stdout_line(&format!($($arg)*)).map_err(::anyhow::Error::from)
    };
}

pub mod app;
pub mod bench;
pub mod design;
pub mod drag_law;
pub mod export_stl;
pub mod figure;
pub mod inspect;
pub mod merge;
pub mod period;
pub mod predict;
pub mod render;
pub mod replay;
pub mod scenes;
pub mod shape;
pub mod simulate;
pub mod sweep;
pub mod track;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};

use crate::geometry::{Body, ShapeFile};
use crate::scene::{DEFAULT_PRESET, Scene, SceneSetup, load_scene_file};

/// `--version`: the version and the optional features this binary was built with, so a bug
/// report (and the tests run against a build without them) can tell which commands it has.
const VERSION: &str = if cfg!(feature = "app") {
    concat!(env!("CARGO_PKG_VERSION"), " (features: render, app)")
} else if cfg!(feature = "render") {
    concat!(env!("CARGO_PKG_VERSION"), " (features: render)")
} else {
    concat!(env!("CARGO_PKG_VERSION"), " (no render or app feature)")
};

/// Irregular cylinders and spheres rolling down a ramp: the models, integrators and analyses of
/// Qian, Jung & Mahadevan, "Phase transitions in rolling of irregular cylinders and spheres".
///
/// Units: force F, drag γ and mean radius ⟨r⟩ are 1; time is in γ/(F⟨r⟩); mass is m/m0 with
/// m0 = γ²/(F⟨r⟩³), and m/m0 = 0 means the viscous (overdamped) model. Angles are in radians.
///
/// A typical session:
///   rollphase shape --dim 3 --seed 1 -o body.json
///   rollphase inspect body.json
///   rollphase simulate body.json --alpha 0.3 --t-end 100 -o traj.csv --summary summary.json
///   rollphase --headless --frames 60 --preset sphere-cruising --out frames
///
/// With no subcommand, rollphase opens the interactive window on a scene (--preset NAME or
/// --scene FILE; `rollphase scenes` lists the presets). --headless writes PNG frames instead
/// (no window, no display, no GPU needed).
#[derive(Debug, Parser)]
#[command(
    name = "rollphase",
    version = VERSION,
    verbatim_doc_comment,
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    /// What to do (none: open the window on a scene, or --headless to write PNG frames).
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Rendering flags, used when no subcommand is given.
    #[command(flatten)]
    pub render: render::RenderArgs,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
#[expect(
    missing_docs,
    reason = "a variant's doc comment would replace its struct's long help: `about` says it"
)]
pub enum Command {
    /// Open the interactive window (the same as no subcommand): live α and m/m0, plots, views.
    App(app::AppArgs),
    #[command(about = "Generate a random body (seeded) and write its shape file (JSON)")]
    Shape(shape::ShapeArgs),
    #[command(about = "Report a body's convexity, curvature range and critical angle α*")]
    Inspect(inspect::InspectArgs),
    #[command(
        about = "Period T and mean angular speed 2π/T of a rolling disk (2D), or that it halts"
    )]
    Period(period::PeriodArgs),
    #[command(
        about = "The periodic motions a body settles into: period, advance per period (⟨r⟩ or mm), stability"
    )]
    Predict(predict::PredictArgs),
    #[command(about = "Simulate one run and write the trajectory as CSV")]
    Simulate(simulate::SimulateArgs),
    /// Measure the speed/accuracy trade of the integrators (tables, CSV, plots).
    Bench(bench::BenchArgs),
    #[command(about = "Regenerate one of the paper's figures as CSV + PNG + summary.json")]
    Figure(figure::FigureArgs),
    #[command(
        about = "Scan bodies × α × m/m0 × orientations × integrators in 3D: one CSV row per run (shardable)"
    )]
    Sweep(sweep::SweepArgs),
    #[command(
        about = "Combine the shards of a figure or sweep (--shard I/N) into the files one run writes"
    )]
    Merge(merge::MergeArgs),
    /// Fit measured lag times t_lag ∝ (α − α*)^β (per-run α*, shared β, bootstrap errors).
    FitLag(figure::FitLagArgs),
    #[command(
        about = "Read a tracked video of a rolling body: period, advance per period, folded track, model"
    )]
    Track(track::TrackArgs),
    /// List the preset scenes for --preset (or print one as TOML).
    Scenes(scenes::ScenesArgs),
    /// Run a saved state again from its scene's start and check it reaches the saved state to
    /// the bit.
    Replay(replay::ReplayArgs),
    #[command(about = "Write a body as a watertight STL mesh in millimetres, for 3D printing")]
    ExportStl(export_stl::ExportStlArgs),
    #[command(
        about = "Design a printable body with a chosen α* or hysteresis window, checked over a bench's band"
    )]
    Design(design::DesignArgs),
}

/// The scene named by --scene or --preset (default preset otherwise), validated.
pub fn pick_scene(scene: Option<&Path>, preset: Option<&str>) -> Result<SceneSetup> {
    match (scene, preset) {
        (Some(path), _) => match load_scene_file(path) {
            Ok(s) => Ok(s),
            // The message already names the scene file.
            Err(e @ crate::scene::SceneError::SceneIo { .. }) => Err(e.into()),
            Err(e) => Err(e).with_context(|| format!("bad scene file {}", path.display())),
        },
        (None, name) => {
            let name = name.unwrap_or(DEFAULT_PRESET);
            let scene = Scene::preset(name)?;
            scene
                .setup(None)
                .with_context(|| format!("preset {name} does not validate"))
        }
    }
}

/// Runs the parsed command.
pub fn run(cli: Cli) -> Result<()> {
    let Some(command) = cli.command else {
        if cli.render.headless {
            let w = &cli.render.window;
            if w.screenshot_after.is_some() || w.exit_after.is_some() {
                bail!(
                    "--screenshot-after and --exit-after are for the window; --headless writes every frame \
                     as a PNG already (see --frames and --out)"
                );
            }
            if w.sweep.is_some() || w.speed.is_some() {
                bail!(
                    "--sweep and --speed are for the window; a --headless run takes its speed \
                     from the scene ([playback] speed), and a lesson's [[timeline]] steps \
                     sweep α or m/m0 in a clip"
                );
            }
            if w.render_scale.is_some() {
                bail!(
                    "--render-scale sets how finely the window draws its 3D view; --headless \
                     frames are always drawn in full (use --size for fewer pixels)"
                );
            }
            if w.step.is_some() {
                bail!(
                    "--step opens the window at a lesson's step; a --headless run renders the \
                     lesson from its start (--frames all for the whole lesson)"
                );
            }
            if w.present || w.class {
                bail!(
                    "--present and --class open the window in presentation or class mode; a \
                     --headless run draws lessons' captions in their own band already (use --size \
                     for the projector's resolution)"
                );
            }
            return render::run_headless(&cli.render);
        }
        if cli.render.gif.is_some() || cli.render.mp4.is_some() {
            bail!(
                "--gif and --mp4 write the frames of a --headless run; add --headless (the \
                 window's Record writes PNG frames)"
            );
        }
        return app::run_window(
            cli.render.scene.as_deref(),
            cli.render.preset.as_deref(),
            &cli.render.window,
            cli.render.plot_data.as_deref(),
        );
    };
    match command {
        Command::App(a) => app::run(a),
        Command::Shape(a) => shape::run(a),
        Command::Inspect(a) => inspect::run(a),
        Command::Period(a) => period::run(a),
        Command::Predict(a) => predict::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Figure(a) => figure::run(a),
        Command::FitLag(a) => figure::run_fit_lag(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Merge(a) => merge::run(a),
        Command::Scenes(a) => scenes::run(a),
        Command::Replay(a) => replay::run(a),
        Command::Track(a) => track::run(a),
        Command::ExportStl(a) => export_stl::run(a),
        Command::Design(a) => design::run(a),
    }
}

/// The error for a command that needs a Cargo feature this build was made without.
#[cfg(not(all(feature = "render", feature = "app")))]
pub fn missing_feature(feature: &str, what: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{what} needs the `{feature}` feature, and this rollphase was built without it \
         (--no-default-features); rebuild with `cargo build --features {feature}` or the default features"
    )
}

/// Reads, parses and validates a shape file; errors name the file and, for JSON, line and column.
pub fn load_body(path: &Path) -> Result<Body> {
    Ok(ShapeFile::load(path)?)
}

/// A number in short form, like C's %g: 1e300 rather than 309 digits.
pub fn short(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e6).contains(&v.abs()) {
        let s = format!("{v:.6e}");
        // Trim the mantissa's trailing zeros: 1.000000e300 → 1e300.
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    } else {
        format!("{v}")
    }
}

/// Parses "a,b,c" into exactly `n` finite numbers for flag `flag`.
pub fn parse_list(text: &str, n: usize, flag: &str, names: &str) -> Result<Vec<f64>> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != n {
        bail!(
            "{flag} expects {n} comma-separated numbers {names}, got {:?}",
            text
        );
    }
    parts
        .iter()
        .map(|p| {
            let v: f64 = p
                .parse()
                .with_context(|| format!("{flag}: {p:?} is not a number (expected {names})"))?;
            if !v.is_finite() {
                bail!("{flag}: {p} is not a finite number (expected {names})");
            }
            Ok(v)
        })
        .collect()
}

/// Warns on standard error before a run in the stiff corner that would take minutes: the
/// inertial model at a tiny m/m0, which an explicit integrator must follow on its relaxation
/// time ([`crate::simulate::stiff_work_estimate`]). `span` is the simulated time, `flag` names it.
pub fn warn_if_stiff(
    body: &crate::geometry::Body,
    ramp: &crate::dynamics::Ramp,
    span: f64,
    flag: &str,
) {
    let evals = crate::simulate::stiff_work_estimate(body, ramp, span);
    if crate::simulate::is_stiff_run(body, ramp, span) {
        eprintln!(
            "warning: m/m0 = {} relaxes to the viscous model on τ ≈ {:.1e}, which an explicit \
             integrator must follow: about {:.0e} right-hand-side evaluations over {flag} {} \
             (minutes or more at a few million a second). --mass 0 runs the viscous limit, which \
             differs by O(m/m0); an --rtol above m/m0 chooses it for you",
            short(ramp.mass_ratio),
            crate::simulate::relaxation_time(body, ramp),
            evals,
            short(span)
        );
    }
}

/// Writes text to a file, or to standard output for `None` or "-", through the output layer
/// ([`crate::output`]); `inputs` are the command's input files, which it refuses to overwrite.
pub fn write_output(
    path: Option<&PathBuf>,
    text: &str,
    inputs: &crate::output::Inputs,
) -> Result<()> {
    let path = path.map_or(Path::new("-"), PathBuf::as_path);
    Ok(crate::output::write_bytes(path, text.as_bytes(), inputs)?)
}
