//! Fuzz target, structure-aware: `arbitrary` builds a scene document (every section and field
//! of the TOML schema, each present or not, with numbers from the whole f64 range, NaN and ±inf
//! included, and some unknown keys and wrong types), writes it as TOML text, and hands it to the
//! same path as `rollphase --scene FILE`: parse, then validate into a `SceneSetup`. Any input
//! must give a setup or an error, never a panic; a setup that validates must hold finite
//! numbers in range.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rollphase::scene::Scene;

/// A number as a user might write it: anything, a small integer, or a fraction.
#[derive(Arbitrary, Debug)]
enum Num {
    Raw(f64),
    Small(i8),
    Fraction(u16),
}

impl Num {
    fn toml(&self) -> String {
        let v = match *self {
            Num::Raw(v) => v,
            Num::Small(k) => f64::from(k),
            Num::Fraction(k) => f64::from(k) / 1000.0,
        };
        if v.is_nan() {
            "nan".into()
        } else if v.is_infinite() {
            if v > 0.0 { "inf".into() } else { "-inf".into() }
        } else {
            format!("{v:?}")
        }
    }
}

/// A value in a field: usually a number, sometimes the wrong type.
#[derive(Arbitrary, Debug)]
enum Value {
    Num(Num),
    Int(i64),
    Bool(bool),
    Text(String),
    List(Vec<Num>),
}

impl Value {
    fn toml(&self) -> String {
        match self {
            Value::Num(n) => n.toml(),
            Value::Int(i) => i.to_string(),
            Value::Bool(b) => b.to_string(),
            Value::Text(s) => format!("{s:?}"),
            Value::List(v) => format!(
                "[{}]",
                v.iter().take(6).map(Num::toml).collect::<Vec<_>>().join(", ")
            ),
        }
    }
}

#[derive(Arbitrary, Debug)]
enum BodyChoice {
    Bundled(u8),
    Missing,
    Random { dimension: u8, seed: u64, sigma: Num, modes: Option<u16> },
    Perfect(bool),
    Inline { sphere: bool, amplitudes: Vec<(u8, i8, Num, Num)> },
    Two,
    None,
}

/// Each field of a section: absent, or set to a value.
#[derive(Arbitrary, Debug)]
struct Section {
    fields: Vec<(u8, Value)>,
}

#[derive(Arbitrary, Debug)]
struct FuzzScene {
    name: Option<String>,
    body: BodyChoice,
    model: Section,
    initial: Option<Section>,
    integrator: Option<Section>,
    playback: Option<Section>,
    views: Option<Section>,
    poincare: Option<Section>,
    unknown_key: bool,
}

const MODEL: &[&str] = &["alpha_rad", "alpha_over_critical", "mass_ratio", "drag"];
const INITIAL: &[&str] = &["contact", "spin", "q0", "omega", "theta0", "theta_dot0"];
const INTEGRATOR: &[&str] = &["preset", "method", "rtol", "dt"];
const PLAYBACK: &[&str] = &["speed", "fps", "start_time", "trail_time"];
const VIEWS: &[&str] = &["body", "ball", "poincare", "overlay"];
const POINCARE: &[&str] = &["arrows", "rtol", "t_max"];
const BUNDLED: &[&str] = &["sphere.json", "disk.json", "disk-inertial.json", "paper-sphere.json"];
const WORDS: &[&str] = &["balanced", "fast", "precise", "dop853", "rk4", "cf4", "sphere", "disk"];

fn section(out: &mut String, name: &str, keys: &[&str], s: &Section) {
    out.push_str(&format!("[{name}]\n"));
    let mut used = Vec::new();
    for (k, v) in s.fields.iter().take(8) {
        let key = keys[*k as usize % keys.len()];
        if used.contains(&key) {
            continue; // a repeated key is a TOML error already covered by the parser
        }
        used.push(key);
        // Keys that take words get one of the schema's words half of the time.
        let value = match v {
            Value::Int(i) if matches!(key, "preset" | "method") => {
                format!("{:?}", WORDS[i.unsigned_abs() as usize % WORDS.len()])
            }
            other => other.toml(),
        };
        out.push_str(&format!("{key} = {value}\n"));
    }
}

fn to_toml(s: &FuzzScene) -> String {
    let mut out = String::new();
    if let Some(name) = &s.name {
        out.push_str(&format!("name = {name:?}\n"));
    }
    if s.unknown_key {
        out.push_str("colour = 3\n");
    }
    match &s.body {
        BodyChoice::Bundled(k) => out.push_str(&format!(
            "[body]\nshape = \"../shapes/{}\"\n",
            BUNDLED[*k as usize % BUNDLED.len()]
        )),
        BodyChoice::Missing => out.push_str("[body]\nshape = \"/nonexistent/shape.json\"\n"),
        BodyChoice::Random { dimension, seed, sigma, modes } => {
            out.push_str(&format!(
                "[body]\nrandom = {{ dimension = {dimension}, seed = {seed}, sigma = {}",
                sigma.toml()
            ));
            if let Some(m) = modes {
                out.push_str(&format!(", modes = {m}"));
            }
            out.push_str(" }\n");
        }
        BodyChoice::Perfect(sphere) => out.push_str(&format!(
            "[body]\nperfect = \"{}\"\n",
            if *sphere { "sphere" } else { "disk" }
        )),
        BodyChoice::Inline { sphere, amplitudes } => {
            if *sphere {
                out.push_str("[body.inline]\nkind = \"sphere\"\ncoeffs = [");
                for (l, m, re, im) in amplitudes.iter().take(12) {
                    out.push_str(&format!(
                        "{{ l = {l}, m = {m}, re = {}, im = {} }}, ",
                        re.toml(),
                        im.toml()
                    ));
                }
            } else {
                out.push_str("[body.inline]\nkind = \"disk\"\nmodes = [");
                for (l, _, a, phase) in amplitudes.iter().take(12) {
                    out.push_str(&format!(
                        "{{ l = {l}, a = {}, phase = {} }}, ",
                        a.toml(),
                        phase.toml()
                    ));
                }
            }
            out.push_str("]\n");
        }
        BodyChoice::Two => out.push_str("[body]\nperfect = \"disk\"\nshape = \"../shapes/disk.json\"\n"),
        BodyChoice::None => {}
    }
    section(&mut out, "model", MODEL, &s.model);
    for (name, keys, sec) in [
        ("initial", INITIAL, &s.initial),
        ("integrator", INTEGRATOR, &s.integrator),
        ("playback", PLAYBACK, &s.playback),
        ("views", VIEWS, &s.views),
        ("poincare", POINCARE, &s.poincare),
    ] {
        if let Some(sec) = sec {
            section(&mut out, name, keys, sec);
        }
    }
    out
}

fuzz_target!(|input: FuzzScene| {
    let text = to_toml(&input);
    let Ok(scene) = Scene::from_toml(&text) else { return };
    let Ok(setup) = scene.setup(None) else { return };
    // What validated is usable: finite, in-range numbers.
    let alpha = setup.ramp.alpha_rad;
    assert!(alpha > 0.0 && alpha < std::f64::consts::FRAC_PI_2, "alpha {alpha} in\n{text}");
    assert!(setup.ramp.mass_ratio.is_finite() && setup.ramp.mass_ratio >= 0.0, "{text}");
    assert!(setup.alpha_star.is_finite(), "{text}");
});
