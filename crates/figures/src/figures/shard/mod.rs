//! Splitting an ensemble across processes (`--shard I/N`) and putting it back together
//! (`rollphase merge OUT/NAME`), for a cluster scheduler's array jobs (docs/guide/cluster.md).
//!
//! Every ensemble figure computes its runs through [`FigureOptions::ensemble`]: a list of `n`
//! jobs whose inputs derive from the index and the options alone. How that call behaves depends
//! on [`Ensemble`]:
//! - `Whole`: all jobs in parallel, results in index order (an ordinary run);
//! - `Shard`: only the jobs of shard I of N (a contiguous index range), written to
//!   `OUT/NAME/shard-I-of-N.json`; the call returns [`Ensembled::Shard`] and the figure stops
//!   there, before any reduction or plot;
//! - `Merge`: the jobs' results are read back from the shard files instead of computed, and
//!   the figure continues exactly as an unsharded run would.
//!
//! A shard file records the results of its jobs as numbers in Rust's shortest round-trip form
//! (`{:e}`: NaN, ±inf and −0 included), so the merged results are bit-identical to computed
//! ones and the reduction writes byte-identical `data.csv` and `summary.json`. It also records
//! the options the figure ran with, so `merge` needs nothing but the folder, and refuses shards
//! that ran with other options or another split.
//!
//! Only the figure's first ensemble is sharded (the bulk of its work: the runs); what a figure
//! computes from the merged runs (e.g. `sphere-bifurcation`'s orbit continuation) runs in
//! `merge`. Each figure's module doc says which.
//!
//! A shard also records the SHA-256 of every body file its runs read (`--shape`, a sweep's
//! `bodies.files`), so shards run on different bodies behind one file name never merge, and
//! `merge` refuses a body file whose contents changed since the shards ran (the merge reads it
//! again for the summary: α*, labels), naming the file.
//!
//! A shard run is a normal outcome, not an error: `compute` takes its ensemble's results
//! through `all_runs!`, which returns [`Ensembled::Shard`] as `Computed::Shard` from the
//! figure, and the command line reports the shard written and what to do next.
//!
//! | file | owns |
//! |---|---|
//! | `mod.rs` | the split (`ShardSpec`), what a run is (`Ensemble`, `JobId`) and what it gave (`Ensembled`, `ShardWritten`) |
//! | `file.rs` | the shard file: its format and digest, writing one, scanning a folder's shards and merging them (`ShardSet`, `Merged`) |
//! | `ensemble.rs` | the ensemble runner (`FigureOptions::ensemble`, `run_ensemble`) and a figure's merge (`merge_figure`) |
//! | `record.rs` | a job's result as numbers (`Record`, `Fields`), with the range checks a reduction relies on |

mod ensemble;
mod file;
mod record;

pub use ensemble::{MergeOutcome, merge_figure, run_ensemble};
pub use file::{
    MAX_SHARD_BYTES, Merged, ShardFile, ShardSet, decode_line, encode_line, merged, read_shards,
    scan_shards, write_shard,
};
pub use record::{Fields, MAX_FATE_MULTIPLICITY, Record};

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::BodyChoice;

/// Most shards one ensemble may be split into.
pub const MAX_SHARDS: usize = 100_000;

/// Shard I of N (1-based), as `--shard I/N` writes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShardSpec {
    /// I, 1 ≤ I ≤ N.
    pub index: usize,
    /// N.
    pub count: usize,
}

impl std::str::FromStr for ShardSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let usage = format!(
            "{s:?} is not a shard: write I/N with 1 ≤ I ≤ N ≤ {MAX_SHARDS}, e.g. 3/8 for the third of eight"
        );
        let (i, n) = s.split_once('/').ok_or_else(|| usage.clone())?;
        let (Ok(index), Ok(count)) = (i.trim().parse::<usize>(), n.trim().parse::<usize>()) else {
            return Err(usage);
        };
        if index == 0 || count == 0 || index > count || count > MAX_SHARDS {
            return Err(usage);
        }
        Ok(ShardSpec { index, count })
    }
}

impl std::fmt::Display for ShardSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl ShardSpec {
    /// The job indices of this shard among `n`: contiguous, sizes differing by at most one, and
    /// together covering 0..n once.
    pub fn range(&self, n: usize) -> std::ops::Range<usize> {
        let cut = |i: usize| (n as u128 * i as u128 / self.count as u128) as usize;
        cut(self.index - 1)..cut(self.index)
    }

    /// The shard's file name: `shard-I-of-N.json`.
    pub fn file_name(&self) -> String {
        format!("shard-{}-of-{}.json", self.index, self.count)
    }
}

