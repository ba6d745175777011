//! `rollphase bench`: measured speed/accuracy trade-offs, printed as tables and written as CSV
//! and PNG, one file per benchmark: [`accuracy`] (every model × integrator setting against a
//! converged reference), [`stiff`] (the inertial model as m/m0 → 0), [`figures`] (wall time of
//! the ensemble figures), [`mesh`] (fitting bodies to meshes of 10⁴ to 5·10⁶ triangles),
//! [`track`] (a tracked run of 10⁴ to 10⁷ rows, beside the old O(n²) search), [`calibration`]
//! (how often `track`'s stated interval holds a known period),
//! [`render`] (headless frames per second, feature `render`) and [`app`] (the app's frame time
//! painted offscreen, feature `app`).

mod accuracy;
#[cfg(feature = "app")]
mod app;
mod calibration;
mod figures;
mod mesh;
#[cfg(feature = "render")]
mod render;
mod speed;
mod stiff;
mod track;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Args, Subcommand};

pub use accuracy::{AccuracyArgs, cheapest_below};
pub use stiff::StiffArgs;

use crate::geometry::{Body, ShapeFile};

/// Measure the speed/accuracy trade of the integrators.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Which benchmark.
    #[command(subcommand)]
    pub which: BenchKind,
}

/// The benchmarks.
#[derive(Debug, Subcommand)]
pub enum BenchKind {
    /// Every model × integrator setting against a converged reference at t = 100.
    Accuracy(AccuracyArgs),
    /// The inertial models as m/m0 → 0: cost (stiffness) and distance from the viscous model.
    Stiff(StiffArgs),
    /// Wall time of every figure at full size, beside a recorded baseline and the targets
    /// (sphere-cruising ≤ 25 s, all figures ≤ 60 s on 2 cores).
    Figures(FiguresBenchArgs),
    /// Fixed and per-step costs of the physics core on the paper's 3D body (body check, α*
    /// search, RHS evaluations per second, whole `simulate` and `inspect` processes) beside a
    /// recorded baseline and the targets.
    Speed(SpeedBenchArgs),
    /// Time to fit a body to a mesh (`shape --from-mesh`): the printed sphere's STL and the
    /// paper's sphere written as STL from 20,480 to 5,242,880 triangles.
    Mesh(MeshBenchArgs),
    /// How often `track`'s stated 95 % intervals hold a synthetic track's known period, advance
    /// per period and speed, and their bias, beside the period estimate it replaced (periods of
    /// 6.3 to 300 frames, noise 2 % and 20 %); then `fit-lag`'s exponent on synthetic runs.
    Calibration(CalibrationBenchArgs),
    /// Time `track` takes on tracks of 10⁴ to 10^k rows (reading, the period search with its
    /// checks, the whole process), beside the search it used before on the smaller ones.
    Track(TrackBenchArgs),
    /// Frames per second of the headless renderer (rendering alone, with readback, with PNG
    /// writing on worker threads) at 1280×720 on whatever adapter is found (a GPU, or llvmpipe
    /// without one).
    Render(RenderBenchArgs),
    /// Frame time of the app (UI, 3D view, plots) painted offscreen while the simulation thread
    /// runs at the "precise" setting, and the playback speed the simulation delivers.
    App(AppBenchArgs),
}

/// Options of `bench app`.
#[derive(Debug, Args)]
pub struct AppBenchArgs {
    /// Preset to run.
    #[arg(long, default_value = "sphere-two-orbits")]
    pub preset: String,
    /// Window size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1600x900", value_parser = super::render::parse_size)]
    pub size: (u32, u32),
    /// Wall seconds timed per setting (after 1 s of warm-up, and 12 s more for the automatic
    /// scale to probe and settle: `--seconds 8` takes about 29 s with both settings).
    #[arg(long, default_value_t = 8.0)]
    pub seconds: f64,
    /// Requested playback speed, simulation time per second [default: the preset's].
    #[arg(long)]
    pub speed: Option<f64>,
    /// MSAA samples of the 3D view (the window uses 4 on a GPU, 1 on a CPU renderer).
    #[arg(long, default_value_t = 1, value_parser = super::render::parse_msaa)]
    pub msaa: u32,
    /// Hide the plots panel (to see what the plots cost).
    #[arg(long)]
    pub no_plots: bool,
    /// How finely the 3D view is drawn: `auto` (on a CPU renderer, as the 30 frames/s budget
    /// allows, never below half) or a share from 0.5 to 1 (1: full resolution). Not given: full
    /// resolution and `auto` are timed in alternate blocks, side by side.
    #[arg(long, value_name = "auto|0.5..1", allow_negative_numbers = true)]
    pub render_scale: Option<String>,
    /// Sculpting strokes timed after the frames (0 to 1000): clicks on the body, a dent then a
    /// bump in turn, each from the click to the restarted run's first frame, with the steps
    /// between (pick, stroke, readout, the scene's setup, the new run); then one drag up from the
    /// body in as many moves (20 at most, to the edge of convexity at most), each from the move
    /// to the restarted run's first frame.
    #[arg(long, default_value_t = 10)]
    pub strokes: usize,
}

