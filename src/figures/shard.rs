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
//! A shard run is a normal outcome, not an error: `compute` takes its ensemble's results
//! through `all_runs!`, which returns [`Ensembled::Shard`] as `Computed::Shard` from the
//! figure, and the command line reports the shard written and what to do next.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, anyhow, bail};
use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{BodyChoice, FigureOptions, par_map, progress};
use crate::analysis::sphere_orbits::{Crossing, Fate};
use crate::geometry::shape_file::read_text_capped;
use crate::output::{self, Inputs};

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
    },
    /// `rollphase sweep SPEC.toml`.
    Sweep {
        /// The spec's text, as read.
        spec: String,
        /// The spec's folder, where its body files are.
        base: PathBuf,
    },
}

/// One shard file.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardFile {
    /// "rollphase shard 2".
    pub format: String,
    /// What ran.
    pub job: JobId,
    /// What the ensemble's jobs are (e.g. "3D and 2D runs").
    pub ensemble: String,
    /// Jobs in the whole ensemble.
    pub jobs: usize,
    /// I.
    pub shard: usize,
    /// N.
    pub of: usize,
    /// Index of this shard's first job.
    pub first: usize,
    /// One record per job: the result's numbers, space-separated.
    pub records: Vec<String>,
    /// SHA-256 (hex) of this file written with an empty digest: an edited, truncated or
    /// damaged shard is refused by name rather than merged into wrong numbers.
    #[serde(default)]
    pub digest: String,
}

impl ShardFile {
    /// The same file with its digest set from its contents.
    pub fn sealed(self) -> Result<Self> {
        Ok(Self {
            digest: self.content_digest()?,
            ..self
        })
    }

    /// The digest of this file's contents (its `digest` field left out).
    pub fn content_digest(&self) -> Result<String> {
        use sha2::{Digest, Sha256};
        /// The file as written, with an empty digest, borrowed (no copy of the records).
        #[derive(Serialize)]
        struct Blank<'a> {
            format: &'a str,
            job: &'a JobId,
            ensemble: &'a str,
            jobs: usize,
            shard: usize,
            of: usize,
            first: usize,
            records: &'a [String],
            digest: &'a str,
        }
        /// Feeds serialised bytes straight into the hash.
        struct Hashing(Sha256);
        impl std::io::Write for Hashing {
            fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
                self.0.update(buf);
                Ok(buf.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let mut hashing = Hashing(Sha256::new());
        serde_json::to_writer(
            &mut hashing,
            &Blank {
                format: &self.format,
                job: &self.job,
                ensemble: &self.ensemble,
                jobs: self.jobs,
                shard: self.shard,
                of: self.of,
                first: self.first,
                records: &self.records,
                digest: "",
            },
        )?;
        Ok(hashing
            .0
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect())
    }
}

/// Version 2 added the digest.
const FORMAT: &str = "rollphase shard 2";

/// Writes one shard's file into `dir` through the output layer (staged, so a killed shard leaves
/// no half-written file behind for `merge` to trip on). Returns its path.
pub fn write_shard(
    dir: &Path,
    job: JobId,
    ensemble: &str,
    spec: ShardSpec,
    jobs: usize,
    records: &[Vec<f64>],
    inputs: &Inputs,
) -> Result<PathBuf> {
    let file = ShardFile {
        format: FORMAT.into(),
        job,
        ensemble: ensemble.into(),
        jobs,
        shard: spec.index,
        of: spec.count,
        first: spec.range(jobs).start,
        records: records.iter().map(|r| encode_line(r)).collect(),
        digest: String::new(),
    }
    .sealed()?;
    let path = dir.join(spec.file_name());
    let text = serde_json::to_string(&file)? + "\n";
    output::create_folder(dir)?;
    output::write_bytes(&path, text.as_bytes(), inputs)?;
    Ok(path)
}

fn encode_line(r: &[f64]) -> String {
    let mut s = String::with_capacity(r.len() * 12);
    for (i, v) in r.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        // LowerExp without a precision is Rust's shortest round-trip form; `parse` reads it
        // back bit for bit, NaN, inf and -0 included.
        s.push_str(&format!("{v:e}"));
    }
    s
}

