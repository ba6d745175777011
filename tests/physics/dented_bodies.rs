//! Dented 2D bodies roll on their convex hull (issue 34): the hull's flats are tangent at both
//! ends; resting on a flat runs from the weight's line through one end to its line through the
//! other (so α* counts the flats); the viscous body tips across a flat or rests on it as the
//! statics say; the inertial body's impacts keep the angular momentum about the new contact and
//! its energy balance, impacts included, closes; a convex body's runs are unchanged.

use crate::cli::rollphase;

use rollphase::analysis::critical_angle;
use rollphase::dynamics::{DiskInertial, Ramp, RollingModel, Switched};
use rollphase::geometry::{Body, Disk};
use rollphase::integrate::run::{Flow, Run};
use rollphase::integrate::{IntegrateError, Method};
use rollphase::simulate::{InitialState, Model, Simulation, Trajectory, simulate};

/// The authors' printed σ = 0.5 cylinder (their `num_modes = 8`: our `--modes 9`).
fn printed() -> (Body, Disk) {
    let body = Body::paper_disk(219, 0.5, 9).unwrap();
    let Body::Disk(d) = body.clone() else {
        unreachable!()
    };
    (body, d)
}

#[test]
fn the_printed_cylinder_has_two_flats_and_its_alpha_star_counts_them() {
    let (body, d) = printed();
    assert!(body.check_convex().is_err() && body.check_rollable().is_ok());
    let bridges = d.hull().bridges();
    assert_eq!(bridges.len(), 2);
    // The dent: about 0.4 mm on a 10 mm radius.
    let deepest = bridges.iter().map(|b| b.depth).fold(0.0, f64::max);
    assert!((deepest - 0.04).abs() < 0.002, "{deepest}");
    for b in bridges {
        // Resting on a flat ends where the weight's line passes through its far end, which is
        // where the curve there would rest: atan Q(θ_b). Geometry (the bitangent) and statics
        // (the torque on the curve) agree to round-off.
        let q_b = d.jet(b.theta_b).quality();
        assert!((b.rest_angle().unwrap() - q_b.atan()).abs() < 1e-9, "{b:?}");
        let q_a = d.jet(b.theta_a).quality();
        assert!(
            ((-b.foot).atan2(b.height) - q_a.atan()).abs() < 1e-9,
            "{b:?}"
        );
    }
    let ca = critical_angle(&body);
    let flat = ca.flat.expect("a dented body reports its flats");
    assert_eq!(ca.alpha_star, flat.alpha.max(flat.curve_alpha));
    assert!(
        flat.alpha > flat.curve_alpha,
        "here a flat is the steepest rest"
    );
}

fn run(
    alpha: f64,
    model: Model,
    drag: f64,
    t_end: f64,
    theta0: f64,
) -> (Trajectory, rollphase::simulate::Summary) {
    let (body, _) = printed();
    let sim = Simulation::new(alpha, t_end)
        .model(model)
        .drag(drag)
        .samples(2001)
        .initial(InitialState::Disk {
            theta0,
            theta_dot0: 0.0,
        });
    simulate(&body, &sim).unwrap()
}

#[test]
fn viscous_it_rests_on_a_flat_below_alpha_star_and_tips_across_above() {
    let (body, _) = printed();
    let alpha_star = body.alpha_star();
    // Just below α*: from a start before the steepest flat it rolls onto it and rests there.
    let (tr, s) = run(alpha_star - 0.003, Model::Viscous, 1.0, 200.0, 4.5);
    let hull = s.hull.expect("a dented body reports its hull");
    assert!(hull.rested_t.is_some(), "{hull:?}");
    let Trajectory::Disk(d) = tr else {
        unreachable!()
    };
    let n = d.x.len();
    assert_eq!(d.x[n - 1], d.x[n - 2], "at rest");
    assert_eq!(d.theta_dot[n - 1], 0.0);
    // Just above: no rest anywhere, it tips across both flats every turn.
    let (tr, s) = run(alpha_star + 0.003, Model::Viscous, 1.0, 400.0, 4.5);
    let hull = s.hull.unwrap();
    assert_eq!(hull.rested_t, None);
    let Trajectory::Disk(d) = tr else {
        unreachable!()
    };
    let turns = ((d.theta[d.theta.len() - 1] - d.theta[0]) / std::f64::consts::TAU).floor();
    assert!(turns >= 2.0, "{turns}");
    assert!(
        hull.tips as f64 >= 2.0 * turns,
        "{hull:?} over {turns} turns"
    );
    assert_eq!(
        hull.tip_energy_lost, 0.0,
        "the viscous model has no kinetic energy"
    );
    // The motion is monotone: the centre only moves downhill.
    assert!(d.x.windows(2).all(|w| w[1] >= w[0] - 1e-12));
}

