//! The numerics hold at the extremes: α within 1e-6 of α*, α → 0 and α → π/2, m/m0 from 1e-4 to
//! 1e3, and bodies at the edge of convexity. Every run must finish with finite output and the
//! constraints intact; where a limit is known the result must approach it.

use crate::common;

use glam::DVec3;
use rollphase::analysis::{critical_angle, viscous_disk_period};
use rollphase::dynamics::Ramp;
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::geometry::{Body, Disk, DiskMode};
use rollphase::integrate::Method;
use rollphase::simulate::InitialState;
use std::f64::consts::{FRAC_PI_2, TAU};

/// Every value of every row is finite, but the last column, the friction needed, which is
/// infinite where the ramp no longer presses the body (N ≤ 0, as on a near-vertical ramp).
fn finite(rows: &[Vec<f64>]) -> bool {
    rows.iter()
        .all(|r| r[..r.len() - 1].iter().all(|v| v.is_finite()) && !r[r.len() - 1].is_nan())
}

#[test]
fn within_1e6_of_alpha_star_the_disk_halts_below_and_its_simulated_period_matches_above() {
    let body = common::disk(5, 0.08, 10);
    let Body::Disk(d) = &body else { unreachable!() };
    let ca = critical_angle(&body);
    // Below: starting just past the bottleneck θ*, the disk creeps to the stable rest point.
    let below = Ramp::new(ca.alpha_star - 1e-6, 0.0).unwrap();
    let init = InitialState::Disk {
        theta0: ca.theta + 0.5,
        theta_dot0: 0.0,
    };
    let (rows, _) = common::run_rows(&body, below, init, Method::dop853(1e-10), 20_000.0, 201);
    assert!(finite(&rows));
    let last = rows.last().unwrap();
    assert!(last[2].abs() < 1e-9, "θ̇ at the end {}", last[2]);
    assert!(
        last[1] < ca.theta + TAU,
        "it never completed a turn: θ = {}",
        last[1]
    );
    // Above: the simulated time for one turn from θ* equals the quadrature period, although it is
    // dominated by the passage through the bottleneck, T ≈ T*/√δα.
    let above = Ramp::new(ca.alpha_star + 1e-6, 0.0).unwrap();
    let t_quad = viscous_disk_period(d, &above).period.unwrap();
    let init = InitialState::Disk {
        theta0: ca.theta,
        theta_dot0: 0.0,
    };
    let (rows, _) = common::run_rows(&body, above, init, Method::dop853(1e-12), t_quad, 2);
    let turned = rows.last().unwrap()[1] - ca.theta;
    assert!(
        (turned - TAU).abs() < 1e-5,
        "after one quadrature period θ advanced {turned} (T = {t_quad})"
    );
    assert!(t_quad > 1000.0, "near α* the period diverges: T = {t_quad}");
}

#[test]
fn at_alpha_near_zero_bodies_halt_without_drift() {
    for body in [common::disk(2, 0.08, 10), common::sphere(2)] {
        let ramp = Ramp::new(1e-6, 0.0).unwrap();
        let init = match &body {
            Body::Disk(_) => InitialState::Disk {
                theta0: 1.0,
                theta_dot0: 0.0,
            },
            Body::Sphere(s) => InitialState::Sphere {
                q0: orientation_touching(s, DVec3::new(0.3, 0.4, -0.8).normalize(), 0.2),
                omega0: DVec3::ZERO,
            },
        };
        let (rows, sum) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 2000.0, 5);
        assert!(finite(&rows));
        let x = |r: &Vec<f64>| if body.dimension() == 2 { r[4] } else { r[11] };
        let (mid, end) = (&rows[2], &rows[4]);
        assert!(
            (x(end) - x(mid)).abs() < 1e-9,
            "drift after halting: {} → {}",
            x(mid),
            x(end)
        );
        if let Some(e) = sum.max_contact_normal_error {
            assert!(e < 1e-12);
        }
    }
}

#[test]
fn at_alpha_near_a_quarter_turn_rolling_is_fast_and_controlled() {
    let alpha = FRAC_PI_2 - 1e-6;
    let Body::Disk(d) = common::disk(2, 0.08, 10) else {
        unreachable!()
    };
    let p = viscous_disk_period(&d, &Ramp::new(alpha, 0.0).unwrap());
    // Nearly vertical: θ̇ ≈ r(r·1 − r'·0)/((r² + r'²)κ) ≈ 1, so 2π/T ≈ 1 to O(σ).
    assert!(
        (p.mean_angular_speed - 1.0).abs() < 0.05,
        "2π/T = {}",
        p.mean_angular_speed
    );
    for (body, m) in [
        (common::sphere(2), 0.0),
        (common::sphere(2), 1.0),
        (common::disk(2, 0.12, 5), 1.0),
    ] {
        let ramp = Ramp::new(alpha, m).unwrap();
        let init = match &body {
            Body::Disk(_) => InitialState::Disk {
                theta0: 0.0,
                theta_dot0: 0.0,
            },
            Body::Sphere(s) => InitialState::Sphere {
                q0: orientation_touching(s, DVec3::X, 0.0),
                omega0: DVec3::ZERO,
            },
        };
        let (rows, sum) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 100.0, 11);
        assert!(finite(&rows));
        // ~1 turn per 2π time units: a few hundred steps, not a collapse of the step size.
        assert!(sum.steps < 5000, "{} steps", sum.steps);
        let x = if body.dimension() == 2 {
            rows.last().unwrap()[4]
        } else {
            rows.last().unwrap()[11]
        };
        assert!(x > 50.0, "rolled only {x}");
    }
}

