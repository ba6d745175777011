//! placeholder
use super::FigureOptions;
use anyhow::Result;
/// Placeholder.
pub fn run(_o: &FigureOptions) -> Result<()> {
    anyhow::bail!("not yet")
}
