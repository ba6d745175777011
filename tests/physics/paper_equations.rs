//! The paper's 2D inertial equation (SI §1A, dimensionless θ̈) checked against ours, derived from
//! the Lagrangian (see `dynamics::disk2d`). Finding: they agree. The drive and drag terms agree
//! exactly, and the θ̇² ("centrifugal") coefficients agree to 1.3e-9 relative, the accuracy of the
//! finite-difference κ' used to evaluate the paper's form.

use crate::common;

use rollphase::dynamics::{DiskInertial, Ramp};
use rollphase::geometry::Body;

/// The paper's θ̈ (SI, dimensionless, F = γ = ⟨r⟩ = 1, I = m/2), derivatives of κ by central
/// differences (h = 1e-5, error ~1e-10, far below the differences that matter here).
fn paper_theta_ddot(
    disk: &rollphase::geometry::Disk,
    m: f64,
    alpha: f64,
    theta: f64,
    td: f64,
) -> f64 {
    let j = disk.jet(theta);
    let (r, r1, r2) = (j.r, j.r1, j.r2);
    let kappa = |t: f64| disk.jet(t).curvature();
    let h = 1e-5;
    let k = kappa(theta);
    let dk = (kappa(theta + h) - kappa(theta - h)) / (2.0 * h);
    let d_rk = r1 * k + r * dk; // (r κ)'
    let d_r2k = 2.0 * r * r1 * k + r * r * dk; // (r² κ)'
    let i = 0.5 * m;
    let big = i + m * r * r;
    let drive = r * (r * alpha.sin() - r1 * alpha.cos()) / (k * (r * r + r1 * r1));
    let bracket = (i + m * r1 * r1) / big * r * d_rk
        + k * r1 * r2
        + m * r * r / big * d_r2k
        + i / big * r1 * r1 * dk;
    (drive - td) / big - bracket * td * td / (k * (r * r + r1 * r1))
}

#[test]
fn drive_and_drag_terms_match_the_paper_exactly() {
    let body = common::disk(21, 0.12, 5);
    let Body::Disk(d) = &body else { unreachable!() };
    for m in [0.5, 2.0, 10.0] {
        let ramp = Ramp::new(0.15, m).unwrap();
        let ours = DiskInertial::new(d, &ramp);
        for k in 0..64 {
            let theta = k as f64 * 0.1;
            // θ̇ = 0 isolates the drive term; the drag term is linear in θ̇ and tested at ±θ̇.
            let a0 = ours.theta_ddot(theta, 0.0);
            let p0 = paper_theta_ddot(d, m, 0.15, theta, 0.0);
            assert!(
                (a0 - p0).abs() <= 1e-12 * (1.0 + p0.abs()),
                "drive at θ = {theta}: {a0} vs {p0}"
            );
            let lin_ours = 0.5 * (ours.theta_ddot(theta, 1e-3) - ours.theta_ddot(theta, -1e-3));
            let lin_paper = 0.5
                * (paper_theta_ddot(d, m, 0.15, theta, 1e-3)
                    - paper_theta_ddot(d, m, 0.15, theta, -1e-3));
            assert!(
                (lin_ours - lin_paper).abs() <= 1e-10 * (1.0 + lin_paper.abs()),
                "drag at θ = {theta}"
            );
        }
    }
}

/// Coefficient of θ̇² in θ̈, from the even part of θ̈(θ̇).
fn quadratic_coefficient(f: impl Fn(f64) -> f64) -> f64 {
    (f(1.0) + f(-1.0) - 2.0 * f(0.0)) / 2.0
}

#[test]
fn centrifugal_coefficient_compared_with_the_paper() {
    let body = common::disk(21, 0.12, 5);
    let Body::Disk(d) = &body else { unreachable!() };
    let m = 2.0;
    let ramp = Ramp::new(0.15, m).unwrap();
    let ours = DiskInertial::new(d, &ramp);
    let mut worst = 0.0f64;
    for k in 0..64 {
        let theta = k as f64 * 0.1;
        let a = quadratic_coefficient(|td| ours.theta_ddot(theta, td));
        let p = quadratic_coefficient(|td| paper_theta_ddot(d, m, 0.15, theta, td));
        worst = worst.max((a - p).abs() / (1e-3 + a.abs()));
    }
    println!("largest relative difference in the θ̇² coefficient: {worst:e}");
    assert!(
        worst < 1e-7,
        "the paper's θ̇² coefficient differs from the Lagrangian one by {worst:e}"
    );
}
