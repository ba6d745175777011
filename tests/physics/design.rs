//! `analysis::design` against exact results and independent runs: a one-mode cylinder whose
//! amplitude the critical angle fixes in closed form, a cylinder that rests below and rolls
//! above its designed α* (the viscous model's own verdict), a hysteresis window re-measured by the
//! period run, the same design on one thread and on several, and a target no body can meet.

use std::sync::atomic::AtomicBool;

use rollphase::analysis::critical_angle;
use rollphase::analysis::design::{
    Band, DesignOptions, DesignSpace, Ended, Printability, Target, design_until,
};
use rollphase::analysis::orbits::disk_period::{inertial_disk_period, viscous_disk_period};
use rollphase::analysis::verdict::Fate;
use rollphase::dynamics::Ramp;
use rollphase::geometry::{Body, Disk, DiskMode};

fn options(dimension: u32, modes: u32, targets: Vec<Target>) -> DesignOptions {
    DesignOptions {
        space: DesignSpace { dimension, modes },
        targets,
        scale_mm: 10.0,
        min_radius_mm: 0.4,
        max_amplitude: 1.0,
        start: None,
        seed: 3,
        max_generations: 400,
        band: Band {
            delta_alpha: 0.01,
            mass_fraction: 0.2,
            surface_mm: 0.01,
            draws: 4,
            seed: 3,
        },
    }
}

fn design(o: &DesignOptions) -> rollphase::analysis::design::Design {
    design_until(o, &AtomicBool::new(false), &|_| {}).expect("a design")
}

#[test]
fn a_one_mode_cylinder_gets_the_amplitude_its_critical_angle_fixes() {
    // r = 1 + (a/4) sin 2(θ − θ2) has Q* = (a/2)/√(1 − a²/16): with L = 2 the design space is
    // this family alone, and α* decides |a| exactly.
    for target in [0.05, 0.2, 0.35] {
        let d = design(&options(2, 2, vec![Target::AlphaStar { alpha: target }]));
        assert_eq!(
            d.ended,
            Ended::Met,
            "α* = {target}: {} after {} generations",
            d.alpha_star,
            d.generations
        );
        let Body::Disk(disk) = &d.body else {
            panic!("a 2D design is a disk")
        };
        let a = disk.modes()[0].a.abs();
        let q = target.tan();
        let exact = 2.0 * q / (1.0 + q * q / 4.0).sqrt();
        // α* within 5e-5 rad (half the tolerance), so |a| within 5e-5 · da/dα*.
        let slope = 2.0 / target.cos().powi(2) / (1.0 + q * q / 4.0).powf(1.5);
        assert!(
            (a - exact).abs() < 5e-5 * slope * 1.01,
            "α* = {target}: |a| = {a}, exactly {exact}"
        );
        assert!((critical_angle(&d.body).alpha_star - target).abs() <= 5e-5);
    }
}

#[test]
fn a_cylinder_designed_for_an_angle_rests_below_it_and_rolls_above_it() {
    // The teacher's cylinder: rests at 10°, rolls at 11°.
    let target = 10.5f64.to_radians();
    let d = design(&options(2, 4, vec![Target::AlphaStar { alpha: target }]));
    assert!(d.holds(), "{:?}", d.check);
    let Body::Disk(disk) = &d.body else {
        panic!("a 2D design is a disk")
    };
    // Either way round on the ramp (turned end for end, its section is mirrored).
    for disk in [disk.clone(), disk.turned()] {
        let rests = viscous_disk_period(&disk, &Ramp::new(10f64.to_radians(), 0.0).unwrap());
        assert!(matches!(
            rests.fate(-0.5f64.to_radians(), 0.0),
            Fate::Halted { .. }
        ));
        let rolls = viscous_disk_period(&disk, &Ramp::new(11f64.to_radians(), 0.0).unwrap());
        assert!(matches!(
            rolls.fate(0.5f64.to_radians(), 0.0),
            Fate::Periodic { multiplicity: 1 }
        ));
    }
    let turned = d.alpha_star_turned.expect("a cylinder has two ways round");
    assert!((turned - target).abs() <= 1e-4 && (d.alpha_star - target).abs() <= 1e-4);
    // What the report says of the printer's view is what the body is.
    let p = Printability::of(&d.body, 10.0);
    assert!(p.convex && p.smallest_radius_mm >= 0.4);
    assert_eq!(d.printability, p);
}

