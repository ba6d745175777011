//! Speed of the physics core (criterion): a 3D viscous run of t = 0..100 at rtol 1e-10 (target:
//! under 10 ms on one core; the authors' Python needs 13 s), the 3D right-hand sides as a run
//! calls them (target: ≤ 1 µs per evaluation), the contact solve alone, the body check, and the
//! 2D period quadrature. Run with `cargo bench --bench core`; criterion prints evaluations per
//! second ("thrpt") for the per-evaluation benchmarks.
//!
//! A right-hand side is timed on the exact sequence of states a DOP853 run passed to it
//! (recorded once, replayed in order), so the contact solver's warm start sees the same
//! neighbour-to-neighbour distances as in a real run. Repeating one state would let Newton
//! stop after one iteration and flatter the figure by a factor of three.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use rollphase::analysis::{critical_angle, viscous_disk_period};
use rollphase::dynamics::sphere3d::{DOWN, orientation_touching};
use rollphase::dynamics::{Ramp, SphereInertial, SphereViscous};
use rollphase::geometry::{Body, Sphere, random_disk, random_sphere};
use rollphase::integrate::record::{self, replay};
use rollphase::integrate::run::{Flow, Run};
use rollphase::integrate::{IntegrateError, Method, OdeSystem};

fn default_sphere() -> Sphere {
    (1..)
        .map(|s| random_sphere(s, 0.25, 5).expect("valid generator parameters"))
        .find(|s| Body::Sphere(s.clone()).check_convex().is_ok())
        .expect("a convex sphere")
}

fn run_3d(s: &Sphere, alpha: f64) -> u64 {
    let model = SphereViscous::new(s, &Ramp::new(alpha, 0.0).expect("valid ramp"));
    let q0 = orientation_touching(s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let mut run = Run::new(
        &model,
        0.0,
        SphereViscous::initial_state(q0),
        Method::dop853(1e-10),
    )
    .expect("valid method");
    run.until::<IntegrateError>(100.0, u64::MAX, |_| Ok(Flow::Continue))
        .expect("integrates");
    black_box(run.y());
    run.stats().rhs_evals
}

/// The states a DOP853 run at rtol 1e-10 to t = `t_end` evaluates, in order.
fn recorded_states<S: OdeSystem<N>, const N: usize>(
    system: &S,
    y0: [f64; N],
    t_end: f64,
) -> Vec<[f64; N]> {
    record::recorded_states(system, y0, t_end, Method::dop853(1e-10)).expect("integrates")
}

fn bench(c: &mut Criterion) {
    let s = default_sphere();
    let alpha = critical_angle(&Body::Sphere(s.clone())).alpha_star + 0.05;
    let evals = run_3d(&s, alpha);
    println!("3D viscous, t = 0..100, rtol 1e-10: {evals} RHS evaluations per run");
    c.bench_function("sphere_viscous_t100_rtol1e-10", |b| {
        b.iter(|| run_3d(&s, alpha))
    });

    let ramp = Ramp::new(alpha, 0.0).expect("valid ramp");
    let q0 = orientation_touching(&s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let mut group = c.benchmark_group("rhs_in_run");

    let viscous = SphereViscous::new(&s, &ramp);
    let states = recorded_states(&viscous, SphereViscous::initial_state(q0), 100.0);
    group.throughput(Throughput::Elements(states.len() as u64));
    group.bench_function("sphere_viscous", |b| {
        b.iter(|| replay(&viscous, black_box(&states)))
    });

    let inertial_ramp = Ramp::new(alpha, 1.0).expect("valid ramp");
    let inertial = SphereInertial::new(&s, &inertial_ramp);
    let states = recorded_states(
        &inertial,
        SphereInertial::initial_state(q0, DVec3::ZERO),
        100.0,
    );
    group.throughput(Throughput::Elements(states.len() as u64));
    group.bench_function("sphere_inertial_m1", |b| {
        b.iter(|| replay(&inertial, black_box(&states)))
    });

    // The contact solve alone, on the downward directions of the viscous run's states,
    // warm-started from the previous contact as the models do.
    let directions: Vec<DVec3> = recorded_states(&viscous, SphereViscous::initial_state(q0), 100.0)
        .iter()
        .map(|y| {
            let q = glam::DQuat::from_xyzw(y[1], y[2], y[3], y[0]).normalize();
            q.conjugate() * DOWN
        })
        .collect();
    group.throughput(Throughput::Elements(directions.len() as u64));
    group.bench_function("contact_solve", |b| {
        b.iter(|| {
            let d0 = directions[0];
            let mut contact = s.support_point(d0, d0).expect("convex body");
            for &d in black_box(&directions) {
                contact = s.support_point_from(d, contact).expect("convex body");
            }
            contact.u
        })
    });
    group.finish();

    let body = Body::Sphere(s.clone());
    c.bench_function("sphere_body_check", |b| {
        b.iter(|| black_box(&body).check_convex())
    });
    c.bench_function("sphere_critical_angle", |b| {
        b.iter(|| critical_angle(black_box(&body)))
    });

    let disk = random_disk(3, 0.08, 10).expect("valid generator parameters");
    let a_star = critical_angle(&Body::Disk(disk.clone())).alpha_star;
    let ramp = Ramp::new(a_star + 1e-4, 0.0).expect("valid ramp");
    c.bench_function("disk_viscous_period_quadrature_near_critical", |b| {
        b.iter(|| viscous_disk_period(black_box(&disk), &ramp))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