#[test]
fn mass_ratio_from_1e_minus_4_to_1e3_stays_finite_and_meets_its_limits() {
    for body in [common::disk(2, 0.12, 5), common::sphere(2)] {
        let alpha = critical_angle(&body).alpha_star + 0.1;
        let init = match &body {
            Body::Disk(_) => InitialState::Disk {
                theta0: 0.0,
                theta_dot0: 0.0,
            },
            Body::Sphere(s) => InitialState::Sphere {
                q0: orientation_touching(s, DVec3::Y, 0.3),
                omega0: DVec3::ZERO,
            },
        };
        let t_end = if body.dimension() == 2 { 20.0 } else { 5.0 };
        let (viscous, _) = common::run_rows(
            &body,
            Ramp::new(alpha, 0.0).unwrap(),
            init,
            Method::dop853(1e-10),
            t_end,
            2,
        );
        for m in [1e-4, 1e-2, 1.0, 1e3] {
            let (rows, sum) = common::run_rows(
                &body,
                Ramp::new(alpha, m).unwrap(),
                init,
                Method::dop853(1e-10),
                t_end,
                2,
            );
            assert!(finite(&rows), "m = {m}");
            let last = rows.last().unwrap();
            let scale = last.iter().map(|v| v.abs()).fold(1.0, f64::max);
            assert!(
                sum.energy_drift.unwrap() < 1e-7 * scale,
                "m = {m}: energy drift {:?}",
                sum.energy_drift
            );
            if m == 1e-4 {
                // The inertial correction is O(m): positions agree with the viscous model to ≈ m.
                let (i, v) = if body.dimension() == 2 {
                    (last[4], viscous[1][4])
                } else {
                    (last[11], viscous[1][11])
                };
                assert!((i - v).abs() < 10.0 * m, "m = {m}: x {i} vs viscous {v}");
            }
            if m == 1e3 {
                // Heavy: drag is negligible (τ ≈ 1.5 m ≫ t) and the drag-free equations are
                // invariant under t → t√m, so x(2t; 4m) = x(t; m) up to O(t/m) drag corrections.
                let (heavier, _) = common::run_rows(
                    &body,
                    Ramp::new(alpha, 4.0 * m).unwrap(),
                    init,
                    Method::dop853(1e-10),
                    2.0 * t_end,
                    2,
                );
                let col = if body.dimension() == 2 { 4 } else { 11 };
                let x1 = last[col] - rows[0][col];
                let x4 = heavier[1][col] - heavier[0][col];
                assert!(
                    x1 > 0.0 && (x4 / x1 - 1.0).abs() < 0.02,
                    "m = {m}: x(t; m) = {x1}, x(2t; 4m) = {x4}"
                );
            }
        }
    }
}

/// Scales every amplitude of a body by `s`.
fn scaled_disk(d: &Disk, s: f64) -> Disk {
    Disk::new(
        d.modes()
            .iter()
            .map(|m| DiskMode { a: m.a * s, ..*m })
            .collect(),
    )
}

/// The largest scale factor that keeps the body convex, by bisection.
fn convexity_limit(make: impl Fn(f64) -> Body) -> f64 {
    let (mut lo, mut hi) = (1.0, 64.0);
    assert!(make(lo).check_convex().is_ok() && make(hi).check_convex().is_err());
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if make(mid).check_convex().is_ok() {
            lo = mid
        } else {
            hi = mid
        }
    }
    lo
}

#[test]
fn bodies_at_the_edge_of_convexity_still_roll_cleanly() {
    let Body::Disk(d) = common::disk(2, 0.08, 10) else {
        unreachable!()
    };
    let s = convexity_limit(|s| Body::Disk(scaled_disk(&d, s)));
    let edge = Body::Disk(scaled_disk(&d, 0.98 * s));
    let c = edge.curvature();
    assert!(
        c.convex && c.convexity_min < 0.1,
        "κ_min = {}",
        c.convexity_min
    );
    let (rows, _) = common::run_rows(
        &edge,
        Ramp::new(0.6, 0.0).unwrap(),
        InitialState::Disk {
            theta0: 0.0,
            theta_dot0: 0.0,
        },
        Method::dop853(1e-10),
        100.0,
        101,
    );
    assert!(finite(&rows));

    let Body::Sphere(sp) = common::sphere(2) else {
        unreachable!()
    };
    let s = convexity_limit(|s| Body::Sphere(common::scaled_sphere(&sp, s)));
    let edge_sphere = common::scaled_sphere(&sp, 0.98 * s);
    let body = Body::Sphere(edge_sphere.clone());
    let c = body.curvature();
    assert!(
        c.convex && c.convexity_min < 0.1,
        "k_min = {}",
        c.convexity_min
    );
    let alpha = (critical_angle(&body).alpha_star + 0.1).min(1.5);
    for m in [0.0, 1.0] {
        let init = InitialState::Sphere {
            q0: orientation_touching(&edge_sphere, DVec3::new(0.1, 0.9, 0.3).normalize(), 1.0),
            omega0: DVec3::ZERO,
        };
        let (rows, sum) = common::run_rows(
            &body,
            Ramp::new(alpha, m).unwrap(),
            init,
            Method::dop853(1e-10),
            100.0,
            101,
        );
        assert!(finite(&rows));
        assert!(
            sum.max_quat_norm_error.unwrap() < 1e-12
                && sum.max_contact_normal_error.unwrap() < 1e-12,
            "{sum:?}"
        );
    }
}
