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

/// The starts of the `predict` whose runs are counted.
const PREDICT_STARTS: usize = 8;

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

/// Mean seconds from reading the paper body's shape file to `simulate::run`'s first step.
fn setup_seconds(budget: Duration) -> Result<f64> {
    let dir = std::env::temp_dir().join(format!("rollphase-bench-setup-{}", std::process::id()));
    crate::output::create_folder(&dir)?;
    let shape = dir.join("paper-sphere.json");
    crate::output::write_bytes(
        &shape,
        crate::assets::PAPER_SPHERE.as_bytes(),
        &crate::output::Inputs::none(),
    )?;
    let once = || -> Result<()> {
        let body = crate::geometry::ShapeFile::load(&shape)?;
        let spec = crate::simulate::RunSpec {
            ramp: Ramp::new(0.15, 0.0)?,
            initial: crate::simulate::InitialState::at_rest(&body),
            method: Method::dop853(1e-10),
            t_end: 1e-9,
            samples: 2,
            max_steps: 10,
            limits: Default::default(),
        };
        std::hint::black_box(crate::simulate::run(&body, &spec, |_| {})?);
        Ok(())
    };
    let result = once().map(|()| mean_seconds(budget, || once().unwrap_or(())));
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn paper_body() -> Result<Sphere> {
    match super::bundled(crate::assets::PAPER_SPHERE)? {
        Body::Sphere(s) => Ok(s),
        Body::Disk(_) => bail!("the bundled paper body is not a sphere"),
    }
}

/// How many trajectories one `predict` of `body` at α = 0.2014 integrates (the stepper each
/// builds, all through `integrate::run`): its starts, then the orbits' refinement, multipliers
/// and paths.
fn runs_per_predict(body: &Body, mass: f64) -> Result<f64> {
    let options = crate::analysis::experiment::prediction::PredictOptions {
        starts: PREDICT_STARTS,
        ..Default::default()
    };
    let before = crate::integrate::run::runs_started();
    crate::analysis::experiment::prediction::predict(body, 0.2014, mass, &options)?;
    Ok((crate::integrate::run::runs_started() - before) as f64)
}

/// Runs `bench speed`.
pub fn run(a: SpeedBenchArgs) -> Result<()> {
    let s = paper_body()?;
    let body = Body::Sphere(s.clone());
    let budget = Duration::from_millis(500);
    let check = mean_seconds(budget, || {
        let _ = std::hint::black_box(&body).check_convex();
    });
    // What the check cost until 2026-11-27: the full curvature report (its extremes too).
    let full_report = mean_seconds(budget, || {
        let _ = std::hint::black_box(std::hint::black_box(&body).curvature().convex);
    });
    // A run's set-up: the body from its shape file, then `simulate::run` to its first step
    // (the check, the model choice, the start, the model, the contact watch; one step taken).
    let setup = setup_seconds(budget)?;
    let alpha_star = mean_seconds(budget, || {
        std::hint::black_box(critical_angle(std::hint::black_box(&body)));
    });
    let q0 = orientation_touching(&s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let viscous = SphereViscous::new(&s, &Ramp::new(0.15, 0.0)?);
    let viscous_rate = evals_per_second(&viscous, SphereViscous::initial_state(q0))?;
    let inertial = SphereInertial::new(&s, &Ramp::new(0.15, 1.0)?);
    let inertial_rate =
        evals_per_second(&inertial, SphereInertial::initial_state(q0, DVec3::ZERO))?;

    let predict_viscous = runs_per_predict(&body, 0.0)?;
    let predict_inertial = runs_per_predict(&body, 6.0)?;

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
            name: "body check: report → measure",
            unit: "ms",
            before: full_report * 1e3,
            now: check * 1e3,
            target: f64::NAN,
            lower_is_better: true,
        },
        Row {
            name: "simulate set-up (warm, in process)",
            unit: "ms",
            // The check is the one part of the set-up that changed: before it, the same set-up
            // with the full report in its place, measured here side by side.
            before: (setup - check + full_report) * 1e3,
            now: setup * 1e3,
            target: 1.0,
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
            name: "runs per predict, 8 starts, m/m0 0",
            unit: "runs",
            // Not counted before the one run loop (2026-11-27).
            before: f64::NAN,
            now: predict_viscous,
            target: f64::NAN,
            lower_is_better: true,
        },
        Row {
            name: "runs per predict, 8 starts, m/m0 6",
            unit: "runs",
            before: f64::NAN,
            now: predict_inertial,
            target: f64::NAN,
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
        "{:<36} {:>10} {:>10} {:>10}   {}",
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
            "{:<36} {:>10} {:>10.3} {:>10}   {}{}",
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
