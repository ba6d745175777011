//! `rollphase merge DIR`: put the shards of a figure or a sweep back together.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use crate::figures::shard::{JobId, merge_figure, merged, scan_shards};
use crate::figures::sweep;

/// Combine the shards (shard-I-of-N.json) that `figure NAME --shard I/N` or `sweep --shard I/N`
/// wrote into DIR, and write exactly the files an unsharded run writes: data.csv, summary.json
/// and figure.png for a figure (DIR is OUT/NAME), sweep.csv and summary.json for a sweep.
///
/// The shards must all be there, once each, from the same command and options; merge says
/// which are missing, duplicated or from another run. Work that follows the runs (clustering,
/// fits, a figure's later stages) happens here. See docs/guide/cluster.md.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct MergeArgs {
    /// The folder holding the shard files: OUT/NAME for a figure, --out of a sweep.
    pub dir: PathBuf,
}

/// Runs `merge`.
pub fn run(a: MergeArgs) -> Result<()> {
    let shards = scan_shards(&a.dir)?;
    match shards.job {
        JobId::Figure { .. } => {
            let m = merge_figure(&a.dir, merged(shards)?)?;
            outln!(
                "{}: merged {} runs from {} shards; wrote {}",
                m.name,
                m.jobs,
                m.shards,
                a.dir.display()
            )?;
        }
        JobId::Sweep { .. } => {
            let s = sweep::merge(&a.dir, &shards)?;
            let shards = shards.shards;
            outln!(
                "sweep: merged {} runs from {shards} shards ({} halted, {} periodic, {} left the \
                 model, {} undecided); wrote {}",
                s.runs,
                s.halts,
                s.periodic,
                s.left_model,
                s.undecided,
                a.dir.join("sweep.csv").display()
            )?;
        }
    }
    Ok(())
}
