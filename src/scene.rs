//! Scenes: everything one interactive or headless run needs (body, model, α, m/m0, initial
//! state, integrator, playback speed, views) as a serde/TOML document, and the bundled presets
//! in `assets/scenes/*.toml`, the one list the app menu, the CLI (`--preset`, `rollphase scenes`)
//! and the tests use.
//!
//! A scene is validated once, by [`Scene::setup`], into a [`SceneSetup`] holding the built body,
//! ramp, integrator and start; errors name the field, the value and what is allowed. Imports the
//! core only (no GPU, no window).
//!
//! ```toml
//! name = "sphere-cruising"
//! description = "3D viscous sphere cruising down the ramp"
//! [body]
//! shape = "../shapes/sphere.json"    # or: random = { dimension = 3, seed = 1, sigma = 0.25, modes = 5 }
//! [model]                            #  or: perfect = "sphere" | "disk", or an inline shape
//! alpha_rad = 0.3                    # or alpha_over_critical = 1.05 (α = 1.05 α*)
//! mass_ratio = 0.0                   # 0 = viscous model
//! [initial]
//! contact = [1.0, 2.0]               # 3D: body point (θ, φ) on the ramp, then `spin` about +z
//! [integrator]
//! preset = "balanced"                # or method = "dop853" + rtol, or "rk4"/"cf4" + dt
//! [playback]
//! speed = 4.0                        # simulation time per second of video
//! [views]
//! ball = true
//! ```

use std::path::{Path, PathBuf};

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::analysis::critical_angle::critical_angle;
use crate::dynamics::sphere3d::orientation_touching;
use crate::dynamics::{ModelError, Ramp};
use crate::geometry::shape_file::{MAX_INPUT_FILE_BYTES, read_text_capped};
use crate::geometry::sphere::direction;
use crate::geometry::{Body, Disk, ShapeError, ShapeFile, Sphere, random_disk, random_sphere};
use crate::integrate::{IntegrateError, Method, Preset};
use crate::simulate::{InitialState, choose_model};

/// The bundled shape files, by file name (scenes refer to them as `../shapes/NAME`).
pub const BUNDLED_SHAPES: &[(&str, &str)] = &[
    ("sphere.json", include_str!("../assets/shapes/sphere.json")),
    ("disk.json", include_str!("../assets/shapes/disk.json")),
    (
        "disk-inertial.json",
        include_str!("../assets/shapes/disk-inertial.json"),
    ),
    (
        "paper-sphere.json",
        include_str!("../assets/shapes/paper-sphere.json"),
    ),
];

/// The preset scenes (name = file stem), the default first.
pub const PRESETS: &[(&str, &str)] = &[
    (
        "sphere-cruising",
        include_str!("../assets/scenes/sphere-cruising.toml"),
    ),
    (
        "sphere-two-orbits",
        include_str!("../assets/scenes/sphere-two-orbits.toml"),
    ),
    (
        "sphere-doubling",
        include_str!("../assets/scenes/sphere-doubling.toml"),
    ),
    (
        "sphere-flip",
        include_str!("../assets/scenes/sphere-flip.toml"),
    ),
    (
        "perfect-sphere",
        include_str!("../assets/scenes/perfect-sphere.toml"),
    ),
    (
        "cylinder-near-critical",
        include_str!("../assets/scenes/cylinder-near-critical.toml"),
    ),
    (
        "cylinder-hysteresis",
        include_str!("../assets/scenes/cylinder-hysteresis.toml"),
    ),
    (
        "poincare-field",
        include_str!("../assets/scenes/poincare-field.toml"),
    ),
];

/// The preset shown when none is asked for.
pub const DEFAULT_PRESET: &str = "sphere-cruising";

