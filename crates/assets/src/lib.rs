//! rollphase-assets: the files bundled into the program ([`assets`]: shapes, preset scenes,
//! the font) and the colour maps ([`colormap`]). The bottom of the app's crates; it depends on
//! nothing, and `rollphase::assets` and `rollphase::colormap` re-export it.

pub mod assets;
pub mod colormap;
