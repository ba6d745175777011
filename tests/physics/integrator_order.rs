//! Convergence of the integrators: RK4 and CF4 errors fall as h⁴; DOP853's global error tracks
//! its tolerance; the 7th-order dense output and the event locator are accurate to the same
//! level. References are analytic where one exists, else DOP853 at rtol 1e-13.

use crate::common;

use glam::DVec3;
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::dynamics::{Ramp, SphereViscous};
use rollphase::geometry::Body;
use rollphase::integrate::events::{Direction, integrate_collecting};
use rollphase::integrate::run::{Flow, Run};
use rollphase::integrate::{IntegrateError, Method, OdeSystem, Stepper};

/// Harmonic oscillator x'' = −x: exact x = sin t, crossings at kπ.
struct Oscillator;
impl OdeSystem<2> for Oscillator {
    fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
        [y[1], -y[0]]
    }
}

/// Ball thrown up: h'' = −g.
struct Ballistic;
impl OdeSystem<2> for Ballistic {
    fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
        [y[1], -9.81]
    }
}

fn final_state<S: OdeSystem<N>, const N: usize>(
    sys: &S,
    y0: [f64; N],
    t_end: f64,
    method: Method,
) -> [f64; N] {
    let mut run = Run::new(sys, 0.0, y0, method).unwrap();
    run.until::<IntegrateError>(t_end, u64::MAX, |_| Ok(Flow::Continue))
        .unwrap();
    *run.y()
}

/// Steps `sys` from `y0` to `t_end`, calling `visit` after every step.
fn each_step<S: OdeSystem<N>, const N: usize>(
    sys: &S,
    y0: [f64; N],
    t_end: f64,
    method: Method,
    mut visit: impl FnMut(&mut dyn Stepper<N>),
) -> [f64; N] {
    let mut run = Run::new(sys, 0.0, y0, method).unwrap();
    run.until::<IntegrateError>(t_end, u64::MAX, |st| {
        visit(st);
        Ok(Flow::Continue)
    })
    .unwrap();
    *run.y()
}

fn distance<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Observed order from errors at h and h/2.
fn order(e_h: f64, e_half: f64) -> f64 {
    (e_h / e_half).log2()
}

#[test]
fn rk4_error_falls_as_h_to_the_fourth_on_the_oscillator() {
    let exact = [10f64.sin(), 10f64.cos()];
    let errs: Vec<f64> = [0.1, 0.05, 0.025]
        .iter()
        .map(|&dt| {
            distance(
                &final_state(&Oscillator, [0.0, 1.0], 10.0, Method::Rk4 { dt }),
                &exact,
            )
        })
        .collect();
    for w in errs.windows(2) {
        let p = order(w[0], w[1]);
        assert!((p - 4.0).abs() < 0.15, "observed order {p} from {errs:?}");
    }
}

fn sphere_setup() -> (Body, glam::DQuat) {
    let body = common::sphere(1);
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let q0 = orientation_touching(s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    (body, q0)
}

#[test]
fn rk4_and_cf4_are_fourth_order_on_the_3d_viscous_model() {
    let (body, q0) = sphere_setup();
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let ramp = Ramp::new(0.5, 0.0).unwrap();
    let model = SphereViscous::new(s, &ramp);
    let y0 = SphereViscous::initial_state(q0);
    let reference = final_state(&model, y0, 10.0, Method::dop853(1e-13));
    for make in [|dt| Method::Rk4 { dt }, |dt| Method::Cf4 { dt }] {
        let errs: Vec<f64> = [0.2, 0.1, 0.05]
            .iter()
            .map(|&dt| distance(&final_state(&model, y0, 10.0, make(dt)), &reference))
            .collect();
        for w in errs.windows(2) {
            let p = order(w[0], w[1]);
            assert!(
                (p - 4.0).abs() < 0.35,
                "{}: observed order {p} from {errs:?}",
                make(0.1).name()
            );
        }
    }
}

#[test]
fn cf4_keeps_the_quaternion_unit_without_projection() {
    let (body, q0) = sphere_setup();
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let model = SphereViscous::new(s, &Ramp::new(0.5, 0.0).unwrap());
    let mut worst = 0.0f64;
    each_step(
        &model,
        SphereViscous::initial_state(q0),
        2000.0,
        Method::Cf4 { dt: 0.2 },
        |st| {
            let y = st.y();
            worst = worst
                .max(((y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]).sqrt() - 1.0).abs());
        },
    );
    assert!(
        worst < 1e-13,
        "||q| − 1| reached {worst:e} over 10⁴ CF4 steps"
    );
    // RK4 on the same problem drifts off the unit sphere, which is why CF4 exists.
    let y = final_state(
        &model,
        SphereViscous::initial_state(q0),
        2000.0,
        Method::Rk4 { dt: 0.2 },
    );
    let rk4_drift = ((y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]).sqrt() - 1.0).abs();
    assert!(
        rk4_drift > 100.0 * worst.max(1e-16),
        "RK4 drift {rk4_drift:e}"
    );
}

