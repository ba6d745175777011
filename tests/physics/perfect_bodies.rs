//! A perfect disk and a perfect sphere roll straight down at the exact speeds: viscous
//! 2π/T = sin α and v = sin α; inertial from rest ω(t) = sin α (1 − e^{−t/τ}) with
//! τ = (I + m)/γ (= 1.5 m for the disk, 1.4 m for the sphere). Tolerances follow from the
//! integrator tolerance (rtol 1e-10 → errors ≲ 1e-8 over these spans).

use crate::common;

use glam::{DQuat, DVec3};
use rollphase::analysis::viscous_disk_period;
use rollphase::dynamics::Ramp;
use rollphase::geometry::{Body, Disk, Sphere};
use rollphase::integrate::Method;
use rollphase::simulate::InitialState;

const ALPHA: f64 = 0.3;

#[test]
fn perfect_disk_viscous_period_is_2pi_over_sin_alpha() {
    for alpha in [1e-3, 0.1, ALPHA, 1.2, 1.5] {
        let ramp = Ramp::new(alpha, 0.0).unwrap();
        let p = viscous_disk_period(&Disk::perfect(), &ramp);
        assert!(!p.halts);
        assert!(
            (p.mean_angular_speed - alpha.sin()).abs() <= 1e-12 * alpha.sin(),
            "α = {alpha}: 2π/T = {} vs sin α = {}",
            p.mean_angular_speed,
            alpha.sin()
        );
    }
}

#[test]
fn perfect_disk_rolls_at_sin_alpha() {
    let body = Body::Disk(Disk::perfect());
    let ramp = Ramp::new(ALPHA, 0.0).unwrap();
    let init = InitialState::Disk {
        theta0: 0.4,
        theta_dot0: 0.0,
    };
    let (rows, _) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 50.0, 11);
    for r in &rows {
        let t = r[0];
        assert!(
            (r[1] - (0.4 + t * ALPHA.sin())).abs() < 1e-9,
            "θ({t}) = {}",
            r[1]
        );
        assert!((r[2] - ALPHA.sin()).abs() < 1e-12);
        // the centre sits at height 1 and moves downhill at sin α (it starts at x = 0)
        assert!((r[4] - t * ALPHA.sin()).abs() < 1e-9);
        assert!((r[5] - 1.0).abs() < 1e-14);
    }
}

#[test]
fn perfect_disk_inertial_relaxes_exponentially() {
    let body = Body::Disk(Disk::perfect());
    let m = 2.0;
    let ramp = Ramp::new(ALPHA, m).unwrap();
    let init = InitialState::Disk {
        theta0: 0.0,
        theta_dot0: 0.0,
    };
    let (rows, _) = common::run_rows(&body, ramp, init, Method::dop853(1e-11), 30.0, 31);
    let tau = 1.5 * m;
    for r in &rows {
        let t = r[0];
        let omega = ALPHA.sin() * (1.0 - (-t / tau).exp());
        let theta = ALPHA.sin() * (t - tau * (1.0 - (-t / tau).exp()));
        assert!((r[2] - omega).abs() < 1e-9, "θ̇({t}) = {} vs {omega}", r[2]);
        assert!((r[1] - theta).abs() < 1e-9, "θ({t}) = {} vs {theta}", r[1]);
    }
}

#[test]
fn perfect_sphere_rolls_straight_down_at_sin_alpha() {
    let body = Body::Sphere(Sphere::perfect());
    let ramp = Ramp::new(ALPHA, 0.0).unwrap();
    let q0 = DQuat::from_euler(glam::EulerRot::ZYX, 0.7, -0.3, 1.9);
    let init = InitialState::Sphere {
        q0,
        omega0: DVec3::ZERO,
    };
    let (rows, summary) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 100.0, 21);
    for r in &rows {
        let t = r[0];
        // ω = (0, sin α, 0), centre (t sin α, 0, 1)
        assert!((r[8]).abs() < 1e-12 && (r[9] - ALPHA.sin()).abs() < 1e-12 && r[10].abs() < 1e-12);
        assert!((r[11] - t * ALPHA.sin()).abs() < 1e-9, "x({t}) = {}", r[11]);
        assert!(r[12].abs() < 1e-9 && (r[13] - 1.0).abs() < 1e-12);
    }
    // The orientation is a rotation about y by angle t sin α applied to q0.
    let last = rows.last().unwrap();
    let expect = DQuat::from_rotation_y(100.0 * ALPHA.sin()) * q0;
    let got = DQuat::from_xyzw(last[2], last[3], last[4], last[1]);
    assert!(
        got.dot(expect).abs() > 1.0 - 1e-16,
        "q(100) = {got:?}, expected {expect:?}"
    );
    assert!(summary.max_quat_norm_error.unwrap() < 1e-14);
    assert!(summary.max_contact_normal_error.unwrap() < 1e-13);
}

#[test]
fn perfect_sphere_inertial_relaxes_exponentially() {
    let body = Body::Sphere(Sphere::perfect());
    let m = 3.0;
    let ramp = Ramp::new(ALPHA, m).unwrap();
    let init = InitialState::Sphere {
        q0: DQuat::IDENTITY,
        omega0: DVec3::ZERO,
    };
    let (rows, summary) = common::run_rows(&body, ramp, init, Method::dop853(1e-11), 30.0, 16);
    let tau = 1.4 * m;
    for r in &rows {
        let t = r[0];
        let omega = ALPHA.sin() * (1.0 - (-t / tau).exp());
        let x = ALPHA.sin() * (t - tau * (1.0 - (-t / tau).exp()));
        assert!(
            (r[9] - omega).abs() < 1e-9,
            "ω_y({t}) = {} vs {omega}",
            r[9]
        );
        assert!((r[11] - x).abs() < 1e-9, "x({t}) = {} vs {x}", r[11]);
    }
    assert!(
        summary.energy_drift.unwrap() < 1e-9,
        "{:?}",
        summary.energy_drift
    );
}
