//! The guide's library example (docs/guide/library.md) compiles and runs as written: it is read
//! from there, and the same code is run here. The typed API gives the command line's numbers to
//! the last digit, for every model and for the command line's ways to start a sphere. Needs no feature: `cargo test --no-default-features` runs it.

use crate::cli;
use rollphase::geometry::Body;
use rollphase::glam::{DQuat, DVec3};
use rollphase::integrate::Method;
use rollphase::simulate::{
    InitialState, Model, Sample, Simulation, Trajectory, simulate, simulate_streaming,
};

/// The example, as in the guide's `rust` block.
const EXAMPLE: &str = r#"use rollphase::geometry::Body;
use rollphase::simulate::{Model, Simulation, Trajectory, simulate};

let body = Body::paper_sphere(219, 0.25, 5)?; // the paper's own body (numpy seed 219)
println!("α* = {:.4}", body.alpha_star()); // 0.1394
let sim = Simulation::new(0.15, 200.0).model(Model::Inertial { mass_ratio: 6.0 });
let (trajectory, summary) = simulate(&body, &sim)?;
if let Trajectory::Sphere(path) = &trajectory {
    let (end, omega) = (path.com.last().unwrap(), path.omega.last().unwrap());
    println!("{} samples; x = {:.2} downhill, ω = {omega:?} at t = 200", path.t.len(), end.x);
}
println!("{} ran {} steps, |q| − 1 ≤ {:?}", summary.model, summary.steps, summary.max_quat_norm_error);"#;

#[test]
fn the_guide_shows_this_example() {
    let page = include_str!("../../docs/guide/library.md");
    assert!(
        page.contains(EXAMPLE),
        "the guide's library example (docs/guide/library.md) differs from tests/physics/library_use.rs; keep them the same"
    );
}

#[test]
fn the_library_example_runs() -> Result<(), Box<dyn std::error::Error>> {
    let body = Body::paper_sphere(219, 0.25, 5)?;
    assert!((body.alpha_star() - 0.1394).abs() < 1e-4);
    let sim = Simulation::new(0.15, 200.0).model(Model::Inertial { mass_ratio: 6.0 });
    let (trajectory, summary) = simulate(&body, &sim)?;
    let Trajectory::Sphere(path) = &trajectory else {
        panic!("a sphere's run gave a disk's trajectory");
    };
    assert_eq!(path.t.len(), 1001);
    assert_eq!(
        (path.q.len(), path.omega.len(), path.com.len()),
        (1001, 1001, 1001)
    );
    assert!(path.com.last().unwrap().x > 5.0, "it rolled downhill");
    assert_eq!(summary.model.to_string(), "sphere-inertial");
    assert!(summary.max_quat_norm_error.unwrap() < 1e-12);
    Ok(())
}