fn decode_line(line: &str) -> Option<Vec<f64>> {
    line.split_ascii_whitespace()
        .map(|f| f.parse::<f64>().ok())
        .collect()
}

/// All shards of one ensemble, read back and checked.
#[derive(Debug)]
pub struct Merged {
    /// What ran.
    pub job: JobId,
    /// The ensemble's name.
    pub ensemble: String,
    /// N.
    pub shards: usize,
    /// Every job's record, in index order.
    pub records: Vec<Vec<f64>>,
    /// The shard files read, in shard order, which the merged outputs must not overwrite.
    pub files: Vec<PathBuf>,
    /// The index of each file's first job, in the same order.
    pub firsts: Vec<usize>,
}

impl Merged {
    /// Where job `k`'s record came from: the shard file and the record's place in it.
    pub fn source_of(&self, k: usize) -> (&Path, usize) {
        let i = self.firsts.partition_point(|&f| f <= k).saturating_sub(1);
        match (self.files.get(i), self.firsts.get(i)) {
            (Some(p), Some(&first)) => (p, k - first),
            _ => (Path::new("?"), k),
        }
    }
}

/// The N shards of one ensemble in a folder, checked, with their records left on disk: what
/// [`scan_shards`] finds. [`read_shards`] collects every record (the figures); a sweep's merge
/// streams them one file at a time ([`ShardSet::for_each_record`]).
#[derive(Debug)]
pub struct ShardSet {
    /// What ran.
    pub job: JobId,
    /// The ensemble's name.
    pub ensemble: String,
    /// N.
    pub shards: usize,
    /// Jobs in the whole ensemble.
    pub jobs: usize,
    /// Each shard file in shard order with the index of its first job.
    entries: Vec<(PathBuf, usize)>,
}

impl ShardSet {
    /// The shard files, in shard order.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        self.entries.iter().map(|(p, _)| p.as_path())
    }

    /// Calls `f(k, numbers)` for every job's record in index order, reading one shard file at a
    /// time (each checked against its digest again, so a file changed since the scan is refused).
    pub fn for_each_record(&self, mut f: impl FnMut(usize, &[f64]) -> Result<()>) -> Result<()> {
        for (path, first) in &self.entries {
            let file = read_shard_file(path)?;
            if file.first != *first || file.job != self.job {
                bail!("{} changed while merging; merge again", path.display());
            }
            for (i, line) in file.records.iter().enumerate() {
                let numbers = decode_line(line).ok_or_else(|| {
                    anyhow!(
                        "shard file {}, record {i} (job {}): not a list of numbers",
                        path.display(),
                        first + i
                    )
                })?;
                f(first + i, &numbers)?;
            }
        }
        Ok(())
    }

    /// Decodes job `k`'s record as a `T`, naming the file, record and field of a bad one.
    pub fn decode<T: Record>(&self, name: &str, k: usize, record: &[f64]) -> Result<T> {
        let i = self
            .entries
            .partition_point(|(_, f)| *f <= k)
            .saturating_sub(1);
        let (file, first) = self
            .entries
            .get(i)
            .map_or((Path::new("?"), 0), |(p, f)| (p.as_path(), *f));
        decode_record(name, file, k - first, k, record)
    }
}

/// Decodes one record as a `T`; an error names the file, the record and the field.
fn decode_record<T: Record>(
    name: &str,
    file: &Path,
    local: usize,
    k: usize,
    record: &[f64],
) -> Result<T> {
    let mut fields = Fields(record.iter());
    let place = |left: usize| {
        format!(
            "{name}: shard file {}, record {local} (job {k}), field {}",
            file.display(),
            record.len() - left
        )
    };
    let v =
        T::decode(&mut fields).map_err(|e| anyhow!("{}: {e:#}", place(fields_left(&fields))))?;
    if fields_left(&fields) > 0 {
        bail!(
            "{}: more numbers than a result",
            place(fields_left(&fields))
        );
    }
    Ok(v)
}