/// How a figure's ensemble runs (see the module doc).
#[derive(Debug, Clone, Default)]
pub enum Ensemble {
    /// All jobs here.
    #[default]
    Whole,
    /// Only this shard's jobs; write them and stop.
    Shard(ShardSpec),
    /// Every job's result, read back from the shard files (records in index order).
    Merge(Arc<Merged>),
}

/// What a sharded run wrote: the outcome of a `--shard I/N` run ([`Ensembled::Shard`]).
#[derive(Debug, Clone)]
pub struct ShardWritten {
    /// The shard.
    pub shard: ShardSpec,
    /// Jobs in this shard.
    pub jobs: usize,
    /// Jobs in the whole ensemble.
    pub of_jobs: usize,
    /// The file written.
    pub path: PathBuf,
}

impl std::fmt::Display for ShardWritten {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "shard {} wrote {} of {} runs to {}",
            self.shard,
            self.jobs,
            self.of_jobs,
            self.path.display()
        )
    }
}

/// What an ensemble gave.
#[derive(Debug)]
pub enum Ensembled<T> {
    /// Every job's result, in index order: a whole run, or read back from merged shards.
    All(Vec<T>),
    /// A `--shard I/N` run: only this shard's jobs ran, and their results are in the file
    /// written; the figure stops here (no plot) and says what to do next.
    Shard(ShardWritten),
}

impl<T> Ensembled<T> {
    /// The results of a whole or merged run. A shard's results are in its file, not here:
    /// asking for them is a caller's mistake, reported as an error.
    pub fn all(self) -> Result<Vec<T>> {
        match self {
            Ensembled::All(v) => Ok(v),
            Ensembled::Shard(w) => bail!("internal error: {w}, where all the results were needed"),
        }
    }
}

impl ShardWritten {
    /// What to do next, for the user: the merge command for `dir`.
    pub fn next_step(&self, dir: &Path) -> String {
        let when = if self.shard.count == 1 {
            "now".to_string()
        } else {
            format!("when all {} shards are done", self.shard.count)
        };
        format!("{when}: rollphase merge {}", dir.display())
    }
}

/// Most bytes of a body file that [`body_digest`] reads: far above any shape file (a few kB),
/// so a device or a huge file named as a body cannot stall a shard run.
const MAX_BODY_FILE_BYTES: u64 = 64 << 20;

/// The SHA-256 of a body file's bytes, in hex: shards record it ([`JobId`]), and `merge`
/// compares it with the file's contents then.
pub fn body_digest(path: &Path) -> Result<String> {
    use sha2::{Digest, Sha256};
    use std::io::Read;
    let file =
        std::fs::File::open(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut bytes = Vec::new();
    file.take(MAX_BODY_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .with_context(|| format!("cannot read {}", path.display()))?;
    if bytes.len() as u64 > MAX_BODY_FILE_BYTES {
        bail!(
            "{} is over {} MiB; a body file is a few kB",
            path.display(),
            MAX_BODY_FILE_BYTES >> 20
        );
    }
    Ok(format!("{:x}", Sha256::digest(&bytes)))
}

/// Refuses a merge whose body file changed since its shards ran: `file` now digests to
/// something other than `recorded`.
pub fn check_body_unchanged(file: &Path, recorded: Option<&str>) -> Result<()> {
    let now = body_digest(file)?;
    match recorded {
        Some(r) if r == now => Ok(()),
        Some(r) => bail!(
            "{} changed since the shards ran on it (SHA-256 {}… then, {}… now); the merge would \
             describe runs of one body with another. Restore the body the shards ran on, or run \
             the shards again",
            file.display(),
            &r[..r.len().min(12)],
            &now[..12]
        ),
        None => bail!(
            "the shards record no digest of {}, so they cannot be checked against it (written \
             by an older rollphase); run the shards again",
            file.display()
        ),
    }
}

/// What ran: a figure with its options, or a sweep with its spec. Shards merge only with
/// shards of the same job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum JobId {
    /// `rollphase figure NAME`.
    Figure {
        /// The figure's name.
        name: String,
        /// `--seed` (the default's value when not given).
        seed: u64,
        /// `--quick`.
        quick: bool,
        /// Where the body came from.
        body: BodyChoice,
        /// `--alpha`.
        alpha: Option<f64>,
        /// The SHA-256 of the `--shape` file ([`body_digest`]); none for other bodies.
        #[serde(default)]
        body_sha256: Option<String>,
    },
    /// `rollphase sweep SPEC.toml`.
    Sweep {
        /// The spec's text, as read.
        spec: String,
        /// The spec's folder, where its body files are.
        base: PathBuf,
        /// The SHA-256 of each of the spec's `bodies.files`, in its order.
        #[serde(default)]
        body_sha256: Vec<String>,
    },
}
