//! `rollphase scenes`: the bundled presets, one line each (`--toml NAME` prints one in full, a
//! starting point for a scene file of your own).

use anyhow::Result;
use clap::Args;

use crate::scene::{DEFAULT_PRESET, PRESETS, Scene};

/// List the preset scenes (`--preset NAME`), or print one as TOML.
#[derive(Debug, Args)]
pub struct ScenesArgs {
    /// Print this preset's TOML instead of the list.
    #[arg(long)]
    pub toml: Option<String>,
}

/// Runs `scenes`.
pub fn run(a: ScenesArgs) -> Result<()> {
    if let Some(name) = a.toml {
        Scene::preset(&name)?;
        if let Some((_, text)) = PRESETS.iter().find(|(n, _)| *n == name) {
            super::output::write_text(None, text, &[], "--toml")?;
        }
        return Ok(());
    }
    let width = PRESETS.iter().map(|(n, _)| n.len()).max().unwrap_or(0);
    for (name, _) in PRESETS {
        let scene = Scene::preset(name)?;
        let mark = if *name == DEFAULT_PRESET {
            " (default)"
        } else {
            ""
        };
        outln!("{name:width$}  {}{mark}", scene.description)?;
    }
    Ok(())
}
