//! rollphase: irregular cylinders and spheres rolling down a ramp, after Qian, Jung & Mahadevan,
//! *Phase transitions in rolling of irregular cylinders and spheres*.
//!
//! Data flows one way: shape → model → integrator → trajectory → analysis / frame → pixels.
//!
//! | module | owns |
//! |---|---|
//! | [`assets`] | the bundled shapes, preset scenes and font, each included once |
//! | [`colormap`] | the colour maps shared by charts, views and the overlay |
//! | [`geometry`] | bodies r(θ), r(u): exact derivatives, curvature, support points, shape files, generators (ours, and the paper authors' numpy bodies bit for bit) |
//! | [`numeric`] | quadrature, golden-section search, root finding, marching squares, eigenvalues (nalgebra) |
//! | [`dynamics`] | the four rolling models (2D/3D, viscous/inertial) as ODE systems |
//! | [`integrate`] | RK4, DOP853 with dense output, the Lie-group CF4 step, event location |
//! | [`analysis`] | critical angle α*, 2D periods, accuracy tables, orbits through ∂Ω, return maps and their Floquet multipliers |
//! | [`simulate`] | one run from a body, a ramp and an initial state to sampled rows + a summary |
//! | [`scene`] | scenes (TOML) and the bundled presets |
//! | [`live`] | one scene's live run advanced frame by frame, observed as plain snapshots; the app's controller and thread; the plots' history; the Poincaré-field cache |
//! | [`view`] | snapshots to draw data: layout, cameras, colours, overlay |
//! | [`render`] | the wgpu renderer (plain draw data in, pixels out) and headless GPU set-up |
//! | [`headless`] | offscreen frames to PNG through the same renderer |
//! | [`ui`] | the app's egui panels, plots and painter, and the windowless app core |
//! | [`app`] | the winit window around the app core (the only module that knows winit) |
//! | [`output`] | the one output layer: every file rollphase writes is staged and moved into place, devices written through, inputs refused |
//! | [`png`] | PNG frames out on writer threads (headless frames, the app's recording) |
//! | [`chart`] | PNG charts for the command line (not used by the core) |
//! | [`figures`] | the paper's figures (and `sphere-bifurcation`) as data.csv, figure.png, summary.json |
//! | [`cli`] | the command line (one file per subcommand) |
//!
//! `geometry`, `numeric`, `dynamics`, `integrate`, `analysis` and `simulate` are the crate `rollphase-core`
//! (crates/core), re-exported: they never touch a GPU, a window or the wall clock, and the
//! compiler keeps it so. The same inputs give the same numbers on every run.

// The physics core lives in crates/core (package rollphase-core); its modules are re-exported
// here so `rollphase::geometry::…` and `crate::geometry::…` keep working.
pub use rollphase_core::{analysis, dynamics, geometry, glam, integrate, numeric, simulate};

pub mod cli;
pub use rollphase_output::output;
// The layers below the command line are crates of their own (crates/assets, crates/scene,
// crates/figures, crates/viewer), so Cargo keeps each from naming what sits above it;
// re-exported here so `crate::scene::…` and `rollphase::render::…` read as before.
pub use rollphase_assets::{assets, colormap};
pub use rollphase_figures::{chart, figures, fit_lag};
pub use rollphase_scene::{live, scene};
#[cfg(feature = "app")]
pub use rollphase_viewer::{app, ui};
pub use rollphase_viewer::{clip, png};
#[cfg(feature = "render")]
pub use rollphase_viewer::{headless, render, view};
