//! Fuzz target, structure-aware: `arbitrary` builds one to four shard files of a figure's or a
//! sweep's ensemble (shard index and count, job range, records of numbers from the whole f64
//! range with small integers for the tags and lengths a record holds), sealed with a correct
//! digest (a forged shard) or not (an edited one), sometimes of another format, with a byte
//! flipped or cut short; writes them to a folder and hands it to the same path as
//! `rollphase merge DIR`: scan and check the shards, read their records, and decode every record
//! as the job's record type, with the range checks a figure's reduction relies on. Any input must
//! give the records or an error, never a panic or a hang.
#![no_main]

use std::path::PathBuf;

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rollphase::figures::BodyChoice;
use rollphase::figures::shard::{JobId, ShardFile, merged, scan_shards};

/// The jobs a shard can belong to: the sharded figures and sweeps.
const JOBS: [&str; 8] = [
    "disk-transition",
    "model-validity",
    "sphere-cruising",
    "sphere-poincare",
    "sphere-orbits",
    "sphere-doubling",
    "sphere-bifurcation",
    "sweep",
];

/// A number in a record: anything, a small integer (tags, lengths, flags, multiplicities), or
/// a fraction.
#[derive(Arbitrary, Debug)]
enum Num {
    Raw(f64),
    Small(i8),
    Fraction(u16),
}

impl Num {
    fn value(&self) -> f64 {
        match *self {
            Num::Raw(v) => v,
            Num::Small(k) => f64::from(k),
            Num::Fraction(k) => f64::from(k) / 1000.0,
        }
    }
}

#[derive(Arbitrary, Debug)]
struct Shard {
    shard: u8,
    of: u8,
    jobs: u8,
    first: u8,
    records: Vec<Vec<Num>>,
    /// Recompute the digest after building (a forged shard) rather than leave it wrong.
    seal: bool,
    /// Write this rollphase's format string.
    format_ok: bool,
    /// Flip the byte at this position of the file's text.
    flip: Option<u16>,
    /// Cut the file's text at this length.
    truncate: Option<u16>,
    /// The file's own name: shard-I-of-N.json from its fields, or another index.
    name_index: Option<u8>,
}

#[derive(Arbitrary, Debug)]
struct Input {
    job: u8,
    seed: u8,
    /// Make the first shard a whole, sealed, well-formed ensemble of one shard, so most inputs
    /// reach the record decoding (the part a forged shard attacks) rather than stopping at the
    /// file checks.
    coherent: bool,
    shards: Vec<Shard>,
}

fn folder() -> PathBuf {
    let base = if std::path::Path::new("/dev/shm").is_dir() {
        PathBuf::from("/dev/shm")
    } else {
        std::env::temp_dir()
    };
    base.join(format!("rollphase-fuzz-shards-{}", std::process::id()))
}

fuzz_target!(|input: Input| {
    let dir = folder();
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let name = JOBS[input.job as usize % JOBS.len()];
    let job = if name == "sweep" {
        JobId::Sweep {
            spec: String::new(),
            base: PathBuf::from("/"),
            body_sha256: Vec::new(),
        }
    } else {
        JobId::Figure {
            name: name.into(),
            seed: u64::from(input.seed % 3),
            quick: true,
            body: BodyChoice::FigureDefault,
            alpha: None,
            body_sha256: None,
        }
    };
    for (i, s) in input.shards.iter().take(4).enumerate() {
        let whole = input.coherent && i == 0;
        let records: Vec<String> = s
            .records
            .iter()
            .take(16)
            .map(|r| {
                r.iter()
                    .take(64)
                    .map(|n| format!("{:e}", n.value()))
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect();
        let n = records.len();
        let file = ShardFile {
            format: if s.format_ok || whole {
                "rollphase shard 2".into()
            } else {
                "rollphase shard 1".into()
            },
            job: job.clone(),
            ensemble: "runs".into(),
            jobs: if whole { n } else { usize::from(s.jobs) },
            shard: if whole { 1 } else { usize::from(s.shard) },
            of: if whole { 1 } else { usize::from(s.of) },
            first: if whole { 0 } else { usize::from(s.first) },
            records,
            digest: "0".repeat(64),
        };
        let file = if s.seal || whole { file.sealed().unwrap() } else { file };
        let mut bytes = serde_json::to_vec(&file).unwrap();
        if whole {
            let path = dir.join("shard-1-of-1.json");
            std::fs::write(path, bytes).unwrap();
            continue;
        }
        if let Some(at) = s.flip {
            let len = bytes.len();
            bytes[usize::from(at) % len] ^= 0x55;
        }
        if let Some(at) = s.truncate {
            bytes.truncate(usize::from(at));
        }
        let index = s.name_index.map_or(usize::from(s.shard), usize::from);
        let path = dir.join(format!("shard-{index}-of-{}.json", s.of));
        std::fs::write(path, bytes).unwrap();
    }
    if let Ok(set) = scan_shards(&dir)
        && let Ok(m) = merged(set)
    {
        let n = m.records.len();
        if let Ok(decoded) = rollphase::figures::decode_merged(name, m) {
            assert_eq!(decoded, n);
        }
    }
});
