//! Energy balance of the inertial models, for irregular bodies (SI §1A, §2A):
//! with zero drag E = ½Iω² + ½m|v|² − F·x_cm is conserved; with drag, E(t) + W(t) = E(0) where
//! W = ∫γ|ω|²dt is the dissipated work. Over 1000 time units at rtol 1e-10 the issue requires
//! |ΔE| ≤ 1e-8. Also: as m/m0 → 0 the inertial disk approaches the viscous one.

use crate::common;

use glam::DVec3;
use rollphase::analysis::{critical_angle, inertial_disk_period, viscous_disk_period};
use rollphase::dynamics::Ramp;
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::geometry::Body;
use rollphase::integrate::Method;
use rollphase::simulate::InitialState;

/// The rest contact angle the viscous disk reaches from θ₀ below α* (a stable equilibrium).
fn disk_rest_angle(body: &Body, alpha: f64, theta0: f64) -> f64 {
    let ramp = Ramp::new(alpha, 0.0).unwrap();
    let init = InitialState::Disk {
        theta0,
        theta_dot0: 0.0,
    };
    let (rows, _) = common::run_rows(body, ramp, init, Method::dop853(1e-12), 400.0, 2);
    let last = rows.last().unwrap();
    assert!(
        last[2].abs() < 1e-9,
        "the viscous disk has not halted: θ̇ = {}",
        last[2]
    );
    last[1]
}

#[test]
fn disk_without_drag_conserves_energy_over_1000_time_units() {
    let body = common::disk(7, 0.12, 5);
    let alpha = 0.5 * critical_angle(&body).alpha_star;
    // Kicked gently from a stable rest point, the disk rocks in its potential well forever:
    // a bounded conservative motion, so the energy error cannot hide behind growing energies.
    let theta_rest = disk_rest_angle(&body, alpha, 1.0);
    let ramp = Ramp::with_drag(alpha, 2.0, 0.0).unwrap();
    let init = InitialState::Disk {
        theta0: theta_rest,
        theta_dot0: 0.01,
    };
    let (rows, s) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 1000.0, 2001);
    let drift = s.energy_drift.unwrap();
    assert!(drift <= 1e-8, "|ΔE| = {drift:e}");
    let thetas: Vec<f64> = rows.iter().map(|r| r[1]).collect();
    let span = thetas.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - thetas.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(
        span > 1e-3 && span < 1.0,
        "θ stays in its well and moves: range {span}"
    );
}

#[test]
fn disk_rolling_freely_without_drag_conserves_energy() {
    // Above α* with no drag the disk accelerates without bound: E stays constant while the
    // kinetic and potential parts each grow large.
    let body = common::disk(3, 0.12, 5);
    let ramp = Ramp::with_drag(0.3, 1.0, 0.0).unwrap();
    let init = InitialState::Disk {
        theta0: 0.0,
        theta_dot0: 0.0,
    };
    let (rows, s) = common::run_rows(&body, ramp, init, Method::dop853(1e-12), 30.0, 11);
    let x_end = rows.last().unwrap()[4];
    assert!(x_end > 20.0, "rolled {x_end}");
    let rel = s.energy_drift.unwrap() / (0.3f64.sin() * x_end);
    assert!(rel <= 1e-10, "relative energy drift {rel:e}");
}

#[test]
fn disk_with_drag_balances_energy_and_dissipation() {
    let body = common::disk(11, 0.12, 5);
    let ramp = Ramp::new(0.2, 5.0).unwrap();
    let init = InitialState::Disk {
        theta0: 0.3,
        theta_dot0: 0.1,
    };
    let (rows, s) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 1000.0, 11);
    // E and W each grow by the work gravity does (sin α · x); the integrator controls them to
    // rtol relative, so their balance holds to a small multiple of rtol times that work.
    let work = 0.2f64.sin() * rows.last().unwrap()[4];
    assert!(work > 10.0, "the disk rolled: gravity did work {work}");
    let rel = s.energy_drift.unwrap() / work;
    assert!(
        rel <= 1e-9,
        "energy balance off by {rel:e} of the work done"
    );
}

