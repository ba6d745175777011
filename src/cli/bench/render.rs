//! `bench render`: frames per second of the headless renderer (rendering alone, with readback,
//! with PNG writing on worker threads).

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Result;

use super::RenderBenchArgs;

/// Most frames a row of `bench render` times.
const MAX_BENCH_FRAMES: u64 = 100_000;

/// Runs `bench render`.
pub fn run(a: RenderBenchArgs) -> Result<()> {
    use crate::headless::HeadlessRenderer;
    use crate::png::{PngWriter, frame_name};
    if !(1..=MAX_BENCH_FRAMES).contains(&a.frames) {
        anyhow::bail!(
            "--frames {} is not allowed (needs 1 ≤ frames ≤ {MAX_BENCH_FRAMES}: each row of the \
             table renders that many, and a few hundred give a steady rate)",
            a.frames
        );
    }
    let setup = crate::cli::pick_scene(None, Some(&a.preset))?;
    // The PNGs of the last row go to a scratch folder, removed at the end or on Ctrl-C.
    let scratch = crate::output::ScratchFolder::create("bench-render")?;
    let out = scratch.path().to_path_buf();
    let mut table = String::new();
    let (w, h) = a.size;
    let mut adapter = String::new();
    writeln!(table, "| MSAA | what is timed | frames/s | ms/frame |")?;
    writeln!(table, "|---|---|---|---|")?;
    for samples in [4, 1] {
        let mut r = HeadlessRenderer::new(setup.clone(), a.size, samples)?;
        adapter = r.adapter();
        let mut k = 0u64;
        for _ in 0..5 {
            r.frame(k)?;
            k += 1;
        }
        let mut row = |what: &str,
                       f: &mut dyn FnMut(&mut HeadlessRenderer, u64) -> Result<()>|
         -> Result<()> {
            let start = Instant::now();
            for _ in 0..a.frames {
                f(&mut r, k)?;
                k += 1;
            }
            rate_row(
                &mut table,
                samples,
                what,
                a.frames,
                start.elapsed().as_secs_f64(),
            )
        };
        row(
            "rendering alone (simulate, build, draw, wait for the GPU)",
            &mut |r, k| {
                r.draw(k)?;
                r.finish()
            },
        )?;
        row(
            "rendering alone, pipelined (wait for the GPU every 4th frame)",
            &mut |r, k| {
                r.draw(k)?;
                if k % 4 == 3 { r.finish() } else { Ok(()) }
            },
        )?;
        row("+ readback to memory", &mut |r, k| r.frame(k).map(|_| ()))?;
        let mut writer = PngWriter::new(2, crate::output::Inputs::none());
        let start = Instant::now();
        for _ in 0..a.frames {
            let img = r.frame(k)?;
            writer.write(out.join(frame_name(k)), img)?;
            k += 1;
        }
        writer.close()?;
        let seconds = start.elapsed().as_secs_f64();
        rate_row(
            &mut table,
            samples,
            "+ PNG writing on 2 threads",
            a.frames,
            seconds,
        )?;
    }
    drop(scratch);
    outln!(
        "{} at {w}x{h}, {} frames a row, on {adapter}\n",
        a.preset,
        a.frames
    )?;
    crate::cli::write_output(None, &table, &crate::output::Inputs::none())?;
    Ok(())
}

/// One row of the render table: frames per second and milliseconds per frame.
fn rate_row(table: &mut String, samples: u32, what: &str, frames: u64, seconds: f64) -> Result<()> {
    writeln!(
        table,
        "| {samples}× | {what} | {:.1} | {:.1} |",
        frames as f64 / seconds,
        1000.0 * seconds / frames as f64
    )?;
    Ok(())
}