/// Reads one shard file: a regular file (a FIFO or device named like a shard would block or
/// never end), of this format, matching its digest.
fn read_shard_file(path: &Path) -> Result<ShardFile> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => {}
        Ok(_) => bail!(
            "{} is not a regular file (a FIFO, device or folder); merge reads shard files \
             only; remove it and merge again",
            path.display()
        ),
        Err(e) => bail!("cannot read shard file {}: {e}", path.display()),
    }
    let text = read_text_capped(path, MAX_SHARD_BYTES)
        .with_context(|| format!("cannot read shard file {}", path.display()))?;
    let f: ShardFile = serde_json::from_str(&text)
        .with_context(|| format!("shard file {} is not a rollphase shard", path.display()))?;
    drop(text);
    if f.format != FORMAT {
        bail!(
            "shard file {} has format {:?}; this rollphase reads {FORMAT:?} (run the shard \
             again with this version)",
            path.display(),
            f.format
        );
    }
    if f.content_digest()? != f.digest {
        bail!(
            "shard file {} does not match its digest: it was edited, truncated or damaged \
             after it was written; run that shard again",
            path.display()
        );
    }
    Ok(f)
}

/// Finds every `shard-*.json` in `dir` and checks that they are the N shards of one ensemble:
/// the same job and options, each index 1..N exactly once, ranges covering every job. Only one
/// file's records are in memory at a time.
pub fn scan_shards(dir: &Path) -> Result<ShardSet> {
    let entries =
        std::fs::read_dir(dir).with_context(|| format!("cannot read folder {}", dir.display()))?;
    let mut files = Vec::new();
    for e in entries {
        let path = e?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.starts_with("shard-") && name.ends_with(".json") {
            files.push(path);
        }
    }
    files.sort();
    if files.is_empty() {
        bail!(
            "no shard files (shard-I-of-N.json) in {}: run the figure or sweep with --shard I/N \
             and --out pointing here first",
            dir.display()
        );
    }
    let mut by_index: BTreeMap<usize, (PathBuf, usize)> = BTreeMap::new();
    let mut reference: Option<(PathBuf, usize, JobId, usize)> = None;
    let mut ensemble = String::new();
    for path in files {
        let f = read_shard_file(&path)?;
        match &reference {
            None => reference = Some((path.clone(), f.of, f.job.clone(), f.jobs)),
            Some((first, of, job, jobs)) => {
                if f.of != *of {
                    bail!(
                        "shards of two different splits: {} is shard {}/{} but {} is of {of}; \
                         delete the stale ones and merge again",
                        path.display(),
                        f.shard,
                        f.of,
                        first.display()
                    );
                }
                if f.job != *job || f.jobs != *jobs {
                    bail!(
                        "{} and {} ran with different options ({} against {}); shards merge \
                         only with shards of the same command",
                        first.display(),
                        path.display(),
                        describe(job),
                        describe(&f.job)
                    );
                }
            }
        }
        let spec = ShardSpec {
            index: f.shard,
            count: f.of,
        };
        if f.shard == 0 || f.shard > f.of {
            bail!(
                "{} names shard {spec}, which does not exist",
                path.display()
            );
        }
        let range = spec.range(f.jobs);
        if f.first != range.start || f.records.len() != range.len() {
            bail!(
                "{} holds {} runs from index {}, but shard {spec} of {} runs is {} runs from {}: \
                 the file is damaged or was edited",
                path.display(),
                f.records.len(),
                f.first,
                f.jobs,
                range.len(),
                range.start
            );
        }
        if let Some((other, _)) = by_index.get(&f.shard) {
            bail!(
                "shard {spec} appears twice: {} and {}; keep one",
                other.display(),
                path.display()
            );
        }
        ensemble = f.ensemble;
        by_index.insert(f.shard, (path, f.first));
    }
    let Some((_, of, job, jobs)) = reference else {
        unreachable!("at least one shard file was read")
    };
    let missing: Vec<String> = (1..=of)
        .filter(|i| !by_index.contains_key(i))
        .map(|i| format!("{i}/{of}"))
        .collect();
    if !missing.is_empty() {
        bail!(
            "{} of {of} shards are missing from {}: {}; run them (--shard I/N) and merge again",
            missing.len(),
            dir.display(),
            abbreviate(&missing)
        );
    }
    Ok(ShardSet {
        job,
        ensemble,
        shards: of,
        jobs,
        entries: by_index.into_values().collect(),
    })
}

