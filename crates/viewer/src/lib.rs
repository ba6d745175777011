//! rollphase-viewer: what draws a scene. [`view`] turns a live run's snapshot into draw data,
//! [`render`] draws it with wgpu, [`headless`] writes frames and clips ([`png`], [`clip`]) with no
//! window; with the `app` feature, [`ui`] is the egui workbench and [`app`] the winit window
//! around it. It sits over the scenes and the live run (`rollphase-scene`), the physics core,
//! the output layer and the assets, and Cargo keeps it there: it cannot name the figures or the
//! command line. The root crate re-exports every module (`rollphase::render`, …).
//!
//! The modules it builds on are re-exported here under the names the root crate gives them, so
//! the code reads `crate::scene`, `crate::geometry`, `crate::output` in every crate alike.

pub use rollphase_assets::{assets, colormap};
pub use rollphase_core::{analysis, dynamics, geometry, glam, integrate, numeric, simulate};
pub use rollphase_output::output;
pub use rollphase_scene::{live, scene};

#[cfg(feature = "app")]
pub mod app;
pub mod clip;
#[cfg(feature = "render")]
pub mod headless;
pub mod png;
#[cfg(feature = "render")]
pub mod render;
#[cfg(feature = "app")]
pub mod ui;
#[cfg(feature = "render")]
pub mod view;
