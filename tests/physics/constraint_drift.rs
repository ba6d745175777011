//! Over 10⁵ time units a 3D run keeps |q| = 1 and the contact normal at (0, 0, −1) to ≤ 1e-9
//! (the bound), with no periodic re-projection: q is projected after every step
//! (DOP853) or moved by exponentials (CF4), and the contact is recovered from q each time.

use crate::common;

use glam::DVec3;
use rollphase::analysis::critical_angle;
use rollphase::dynamics::Ramp;
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::geometry::Body;
use rollphase::integrate::Method;
use rollphase::simulate::InitialState;

#[test]
fn viscous_run_of_1e5_time_units_holds_the_constraints() {
    let body = common::sphere(1);
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let alpha = critical_angle(&body).alpha_star + 0.05;
    let q0 = orientation_touching(s, DVec3::new(0.2, -0.5, 0.7).normalize(), 0.9);
    let init = InitialState::Sphere {
        q0,
        omega0: DVec3::ZERO,
    };
    let ramp = Ramp::new(alpha, 0.0).unwrap();
    let (rows, sum) = common::run_rows(&body, ramp, init, Method::dop853(1e-10), 1e5, 101);
    let qe = sum.max_quat_norm_error.unwrap();
    let ne = sum.max_contact_normal_error.unwrap();
    println!(
        "10⁵ units: max ||q|−1| = {qe:e}, max contact-normal error = {ne:e}, {} RHS",
        sum.rhs_evals
    );
    assert!(qe <= 1e-9 && ne <= 1e-9, "|q|−1 {qe:e}, normal {ne:e}");
    // it cruised the whole time (above α*): the centre went far downhill
    assert!(rows.last().unwrap()[11] > 1e3);
}

#[test]
fn inertial_cf4_run_holds_the_quaternion_norm() {
    let body = common::sphere(3);
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    let q0 = orientation_touching(s, DVec3::new(-0.6, 0.1, 0.4).normalize(), 2.0);
    let init = InitialState::Sphere {
        q0,
        omega0: DVec3::ZERO,
    };
    let ramp = Ramp::new(0.4, 2.0).unwrap();
    let (_, sum) = common::run_rows(&body, ramp, init, Method::Cf4 { dt: 0.05 }, 1e4, 11);
    assert!(
        sum.max_quat_norm_error.unwrap() <= 1e-12,
        "{:?}",
        sum.max_quat_norm_error
    );
    assert!(sum.max_contact_normal_error.unwrap() <= 1e-12);
}
