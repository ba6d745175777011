//! `bench track`: the time `track` takes on synthetic tracks of 10⁴ to 10⁷ rows (a 20.5-frame
//! period, the printed sphere's at m/m0 = 2.5 and 30 frames/s, with drift and noise): reading
//! the CSV, the period search with its checks (`measure`), and the whole `track` process with its
//! figure and files; beside them, on the smaller tracks, the search the command used before
//! (every quarter-frame shift, each over the whole track: O(n²)), so old and new are timed in
//! one run.

use std::time::Instant;

use anyhow::{Result, bail};

use super::TrackBenchArgs;
use crate::analysis::experiment::tracking::measure;
use crate::output::{self, ScratchFolder};

/// A track of `rows` frames in the authors' units (xn across, yn down).
fn synthetic(rows: usize) -> String {
    let w = std::f64::consts::TAU / 20.5;
    let mut state = 1u64;
    let mut noise = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let mut text = String::with_capacity(rows * 24);
    text.push_str("frame,xn,yn\n");
    for i in 0..rows {
        let t = i as f64;
        let down = 8.4 * t + 20.0 * (w * t).sin() + 6.0 * (2.0 * w * t + 1.0).sin() + noise();
        let across = 15.0 * (w * t + 0.3).cos() - 0.01 * t + noise();
        text.push_str(&format!("{i},{across:.3},{down:.3}\n"));
    }
    text
}

/// The old search's cost: the mismatch at every quarter-frame shift from 15 frames (half a
/// second at 30 frames/s) to half the track, each a pass over the whole track.
fn direct_search(down: &[f64], across: &[f64]) -> f64 {
    let n = down.len();
    let at = |v: &[f64], x: f64| {
        let i = (x.floor() as usize).min(n - 2);
        let s = x - i as f64;
        v[i] + s * (v[i + 1] - v[i])
    };
    let mut best = f64::INFINITY;
    for q in 60..=4 * ((n - 1) / 2) {
        let tau = q as f64 / 4.0;
        let count = ((n - 1) as f64 - tau).floor() as usize + 1;
        let (mut sd, mut sa, mut sq) = (0.0, 0.0, 0.0);
        for i in 0..count {
            let d = at(down, i as f64 + tau) - down[i];
            let a = at(across, i as f64 + tau) - across[i];
            sd += d;
            sa += a;
            sq += d * d + a * a;
        }
        let c = count as f64;
        best = best.min(sq / c - (sd / c).powi(2) - (sa / c).powi(2));
    }
    best
}

/// Runs `bench track`.
pub fn run(a: TrackBenchArgs) -> Result<()> {
    if !(4..=7).contains(&a.largest) {
        bail!(
            "--largest {} is not allowed (needs 4 ≤ k ≤ 7: tracks of 10⁴ to 10^k rows)",
            a.largest
        );
    }
    let scratch = ScratchFolder::create("bench-track")?;
    outln!(
        "{:>10} {:>9} {:>11} {:>13} {:>11} {:>10} {:>16}",
        "rows",
        "read (s)",
        "search (s)",
        "command (s)",
        "period",
        "± (frames)",
        "old search (s)"
    )?;
    for k in 4..=a.largest {
        let rows = 10usize.pow(k);
        let path = scratch.path().join(format!("track-{rows}.csv"));
        output::write_bytes(&path, synthetic(rows).as_bytes(), &output::Inputs::none())?;
        let start = Instant::now();
        let mut reader = csv::Reader::from_path(&path)?;
        let (mut frames, mut down, mut across) = (Vec::new(), Vec::new(), Vec::new());
        for record in reader.records() {
            let r = record?;
            frames.push(r[0].parse::<f64>()?);
            across.push(r[1].parse::<f64>()? * 0.0404);
            down.push(r[2].parse::<f64>()? * 0.0361);
        }
        let read = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let (_, fit) = measure(&frames, &down, &across, &|_, _| {})?;
        let search = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let out = scratch.path().join(format!("out-{rows}"));
        let status = std::process::Command::new(std::env::current_exe()?)
            .arg("track")
            .arg(&path)
            .arg("--out")
            .arg(&out)
            .stdout(std::process::Stdio::null())
            .status()?;
        if !status.success() {
            bail!("`rollphase track` on {} failed ({status})", path.display());
        }
        let command = start.elapsed().as_secs_f64();
        let old = if rows <= a.old_up_to {
            let start = Instant::now();
            std::hint::black_box(direct_search(&down, &across));
            format!("{:.2}", start.elapsed().as_secs_f64())
        } else {
            "—".into()
        };
        outln!(
            "{:>10} {:>9.3} {:>11.3} {:>13.3} {:>11.4} {:>10.4} {:>16}",
            rows,
            read,
            search,
            command,
            fit.period_frames,
            fit.period_error_frames,
            old
        )?;
    }
    Ok(())
}