/// A scene as written in TOML.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name (presets: the file stem).
    pub name: String,
    /// One line saying what the scene shows.
    #[serde(default)]
    pub description: String,
    /// The body.
    pub body: BodySpec,
    /// Ramp angle, mass and drag.
    pub model: ModelSpec,
    /// Where the run starts.
    #[serde(default)]
    pub initial: InitialSpec,
    /// Integrator and tolerance.
    #[serde(default)]
    pub integrator: IntegratorSpec,
    /// Playback speed and trails.
    #[serde(default)]
    pub playback: PlaybackSpec,
    /// Which views are drawn (and so computed).
    #[serde(default)]
    pub views: ViewsSpec,
    /// Resolution of the Poincaré field, used only when that view is on.
    #[serde(default)]
    pub poincare: PoincareSpec,
}

/// Where the body comes from: exactly one of the four fields.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// A shape file, relative to the scene file (presets: `../shapes/NAME` of the bundled ones).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<PathBuf>,
    /// A shape given inline, in the shape-file schema.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inline: Option<ShapeFile>,
    /// A seeded random body.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub random: Option<RandomBody>,
    /// A perfect disk or sphere (r = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub perfect: Option<PerfectBody>,
}

/// A seeded random body (SI §1C, §2F).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomBody {
    /// 2 (cylinder) or 3 (sphere).
    pub dimension: u32,
    /// Seed of the ChaCha8 stream.
    pub seed: u64,
    /// Amplitude spread σ.
    pub sigma: f64,
    /// Highest mode l.
    #[serde(default = "default_modes")]
    pub modes: u32,
}

fn default_modes() -> u32 {
    5
}

/// A perfect body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PerfectBody {
    /// A circular cylinder (2D).
    Disk,
    /// A ball (3D).
    Sphere,
}

/// Ramp angle (one of `alpha_rad`, `alpha_over_critical`), mass ratio and drag.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// α in radians.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_rad: Option<f64>,
    /// α as a multiple of the body's critical angle α*.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_over_critical: Option<f64>,
    /// m/m0; 0 selects the viscous model.
    #[serde(default)]
    pub mass_ratio: f64,
    /// Rotational drag γ in units of γ0.
    #[serde(default = "one")]
    pub drag: f64,
}

fn one() -> f64 {
    1.0
}

/// Initial state; fields of the other dimension are ignored.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// 3D: body point (θ, φ) put on the ramp by the shortest rotation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<[f64; 2]>,
    /// 3D: then a turn about the ramp normal, radians.
    #[serde(default)]
    pub spin: f64,
    /// 3D: the orientation quaternion (w, x, y, z) instead of `contact`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q0: Option<[f64; 4]>,
    /// 3D inertial: lab angular velocity.
    #[serde(default)]
    pub omega: [f64; 3],
    /// 2D: contact angle θ₀.
    #[serde(default)]
    pub theta0: f64,
    /// 2D inertial: θ̇₀.
    #[serde(default)]
    pub theta_dot0: f64,
}

/// The integrator: a named preset, or a method with its tolerance or step.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntegratorSpec {
    /// fast / balanced / precise (DOP853 at rtol 1e-6 / 1e-8 / 1e-12).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<Preset>,
    /// dop853, rk4 or cf4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<MethodName>,
    /// DOP853 relative (and absolute) tolerance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rtol: Option<f64>,
    /// RK4/CF4 step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
}

/// Integrator names as written in scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MethodName {
    /// Adaptive DOP853.
    Dop853,
    /// Fixed-step RK4.
    Rk4,
    /// Fixed-step Lie-group RK4.
    Cf4,
}

/// Playback: how simulation time maps to video time, and how much history the trails keep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaybackSpec {
    /// Simulation time per second of video.
    #[serde(default = "default_speed")]
    pub speed: f64,
    /// Frames per second of video (headless frames are 1/fps seconds apart).
    #[serde(default = "default_fps")]
    pub fps: f64,
    /// Simulation time run before the first frame (to skip a transient).
    #[serde(default)]
    pub start_time: f64,
    /// Simulation time of history kept in the trails.
    #[serde(default = "default_trail")]
    pub trail_time: f64,
}

fn default_speed() -> f64 {
    4.0
}
fn default_fps() -> f64 {
    30.0
}
fn default_trail() -> f64 {
    60.0
}

