use glam::DVec3;
use rollphase::dynamics::{Ramp, SphereViscous};
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::geometry::{Body, random_sphere};
use rollphase::integrate::{self, Method, OdeSystem};
fn fin<S: OdeSystem<6>>(m: &S, y0: [f64;6], meth: Method) -> [f64;6] { let mut st = integrate::stepper(m, 0.0, y0, meth).unwrap(); while st.t() < 10.0 { st.step(10.0).unwrap(); } *st.y() }
fn main() {
    let s = (1..).map(|k| random_sphere(k, 0.25, 5).unwrap()).find(|d| Body::Sphere(d.clone()).check_convex().is_ok()).unwrap();
    let q0 = orientation_touching(&s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let m = SphereViscous::new(&s, &Ramp::new(0.5, 0.0).unwrap());
    let y0 = SphereViscous::initial_state(q0);
    let r = fin(&m, y0, Method::dop853(1e-13));
    for dt in [0.2, 0.1, 0.05, 0.025] {
        let a = fin(&m, y0, Method::Cf4{dt}); let b = fin(&m, y0, Method::Rk4{dt});
        let eq = |y: &[f64;6]| (0..4).map(|i| (y[i]-r[i]).powi(2)).sum::<f64>().sqrt();
        let ex = |y: &[f64;6]| (4..6).map(|i| (y[i]-r[i]).powi(2)).sum::<f64>().sqrt();
        println!("dt={dt} cf4 q {:.3e} x {:.3e} | rk4 q {:.3e} x {:.3e}", eq(&a), ex(&a), eq(&b), ex(&b));
    }
}
