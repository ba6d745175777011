//! The ensemble runner: a figure's (or a sweep's) jobs run whole, as one shard, or read back
//! from merged shards ([`run_ensemble`]), and a figure's merge ([`merge_figure`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Result, anyhow, bail};

use super::file::decode_record;
use super::{Ensemble, Ensembled, JobId, Merged, Record, ShardWritten, write_shard};
use crate::figures::{BodyChoice, FigureOptions, par_map, progress};
use crate::output::{self, Inputs};

impl FigureOptions {
    /// What this figure run is, for its shard files: its options and its body file's digest.
    pub fn job_id(&self, figure: &str) -> Result<JobId> {
        let body_sha256 = match &self.body {
            BodyChoice::File(p) => Some(super::body_digest(p)?),
            _ => None,
        };
        Ok(JobId::Figure {
            name: figure.into(),
            seed: self.seed,
            quick: self.quick,
            body: self.body.clone(),
            alpha: self.alpha,
            body_sha256,
        })
    }

    /// The figure's ensemble: `f(k)` for every job k in 0..n, in index order, computed here,
    /// for one shard only ([`Ensembled::Shard`]: the figure stops there), or read back from
    /// the shards (see the module doc). `what` labels the progress bar and the shard files.
    pub fn ensemble<T, F>(&self, figure: &str, n: usize, what: &str, f: F) -> Result<Ensembled<T>>
    where
        T: Record + Send,
        F: Fn(usize) -> Result<T> + Sync + Send,
    {
        run_ensemble(
            &self.ensemble,
            figure,
            n,
            what,
            || Ok((self.out.join(figure), self.job_id(figure)?, self.inputs())),
            f,
        )
    }
}

/// The one implementation behind [`FigureOptions::ensemble`] and `sweep`: `f(k)` for k in 0..n
/// as `ensemble` says. `place` gives the folder and identity of a shard file, asked only when
/// one is written (before its runs, so the body digests are of the files the runs read);
/// `name` prefixes messages.
pub fn run_ensemble<T, F>(
    ensemble: &Ensemble,
    name: &str,
    n: usize,
    what: &str,
    place: impl FnOnce() -> Result<(PathBuf, JobId, Inputs)>,
    f: F,
) -> Result<Ensembled<T>>
where
    T: Record + Send,
    F: Fn(usize) -> Result<T> + Sync + Send,
{
    match ensemble {
        Ensemble::Whole => {
            let bar = progress(n, what);
            Ok(Ensembled::All(
                par_map(n, &bar, f).into_iter().collect::<Result<_>>()?,
            ))
        }
        Ensemble::Shard(spec) => {
            // The identity first: the body files' digests as the runs read them, not after.
            let (dir, job, inputs) = place()?;
            let range = spec.range(n);
            let bar = progress(range.len(), what);
            let start = range.start;
            let results = par_map(range.len(), &bar, |k| f(start + k));
            let mut records = Vec::with_capacity(results.len());
            for r in results {
                let mut fields = Vec::new();
                r?.encode(&mut fields);
                records.push(fields);
            }
            let path = write_shard(&dir, job, what, *spec, n, &records, &inputs)?;
            Ok(Ensembled::Shard(ShardWritten {
                shard: *spec,
                jobs: records.len(),
                of_jobs: n,
                path,
            }))
        }
        Ensemble::Merge(merged) => {
            let records = &merged.records;
            if records.len() != n {
                bail!(
                    "{name}: the shards hold {} runs, but this command has {n}; were they \
                     written by another rollphase version?",
                    records.len()
                );
            }
            let all = records
                .iter()
                .enumerate()
                .map(|(k, r)| {
                    let (file, local) = merged.source_of(k);
                    decode_record(name, file, local, k, r)
                })
                .collect::<Result<_>>()?;
            Ok(Ensembled::All(all))
        }
    }
}

/// What `merge` did.
#[derive(Debug)]
pub struct MergeOutcome {
    /// Shards merged.
    pub shards: usize,
    /// Jobs merged.
    pub jobs: usize,
    /// The figure or "sweep".
    pub name: String,
}

/// Merges the shards in `dir` (OUT/NAME) of a figure: runs the figure's reduction on the
/// merged runs and writes its data.csv, summary.json and figure.png into `dir`. Sweeps are
/// merged by the caller (see [`super::sweep::merge`]).
pub fn merge_figure(dir: &Path, merged: Merged) -> Result<MergeOutcome> {
    let shards = merged.shards;
    let JobId::Figure {
        name,
        seed,
        quick,
        body,
        alpha,
        body_sha256,
    } = merged.job.clone()
    else {
        bail!("{} holds sweep shards, not a figure's", dir.display());
    };
    let entry = crate::figures::figure(&name)
        .ok_or_else(|| anyhow!("the shards name figure {name:?}, which this rollphase lacks"))?;
    if !entry.sharded() {
        bail!(
            "the shards name figure {name}, which has no ensemble to merge (a figure with one: {}); \
             they were not written by this rollphase",
            crate::figures::sharded_figures().join(", ")
        );
    }
    // By its real name: `merge .` from inside OUT/NAME is that folder too.
    let real = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    if real.file_name().and_then(|n| n.to_str()) != Some(name.as_str()) {
        bail!(
            "{} holds shards of {name}; merge writes into OUT/{name}, so the folder must keep \
             that name",
            dir.display()
        );
    }
    let jobs = merged.records.len();
    // Checked before the figure's reduction: no output may be one of the shards (a data.csv
    // linked to a shard file, say).
    let mut inputs = Inputs::of(&merged.files);
    if let BodyChoice::File(p) = &body {
        super::check_body_unchanged(p, body_sha256.as_deref())?;
        inputs.add(p);
    }
    output::check_folder(dir, &crate::figures::FIGURE_FILES, &inputs)?;
    let opts = FigureOptions {
        out: real.parent().map(Path::to_path_buf).unwrap_or_default(),
        seed,
        quick,
        body,
        alpha,
        ensemble: Ensemble::Merge(Arc::new(merged)),
    };
    (entry.run)(&opts)?;
    Ok(MergeOutcome { shards, jobs, name })
}