impl Default for PlaybackSpec {
    fn default() -> Self {
        Self {
            speed: default_speed(),
            fps: default_fps(),
            start_time: 0.0,
            trail_time: default_trail(),
        }
    }
}

/// Which views are drawn. Only what is drawn is computed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewsSpec {
    /// The body rolling on the ramp.
    #[serde(default = "yes")]
    pub body: bool,
    /// The SO(3) ball with the orientation's trajectory (3D only).
    #[serde(default)]
    pub ball: bool,
    /// The Poincaré field on ∂Ω (3D viscous only).
    #[serde(default)]
    pub poincare: bool,
    /// The text overlay and the colour legends.
    #[serde(default = "yes")]
    pub overlay: bool,
}

fn yes() -> bool {
    true
}

impl Default for ViewsSpec {
    fn default() -> Self {
        Self {
            body: true,
            ball: false,
            poincare: false,
            overlay: true,
        }
    }
}

/// How finely the Poincaré field is sampled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoincareSpec {
    /// Number of arrows on ∂Ω (antipodal pairs count twice).
    #[serde(default = "default_arrows")]
    pub arrows: usize,
    /// DOP853 tolerance of each map step.
    #[serde(default = "default_field_rtol")]
    pub rtol: f64,
    /// Longest time a start is followed before it counts as halted.
    #[serde(default = "default_field_tmax")]
    pub t_max: f64,
}

fn default_arrows() -> usize {
    600
}
fn default_field_rtol() -> f64 {
    1e-8
}
fn default_field_tmax() -> f64 {
    200.0
}

impl Default for PoincareSpec {
    fn default() -> Self {
        Self {
            arrows: default_arrows(),
            rtol: default_field_rtol(),
            t_max: default_field_tmax(),
        }
    }
}

/// What is wrong with a scene.
#[derive(Debug, Error)]
pub enum SceneError {
    /// TOML syntax or an unknown/mistyped field (transparent, so the message is printed once).
    #[error(transparent)]
    Parse(#[from] toml::de::Error),
    /// A value out of range or fields that do not fit together.
    #[error("{0}")]
    Invalid(String),
    /// The body is bad.
    #[error(transparent)]
    Shape(#[from] ShapeError),
    /// α, m/m0 or drag out of range.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// Bad integrator settings.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
    /// The shape file could not be read.
    #[error("cannot read shape file {}: {reason}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: std::io::Error,
    },
    /// The scene file could not be read.
    #[error("cannot read scene file {}: {reason}", path.display())]
    SceneIo {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: std::io::Error,
    },
    /// No preset of that name.
    #[error("no preset named {0:?}; `rollphase scenes` lists them: {1}")]
    UnknownPreset(String, String),
}

fn invalid(msg: impl Into<String>) -> SceneError {
    SceneError::Invalid(msg.into())
}

/// A validated scene with its body, ramp, integrator and start built.
#[derive(Debug, Clone)]
pub struct SceneSetup {
    /// The scene as written.
    pub scene: Scene,
    /// The body.
    pub body: Body,
    /// Its critical angle α*.
    pub alpha_star: f64,
    /// The ramp actually simulated (the stiff-corner policy may select the viscous model).
    pub ramp: Ramp,
    /// Why the model differs from the request, if it does.
    pub model_note: Option<String>,
    /// The integrator.
    pub method: Method,
    /// The start.
    pub initial: InitialState,
}

impl Scene {
    /// Parses TOML text.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        Ok(toml::from_str(text)?)
    }

    /// TOML text of the scene.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }

