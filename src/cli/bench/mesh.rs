//! `bench mesh`: the time and peak memory `shape --from-mesh` takes on the paper's sphere
//! written as binary STL and as binary PLY, from 20,480 to 5,242,880 triangles (and the printed
//! sphere's own mesh), with the fit's residual, so that the cost per triangle, its flatness and
//! the indexed format's memory against the streamed STL's are seen, not assumed. Each row is
//! fitted in a child process of its own, so its peak memory is its own.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};

use super::MeshBenchArgs;
use crate::geometry::mesh::sphere_mesh;
use crate::geometry::mesh_fit::{FitOptions, fit_mesh};
use crate::geometry::mesh_read::MeshSource;
use crate::output::{self, ScratchFolder};

/// What one child process measured.
#[derive(Debug, Serialize, Deserialize)]
struct Row {
    triangles: usize,
    seconds: f64,
    modes: u32,
    rms_residual: f64,
    /// The process's peak resident memory in kB (Linux's VmHWM), when the system says.
    peak_kb: Option<u64>,
}

/// Runs `bench mesh`.
pub fn run(a: MeshBenchArgs) -> Result<()> {
    if let Some(path) = &a.fit_one {
        return fit_one(path);
    }
    if !(5..=9).contains(&a.largest) {
        bail!(
            "--largest {} is not allowed (needs 5 ≤ level ≤ 9: 20·4^level triangles, 20,480 to \
             5,242,880)",
            a.largest
        );
    }
    let body = super::bundled(crate::assets::PAPER_SPHERE)?;
    let crate::geometry::Body::Sphere(sphere) = &body else {
        bail!("the bundled paper sphere is not a sphere")
    };
    let scratch = ScratchFolder::create("bench-mesh")?;
    outln!(
        "{:<32} {:>11} {:>9} {:>9} {:>13} {:>9} {:>6} {:>12}",
        "mesh",
        "triangles",
        "file MB",
        "fit (s)",
        "triangles/s",
        "peak MB",
        "L",
        "rms residual"
    )?;
    let mut rows: Vec<(String, PathBuf)> = Vec::new();
    let printed = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/data/printed-sphere.stl");
    if printed.is_file() {
        rows.push(("printed-sphere.stl".into(), printed));
    }
    for level in 5..=a.largest {
        let mesh = sphere_mesh(sphere, level);
        let stl = scratch.path().join(format!("paper-sphere-{level}.stl"));
        let mut bytes = Vec::new();
        mesh.write_stl(&mut bytes, 10.0, "paper sphere")?;
        output::write_bytes(&stl, &bytes, &output::Inputs::none())?;
        rows.push((format!("paper sphere, level {level}, STL"), stl));
        let ply = scratch.path().join(format!("paper-sphere-{level}.ply"));
        bytes.clear();
        mesh.write_ply(&mut bytes, 10.0)?;
        output::write_bytes(&ply, &bytes, &output::Inputs::none())?;
        rows.push((format!("paper sphere, level {level}, PLY"), ply));
    }
    let exe = std::env::current_exe().context("cannot find this program's path")?;
    for (name, path) in rows {
        let out = Command::new(&exe)
            .args(["bench", "mesh", "--fit-one"])
            .arg(&path)
            .output()
            .with_context(|| format!("cannot start {}", exe.display()))?;
        if !out.status.success() {
            bail!(
                "fitting {} failed: {}",
                path.display(),
                String::from_utf8_lossy(&out.stderr).trim()
            );
        }
        let row: Row = serde_json::from_slice(&out.stdout)
            .with_context(|| format!("the child fitting {} said no result", path.display()))?;
        let bytes = std::fs::metadata(&path)?.len();
        let peak = row
            .peak_kb
            .map_or_else(|| "—".to_string(), |kb| format!("{:.1}", kb as f64 / 1e3));
        outln!(
            "{:<32} {:>11} {:>9.1} {:>9.3} {:>13.3e} {:>9} {:>6} {:>12.2e}",
            name,
            row.triangles,
            bytes as f64 / 1e6,
            row.seconds,
            row.triangles as f64 / row.seconds,
            peak,
            row.modes,
            row.rms_residual
        )?;
    }
    Ok(())
}

/// Fits one mesh and prints a [`Row`] as JSON.
fn fit_one(path: &Path) -> Result<()> {
    let source = MeshSource::open(path)?;
    let start = Instant::now();
    let fit = fit_mesh(&source, &FitOptions::default(), &|_, _, _| {})?;
    let row = Row {
        triangles: source.triangles(),
        seconds: start.elapsed().as_secs_f64(),
        modes: fit.report.modes,
        rms_residual: fit.report.rms_residual,
        peak_kb: peak_kb(),
    };
    outln!("{}", serde_json::to_string(&row)?)?;
    Ok(())
}

/// This process's peak resident memory in kB, from `/proc/self/status` (Linux only).
fn peak_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
}