#[test]
fn sphere_without_drag_conserves_energy_over_1000_time_units() {
    let body = common::sphere(5);
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let ca = critical_angle(&body);
    // Well below α*: at α*/2 a gentle kick can carry the body along its neutral loop of
    // equilibria (SI §2E) and off it, after which it accelerates without bound.
    let alpha = 0.25 * ca.alpha_star;
    // Let the viscous body halt from the point of highest Q: that is a stable rest orientation.
    let q_start = orientation_touching(s, DVec3::from_array(ca.direction), 0.4);
    let viscous = Ramp::new(alpha, 0.0).unwrap();
    let init = InitialState::Sphere {
        q0: q_start,
        omega0: DVec3::ZERO,
    };
    let (rows, _) = common::run_rows(&body, viscous, init, Method::dop853(1e-12), 400.0, 2);
    let last = rows.last().unwrap();
    let w = DVec3::new(last[8], last[9], last[10]).length();
    assert!(w < 1e-9, "the viscous body has not halted: |ω| = {w}");
    let q_rest = glam::DQuat::from_xyzw(last[2], last[3], last[4], last[1]);
    // Kicked gently, with no drag, it rocks about that orientation forever.
    let ramp = Ramp::with_drag(alpha, 1.0, 0.0).unwrap();
    let init = InitialState::Sphere {
        q0: q_rest,
        omega0: DVec3::new(0.004, -0.003, 0.002),
    };
    let (rows, sum) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 1000.0, 2001);
    let drift = sum.energy_drift.unwrap();
    assert!(drift <= 1e-8, "|ΔE| = {drift:e}");
    assert!(sum.max_quat_norm_error.unwrap() <= 1e-12);
    assert!(sum.max_contact_normal_error.unwrap() <= 1e-12);
    let travel = rows
        .iter()
        .map(|r| r[11].abs() + r[12].abs())
        .fold(0.0, f64::max);
    let spin = rows
        .iter()
        .map(|r| DVec3::new(r[8], r[9], r[10]).length())
        .fold(0.0, f64::max);
    assert!(
        travel < 1.0 && spin > 1e-3,
        "bounded rocking: travel {travel}, max |ω| {spin}"
    );
}

#[test]
fn sphere_rolling_freely_without_drag_conserves_energy() {
    let body = common::sphere(2);
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let ramp = Ramp::with_drag(0.35, 2.0, 0.0).unwrap();
    let q0 = orientation_touching(s, DVec3::new(0.3, 0.5, -0.8).normalize(), 1.0);
    let init = InitialState::Sphere {
        q0,
        omega0: DVec3::ZERO,
    };
    let (rows, sum) = common::run_rows(&body, ramp, init, Method::dop853(1e-12), 40.0, 11);
    let x_end = rows.last().unwrap()[11];
    assert!(x_end > 20.0, "rolled {x_end}");
    let rel = sum.energy_drift.unwrap() / (0.35f64.sin() * x_end);
    assert!(rel <= 1e-10, "relative energy drift {rel:e}");
}

#[test]
fn sphere_with_drag_balances_energy_and_dissipation() {
    let body = common::sphere(9);
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let ramp = Ramp::new(0.3, 4.0).unwrap();
    let q0 = orientation_touching(s, DVec3::new(-0.2, 0.9, 0.1).normalize(), 2.0);
    let init = InitialState::Sphere {
        q0,
        omega0: DVec3::new(0.0, 0.1, 0.0),
    };
    let (rows, sum) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 1000.0, 11);
    let work = 0.3f64.sin() * rows.last().unwrap()[11];
    assert!(work > 10.0, "the body rolled: gravity did work {work}");
    let rel = sum.energy_drift.unwrap() / work;
    assert!(
        rel <= 1e-9,
        "energy balance off by {rel:e} of the work done"
    );
}

#[test]
fn inertial_disk_approaches_the_viscous_limit_as_mass_vanishes() {
    let body = common::disk(4, 0.08, 10);
    let Body::Disk(d) = &body else { unreachable!() };
    let alpha = critical_angle(&body).alpha_star + 0.05;
    let viscous = viscous_disk_period(d, &Ramp::new(alpha, 0.0).unwrap()).mean_angular_speed;
    let mut last_gap = f64::INFINITY;
    for m in [1e-1, 1e-2, 1e-3] {
        let p = inertial_disk_period(d, &Ramp::new(alpha, m).unwrap(), 0.0, 0.0, 1e-10, 5000.0)
            .unwrap();
        assert!(p.converged && !p.halts, "m = {m}: {p:?}");
        let gap = (p.mean_angular_speed - viscous).abs() / viscous;
        // The correction is first order in m: the gap must shrink roughly tenfold per decade.
        assert!(
            gap < last_gap / 5.0,
            "m = {m}: gap {gap:e} after {last_gap:e}"
        );
        last_gap = gap;
    }
    assert!(last_gap < 1e-2, "at m = 1e-3 the gap is {last_gap:e}");
}