#[test]
fn dop853_global_error_tracks_its_tolerance() {
    let (body, q0) = sphere_setup();
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let model = SphereViscous::new(s, &Ramp::new(0.5, 0.0).unwrap());
    let y0 = SphereViscous::initial_state(q0);
    let reference = final_state(&model, y0, 20.0, Method::dop853(1e-14));
    let mut last = f64::INFINITY;
    for rtol in [1e-5, 1e-7, 1e-9, 1e-11] {
        let err = distance(
            &final_state(&model, y0, 20.0, Method::dop853(rtol)),
            &reference,
        );
        // The error is within two decades of the tolerance, and falls as the tolerance does.
        assert!(err < 100.0 * rtol, "rtol {rtol:e}: error {err:e}");
        assert!(
            err < last / 10.0,
            "rtol {rtol:e}: error {err:e} did not fall from {last:e}"
        );
        last = err;
    }
}

#[test]
fn dense_output_is_as_accurate_as_the_steps() {
    let mut worst = 0.0f64;
    each_step(&Oscillator, [0.0, 1.0], 30.0, Method::dop853(1e-11), |st| {
        let (a, b) = (st.t_prev(), st.t());
        for k in 1..8 {
            let t = a + (b - a) * k as f64 / 8.0;
            let y = st.dense(t);
            worst = worst
                .max((y[0] - t.sin()).abs())
                .max((y[1] - t.cos()).abs());
        }
    });
    assert!(worst < 1e-9, "dense output error {worst:e}");
}

#[test]
fn events_are_located_on_the_dense_output() {
    // Ballistic: h(0) = 2, v(0) = 5: lands at t* = (5 + √(25 + 2·9.81·2))/9.81.
    let exact = (5.0 + (25.0f64 + 2.0 * 9.81 * 2.0).sqrt()) / 9.81;
    let mut run = Run::new(&Ballistic, 0.0, [2.0, 5.0], Method::dop853(1e-10)).unwrap();
    let ev = integrate_collecting(
        &mut run,
        10.0,
        10_000,
        &|_t, y: &[f64; 2]| y[0],
        Direction::Falling,
        |_| true,
    )
    .unwrap();
    assert_eq!(ev.len(), 1);
    assert!(
        (ev[0] - exact).abs() < 1e-12,
        "landing at {} vs {exact}",
        ev[0]
    );
    // Oscillator: sin t crosses zero at kπ, rising at even k and falling at odd k; steps are
    // long (≈1) so the locator, not the step, sets the accuracy.
    for method in [Method::dop853(1e-10), Method::Rk4 { dt: 0.01 }] {
        let mut run = Run::new(&Oscillator, 0.0, [0.0, 1.0], method).unwrap();
        let ev = integrate_collecting(
            &mut run,
            20.0,
            100_000,
            &|_t, y: &[f64; 2]| y[0],
            Direction::Both,
            |_| false,
        )
        .unwrap();
        assert_eq!(ev.len(), 6, "{method:?}: {ev:?}");
        for (k, t) in ev.iter().enumerate() {
            let err = (t - (k + 1) as f64 * std::f64::consts::PI).abs();
            let tol = if method.name() == "rk4" { 1e-8 } else { 1e-9 };
            assert!(err < tol, "{method:?}: crossing {k} off by {err:e}");
        }
    }
}