/// `rollphase simulate ARGS` as rows of numbers.
fn cli_rows(args: &[&str]) -> Vec<Vec<f64>> {
    let out = cli::rollphase_ok(std::iter::once("simulate").chain(args.iter().copied()));
    String::from_utf8(out)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// The typed samples as the CLI's rows.
fn typed_rows(body: &Body, sim: &Simulation) -> Vec<Vec<f64>> {
    let mut rows = Vec::new();
    simulate_streaming(body, sim, |s| {
        rows.push(match s {
            Sample::Disk(d) => vec![d.t, d.theta, d.theta_dot, d.psi, d.x, d.y],
            Sample::Sphere(s) => vec![
                s.t,
                s.q.w,
                s.q.x,
                s.q.y,
                s.q.z,
                s.contact.x,
                s.contact.y,
                s.contact.z,
                s.omega.x,
                s.omega.y,
                s.omega.z,
                s.com.x,
                s.com.y,
                s.com.z,
            ],
        })
    })
    .unwrap();
    rows
}

#[test]
fn the_typed_api_gives_the_command_lines_numbers_to_the_last_digit() {
    let shapes = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes");
    let sphere_file = format!("{shapes}/paper-sphere.json");
    let disk_file = format!("{shapes}/disk.json");
    let sphere = Body::from_file(sphere_file.as_ref()).unwrap();
    let disk = Body::from_file(disk_file.as_ref()).unwrap();
    // The paper's body equals the bundled file of it.
    assert_eq!(
        Body::paper_sphere(219, 0.25, 5).unwrap().to_shape(),
        sphere.to_shape()
    );
    let cases: Vec<(&Body, &str, Simulation, Vec<&str>)> = vec![
        (
            &sphere,
            &sphere_file,
            Simulation::new(0.15, 50.0).samples(51),
            vec!["--alpha", "0.15", "--t-end", "50", "--samples", "51"],
        ),
        (
            &sphere,
            &sphere_file,
            Simulation::new(0.15, 50.0)
                .samples(51)
                .model(Model::Inertial { mass_ratio: 6.0 })
                .initial(InitialState::Sphere {
                    q0: DQuat::from_xyzw(0.1, 0.2, 0.3, 0.9),
                    omega0: DVec3::new(0.0, 0.1, 0.0),
                }),
            vec![
                "--alpha",
                "0.15",
                "--t-end",
                "50",
                "--samples",
                "51",
                "--mass",
                "6",
                "--q0",
                "0.9,0.1,0.2,0.3",
                "--omega0",
                "0,0.1,0",
            ],
        ),
        (
            &sphere,
            &sphere_file,
            Simulation::new(0.15, 50.0)
                .samples(51)
                .initial(InitialState::touching(&sphere, 1.0, 2.0, 0.5).unwrap()),
            vec![
                "--alpha",
                "0.15",
                "--t-end",
                "50",
                "--samples",
                "51",
                "--contact",
                "1,2",
                "--spin",
                "0.5",
            ],
        ),
        (
            &disk,
            &disk_file,
            Simulation::new(0.3, 50.0).samples(51),
            vec!["--alpha", "0.3", "--t-end", "50", "--samples", "51"],
        ),
        (
            &disk,
            &disk_file,
            Simulation::new(0.3, 50.0)
                .samples(51)
                .model(Model::Inertial { mass_ratio: 2.0 })
                .method(Method::Cf4 { dt: 0.01 }),
            vec![
                "--alpha",
                "0.3",
                "--t-end",
                "50",
                "--samples",
                "51",
                "--mass",
                "2",
                "--integrator",
                "cf4",
                "--dt",
                "0.01",
            ],
        ),
    ];
    for (body, file, sim, args) in cases {
        let mut cli_args: Vec<&str> = vec![file];
        cli_args.extend(args.iter().copied());
        let (typed, cli) = (typed_rows(body, &sim), cli_rows(&cli_args));
        assert_eq!(typed.len(), cli.len(), "{args:?}");
        for (a, b) in typed.iter().zip(&cli) {
            // The CSV holds each number in its shortest round-trip form: equal as f64.
            assert_eq!(a, b, "{args:?}");
        }
    }
}

#[test]
fn bad_typed_input_is_an_error_not_a_panic() {
    let body = Body::paper_sphere(219, 0.25, 5).unwrap();
    let bad = [
        Simulation::new(f64::NAN, 10.0),
        Simulation::new(2.0, 10.0),
        Simulation::new(0.15, -1.0),
        Simulation::new(0.15, 10.0).model(Model::Inertial { mass_ratio: 0.0 }),
        Simulation::new(0.15, 10.0).model(Model::Inertial {
            mass_ratio: f64::INFINITY,
        }),
        Simulation::new(0.15, 10.0).samples(1),
        Simulation::new(0.15, 10.0).initial(InitialState::Disk {
            theta0: 0.0,
            theta_dot0: 0.0,
        }),
    ];
    for sim in bad {
        let e = simulate(&body, &sim).expect_err(&format!("{sim:?} was accepted"));
        assert!(!e.to_string().is_empty());
    }
    assert!(Body::paper_sphere(1 << 40, 0.25, 5).is_err());
    assert!(Body::random_sphere(1, -0.25, 5).is_err());
    assert!(Body::from_file("/nonexistent/shape.json".as_ref()).is_err());
}
