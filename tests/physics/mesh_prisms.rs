//! The mesh fit of every regular prism OpenSCAD writes, read through the library (no binary
//! starts here, so `.ci/run`'s second pass, which reruns the modules that start the binary
//! against the one built without default features, leaves this sweep out).

use std::f64::consts::TAU;

use super::mesh_import::{extrude, write_binary_stl};
use rollphase::geometry::Body;

/// OpenSCAD's `cylinder(r = 10, h = 20, $fn = K)` for every K from 3 to 512, as written (the
/// first vertex at angle 0, where sample rays of the section fall exactly on vertices) along +z,
/// and for the K where a turn or the axis's sign could matter (every K to 64, where the sides
/// are few and wide, and 97, 128, 255, 256, 511, 512) also turned by 0.1 rad and along −z:
/// every one fits as a 2D body with the polygon's own mean radius, its hull has K sides and
/// rests up to π/K (OpenSCAD's defaults, `$fa = 12, $fs = 2`, give 16 sides at r = 5 mm and 30
/// at 10 and 20 mm), and the fit warns exactly when its smooth α* misses π/K by more than the
/// tolerance. (All four ways for every K were 2,040 fits and 55 s of CI on 2 cores; every one
/// passed, through 2026-12-03.)
#[test]
fn regular_prisms_of_every_fn_fit_at_any_turn_and_axis_sign() {
    use rollphase::geometry::mesh_fit::{FitOptions, fit_mesh};
    use rollphase::geometry::mesh_read::MeshSource;
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    let mut refused = Vec::new();
    let mut fitted = 0;
    let all_four = |k: usize| k <= 64 || [97, 128, 255, 256, 511, 512].contains(&k);
    let mut expected = 0;
    for k in 3..=512usize {
        let variants: &[(f64, f64)] = if all_four(k) {
            &[(0.0, 1.0), (0.0, -1.0), (0.1, 1.0), (0.1, -1.0)]
        } else {
            &[(0.0, 1.0)]
        };
        expected += variants.len();
        for turn in [0.0, 0.1] {
            if !variants.iter().any(|v| v.0 == turn) {
                continue;
            }
            let polygon: Vec<[f64; 2]> = (0..k)
                .map(|j| {
                    let a = TAU * j as f64 / k as f64 + turn;
                    [10.0 * a.cos(), 10.0 * a.sin()]
                })
                .collect();
            let path = dir.join(format!("fn{k}-{turn}.stl"));
            write_binary_stl(&extrude(&polygon, 20.0), &path, 1.0);
            let source = MeshSource::open(&path).unwrap();
            for axis in [1.0, -1.0] {
                if !variants.contains(&(turn, axis)) {
                    continue;
                }
                let options = FitOptions {
                    dim: Some(2),
                    axis: Some(rollphase::glam::DVec3::new(0.0, 0.0, axis)),
                    // The sweep checks the fit; its errors are mesh_errors.rs's (and 2,040
                    // α* bootstraps would take most of this test's time).
                    errors: false,
                    ..FitOptions::default()
                };
                match fit_mesh(&source, &options, &|_, _, _| {}) {
                    Ok(fit) => {
                        // The mean of r(θ) = a/cos θ over a regular K-gon of circumradius 10 (apothem a).
                        let half = std::f64::consts::PI / k as f64;
                        let exact = 10.0 * half.cos() * half.sin().atanh() / half;
                        let scale = fit.report.scale_mm;
                        assert!(
                            (scale - exact).abs() < 1e-3 * exact,
                            "$fn = {k}, turn {turn}, axis {axis}: ⟨r⟩ {scale} against {exact}"
                        );
                        // The print rests on a side up to π/K whatever the fit sees, and a fit
                        // that does not see it says so.
                        let hull = fit.report.mesh_hull.expect("a 2D fit reports its hull");
                        assert_eq!(hull.sides, k, "$fn = {k}");
                        assert!(
                            // STL's f32 coordinates: 1e-6 mm on sides of 0.1 mm and more.
                            (hull.alpha_star - half).abs() < 1e-5,
                            "$fn = {k}, turn {turn}: the hull's α* {} against π/K = {half}",
                            hull.alpha_star
                        );
                        let misses = (half - fit.report.alpha_star).abs()
                            > rollphase::geometry::mesh_fit::FACET_TOLERANCE;
                        let warned = fit
                            .report
                            .warnings
                            .iter()
                            .any(|w| w.contains(&format!("{k} flat sides")));
                        assert_eq!(
                            warned, misses,
                            "$fn = {k}: fit α* {}, π/K {half}; {:?}",
                            fit.report.alpha_star, fit.report.warnings
                        );
                        // The shape file keeps the print's section, and the body rolls on it
                        // (issue 59's wrong answer: `period --alpha 0.05` on a 30- to 62-sided
                        // prism said "periodic" on the smooth fit): its α* is π/K less the
                        // corners' rounding, a relative ρ/d ≤ 2e-3.
                        let Body::Disk(d) = &fit.body else {
                            panic!("$fn = {k}: a 2D fit gives a disk")
                        };
                        let printed = d.printed_section().expect("the print's section is kept");
                        let h = printed.hull().unwrap();
                        assert_eq!(h.sides, k, "$fn = {k}");
                        assert!((h.alpha_star - half).abs() < 1e-5, "$fn = {k}: {h:?}");
                        let rolled = fit.body.alpha_star();
                        assert!(
                            rolled < half + 1e-5 && rolled > half * (1.0 - 2.5e-3),
                            "$fn = {k}: rolls with α* {rolled} against π/K = {half}"
                        );
                        assert_eq!(d.hull().bridges().len(), k, "$fn = {k}");
                        fitted += 1;
                    }
                    Err(e) => refused.push(format!("$fn = {k}, turn {turn}, axis {axis}: {e}")),
                }
            }
        }
        std::fs::remove_file(dir.join(format!("fn{k}-0.stl"))).ok();
    }
    assert!(
        refused.is_empty(),
        "{} refused:\n{}",
        refused.len(),
        refused[..refused.len().min(20)].join("\n")
    );
    assert_eq!(fitted, expected);
    assert_eq!(expected, 510 + 3 * (62 + 6));
}