#[test]
fn a_hysteresis_window_holds_when_measured_by_the_period_run_itself() {
    let (mass, fraction) = (10.0, 0.8);
    let mut o = options(2, 4, vec![Target::Hysteresis { mass, fraction }]);
    o.band.delta_alpha = 0.002;
    let d = design(&o);
    assert!(d.holds(), "{:?}", d.check);
    let Body::Disk(disk) = &d.body else {
        panic!("a 2D design is a disk")
    };
    let alpha_star = critical_angle(&d.body).alpha_star;
    // Released rolling fast on the ramp lowered to F·α* − δα: it settles on a period.
    let alpha = fraction * alpha_star - o.band.delta_alpha;
    let p = inertial_disk_period(
        disk,
        &Ramp::new(alpha, mass).unwrap(),
        0.0,
        0.2,
        1e-11,
        20_000.0,
    )
    .unwrap();
    assert_eq!(
        p.fate(alpha - alpha_star, 20_000.0),
        Fate::Periodic { multiplicity: 1 },
        "{p:?}"
    );
    // Released from rest there, it stays: the window is one of hysteresis, not of rolling.
    let rest = rollphase::analysis::studies::disk::fixed_points(disk, alpha)
        .into_iter()
        .find(|f| f.stable)
        .expect("a stable rest below α*");
    let from_rest = inertial_disk_period(
        disk,
        &Ramp::new(alpha, mass).unwrap(),
        rest.theta,
        0.0,
        1e-11,
        2000.0,
    )
    .unwrap();
    assert!(from_rest.halts, "{from_rest:?}");
}

#[test]
fn the_same_seed_gives_the_same_body_on_one_thread_and_on_several() {
    let o = options(3, 3, vec![Target::AlphaStar { alpha: 0.25 }]);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| design(&o));
    let four = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .unwrap()
        .install(|| design(&o));
    assert_eq!(one.vector, four.vector);
    assert_eq!(one.check.targets[0].worst, four.check.targets[0].worst);
    // Another seed is another search.
    let mut other = o.clone();
    other.seed = 4;
    assert_ne!(design(&other).vector, one.vector);
}

#[test]
fn a_one_mode_cylinder_stops_at_the_convexity_limit_of_its_family() {
    // r = 1 + ε sin 2θ is convex while ε < 1/5 (r² + 2r'² − r r'' = (1 − ε)(1 − 5ε) at its
    // flattest): its α* cannot pass atan(0.4/√0.96) = 0.38760. Asking for 0.4 finds the limit,
    // says the convexity binds, and does not claim the target.
    let mut o = options(2, 2, vec![Target::AlphaStar { alpha: 0.4 }]);
    o.max_generations = 300;
    let d = design(&o);
    let limit = (0.4f64 / 0.96f64.sqrt()).atan();
    assert!(
        d.alpha_star <= limit && limit - d.alpha_star < 1e-3,
        "{}",
        d.alpha_star
    );
    assert!(!d.holds() && !d.achieved[0].met);
    let convexity = d
        .constraints
        .iter()
        .find(|c| c.name.starts_with("convexity"))
        .unwrap();
    assert!(convexity.binding, "{:?}", d.constraints);
}

#[test]
fn a_target_no_printable_body_meets_is_reported_with_what_binds() {
    // α* = 1.2 rad asks for |r'/r| = 2.6 somewhere; a convex body of degree 4 does not reach it.
    let mut o = options(2, 4, vec![Target::AlphaStar { alpha: 1.2 }]);
    o.max_generations = 150;
    let d = design(&o);
    assert_ne!(d.ended, Ended::Met);
    assert!(!d.holds() && !d.achieved[0].met);
    assert!(d.alpha_star < 1.0, "{}", d.alpha_star);
    let binding: Vec<&str> = d
        .constraints
        .iter()
        .filter(|c| c.binding)
        .map(|c| c.name)
        .collect();
    assert!(!binding.is_empty(), "{:?}", d.constraints);
}