/// Reads every shard in `dir` ([`scan_shards`]) and collects all records, for a figure's merge.
pub fn read_shards(dir: &Path) -> Result<Merged> {
    merged(scan_shards(dir)?)
}

/// Every record of `set`, in index order.
pub fn merged(set: ShardSet) -> Result<Merged> {
    let mut records = Vec::with_capacity(set.jobs.min(1 << 20));
    set.for_each_record(|_, r| {
        records.push(r.to_vec());
        Ok(())
    })?;
    Ok(Merged {
        files: set.entries.iter().map(|(p, _)| p.clone()).collect(),
        firsts: set.entries.iter().map(|(_, f)| *f).collect(),
        job: set.job,
        ensemble: set.ensemble,
        shards: set.shards,
        records,
    })
}

/// Largest shard file `merge` reads.
pub const MAX_SHARD_BYTES: u64 = 1 << 30;

fn abbreviate(items: &[String]) -> String {
    if items.len() <= 10 {
        items.join(", ")
    } else {
        format!("{}, … ({} more)", items[..10].join(", "), items.len() - 10)
    }
}

fn describe(job: &JobId) -> String {
    match job {
        JobId::Figure {
            name,
            seed,
            quick,
            body,
            alpha,
        } => format!(
            "figure {name}, seed {seed}{}{}{}",
            if *quick { ", --quick" } else { "" },
            match body {
                BodyChoice::FigureDefault => String::new(),
                BodyChoice::Seeded => ", --seed body".into(),
                BodyChoice::File(p) => format!(", --shape {}", p.display()),
            },
            alpha.map(|a| format!(", --alpha {a}")).unwrap_or_default()
        ),
        JobId::Sweep { .. } => "a sweep spec".into(),
    }
}

impl FigureOptions {
    /// What this figure run is, for its shard files.
    pub fn job_id(&self, figure: &str) -> JobId {
        JobId::Figure {
            name: figure.into(),
            seed: self.seed,
            quick: self.quick,
            body: self.body.clone(),
            alpha: self.alpha,
        }
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
            || Ok((self.out.join(figure), self.job_id(figure), self.inputs())),
            f,
        )
    }
}

/// The one implementation behind [`FigureOptions::ensemble`] and `sweep`: `f(k)` for k in 0..n
/// as `ensemble` says. `place` gives the folder and identity of a shard file, asked only when
/// one is written; `name` prefixes messages.
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
            let (dir, job, inputs) = place()?;
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
    } = merged.job.clone()
    else {
        bail!("{} holds sweep shards, not a figure's", dir.display());
    };
    let entry = super::figure(&name)
        .ok_or_else(|| anyhow!("the shards name figure {name:?}, which this rollphase lacks"))?;
    if dir.file_name().and_then(|n| n.to_str()) != Some(name.as_str()) {
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
        inputs.add(p);
    }
    output::check_folder(dir, &super::FIGURE_FILES, &inputs)?;
    let opts = FigureOptions {
        out: dir.parent().map(Path::to_path_buf).unwrap_or_default(),
        seed,
        quick,
        body,
        alpha,
        ensemble: Ensemble::Merge(Arc::new(merged)),
    };
    (entry.run)(&opts)?;
    Ok(MergeOutcome { shards, jobs, name })
}

/// The largest period multiplicity a shard's fate may hold (a sweep's `max_multiplicity` is
/// capped at it).
pub const MAX_FATE_MULTIPLICITY: usize = 64;

fn fields_left(f: &Fields) -> usize {
    f.0.len()
}

/// The numbers of one record, read in order by [`Record::decode`].
pub struct Fields<'a>(std::slice::Iter<'a, f64>);

impl<'a> Fields<'a> {
    /// The numbers of `record`.
    pub fn of(record: &'a [f64]) -> Self {
        Fields(record.iter())
    }