    /// A bundled preset by name.
    pub fn preset(name: &str) -> Result<Self, SceneError> {
        let text = PRESETS
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, t)| *t)
            .ok_or_else(|| {
                SceneError::UnknownPreset(
                    name.to_string(),
                    PRESETS
                        .iter()
                        .map(|(n, _)| *n)
                        .collect::<Vec<_>>()
                        .join(", "),
                )
            })?;
        Self::from_toml(text)
    }

    /// Validates the scene and builds what a run needs. `base` is the folder of the scene file
    /// (shape paths are relative to it); `None` for a bundled preset.
    pub fn setup(&self, base: Option<&Path>) -> Result<SceneSetup, SceneError> {
        let body = self.body.build(base)?;
        body.check_convex()?;
        let alpha_star = critical_angle(&body).alpha_star;
        let m = &self.model;
        let alpha = match (m.alpha_rad, m.alpha_over_critical) {
            (Some(a), None) => a,
            (None, Some(f)) => {
                if !(f.is_finite() && f > 0.0) {
                    return Err(invalid(format!(
                        "model.alpha_over_critical = {f} is not allowed (needs a finite factor > 0)"
                    )));
                }
                if alpha_star == 0.0 {
                    return Err(invalid(
                        "model.alpha_over_critical needs a body with α* > 0; a perfect body has \
                         α* = 0, so give model.alpha_rad",
                    ));
                }
                let alpha = f * alpha_star;
                if alpha >= std::f64::consts::FRAC_PI_2 {
                    return Err(invalid(format!(
                        "model.alpha_over_critical = {f} is not allowed for this body: it makes \
                         α = {f} × α* = {alpha:.4} rad, steeper than a vertical wall (needs \
                         alpha_over_critical < {:.4}, i.e. α < π/2)",
                        std::f64::consts::FRAC_PI_2 / alpha_star
                    )));
                }
                alpha
            }
            _ => {
                return Err(invalid(
                    "give exactly one of model.alpha_rad (radians) and model.alpha_over_critical (α/α*)",
                ));
            }
        };
        let ramp = Ramp::with_drag(alpha, m.mass_ratio, m.drag)?;
        let method = self.integrator.method()?;
        let choice = choose_model(&body, ramp, method).map_err(|e| invalid(e.to_string()))?;
        let initial = self.initial.build(&body)?;
        self.playback.validate()?;
        self.views.validate(&body, &choice.ramp)?;
        self.poincare.validate()?;
        Ok(SceneSetup {
            scene: self.clone(),
            body,
            alpha_star,
            ramp: choice.ramp,
            model_note: choice.note,
            method,
            initial,
        })
    }
}

impl BodySpec {
    /// Builds the body (not yet checked for convexity).
    pub fn build(&self, base: Option<&Path>) -> Result<Body, SceneError> {
        let given = [
            self.shape.is_some(),
            self.inline.is_some(),
            self.random.is_some(),
            self.perfect.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(invalid(
                "give exactly one of body.shape (a shape file), body.inline, body.random or body.perfect",
            ));
        }
        if let Some(path) = &self.shape {
            let text = match base {
                Some(dir) => {
                    let full = dir.join(path);
                    read_text_capped(&full, MAX_INPUT_FILE_BYTES)
                        .map_err(|reason| SceneError::Io { path: full, reason })?
                }
                None => bundled_shape(path)?.to_string(),
            };
            let file = ShapeFile::from_json(&text).map_err(|e| {
                invalid(format!(
                    "body.shape {} is not a valid shape file: {e}",
                    path.display()
                ))
            })?;
            return Ok(Body::from_file(&file)?);
        }
        if let Some(file) = &self.inline {
            return Ok(Body::from_file(file)?);
        }
        if let Some(r) = &self.random {
            return match r.dimension {
                2 => Ok(Body::Disk(random_disk(r.seed, r.sigma, r.modes)?)),
                3 => Ok(Body::Sphere(random_sphere(r.seed, r.sigma, r.modes)?)),
                d => Err(invalid(format!(
                    "body.random.dimension = {d} is not allowed (needs 2 for a cylinder or 3 for a sphere)"
                ))),
            };
        }
        Ok(match self.perfect {
            Some(PerfectBody::Disk) => Body::Disk(Disk::perfect()),
            _ => Body::Sphere(Sphere::perfect()),
        })
    }
}