#[test]
fn a_design_space_vector_is_the_body_it_describes() {
    // 2D: the modes' pairs (a cos lθ_l, a sin lθ_l) give back r(θ).
    let space = DesignSpace {
        dimension: 2,
        modes: 5,
    };
    let body = Body::paper_disk(84, 0.12, 5).unwrap();
    let again = space.body(&space.vector(&body).unwrap());
    let (Body::Disk(a), Body::Disk(b)) = (&body, &again) else {
        panic!("disks")
    };
    for i in 0..50 {
        let t = i as f64 * 0.13;
        assert!((a.jet(t).r - b.jet(t).r).abs() < 1e-14);
    }
    // A body of higher degree is not in the space.
    let fine = Body::Disk(Disk::new(vec![DiskMode {
        l: 7,
        a: 0.1,
        phase: 0.0,
    }]));
    assert!(space.vector(&fine).is_none());
}

#[test]
#[ignore = "slow: the doubling check of the guide's designed sphere (about 30 s)"]
fn the_guides_designed_sphere_doubles_at_the_uncoated_prints_mass_and_the_printed_one_does_not() {
    use rollphase::analysis::design::evaluate;
    use rollphase::analysis::orbits::sphere_orbits::Decide;
    use rollphase::analysis::studies::sphere::period_counts;
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let designed = Body::from_file(&repo.join("docs/design/doubling-sphere.json")).unwrap();
    let mut o = options(
        3,
        5,
        vec![Target::Doubling {
            mass: 2.5,
            alpha: 0.2014,
        }],
    );
    o.start = Some(designed.clone());
    o.band = Band {
        delta_alpha: 0.005,
        mass_fraction: 0.2,
        surface_mm: 0.05,
        draws: 2,
        seed: 1,
    };
    let d = evaluate(&o).unwrap();
    assert!(d.holds(), "{:?}", d.check);
    let e = d.check.targets[0].evidence.as_ref().unwrap();
    let (onset, end) = (e.onset_mass.unwrap(), e.end_mass.unwrap());
    assert!(onset < 2.0 && end > 3.0, "window {onset} to {end}");
    // Independently of the design's own runs: other starts from rest, decided by the period
    // statistics, repeat after two crossings at m/m0 = 2.5 and after one at 1.0 and 7.0.
    let decide = Decide {
        t_min: 1200.0,
        t_cap: 12_000.0,
        max_k: 4,
        tol: 1e-5,
    };
    for (mass, k) in [(1.0, 0), (2.5, 1), (7.0, 0)] {
        let c = period_counts(&designed, 0.2014, mass, 6, 99, &decide).unwrap();
        assert_eq!(c.cycle_counts[k], 6, "m/m0 = {mass}: {c:?}");
    }
    // The authors' printed sphere (its generator body) at m/m0 = 2.5: period 1, the target not met.
    o.start = Some(Body::paper_sphere(6, 0.25, 4).unwrap());
    o.space.modes = 4;
    let printed = evaluate(&o).unwrap();
    assert!(!printed.holds() && !printed.achieved[0].met);
    let runs = printed.check.targets[0].evidence.as_ref().unwrap().runs;
    assert_eq!(runs.cycle_counts[0], 12, "{runs:?}");
}

#[test]
fn a_drift_target_reads_every_stable_orbit_that_predict_finds() {
    use rollphase::analysis::design::Setting;
    use rollphase::analysis::experiment::prediction::{PredictOptions, predict};
    // The paper's sphere at α = 0.15 has two stable orbits drifting opposite ways (Fig. 3d):
    // the target's value is the one farther from what is asked, so asking for either drift
    // reads the other.
    let body = Body::paper_sphere(219, 0.25, 5).unwrap();
    let options = PredictOptions {
        starts: 8,
        ..PredictOptions::default()
    };
    let drifts: Vec<f64> = predict(&body, 0.15, 0.0, &options)
        .unwrap()
        .orbits
        .iter()
        .filter(|o| o.stable)
        .map(|o| o.advance_across / o.advance_down)
        .collect();
    assert_eq!(drifts.len(), 2);
    assert!(drifts[0] * drifts[1] < 0.0, "{drifts:?}");
    for (asked, other) in [(drifts[0], drifts[1]), (drifts[1], drifts[0])] {
        let target = Target::Drift {
            drift: asked,
            alpha: 0.15,
            mass: 0.0,
        };
        let value = target.measure(&body, 1.0, &Setting::FAST).unwrap();
        assert!(
            (value - other).abs() < 1e-6,
            "asked {asked}: {value} against {other}"
        );
        assert!(!target.met_by(value));
    }
}

