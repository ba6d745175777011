//! The files bundled into the binary, each included once: the shapes and preset scenes under
//! `assets/` (so presets and benchmarks run from any directory) and the font the PNG charts and
//! the headless overlay share. Imports nothing.

/// The bundled 3D body most presets and the benchmarks use.
pub const SPHERE: &str = include_str!("../../../assets/shapes/sphere.json");
/// The bundled 2D body for viscous runs (σ = 0.08, M = 10).
pub const DISK: &str = include_str!("../../../assets/shapes/disk.json");
/// The bundled 2D body for inertial runs (σ = 0.12, M = 5).
pub const DISK_INERTIAL: &str = include_str!("../../../assets/shapes/disk-inertial.json");
/// The paper's 3D body (numpy seed 219, σ = 0.25, l ≤ 5).
pub const PAPER_SPHERE: &str = include_str!("../../../assets/shapes/paper-sphere.json");
/// A cylinder designed to rest below 10° (`rollphase design --dim 2 --alpha-star 0.174533
/// --alpha-band 0.0087 --scale-mm 40 --seed 1`): the "which one stops?" preset's.
pub const CYLINDER_10DEG: &str = include_str!("../../../assets/shapes/cylinder-10deg.json");

/// The bundled shape files, by file name (scenes refer to them as `../shapes/NAME`).
pub const BUNDLED_SHAPES: &[(&str, &str)] = &[
    ("sphere.json", SPHERE),
    ("disk.json", DISK),
    ("disk-inertial.json", DISK_INERTIAL),
    ("paper-sphere.json", PAPER_SPHERE),
    ("cylinder-10deg.json", CYLINDER_10DEG),
];

/// The preset scenes (name = file stem), the default first.
pub const PRESETS: &[(&str, &str)] = &[
    (
        "sphere-cruising",
        include_str!("../../../assets/scenes/sphere-cruising.toml"),
    ),
    (
        "sphere-two-orbits",
        include_str!("../../../assets/scenes/sphere-two-orbits.toml"),
    ),
    (
        "sphere-doubling",
        include_str!("../../../assets/scenes/sphere-doubling.toml"),
    ),
    (
        "sphere-flip",
        include_str!("../../../assets/scenes/sphere-flip.toml"),
    ),
    (
        "perfect-sphere",
        include_str!("../../../assets/scenes/perfect-sphere.toml"),
    ),
    (
        "cylinder-near-critical",
        include_str!("../../../assets/scenes/cylinder-near-critical.toml"),
    ),
    (
        "cylinder-hysteresis",
        include_str!("../../../assets/scenes/cylinder-hysteresis.toml"),
    ),
    (
        "which-one-stops",
        include_str!("../../../assets/scenes/which-one-stops.toml"),
    ),
    (
        "poincare-field",
        include_str!("../../../assets/scenes/poincare-field.toml"),
    ),
    (
        "lesson-critical-angle",
        include_str!("../../../assets/scenes/lesson-critical-angle.toml"),
    ),
    (
        "lesson-inertia-hysteresis",
        include_str!("../../../assets/scenes/lesson-inertia-hysteresis.toml"),
    ),
    (
        "lesson-period-doubling",
        include_str!("../../../assets/scenes/lesson-period-doubling.toml"),
    ),
];

/// DejaVu Sans, for chart labels (`plot`) and the headless text overlay (`render::overlay`).
pub const FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