    /// The next number.
    pub fn number(&mut self) -> Result<f64> {
        self.0
            .next()
            .copied()
            .ok_or_else(|| anyhow!("the record ends early"))
    }

    /// The next number as a count or index (a whole number ≥ 0).
    pub fn count(&mut self) -> Result<usize> {
        let v = self.number()?;
        if v >= 0.0 && v.fract() == 0.0 && v < 9.0e15 {
            Ok(v as usize)
        } else {
            bail!("{v} is not a count")
        }
    }
}

/// A job's result as numbers, for shard files: `decode(encode(x)) == x` bit for bit.
pub trait Record: Sized {
    /// Appends this result's numbers.
    fn encode(&self, out: &mut Vec<f64>);
    /// Reads a result back.
    fn decode(fields: &mut Fields) -> Result<Self>;
}

impl Record for f64 {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(*self);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        f.number()
    }
}

impl Record for usize {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(*self as f64);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        f.count()
    }
}

impl Record for u64 {
    // Two 32-bit halves: a seed may exceed 2^53, where f64 stops holding every integer.
    fn encode(&self, out: &mut Vec<f64>) {
        out.extend([(*self >> 32) as f64, (*self & 0xffff_ffff) as f64]);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let (hi, lo) = (f.count()?, f.count()?);
        if hi > u32::MAX as usize || lo > u32::MAX as usize {
            bail!("{hi}, {lo} are not the halves of a 64-bit number");
        }
        Ok(((hi as u64) << 32) | lo as u64)
    }
}

impl Record for bool {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(if *self { 1.0 } else { 0.0 });
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        match f.count()? {
            0 => Ok(false),
            1 => Ok(true),
            v => bail!("{v} is not a flag (0 or 1)"),
        }
    }
}

impl Record for DVec3 {
    fn encode(&self, out: &mut Vec<f64>) {
        out.extend(self.to_array());
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok(DVec3::new(f.number()?, f.number()?, f.number()?))
    }
}

impl<A: Record, B: Record> Record for (A, B) {
    fn encode(&self, out: &mut Vec<f64>) {
        self.0.encode(out);
        self.1.encode(out);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok((A::decode(f)?, B::decode(f)?))
    }
}

impl<A: Record, B: Record, C: Record> Record for (A, B, C) {
    fn encode(&self, out: &mut Vec<f64>) {
        self.0.encode(out);
        self.1.encode(out);
        self.2.encode(out);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok((A::decode(f)?, B::decode(f)?, C::decode(f)?))
    }
}

impl<T: Record> Record for Option<T> {
    fn encode(&self, out: &mut Vec<f64>) {
        match self {
            None => out.push(0.0),
            Some(v) => {
                out.push(1.0);
                v.encode(out);
            }
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok(if bool::decode(f)? {
            Some(T::decode(f)?)
        } else {
            None
        })
    }
}

impl<T: Record> Record for Vec<T> {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(self.len() as f64);
        for v in self {
            v.encode(out);
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let n = f.count()?;
        // The length comes from a file: grow as items actually arrive.
        let mut v = Vec::with_capacity(n.min(1 << 16));
        for _ in 0..n {
            v.push(T::decode(f)?);
        }
        Ok(v)
    }
}

impl Record for Crossing {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(self.t);
        out.extend(self.point);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let c = Crossing {
            t: f.number()?,
            point: [f.number()?, f.number()?, f.number()?],
        };
        if !(c.t.is_finite() && c.point.iter().all(|x| x.is_finite())) {
            bail!("a crossing of ∂Ω at t = {} holds a non-finite number", c.t);
        }
        Ok(c)
    }
}

