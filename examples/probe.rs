use glam::DVec3;
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::dynamics::{Ramp, SphereViscous};
use rollphase::geometry::{Body, random_sphere};
use rollphase::integrate::{self, Method, OdeSystem};
struct NoProj<'a>(&'a SphereViscous<'a>);
impl OdeSystem<6> for NoProj<'_> {
    fn rhs(&self, t: f64, y: &[f64; 6]) -> [f64; 6] {
        self.0.rhs(t, y)
    }
}
fn run<S: OdeSystem<6>>(
    m: &S,
    obs: &SphereViscous,
    y0: [f64; 6],
    t_end: f64,
) -> (f64, f64, u64, f64) {
    let t0 = std::time::Instant::now();
    let mut st = integrate::stepper(m, 0.0, y0, Method::dop853(1e-10)).unwrap();
    let (mut qe, mut ne) = (0.0f64, 0.0f64);
    while st.t() < t_end {
        st.step(t_end).unwrap();
        let o = obs.observe(st.y());
        qe = qe.max(o.quat_norm_error);
        ne = ne.max(o.contact_normal_error);
    }
    (qe, ne, st.stats().rhs_evals, t0.elapsed().as_secs_f64())
}
fn main() {
    let s = (1..)
        .map(|k| random_sphere(k, 0.25, 5).unwrap())
        .find(|d| Body::Sphere(d.clone()).check_convex().is_ok())
        .unwrap();
    let q0 = orientation_touching(&s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let ca = rollphase::analysis::critical_angle(&Body::Sphere(s.clone()));
    let alpha = ca.alpha_star + 0.05;
    println!("alpha* {} alpha {alpha}", ca.alpha_star);
    let m = SphereViscous::new(&s, &Ramp::new(alpha, 0.0).unwrap());
    let y0 = SphereViscous::initial_state(q0);
    for _ in 0..3 {
        let r = run(&m, &m, y0, 100.0);
        println!("t=100: {r:?}  evals/s {:.3e}", r.2 as f64 / r.3);
    }
    let t_long: f64 = std::env::args()
        .nth(1)
        .map(|a| a.parse().unwrap())
        .unwrap_or(1e5);
    println!("projected {t_long}: {:?}", run(&m, &m, y0, t_long));
    println!(
        "unprojected {t_long}: {:?}",
        run(&NoProj(&m), &m, y0, t_long)
    );
}