#[test]
fn inertial_impacts_keep_the_energy_balance_and_the_angular_momentum_about_the_new_contact() {
    // No drag: E + W (W holds the impacts' losses) is constant through every impact, and what
    // the impacts took is what gravity gave less the kinetic energy gained.
    let (tr, s) = run(0.3, Model::Inertial { mass_ratio: 2.0 }, 0.0, 200.0, 1.5);
    let hull = s.hull.unwrap();
    assert!(hull.tips > 40, "{hull:?}");
    assert!(s.energy_drift.unwrap() < 1e-6, "{:?}", s.energy_drift);
    let Trajectory::Disk(d) = tr else {
        unreachable!()
    };
    let n = d.t.len() - 1;
    let (_, disk) = printed();
    let model = DiskInertial::new(&disk, &Ramp::with_drag(0.3, 2.0, 0.0).unwrap());
    let kinetic = |i: usize| 0.5 * model.reduced_inertia(d.theta[i]) * d.theta_dot[i].powi(2);
    let released = 0.3f64.sin() * (d.x[n] - d.x[0]) - 0.3f64.cos() * (d.y[n] - d.y[0]);
    let balance = released - (kinetic(n) - kinetic(0)) - hull.tip_energy_lost;
    assert!(balance.abs() < 1e-5 * released, "{balance} of {released}");

    // One impact, directly: arriving at a flat's uphill end, the body pivots onto the far end
    // with the angular momentum about the far end kept.
    let b = disk.hull().bridges()[0];
    let y = [b.theta_a, 0.8, 0.0, 0.0];
    assert!(model.switching(&y).unwrap().abs() < 1e-9);
    let (after, what) = model.switch(&y).unwrap();
    let Switched::Tip { energy_lost } = what else {
        panic!("{what:?}")
    };
    let point = |t: f64| {
        let r = disk.jet(t).r;
        [r * t.cos(), r * t.sin()]
    };
    let (pa, pb) = (point(b.theta_a), point(b.theta_b));
    let m = 2.0;
    let inertia = 0.5 * m;
    let psi = |theta: f64, theta_dot: f64| -disk.jet(theta).turn_rate() * theta_dot;
    let (w_before, w_after) = (psi(b.theta_a, 0.8), psi(after[0], after[1]));
    // About P_b: I ω + m (c − P_b) × v, with v = ω k × (c − P_a) before and ω k × (c − P_b) after.
    let dot = pa[0] * pb[0] + pa[1] * pb[1];
    let h_before = w_before * (inertia + m * dot);
    let h_after = w_after * (inertia + m * (pb[0] * pb[0] + pb[1] * pb[1]));
    assert!(
        (h_before - h_after).abs() < 1e-12 * h_before.abs(),
        "{h_before} {h_after}"
    );
    assert!((after[0] - b.theta_b).abs() < 1e-12 && (after[2] - b.length).abs() < 1e-12);
    assert!(energy_lost > 0.0 && (after[3] - energy_lost).abs() < 1e-15);
}

#[test]
fn a_rocking_body_comes_to_rest_on_a_flat() {
    // Heavy and gentle: it rocks across a flat, each impact taking energy, then rests on it.
    let (_, s) = run(0.1, Model::Inertial { mass_ratio: 5.0 }, 1.0, 300.0, 1.5);
    let hull = s.hull.unwrap();
    assert!(hull.rested_t.is_some() && hull.tips > 5, "{hull:?}");
    assert!(s.energy_drift.unwrap() < 1e-7);
}