impl Record for Fate {
    fn encode(&self, out: &mut Vec<f64>) {
        match self {
            Fate::Halts { t } => out.extend([0.0, *t]),
            Fate::Periodic {
                period,
                k,
                point,
                t,
            } => {
                out.extend([1.0, *period, *k as f64]);
                out.extend(point);
                out.push(*t);
            }
            Fate::Undecided { omega_end } => out.extend([2.0, *omega_end]),
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let fate = match f.count()? {
            0 => Fate::Halts { t: f.number()? },
            1 => Fate::Periodic {
                period: f.number()?,
                k: f.count()?,
                point: [f.number()?, f.number()?, f.number()?],
                t: f.number()?,
            },
            2 => Fate::Undecided {
                omega_end: f.number()?,
            },
            v => bail!("{v} is not a fate (0 halts, 1 periodic, 2 undecided)"),
        };
        // The ranges every reduction relies on: times ≥ 0, a period > 0 of 1 to
        // MAX_FATE_MULTIPLICITY crossings, finite points.
        match fate {
            Fate::Halts { t } if !(t.is_finite() && t >= 0.0) => {
                bail!("halt time {t} is not a finite time ≥ 0")
            }
            Fate::Periodic {
                period,
                k,
                point,
                t,
            } => {
                if !(period.is_finite() && period > 0.0) {
                    bail!("period {period} is not a finite time > 0");
                }
                if !(1..=MAX_FATE_MULTIPLICITY).contains(&k) {
                    bail!("period multiplicity {k} is not 1 to {MAX_FATE_MULTIPLICITY}");
                }
                if !(t.is_finite() && point.iter().all(|x| x.is_finite())) {
                    bail!("the orbit's point or time is not finite");
                }
            }
            Fate::Undecided { omega_end } if !(omega_end.is_finite() && omega_end >= 0.0) => {
                bail!("final |ω| {omega_end} is not a finite number ≥ 0")
            }
            _ => {}
        }
        Ok(fate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip<T: Record + PartialEq + std::fmt::Debug>(x: T) {
        let mut v = Vec::new();
        x.encode(&mut v);
        let line = encode_line(&v);
        let back = decode_line(&line).expect("numbers");
        assert_eq!(
            back.iter().map(|f| f.to_bits()).collect::<Vec<_>>(),
            v.iter().map(|f| f.to_bits()).collect::<Vec<_>>()
        );
        let mut fields = Fields(back.iter());
        assert_eq!(T::decode(&mut fields).expect("decodes"), x);
        assert!(fields.0.next().is_none());
    }

    #[test]
    fn records_round_trip_bit_for_bit() {
        round_trip(0.1f64 + 0.2);
        round_trip(-0.0f64);
        round_trip(f64::MIN_POSITIVE / 3.0);
        round_trip(f64::INFINITY);
        round_trip(Some((DVec3::new(1e-300, -2.5, 1.0 / 3.0), 7.25)));
        round_trip(None::<(DVec3, f64)>);
        round_trip(u64::MAX - 2);
        round_trip((true, 3usize, vec![vec![1.5f64], vec![]]));
        round_trip(vec![
            Fate::Halts { t: 12.5 },
            Fate::Periodic {
                period: 9.87654321,
                k: 2,
                point: [0.6, -0.8, 1e-17],
                t: 1999.9,
            },
            Fate::Undecided { omega_end: 3e-4 },
        ]);
        // NaN compares unequal, so check its bits directly.
        let line = encode_line(&[f64::NAN, f64::NEG_INFINITY]);
        let back = decode_line(&line).expect("numbers");
        assert!(back[0].is_nan() && back[1] == f64::NEG_INFINITY);
    }

    #[test]
    fn shards_cover_every_job_once_in_order() {
        for n in [0, 1, 7, 100, 9001] {
            for count in [1, 2, 3, 8, 13] {
                let mut next = 0;
                for index in 1..=count {
                    let r = ShardSpec { index, count }.range(n);
                    assert_eq!(r.start, next);
                    assert!(r.len() <= n / count + 1);
                    next = r.end;
                }
                assert_eq!(next, n);
            }
        }
    }

    #[test]
    fn bad_shard_specs_are_refused_with_the_form() {
        for bad in ["0/4", "5/4", "1/0", "a/b", "3", "-1/2", "1/200000"] {
            let e = bad.parse::<ShardSpec>().expect_err(bad);
            assert!(e.contains("I/N"), "{bad}: {e}");
        }
        assert_eq!(
            "3/8".parse::<ShardSpec>(),
            Ok(ShardSpec { index: 3, count: 8 })
        );
    }
}