/// The text of a bundled shape named by a path whose file name is one of [`BUNDLED_SHAPES`].
pub fn bundled_shape(path: &Path) -> Result<&'static str, SceneError> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    BUNDLED_SHAPES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t)
        .ok_or_else(|| {
            invalid(format!(
                "body.shape {} is not a bundled shape (have: {})",
                path.display(),
                BUNDLED_SHAPES
                    .iter()
                    .map(|(n, _)| *n)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
}

impl InitialSpec {
    fn build(&self, body: &Body) -> Result<InitialState, SceneError> {
        let finite = |name: &str, v: &[f64]| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(invalid(format!(
                    "initial.{name} = {v:?} is not allowed (needs finite numbers)"
                )))
            }
        };
        match body {
            Body::Disk(_) => {
                if self.contact.is_some()
                    || self.q0.is_some()
                    || self.spin != 0.0
                    || self.omega != [0.0; 3]
                {
                    return Err(invalid(
                        "initial.contact, q0, spin and omega are for a 3D body, and this scene's \
                         body is a 2D disk: give initial.theta0 (and theta_dot0) instead",
                    ));
                }
                finite("theta0", &[self.theta0])?;
                finite("theta_dot0", &[self.theta_dot0])?;
                Ok(InitialState::Disk {
                    theta0: self.theta0,
                    theta_dot0: self.theta_dot0,
                })
            }
            Body::Sphere(s) => {
                if self.theta0 != 0.0 || self.theta_dot0 != 0.0 {
                    return Err(invalid(
                        "initial.theta0 and theta_dot0 are for a 2D body, and this scene's body is \
                         a 3D sphere: give initial.contact = [θ, φ] (and spin) or q0 instead",
                    ));
                }
                finite("spin", &[self.spin])?;
                finite("omega", &self.omega)?;
                let q0 = match (self.q0, self.contact) {
                    (Some(_), Some(_)) => {
                        return Err(invalid("give initial.q0 or initial.contact, not both"));
                    }
                    (Some([w, x, y, z]), None) => {
                        finite("q0", &[w, x, y, z])?;
                        let q = DQuat::from_xyzw(x, y, z, w);
                        if q.length() < 1e-12 {
                            return Err(invalid(
                                "initial.q0 = [0, 0, 0, 0] is not an orientation (needs |q| > 0)",
                            ));
                        }
                        q.normalize()
                    }
                    (None, Some([theta, phi])) => {
                        finite("contact", &[theta, phi])?;
                        orientation_touching(s, direction(theta, phi), self.spin)
                    }
                    (None, None) => orientation_touching(s, DVec3::NEG_Z, self.spin),
                };
                Ok(InitialState::Sphere {
                    q0,
                    omega0: DVec3::from_array(self.omega),
                })
            }
        }
    }
}

impl IntegratorSpec {
    /// The integrator this spec names; `balanced` when nothing is given.
    pub fn method(&self) -> Result<Method, SceneError> {
        let method = match (self.preset, self.method) {
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "give integrator.preset or integrator.method, not both",
                ));
            }
            (Some(p), None) => {
                if self.rtol.is_some() || self.dt.is_some() {
                    return Err(invalid(
                        "integrator.preset fixes the tolerance; drop integrator.rtol/dt or give integrator.method",
                    ));
                }
                p.method()
            }
            (None, None) => Preset::Balanced.method(),
            (None, Some(MethodName::Dop853)) => Method::dop853(self.rtol.unwrap_or(1e-8)),
            (None, Some(MethodName::Rk4)) => Method::Rk4 {
                dt: self.dt.unwrap_or(0.01),
            },
            (None, Some(MethodName::Cf4)) => Method::Cf4 {
                dt: self.dt.unwrap_or(0.01),
            },
        };
        method.validate()?;
        Ok(method)
    }
}

