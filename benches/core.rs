//! Speed of the physics core (criterion): a 3D viscous run of t = 0..100 at rtol 1e-10 (target:
//! under 10 ms on one core; the authors' Python needs 13 s), the raw 3D right-hand side, and the
//! 2D period quadrature. Run with `cargo bench --bench core`; the RHS count of the 3D run is
//! printed first so evaluations per second follow from criterion's time.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use rollphase::analysis::{critical_angle, viscous_disk_period};
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::dynamics::{Ramp, SphereViscous};
use rollphase::geometry::{Body, Sphere, random_disk, random_sphere};
use rollphase::integrate::{self, Method, OdeSystem};

fn default_sphere() -> Sphere {
    (1..)
        .map(|s| random_sphere(s, 0.25, 5).expect("valid generator parameters"))
        .find(|s| Body::Sphere(s.clone()).check_convex().is_ok())
        .expect("a convex sphere")
}

fn run_3d(s: &Sphere, alpha: f64) -> u64 {
    let model = SphereViscous::new(s, &Ramp::new(alpha, 0.0).expect("valid ramp"));
    let q0 = orientation_touching(s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let mut st = integrate::stepper(
        &model,
        0.0,
        SphereViscous::initial_state(q0),
        Method::dop853(1e-10),
    )
    .expect("valid method");
    while st.t() < 100.0 {
        st.step(100.0).expect("integrates");
    }
    black_box(st.y());
    st.stats().rhs_evals
}

fn bench(c: &mut Criterion) {
    let s = default_sphere();
    let alpha = critical_angle(&Body::Sphere(s.clone())).alpha_star + 0.05;
    let evals = run_3d(&s, alpha);
    println!("3D viscous, t = 0..100, rtol 1e-10: {evals} RHS evaluations per run");
    c.bench_function("sphere_viscous_t100_rtol1e-10", |b| {
        b.iter(|| run_3d(&s, alpha))
    });

    let model = SphereViscous::new(&s, &Ramp::new(alpha, 0.0).expect("valid ramp"));
    let q0 = orientation_touching(&s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let y = SphereViscous::initial_state(q0);
    model.rhs(0.0, &y);
    c.bench_function("sphere_viscous_rhs_warm", |b| {
        b.iter(|| model.rhs(0.0, black_box(&y)))
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
