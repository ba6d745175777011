//! `bench speed`: the physics core's fixed and per-step costs on the paper's 3D body, printed
//! beside the figures measured before the speed-up (commit 7ff0f7c, same machine) and the
//! targets: the body check and the α* search alone, right-hand-side evaluations per second in
//! a DOP853 run, and whole processes of `simulate` and `inspect` (this binary started as a
//! child process, as a user or a shell script would).

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use glam::DVec3;

use super::SpeedBenchArgs;
use crate::analysis::critical_angle;
use crate::dynamics::sphere3d::orientation_touching;
use crate::dynamics::{Ramp, SphereInertial, SphereViscous};
use crate::geometry::{Body, Sphere};
use crate::integrate::{Method, OdeSystem, record};

/// One table row: what, unit, before, now, target (NaN: none), and whether smaller is better.
struct Row {
    name: &'static str,
    unit: &'static str,
    before: f64,
    now: f64,
    target: f64,
    lower_is_better: bool,
}

/// Mean seconds per call of `f`, repeated for at least `budget`.
fn mean_seconds(budget: Duration, mut f: impl FnMut()) -> f64 {
    f();
    let start = Instant::now();
    let mut n = 0u32;
    while start.elapsed() < budget || n < 3 {
        f();
        n += 1;
    }
    start.elapsed().as_secs_f64() / f64::from(n)
}

/// RHS evaluations per second on the states a DOP853 run at rtol 1e-10 to t = 100 evaluates,
/// replayed in order (see [`crate::integrate::record`]).
fn evals_per_second<S: OdeSystem<N>, const N: usize>(system: &S, y0: [f64; N]) -> Result<f64> {
    let states = record::recorded_states(system, y0, 100.0, Method::dop853(1e-10))?;
    let seconds = mean_seconds(Duration::from_millis(500), || {
        std::hint::black_box(record::replay(system, std::hint::black_box(&states)));
    });
    Ok(states.len() as f64 / seconds)
}

/// Median wall seconds of `runs` child processes of this binary with `args`.
fn process_seconds(args: &[&str], runs: u64) -> Result<f64> {
    let exe = std::env::current_exe().context("cannot find this program's path")?;
    let mut times = Vec::with_capacity(runs as usize);
    for _ in 0..runs + 2 {
        let start = Instant::now();
        let out = Command::new(&exe)
            .args(args)
            .output()
            .with_context(|| format!("cannot start {}", exe.display()))?;
        times.push(start.elapsed().as_secs_f64());
        if !out.status.success() {
            bail!(
                "rollphase {} failed: {}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr).trim()
            );
        }
    }
    // The first two warm the page cache.
    let mut times = times.split_off(2);
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
}

fn paper_body() -> Result<Sphere> {
    match super::bundled(crate::assets::PAPER_SPHERE)? {
        Body::Sphere(s) => Ok(s),
        Body::Disk(_) => bail!("the bundled paper body is not a sphere"),
    }
}

/// Runs `bench speed`.
pub fn run(a: SpeedBenchArgs) -> Result<()> {
    let s = paper_body()?;
    let body = Body::Sphere(s.clone());
    let budget = Duration::from_millis(500);
    let check = mean_seconds(budget, || {
        let _ = std::hint::black_box(&body).check_convex();
    });
    let alpha_star = mean_seconds(budget, || {
        std::hint::black_box(critical_angle(std::hint::black_box(&body)));
    });
    let q0 = orientation_touching(&s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let viscous = SphereViscous::new(&s, &Ramp::new(0.15, 0.0)?);
    let viscous_rate = evals_per_second(&viscous, SphereViscous::initial_state(q0))?;
    let inertial = SphereInertial::new(&s, &Ramp::new(0.15, 1.0)?);
    let inertial_rate =
        evals_per_second(&inertial, SphereInertial::initial_state(q0, DVec3::ZERO))?;

    let dir = std::env::temp_dir().join(format!("rollphase-bench-speed-{}", std::process::id()));
    crate::output::create_folder(&dir)?;
    let result = process_rows(&dir, a.runs);
    let _ = std::fs::remove_dir_all(&dir);
    let (simulate, inspect) = result?;

    let rows = [
        Row {
            name: "body check (paper body)",
            unit: "ms",
            before: 17.4,
            now: check * 1e3,
            target: f64::NAN,
            lower_is_better: true,
        },
        Row {
            name: "α* search (paper body)",
            unit: "ms",
            before: 13.0,
            now: alpha_star * 1e3,
            target: f64::NAN,
            lower_is_better: true,
        },
        Row {
            name: "3D viscous RHS, replayed run",
            unit: "M evals/s",
            before: 0.36,
            now: viscous_rate / 1e6,
            target: 1.0,
            lower_is_better: false,
        },
        Row {
            name: "3D inertial RHS, replayed run",
            unit: "M evals/s",
            before: 0.37,
            now: inertial_rate / 1e6,
            target: 1.0,
            lower_is_better: false,
        },
        Row {
            name: "simulate process (t = 100)",
            unit: "ms",
            before: 42.7,
            now: simulate * 1e3,
            target: 10.0,
            lower_is_better: true,
        },
        Row {
            name: "inspect process",
            unit: "ms",
            // Not measured on 7ff0f7c with this method.
            before: f64::NAN,
            now: inspect * 1e3,
            target: f64::NAN,
            lower_is_better: true,
        },
    ];
    outln!(
        "{:<28} {:>10} {:>10} {:>10}   {}",
        "measure",
        "before",
        "now",
        "target",
        "unit"
    )?;
    let cell = |v: f64| {
        if v.is_finite() {
            format!("{v:.3}")
        } else {
            "-".into()
        }
    };
    for r in rows {
        let missed = r.target.is_finite()
            && if r.lower_is_better {
                r.now > r.target
            } else {
                r.now < r.target
            };
        outln!(
            "{:<28} {:>10} {:>10.3} {:>10}   {}{}",
            r.name,
            cell(r.before),
            r.now,
            cell(r.target),
            r.unit,
            if missed { "   MISSES TARGET" } else { "" }
        )?;
    }
    outln!(
        "before: commit 7ff0f7c on this 2-core machine (criterion, hyperfine); processes: median of {} runs of this binary (its build profile counts: use --release)",
        a.runs
    )?;
    Ok(())
}

/// (simulate, inspect) median process seconds.
fn process_rows(dir: &Path, runs: u64) -> Result<(f64, f64)> {
    let shape = dir.join("paper-sphere.json");
    super::write(&shape, crate::assets::PAPER_SPHERE)?;
    let csv = dir.join("run.csv");
    let (shape, csv) = (shape.to_string_lossy(), csv.to_string_lossy());
    let simulate = process_seconds(
        &[
            "simulate", &shape, "--alpha", "0.15", "--t-end", "100", "--rtol", "1e-10", "-o", &csv,
        ],
        runs,
    )?;
    let inspect = process_seconds(&["inspect", &shape], runs)?;
    Ok((simulate, inspect))
}