/// Options of `bench render`.
#[derive(Debug, Args)]
pub struct RenderBenchArgs {
    /// Preset to render.
    #[arg(long, default_value = "sphere-cruising")]
    pub preset: String,
    /// Frame size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = super::render::parse_size)]
    pub size: (u32, u32),
    /// Frames timed per row (after 5 warm-up frames).
    #[arg(long, default_value_t = 60)]
    pub frames: u64,
}

/// Options of `bench mesh`.
#[derive(Debug, Args)]
pub struct MeshBenchArgs {
    /// The finest mesh: icosphere level 5 to 9 (20·4^level triangles; 9 is a 262 MB STL).
    #[arg(long, default_value_t = 8)]
    pub largest: u32,
    /// Fits this one mesh and prints its time and this process's peak memory as a JSON line:
    /// how `bench mesh` measures each row in a process of its own.
    #[arg(long, hide = true)]
    pub fit_one: Option<std::path::PathBuf>,
}

/// Options of `bench calibration`.
#[derive(Debug, Args)]
pub struct CalibrationBenchArgs {
    /// Synthetic tracks per case, 10 to 100000 (200 gives each coverage to ±1.5 %).
    #[arg(long, default_value_t = 200)]
    pub draws: usize,
    /// The first track's seed (the next ones count up).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Synthetic lag-time data sets per true exponent for `fit-lag`'s table, 10 to 10000, or 0
    /// to skip it (each is a whole `fit-lag`, a few seconds).
    #[arg(long, default_value_t = 100)]
    pub lag_draws: usize,
    /// Bootstrap resamples of each of those fits (`fit-lag --bootstrap`).
    #[arg(long, default_value_t = 100)]
    pub lag_bootstrap: usize,
    /// Noisy meshes per case for the mesh fit's table, 10 to 10000, or 0 to skip it (a mesh of
    /// 81,920 triangles takes about a second to fit).
    #[arg(long, default_value_t = 200)]
    pub mesh_draws: usize,
}

/// Options of `bench track`.
#[derive(Debug, Args)]
pub struct TrackBenchArgs {
    /// The longest track: 10^k rows, 4 ≤ k ≤ 7.
    #[arg(long, default_value_t = 6)]
    pub largest: u32,
    /// Time the old O(n²) search on tracks of at most this many rows.
    #[arg(long, default_value_t = 20_000)]
    pub old_up_to: usize,
}

/// Options of `bench speed`.
#[derive(Debug, Args)]
pub struct SpeedBenchArgs {
    /// Child processes timed per process row (the median is reported), 1 to 1000.
    #[arg(long, default_value_t = 21, value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub runs: u64,
}

/// Options of `bench figures`.
#[derive(Debug, Args)]
pub struct FiguresBenchArgs {
    /// Output folder for the figures produced while timing.
    #[arg(long, default_value = "bench-figures")]
    pub out: PathBuf,
    /// Time each figure's reduced --quick run instead (for tests; no targets apply).
    #[arg(long)]
    pub quick: bool,
}

/// Runs `bench`.
pub fn run(a: BenchArgs) -> Result<()> {
    match a.which {
        BenchKind::Accuracy(a) => accuracy::run(a),
        BenchKind::Stiff(a) => stiff::run(a),
        BenchKind::Figures(a) => figures::run(a),
        BenchKind::Speed(a) => speed::run(a),
        BenchKind::Mesh(a) => mesh::run(a),
        BenchKind::Track(a) => track::run(a),
        BenchKind::Calibration(a) => calibration::run(a),
        #[cfg(feature = "render")]
        BenchKind::Render(a) => render::run(a),
        #[cfg(not(feature = "render"))]
        BenchKind::Render(_) => Err(super::missing_feature("render", "bench render")),
        #[cfg(feature = "app")]
        BenchKind::App(a) => app::run(a),
        #[cfg(not(feature = "app"))]
        BenchKind::App(_) => Err(super::missing_feature("app", "bench app")),
    }
}

pub(crate) fn bundled(text: &str) -> Result<Body> {
    let file = ShapeFile::from_json(text).context("bundled shape file")?;
    Ok(Body::from_shape(&file)?)
}

pub(crate) fn fmt_num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        String::new()
    }
}

/// Writes a benchmark's table through the output layer.
pub(crate) fn write(path: &Path, text: &str) -> Result<()> {
    Ok(crate::output::write_bytes(
        path,
        text.as_bytes(),
        &crate::output::Inputs::none(),
    )?)
}
