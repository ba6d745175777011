//! `bench mesh`: the time `shape --from-mesh` takes on the paper's sphere written as binary STL
//! meshes from 20,480 to 5,242,880 triangles (and the printed sphere's own mesh), with the fit's
//! residual, so that the cost per triangle and its flatness are seen, not assumed.

use std::time::Instant;

use anyhow::{Result, bail};

use super::MeshBenchArgs;
use crate::geometry::mesh::sphere_mesh;
use crate::geometry::mesh_fit::{FitOptions, fit_mesh};
use crate::geometry::mesh_read::MeshSource;
use crate::output::{self, ScratchFolder};

/// Runs `bench mesh`.
pub fn run(a: MeshBenchArgs) -> Result<()> {
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
        "{:<28} {:>11} {:>9} {:>9} {:>13} {:>6} {:>12}",
        "mesh",
        "triangles",
        "MB",
        "fit (s)",
        "triangles/s",
        "L",
        "rms residual"
    )?;
    let mut rows: Vec<(String, std::path::PathBuf)> = Vec::new();
    let printed =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/data/printed-sphere.stl");
    if printed.is_file() {
        rows.push(("printed-sphere.stl".into(), printed));
    }
    for level in 5..=a.largest {
        let path = scratch.path().join(format!("paper-sphere-{level}.stl"));
        let mut stl = Vec::new();
        sphere_mesh(sphere, level).write_stl(&mut stl, 10.0, "paper sphere")?;
        output::write_bytes(&path, &stl, &output::Inputs::none())?;
        rows.push((format!("paper sphere, level {level}"), path));
    }
    for (name, path) in rows {
        let source = MeshSource::open(&path)?;
        let bytes = std::fs::metadata(&path)?.len();
        let start = Instant::now();
        let fit = fit_mesh(&source, &FitOptions::default(), &|_, _, _| {})?;
        let seconds = start.elapsed().as_secs_f64();
        outln!(
            "{:<28} {:>11} {:>9.1} {:>9.3} {:>13.3e} {:>6} {:>12.2e}",
            name,
            source.triangles(),
            bytes as f64 / 1e6,
            seconds,
            source.triangles() as f64 / seconds,
            fit.report.modes,
            fit.report.rms_residual
        )?;
    }
    Ok(())
}