#[test]
fn an_orbits_target_counts_the_paper_spheres_two_orbits_fast_and_precise() {
    use rollphase::analysis::design::Setting;
    // The paper's sphere at α = 0.15, viscous: two stable orbits (Fig. 3d), each reached from a
    // good share of random starts. Two are met at both settings (independent seeds and counts of
    // starts); one is short by the other orbit's share, three by the whole share asked.
    let body = Body::paper_sphere(219, 0.25, 5).unwrap();
    let orbits = |count, share| Target::Orbits {
        count,
        alpha: 0.15,
        mass: 0.0,
        share,
    };
    for setting in [Setting::FAST, Setting::PRECISE] {
        let two = orbits(2, 0.2).measure(&body, 1.0, &setting).unwrap();
        assert!(two <= -0.05, "two orbits at {setting:?}: shortfall {two}");
        assert!(orbits(2, 0.2).met_by(two));
        let one = orbits(1, 0.5).measure(&body, 1.0, &setting).unwrap();
        // The other orbit's share, the weakest: between the shortfall of two and a half.
        assert!((0.2 - two - 1e-12..=0.5).contains(&one), "one orbit: {one}");
        assert!(!orbits(1, 0.5).met_by(one));
        let three = orbits(3, 0.1).measure(&body, 1.0, &setting).unwrap();
        assert!((three - 0.1).abs() < 1e-12, "three orbits: {three}");
    }
}

#[test]
fn a_checked_body_reports_its_orbits_in_mm_and_seconds_at_its_scale() {
    use rollphase::analysis::design::at_scale::predict_at_scale;
    use rollphase::analysis::design::{Setting, evaluate};
    use rollphase::analysis::experiment::tracking::model::{G, t0_for_mass_ratio};
    let body = Body::paper_sphere(219, 0.25, 5).unwrap();
    let mut o = options(
        3,
        5,
        vec![Target::Orbits {
            count: 2,
            alpha: 0.15,
            mass: 0.0,
            share: 0.2,
        }],
    );
    o.start = Some(body.clone());
    o.scale_mm = 20.0;
    o.band.draws = 2;
    let d = evaluate(&o).unwrap();
    let orbits = &d.check.targets[0];
    assert!(orbits.holds && orbits.margin > 0.0, "{orbits:?}");
    assert_eq!(orbits.margin_unit, "share of starts");
    assert_eq!(d.predicted.len(), 1);
    // Viscous: no t0 in seconds (the liquid sets it); the shares of the two orbits are all
    // the starts, each inside its 95 % interval.
    let viscous = &d.predicted[0];
    assert_eq!(
        (viscous.alpha, viscous.mass_ratio, viscous.t0_s),
        (0.15, 0.0, None)
    );
    let stable: Vec<_> = viscous.orbits.iter().filter(|o| o.stable).collect();
    assert_eq!(stable.len(), 2);
    assert_eq!(
        stable.iter().map(|o| o.starts).sum::<usize>(),
        viscous.starts
    );
    for o in &stable {
        assert!(o.share_95[0] < o.share && o.share < o.share_95[1], "{o:?}");
        assert!(o.period_s.is_none() && o.speed_mm_s.is_none());
        // About 2π⟨r⟩ down per period, in mm at 20 mm per ⟨r⟩.
        assert!((100.0..140.0).contains(&o.advance_down_mm), "{o:?}");
    }
    // With inertia the weight sets t0 = √(⟨r⟩/(g m/m0)): 28.6 ms at 20 mm and m/m0 = 2.5.
    let inertial = predict_at_scale(&body, "", 0.2014, 2.5, 20.0, &Setting::FAST).unwrap();
    let t0 = t0_for_mass_ratio(2.5, 0.02, G);
    assert!((t0 - 0.028_55).abs() < 1e-4);
    assert_eq!(inertial.t0_s, Some(t0));
    for o in &inertial.orbits {
        let s = o.period_s.unwrap();
        assert!((s - o.period_t0 * t0).abs() < 1e-12);
        assert!((o.speed_mm_s.unwrap() - o.advance_down_mm / s).abs() < 1e-9);
    }
}
