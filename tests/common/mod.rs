//! Shared fixtures for the law tests: seeded bodies and a helper that runs a simulation.
#![allow(dead_code)]

pub mod frames;

use rollphase::dynamics::Ramp;
use rollphase::geometry::{Body, Sphere, SphereCoeff, random_disk, random_sphere};
use rollphase::integrate::Method;
use rollphase::simulate::{InitialState, RunSpec, Summary, run};

/// A sphere with every coefficient scaled by `s`.
pub fn scaled_sphere(b: &Sphere, s: f64) -> Sphere {
    Sphere::new(
        b.coeffs()
            .iter()
            .map(|c| SphereCoeff {
                re: c.re * s,
                im: c.im * s,
                ..*c
            })
            .collect(),
    )
}

/// The first convex random disk at or after `seed` (σ, M as given).
pub fn disk(seed: u64, sigma: f64, modes: u32) -> Body {
    (seed..seed + 100)
        .map(|s| Body::Disk(random_disk(s, sigma, modes).unwrap()))
        .find(|b| b.check_convex().is_ok())
        .expect("a convex disk within 100 seeds")
}

/// The first convex random sphere at or after `seed` (σ = 0.25, l ≤ 5, as in the paper).
pub fn sphere(seed: u64) -> Body {
    (seed..seed + 100)
        .map(|s| Body::Sphere(random_sphere(s, 0.25, 5).unwrap()))
        .find(|b| b.check_convex().is_ok())
        .expect("a convex sphere within 100 seeds")
}

/// Runs and collects all rows.
pub fn run_rows(
    body: &Body,
    ramp: Ramp,
    initial: InitialState,
    method: Method,
    t_end: f64,
    samples: usize,
) -> (Vec<Vec<f64>>, Summary) {
    let spec = RunSpec {
        ramp,
        initial,
        method,
        t_end,
        samples,
        max_steps: 100_000_000,
        limits: Default::default(),
    };
    let mut rows = Vec::new();
    let summary = run(body, &spec, |r| rows.push(r.to_vec())).expect("run succeeds");
    (rows, summary)
}
