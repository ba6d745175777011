//! Scenes: the preset list is exactly the files in `assets/scenes`, every preset validates, and
//! a bad scene is refused with a message naming the field, the value and what is allowed.

use crate::cli;
use rollphase::scene::{PRESETS, Scene, load_scene_file};

#[test]
fn presets_are_exactly_the_scene_files() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes");
    let mut files: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut names: Vec<String> = PRESETS.iter().map(|(n, _)| n.to_string()).collect();
    names.sort();
    assert_eq!(files, names);
    // The list: default cruising, two orbits, doubling, perfect sphere, 2D near α*,
    // 2D inertial hysteresis, the Poincaré field.
    assert!(names.len() >= 7);
}

#[test]
fn preset_files_load_from_disk_like_the_bundled_copies() {
    for (name, _) in PRESETS {
        let path = format!("{}/assets/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        let from_disk = load_scene_file(path.as_ref()).unwrap();
        let bundled = Scene::preset(name).unwrap().setup(None).unwrap();
        assert_eq!(from_disk.scene, bundled.scene);
        assert_eq!(from_disk.alpha_star, bundled.alpha_star);
    }
}

/// `rollphase scenes --toml NAME > my.toml` then `--scene my.toml`, from any folder: the printed
/// file stands alone (a bundled shape comes inline) and sets up the same body, start and model.
#[test]
fn a_printed_preset_works_as_a_scene_file_anywhere() {
    let dir = crate::cli::scratch("printed");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, _) in PRESETS {
        let toml = cli::rollphase_ok(["scenes", "--toml", name]);
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, toml).unwrap();
        let printed = load_scene_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let bundled = Scene::preset(name).unwrap().setup(None).unwrap();
        assert_eq!(
            format!("{:?}", printed.body),
            format!("{:?}", bundled.body),
            "{name}"
        );
        assert_eq!(printed.alpha_star, bundled.alpha_star, "{name}");
        assert_eq!(printed.ramp, bundled.ramp, "{name}");
        assert_eq!(printed.scene.model, bundled.scene.model, "{name}");
        assert_eq!(printed.scene.initial, bundled.scene.initial, "{name}");
        assert_eq!(printed.scene.timeline, bundled.scene.timeline, "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn presets_show_what_their_names_promise() {
    let setup = |n: &str| Scene::preset(n).unwrap().setup(None).unwrap();
    let near = setup("cylinder-near-critical");
    assert!(near.ramp.alpha_rad > near.alpha_star && near.ramp.alpha_rad < 1.05 * near.alpha_star);
    let hyst = setup("cylinder-hysteresis");
    assert!(hyst.ramp.alpha_rad < hyst.alpha_star && hyst.ramp.mass_ratio > 0.0);
    assert_eq!(setup("sphere-doubling").ramp.mass_ratio, 6.0);
    assert_eq!(setup("perfect-sphere").alpha_star, 0.0);
    assert!(setup("poincare-field").scene.views.poincare);
    assert!(setup("sphere-two-orbits").scene.views.poincare);
}

fn error_of(toml: &str) -> String {
    match Scene::from_toml(toml).and_then(|s| s.setup(None)) {
        Ok(_) => panic!("scene accepted:\n{toml}"),
        Err(e) => e.to_string(),
    }
}

const BODY: &str = "[body]\nperfect = \"sphere\"\n";

#[test]
fn bad_scenes_are_refused_with_the_reason() {
    let cases: &[(String, &[&str])] = &[
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_rad = 2.0\n"),
            &["alpha = 2", "1e-9 ≤ alpha < π/2"],
        ),
        // Issue 33: a fixed step longer than a frame's simulated time (speed 1 / 30 fps) was
        // rendered with exit 0, cut to a frame's time at every frame.
        (
            format!(
                "name = \"x\"\n{BODY}[model]\nalpha_rad = 0.3\n[integrator]\nmethod = \"rk4\"\ndt = 5.0\n[playback]\nspeed = 1.0\nfps = 30.0\n"
            ),
            &["integrator.dt = 5", "one frame's simulated time", "dt ≤ 0.0333"],
        ),
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_rad = 0.3\nalpha_over_critical = 1.1\n"),
            &["exactly one of model.alpha_rad"],
        ),
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_rad = 0.3\nmas_ratio = 1\n"),
            &["unknown field", "mas_ratio"],
        ),
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_rad = 0.3\n[playback]\nspeed = -1\n"),
            &["playback.speed = -1", "0 < speed"],
        ),
        (
            "name = \"x\"\n[body]\nperfect = \"disk\"\n[model]\nalpha_rad = 0.3\n[views]\nball = true\n"
                .to_string(),
            &["need a 3D body"],
        ),
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_rad = 0.3\nmass_ratio = 2\n[views]\npoincare = true\n"),
            &["views.poincare needs the viscous model"],
        ),
        (
            "name = \"x\"\n[body]\nperfect = \"disk\"\n[model]\nalpha_rad = 0.3\n[views]\nplot = \"crossings\"\n"
                .to_string(),
            &["views.plot = \"crossings\" needs a 3D body", "inverse-period"],
        ),
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_rad = 0.3\n[views]\nplot = \"1/T\"\n"),
            &["unknown variant", "inverse-period"],
        ),
        (
            "name = \"x\"\n[body]\nshape = \"../shapes/nope.json\"\n[model]\nalpha_rad = 0.3\n".to_string(),
            &["nope.json", "not a bundled shape"],
        ),
        (
            "name = \"x\"\n[body]\nrandom = { dimension = 4, seed = 1, sigma = 0.2 }\n[model]\nalpha_rad = 0.3\n"
                .to_string(),
            &["dimension = 4", "2 for a cylinder or 3"],
        ),
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_over_critical = 1.1\n"),
            &["α* = 0"],
        ),
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_rad = 0.3\n[integrator]\nmethod = \"rk4\"\ndt = 0\n"),
            &["dt"],
        ),
        (
            format!("name = \"x\"\n{BODY}[model]\nalpha_rad = 0.3\n[poincare]\narrows = 3\n"),
            &["poincare.arrows = 3"],
        ),
    ];
    for (toml, needles) in cases {
        let e = error_of(toml);
        for n in *needles {
            assert!(e.contains(n), "error {e:?} lacks {n:?} for\n{toml}");
        }
    }
}

#[test]
fn a_scene_file_finds_its_shape_relative_to_itself() {
    let dir = crate::cli::scratch("scene");
    std::fs::create_dir_all(dir.join("shapes")).unwrap();
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/assets/shapes/disk.json"),
        dir.join("shapes/mine.json"),
    )
    .unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "name = \"mine\"\n[body]\nshape = \"shapes/mine.json\"\n[model]\nalpha_over_critical = 1.5\n",
    )
    .unwrap();
    let setup = load_scene_file(&scene).unwrap();
    assert!((setup.ramp.alpha_rad / setup.alpha_star - 1.5).abs() < 1e-12);
    std::fs::write(
        &scene,
        "name = \"mine\"\n[body]\nshape = \"shapes/missing.json\"\n[model]\nalpha_rad = 0.2\n",
    )
    .unwrap();
    let e = load_scene_file(&scene).unwrap_err().to_string();
    assert!(e.contains("missing.json"), "{e}");
}
