use glam::{DQuat, DVec3};
use rollphase::analysis::critical_angle;
use rollphase::dynamics::{Observe, Ramp, SphereInertial, SphereViscous};
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::geometry::{Body, random_sphere};
use rollphase::integrate::{self, Method};
fn main() {
    let s = (5..).map(|k| random_sphere(k, 0.25, 5).unwrap()).find(|d| Body::Sphere(d.clone()).check_convex().is_ok()).unwrap();
    let ca = critical_angle(&Body::Sphere(s.clone()));
    let alpha: f64 = std::env::args().nth(2).map(|a| a.parse::<f64>().unwrap()).unwrap_or(0.5) * ca.alpha_star;
    let q_start = orientation_touching(&s, DVec3::from_array(ca.direction), 0.4);
    let vm = SphereViscous::new(&s, &Ramp::new(alpha, 0.0).unwrap());
    let mut st = integrate::stepper(&vm, 0.0, SphereViscous::initial_state(q_start), Method::dop853(1e-12)).unwrap();
    while st.t() < 400.0 { st.step(400.0).unwrap(); }
    let y = *st.y();
    let q = DQuat::from_xyzw(y[1], y[2], y[3], y[0]);
    println!("rest omega {:?}", vm.observe(&y).omega);
    let rtol: f64 = std::env::args().nth(1).map(|a| a.parse().unwrap()).unwrap_or(1e-10);
    let m = SphereInertial::new(&s, &Ramp::with_drag(alpha, 1.0, 0.0).unwrap());
    let mut st = integrate::stepper(&m, 0.0, SphereInertial::initial_state(q, DVec3::new(0.004, -0.003, 0.002)), Method::dop853(rtol)).unwrap();
    let e0 = m.energy_balance(st.y()).unwrap();
    let mut k = 0; let mut next = 0.0;
    while st.t() < 1000.0 {
        st.step(1000.0).unwrap(); k += 1;
        if st.t() >= next { next += 50.0; let y = st.y(); let o = m.observe(y);
          println!("t={:.1} w={:.3e} u={:.4?} x={:.4} y={:.4} dE={:.3e} steps={k}", st.t(), o.omega.length(), o.contact_dir, y[7], y[8], m.energy_balance(y).unwrap()-e0); }
    }
    println!("{:?}", st.stats());
}
