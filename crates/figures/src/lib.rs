//! rollphase-figures: the paper's figures ([`figures`]: each computed, then written as CSV, PNG
//! and JSON; their ensembles sharded and merged; the general scan behind `rollphase sweep`),
//! `rollphase fit-lag` ([`fit_lag`]: measured lag times fitted, not a figure of the model) and
//! the PNG charts they draw with ([`chart`]). It sits over the physics core, the output layer
//! and the assets, and Cargo keeps it there: it cannot name scenes, the live run, the renderer,
//! the UI or the command line. `rollphase::figures` and `rollphase::chart` re-export it.
//!
//! The modules it builds on are re-exported here under the names the root crate gives them, so
//! the code reads `crate::geometry`, `crate::output`, `crate::colormap` in every crate alike.

pub use rollphase_assets::{assets, colormap};
pub use rollphase_core::{analysis, dynamics, geometry, glam, integrate, numeric, simulate};
pub use rollphase_output::output;

pub mod chart;
pub mod figures;
pub mod fit_lag;