#[test]
fn a_convex_body_runs_exactly_as_before() {
    // The hull adds nothing to a convex body: the run is the plain integration, bit for bit.
    let body = Body::paper_disk(84, 0.12, 5).unwrap();
    let Body::Disk(disk) = body.clone() else {
        unreachable!()
    };
    assert!(disk.hull().bridges().is_empty());
    let sim = Simulation::new(0.1, 50.0)
        .model(Model::Inertial { mass_ratio: 2.0 })
        .samples(2);
    let (tr, s) = simulate(&body, &sim).unwrap();
    assert!(s.hull.is_none());
    let model = DiskInertial::new(&disk, &Ramp::new(0.1, 2.0).unwrap());
    let mut run = Run::new(&model, 0.0, [0.0; 4], Method::dop853(1e-10)).unwrap();
    run.until::<IntegrateError>(50.0, 1_000_000, |_| Ok(Flow::Continue))
        .unwrap();
    let Trajectory::Disk(d) = tr else {
        unreachable!()
    };
    assert_eq!(d.theta[1], run.y()[0]);
    assert_eq!(d.theta_dot[1], run.y()[1]);
    // The same steps (the run's evaluation count is larger: the contact force it follows
    // reads each step's dense output, whose stages DOP853 evaluates on demand).
    assert_eq!(s.steps, run.stats().steps);
}

