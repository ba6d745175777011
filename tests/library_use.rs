//! The guide's library example (docs/guide/library.md) compiles and runs as written: it is read from there, and
//! the same code is run here. Needs no feature: `cargo test --no-default-features` runs it.

use rollphase::analysis::critical_angle;
use rollphase::dynamics::Ramp;
use rollphase::geometry::{Body, random_sphere};
use rollphase::integrate::Method;
use rollphase::simulate::{InitialState, RunSpec, run};

/// The example's lines, as in the README's `rust` block.
const EXAMPLE: &str = r#"use rollphase::analysis::critical_angle;
use rollphase::dynamics::Ramp;
use rollphase::geometry::{Body, random_sphere};
use rollphase::integrate::Method;
use rollphase::simulate::{InitialState, RunSpec, run};

let body = Body::Sphere(random_sphere(1, 0.25, 5)?);
let alpha_star = critical_angle(&body).alpha_star;
let spec = RunSpec {
    ramp: Ramp { alpha_rad: 1.5 * alpha_star, mass_ratio: 0.0, drag: 1.0 },
    initial: InitialState::Sphere { q0: glam::DQuat::IDENTITY, omega0: glam::DVec3::ZERO },
    method: Method::dop853(1e-8),
    t_end: 100.0,
    samples: 101,
    max_steps: 1_000_000,
};
// Each row: t, then the model's columns (see `rollphase simulate --help`).
let summary = run(&body, &spec, |row| println!("{row:?}"))?;
println!("{} ran {} steps", summary.model, summary.steps);"#;

#[test]
fn the_readme_shows_this_example() {
    let readme = include_str!("../docs/guide/library.md");
    assert!(
        readme.contains(EXAMPLE),
        "the guide's library example (docs/guide/library.md) differs from tests/library_use.rs; keep them the same"
    );
}

#[test]
fn the_library_example_runs() -> Result<(), Box<dyn std::error::Error>> {
    let mut rows = 0;
    let body = Body::Sphere(random_sphere(1, 0.25, 5)?);
    let alpha_star = critical_angle(&body).alpha_star;
    let spec = RunSpec {
        ramp: Ramp {
            alpha_rad: 1.5 * alpha_star,
            mass_ratio: 0.0,
            drag: 1.0,
        },
        initial: InitialState::Sphere {
            q0: glam::DQuat::IDENTITY,
            omega0: glam::DVec3::ZERO,
        },
        method: Method::dop853(1e-8),
        t_end: 100.0,
        samples: 101,
        max_steps: 1_000_000,
    };
    let summary = run(&body, &spec, |row| {
        assert!(row.iter().all(|v| v.is_finite()));
        rows += 1;
    })?;
    assert_eq!(rows, 101);
    assert_eq!(summary.model.to_string(), "sphere-viscous");
    assert!(summary.steps > 0);
    Ok(())
}