impl PlaybackSpec {
    fn validate(&self) -> Result<(), SceneError> {
        let checks = [
            (
                "speed",
                self.speed,
                self.speed > 0.0 && self.speed <= 1e4,
                "0 < speed ≤ 10000 time units per second",
            ),
            (
                "fps",
                self.fps,
                self.fps >= 1.0 && self.fps <= 240.0,
                "1 ≤ fps ≤ 240",
            ),
            (
                "start_time",
                self.start_time,
                self.start_time >= 0.0 && self.start_time <= 1e6,
                "0 ≤ start_time ≤ 1e6",
            ),
            (
                "trail_time",
                self.trail_time,
                self.trail_time >= 0.0 && self.trail_time <= 1e5,
                "0 ≤ trail_time ≤ 1e5",
            ),
        ];
        for (name, v, ok, allowed) in checks {
            if !(v.is_finite() && ok) {
                return Err(invalid(format!(
                    "playback.{name} = {v} is not allowed (needs {allowed})"
                )));
            }
        }
        Ok(())
    }

    /// Simulation time of frame `k` (frame 0 at `start_time`).
    pub fn frame_time(&self, k: u64) -> f64 {
        self.start_time + k as f64 * self.speed / self.fps
    }
}

impl ViewsSpec {
    fn validate(&self, body: &Body, ramp: &Ramp) -> Result<(), SceneError> {
        if !(self.body || self.ball || self.poincare) {
            return Err(invalid(
                "views: turn on at least one of body, ball, poincare",
            ));
        }
        if matches!(body, Body::Disk(_)) && (self.ball || self.poincare) {
            return Err(invalid(
                "views.ball and views.poincare need a 3D body (the SO(3) ball shows 3D orientations); \
                 turn them off for a cylinder",
            ));
        }
        if self.poincare && !ramp.is_viscous() {
            return Err(invalid(
                "views.poincare needs the viscous model (model.mass_ratio = 0): the map on ∂Ω is \
                 of orientations alone, which determine the viscous motion but not the inertial one",
            ));
        }
        Ok(())
    }
}

impl PoincareSpec {
    fn validate(&self) -> Result<(), SceneError> {
        if !(8..=20_000).contains(&self.arrows) {
            return Err(invalid(format!(
                "poincare.arrows = {} is not allowed (needs 8 ≤ arrows ≤ 20000)",
                self.arrows
            )));
        }
        if !(self.rtol.is_finite() && self.rtol >= 1e-13 && self.rtol <= 1e-3) {
            return Err(invalid(format!(
                "poincare.rtol = {} is not allowed (needs 1e-13 ≤ rtol ≤ 1e-3)",
                self.rtol
            )));
        }
        if !(self.t_max.is_finite() && self.t_max > 0.0 && self.t_max <= 1e5) {
            return Err(invalid(format!(
                "poincare.t_max = {} is not allowed (needs 0 < t_max ≤ 1e5)",
                self.t_max
            )));
        }
        Ok(())
    }
}

/// Loads a scene file; shape paths in it are relative to its folder.
pub fn load_scene_file(path: &Path) -> Result<SceneSetup, SceneError> {
    let text =
        read_text_capped(path, MAX_INPUT_FILE_BYTES).map_err(|reason| SceneError::SceneIo {
            path: path.to_path_buf(),
            reason,
        })?;
    let scene = Scene::from_toml(&text)?;
    scene.setup(Some(path.parent().unwrap_or(Path::new("."))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_parses_validates_and_is_named_after_its_file() {
        for (name, _) in PRESETS {
            let scene = Scene::preset(name).unwrap();
            assert_eq!(scene.name, *name);
            assert!(!scene.description.is_empty(), "{name} has no description");
            scene.setup(None).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert_eq!(PRESETS[0].0, DEFAULT_PRESET);
    }

    #[test]
    fn scenes_round_trip_through_toml() {
        for (name, _) in PRESETS {
            let scene = Scene::preset(name).unwrap();
            assert_eq!(Scene::from_toml(&scene.to_toml()).unwrap(), scene);
        }
    }

    #[test]
    fn frame_times_follow_the_playback_speed() {
        let p = PlaybackSpec {
            speed: 6.0,
            fps: 30.0,
            start_time: 10.0,
            trail_time: 1.0,
        };
        assert_eq!(p.frame_time(0), 10.0);
        assert!((p.frame_time(30) - 16.0).abs() < 1e-12);
    }
}
