//! rollphase-scene: scenes ([`scene`]: the TOML document, validated into a `SceneSetup`, and a
//! lesson's timeline) and the live run ([`live`]: one scene advanced frame by frame, its plots'
//! history, the app's controller and simulation thread). It sits over the physics core, the
//! output layer and the assets, and Cargo keeps it there: it cannot name the renderer, the UI,
//! the figures or the command line. `rollphase::scene` and `rollphase::live` re-export it.
//!
//! The modules it builds on are re-exported here under the names the root crate gives them, so
//! the code reads `crate::geometry`, `crate::output`, `crate::assets` in every crate alike.

pub use rollphase_assets::assets;
pub use rollphase_core::{analysis, dynamics, geometry, glam, integrate, numeric, simulate};
pub use rollphase_output::output;

pub mod live;
pub mod scene;