#[test]
fn the_command_line_accepts_a_dented_cylinder_and_explains_its_hull() {
    let dir = crate::cli::scratch("dented");
    std::fs::create_dir_all(&dir).unwrap();
    let shape = dir.join("printed.json");
    let summary = dir.join("s.json");
    let path = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let (shape_arg, summary_arg) = (path(&shape), path(&summary));
    let printed = [
        "--dim",
        "2",
        "--paper-seed",
        "219",
        "--sigma",
        "0.5",
        "--modes",
        "9",
    ];
    let out = rollphase([&["shape"][..], &printed, &["-o", &shape_arg]].concat());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("roll it on its convex hull"), "{err}");
    let out = rollphase(["inspect", &shape_arg]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("2 flat(s)") && text.contains("α* is the larger"),
        "{text}"
    );
    let out = rollphase([
        "simulate",
        &shape_arg,
        "--alpha",
        "0.5",
        "--mass",
        "2",
        "--t-end",
        "50",
        "--samples",
        "11",
        "--summary",
        &summary_arg,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    assert!(summary["tips"].as_u64().unwrap() > 0);
    assert!(summary["tip_energy_lost"].as_f64().unwrap() > 0.0);
    // `period` without inertia rolls it on its hull too, and agrees with `simulate`'s run: a
    // turn takes the curved parts' time (the flats are crossed by tipping, in no time).
    let out = rollphase(["period", &shape_arg, "--alpha", "0.5", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let p: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(p["fate"], "periodic", "{p}");
    let period = p["period"].as_f64().unwrap();
    let csv = dir.join("viscous.csv");
    let t_end = 20.0 * period;
    let out = rollphase([
        "simulate",
        &shape_arg,
        "--alpha",
        "0.5",
        "--t-end",
        &t_end.to_string(),
        "--samples",
        "2",
        "-o",
        &path(&csv),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let theta = |line: &str| line.split(',').nth(1).unwrap().parse::<f64>().unwrap();
    let lines: Vec<&str> = text.lines().skip(1).collect();
    let turns = (theta(lines[1]) - theta(lines[0])) / std::f64::consts::TAU;
    // 20 periods from a start that is not on the cycle's phase: within a turn of 20.
    assert!((turns - 20.0).abs() < 1.0, "{turns} turns in 20 periods");
    // With inertia its flats' impacts need the run loop: `period` says to use `simulate`.
    let out = rollphase(["period", &shape_arg, "--alpha", "0.5", "--mass", "1"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("rollphase simulate --mass"));
    // A 3D body that is not convex stays refused, with the place.
    let out = rollphase(["shape", "--dim", "3", "--seed", "1", "--sigma", "2.0"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("not convex"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The rimless wheel, generalised to round lobes: a three-lobed body rolling freely (no drag)
/// settles on the cycle where each impact takes what gravity gives over one lobe and its flat,
/// so the kinetic energy just before an impact is KE⁻ = sin α · (P/3) / (1 − ρ²), with P the
/// hull's perimeter and ρ = (I + m P_a·P_b)/(I + m r²) the impact's ratio (r_a = r_b by
/// symmetry). And the angle below which it stops: a viscous body rests on a flat up to α*, a
/// little under the triangle's π/3 (its corners are round).
#[test]
fn a_three_lobed_body_is_a_rimless_wheel() {
    use rollphase::geometry::DiskMode;
    let disk = Disk::new(vec![DiskMode {
        l: 3,
        a: 2.0,
        phase: 0.0,
    }]);
    let body = Body::Disk(disk.clone());
    let bridges = disk.hull().bridges().to_vec();
    assert_eq!(bridges.len(), 3);
    let b = bridges[0];
    // One lobe's arc, from the end of the previous flat to the start of the next.
    let prev = bridges[2];
    let (from, to) = (prev.theta_b - std::f64::consts::TAU, b.theta_a);
    let n = 20_000;
    let h = (to - from) / n as f64;
    let arc: f64 = (0..n)
        .map(|i| disk.jet(from + (i as f64 + 0.5) * h).arc_rate())
        .sum::<f64>()
        * h;
    let per_lobe = arc + b.length;
    let (m, alpha) = (2.0, 0.8f64);
    let point = |t: f64| {
        let r = disk.jet(t).r;
        [r * t.cos(), r * t.sin()]
    };
    let (pa, pb) = (point(b.theta_a), point(b.theta_b));
    let r2 = pb[0] * pb[0] + pb[1] * pb[1];
    let inertia = 0.5 * m;
    let rho = (inertia + m * (pa[0] * pb[0] + pa[1] * pb[1])) / (inertia + m * r2);
    let predicted = alpha.sin() * per_lobe / (1.0 - rho * rho);

    let sim = Simulation::new(alpha, 80.0)
        .model(Model::Inertial { mass_ratio: m })
        .drag(0.0)
        .samples(400_001)
        .initial(InitialState::Disk {
            theta0: 0.0,
            theta_dot0: 2.0,
        });
    let (tr, s) = simulate(&body, &sim).unwrap();
    let tips = s.hull.unwrap().tips;
    assert!(tips > 20, "{tips} tips, α* = {}", body.alpha_star());
    let Trajectory::Disk(d) = tr else {
        unreachable!()
    };
    let model = DiskInertial::new(&disk, &Ramp::with_drag(alpha, m, 0.0).unwrap());
    // The last samples before the late impacts (θ jumps across a flat between two samples).
    let before: Vec<f64> = (1..d.theta.len())
        .filter(|&i| d.t[i] > 40.0 && d.theta[i] - d.theta[i - 1] > 0.5 * (b.theta_b - b.theta_a))
        .map(|i| {
            // The energy is conserved on the arc: carry the sample's kinetic energy to the flat's
            // end through the potential.
            let j = i - 1;
            let kinetic = 0.5 * model.reduced_inertia(d.theta[j]) * d.theta_dot[j].powi(2);
            let e = kinetic
                + model.potential(d.theta[j], d.x[j] - disk.jet(d.theta[j]).centre_offset());
            let end =
                d.theta[j] + (b.theta_a - d.theta[j]).rem_euclid(2.0 * std::f64::consts::PI / 3.0);
            let arc_left = (b.theta_a - d.theta[j]).rem_euclid(2.0 * std::f64::consts::PI / 3.0);
            let x_c_end = d.x[j] - disk.jet(d.theta[j]).centre_offset()
                + arc_left * disk.jet(0.5 * (d.theta[j] + end)).arc_rate();
            e - model.potential(end, x_c_end)
        })
        .collect();
    assert!(before.len() > 10, "{}", before.len());
    let worst = before
        .iter()
        .map(|ke| (ke - predicted).abs())
        .fold(0.0, f64::max);
    println!(
        "rimless wheel: KE⁻ predicted {predicted:.6}, {} impacts after t = 40, worst relative \
         deviation {:.2e}, ρ = {rho:.4}",
        before.len(),
        worst / predicted
    );
    for ke in &before {
        assert!(
            (ke - predicted).abs() < 1e-6 * predicted,
            "KE⁻ {ke} against {predicted}"
        );
    }

    // The angle below which it stops (viscous): rests on a flat just below α*, rolls above.
    let alpha_star = body.alpha_star();
    // Round lobes rest less steeply than a triangle's corners (π/3): here 0.570.
    let flat = critical_angle(&body).flat.unwrap();
    assert_eq!(alpha_star, flat.alpha.max(flat.curve_alpha));
    assert!(
        alpha_star < std::f64::consts::FRAC_PI_3,
        "α* = {alpha_star}"
    );
    let rests = |a: f64| {
        let sim = Simulation::new(a, 200.0).samples(2);
        simulate(&body, &sim)
            .unwrap()
            .1
            .hull
            .unwrap()
            .rested_t
            .is_some()
    };
    assert!(rests(alpha_star - 1e-3) && !rests(alpha_star + 1e-3));
}
