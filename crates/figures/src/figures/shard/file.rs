//! The shard file: its format ("rollphase shard 3", records in shortest round-trip form, a
//! SHA-256 of the contents), writing one through the output layer, and reading a folder's shards
//! back: scanned one file at a time, checked against each other, and merged in index order.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use serde::{Deserialize, Serialize};

use super::{Fields, JobId, Record, ShardSpec};
use crate::figures::BodyChoice;
use crate::geometry::shape_file::read_text_capped;
use crate::output::{self, Inputs};

/// One shard file.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardFile {
    /// "rollphase shard 3".
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
const FORMAT: &str = "rollphase shard 3";

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

/// A record as one line of a shard file: its numbers in Rust's shortest round-trip form,
/// separated by spaces ([`decode_line`] reads them back bit for bit, NaN, inf and −0 included).
pub fn encode_line(r: &[f64]) -> String {
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

/// A shard file's line as its numbers; `None` if any field is not a number.
pub fn decode_line(line: &str) -> Option<Vec<f64>> {
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
pub(super) fn decode_record<T: Record>(
    name: &str,
    file: &Path,
    local: usize,
    k: usize,
    record: &[f64],
) -> Result<T> {
    let mut fields = Fields::of(record);
    let place = |left: usize| {
        format!(
            "{name}: shard file {}, record {local} (job {k}), field {}",
            file.display(),
            record.len() - left
        )
    };
    let v = T::decode(&mut fields).map_err(|e| anyhow!("{}: {e:#}", place(fields.remaining())))?;
    if fields.remaining() > 0 {
        bail!("{}: more numbers than a result", place(fields.remaining()));
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
        if f.of == 0 || f.of > super::MAX_SHARDS {
            bail!(
                "{} says it is one of {} shards; a split has 1 to {} (the file is damaged or \
                 was edited)",
                path.display(),
                f.of,
                super::MAX_SHARDS
            );
        }
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
    // Counted without listing them all: only the first few are named.
    let missing_count = of - by_index.len();
    if missing_count > 0 {
        let missing: Vec<String> = (1..=of)
            .filter(|i| !by_index.contains_key(i))
            .take(11)
            .map(|i| format!("{i}/{of}"))
            .collect();
        bail!(
            "{missing_count} of {of} shards are missing from {}: {}; run them (--shard I/N) and \
             merge again",
            dir.display(),
            abbreviate_of(&missing, missing_count)
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

/// The first ten of `count` items, and how many more.
fn abbreviate_of(first: &[String], count: usize) -> String {
    if count <= 10 {
        first.join(", ")
    } else {
        format!("{}, … ({} more)", first[..10].join(", "), count - 10)
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
            body_sha256,
        } => format!(
            "figure {name}, seed {seed}{}{}{}{}",
            if *quick { ", --quick" } else { "" },
            match body {
                BodyChoice::FigureDefault => String::new(),
                BodyChoice::Seeded => ", --seed body".into(),
                BodyChoice::File(p) => format!(", --shape {}", p.display()),
            },
            alpha.map(|a| format!(", --alpha {a}")).unwrap_or_default(),
            body_sha256
                .as_deref()
                .map(|d| format!(" (body SHA-256 {}…)", &d[..d.len().min(12)]))
                .unwrap_or_default()
        ),
        JobId::Sweep { body_sha256, .. } if !body_sha256.is_empty() => format!(
            "a sweep spec with body files of SHA-256 {}",
            body_sha256
                .iter()
                .map(|d| format!("{}…", &d[..d.len().min(12)]))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        JobId::Sweep { .. } => "a sweep spec".into(),
    }
}
