//! What an independent implementation will compare with: q(t = 100) at rtol 1e-10 is within
//! 1e-8 of the converged answer (so agreement to ~1e-6 is limited by the other side, not ours),
//! and the same inputs give byte-identical CSV output on every run.

use crate::common;

use std::process::Command;

use glam::DQuat;
use rollphase::cli::load_body;
use rollphase::dynamics::Ramp;
use rollphase::dynamics::sphere3d::orientation_touching;
use rollphase::geometry::{Body, sphere::direction};
use rollphase::integrate::Method;
use rollphase::simulate::InitialState;

fn bundled(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/shapes")
        .join(name)
}

fn final_q(body: &Body, ramp: Ramp, init: InitialState, rtol: f64) -> DQuat {
    let (rows, _) = common::run_rows(body, ramp, init, Method::dop853(rtol), 100.0, 2);
    let r = rows.last().unwrap();
    DQuat::from_xyzw(r[2], r[3], r[4], r[1])
}

#[test]
fn q_at_t100_is_converged_at_rtol_1e10() {
    let body = load_body(&bundled("sphere.json")).unwrap();
    let Body::Sphere(s) = &body else {
        unreachable!()
    };
    for (alpha, mass, theta, phi, spin) in [
        (0.3, 0.0, 1.0, 2.0, 0.5),
        (0.2, 0.0, 2.5, -1.0, 3.0),
        (0.3, 2.0, 0.4, 0.3, 1.0),
    ] {
        let ramp = Ramp::new(alpha, mass).unwrap();
        let init = InitialState::Sphere {
            q0: orientation_touching(s, direction(theta, phi), spin),
            omega0: glam::DVec3::ZERO,
        };
        let q = final_q(&body, ramp, init, 1e-10);
        let reference = final_q(&body, ramp, init, 1e-13);
        let err = (q - reference).length().min((q + reference).length());
        assert!(err < 1e-8, "α {alpha}, m {mass}: |Δq(100)| = {err:e}");
    }
}

#[test]
fn same_inputs_give_byte_identical_csv() {
    let dir = crate::cli::scratch("repro");
    std::fs::create_dir_all(&dir).unwrap();
    let run = |shape: &str, extra: &[&str], out: &str| {
        let path = dir.join(out);
        let status = Command::new(crate::cli::binary())
            .arg("simulate")
            .arg(bundled(shape))
            .args(extra)
            .arg("-o")
            .arg(&path)
            .status()
            .unwrap();
        assert!(status.success());
        std::fs::read(path).unwrap()
    };
    let args3 = [
        "--alpha",
        "0.3",
        "--t-end",
        "50",
        "--contact",
        "1,2",
        "--spin",
        "0.5",
        "--mass",
        "1.5",
    ];
    assert_eq!(
        run("sphere.json", &args3, "a.csv"),
        run("sphere.json", &args3, "b.csv")
    );
    let args2 = [
        "--alpha", "0.2", "--t-end", "50", "--mass", "3", "--theta0", "0.7",
    ];
    assert_eq!(
        run("disk-inertial.json", &args2, "c.csv"),
        run("disk-inertial.json", &args2, "d.csv")
    );
}

/// Observers never move a run: the rows a run records (their dense output, whose extra stages
/// look up the contact aside the steps), its health and its rest test leave its steps bit for
/// bit as they were, so a run sampled 3 times ends where the same run sampled 2001 times does.
#[test]
fn recording_more_rows_never_moves_the_run() {
    use rollphase::simulate::{Model, Simulation, Trajectory, simulate};
    let sphere = Body::paper_sphere(219, 0.25, 5).unwrap();
    let disk = Body::paper_disk(84, 0.12, 5).unwrap();
    for (body, mass) in [(&sphere, 0.0), (&sphere, 6.0), (&disk, 2.0)] {
        let run = |samples: usize| {
            let mut sim = Simulation::new(0.15, 200.0).samples(samples);
            if mass > 0.0 {
                sim = sim.model(Model::Inertial { mass_ratio: mass });
            }
            simulate(body, &sim).unwrap().0
        };
        let (few, many) = (run(3), run(2001));
        match (few, many) {
            (Trajectory::Sphere(a), Trajectory::Sphere(b)) => {
                assert_eq!(a.q[1], b.q[1000], "m/m0 = {mass}, t = 100");
                assert_eq!(a.q[2], b.q[2000], "m/m0 = {mass}, t = 200");
                assert_eq!(a.com[2], b.com[2000]);
            }
            (Trajectory::Disk(a), Trajectory::Disk(b)) => {
                assert_eq!(a.theta[2], b.theta[2000]);
                assert_eq!(a.x[2], b.x[2000]);
            }
            _ => unreachable!(),
        }
    }
}
