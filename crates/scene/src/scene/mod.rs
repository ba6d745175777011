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
//! friction = 0.5                     # optional: the surface's μ, checked against slip
//! # KEY = VALUE                      # optional: drag-law parameters (dynamics::drag::REGISTERED)
//! [initial]
//! contact = [1.0, 2.0]               # 3D: body point (θ, φ) on the ramp, then `spin` about +z
//! [integrator]
//! preset = "balanced"                # or method = "dop853" + rtol, or "rk4"/"cf4" + dt
//! [playback]
//! speed = 4.0                        # simulation time per second of video
//! [views]
//! ball = true
//! [[timeline]]                       # optional: a lesson's steps (see `timeline`)
//! at = 10.0
//! caption = "Now watch the contact point"
//! ```

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::geometry::ShapeFile;
use crate::integrate::Preset;

pub use crate::assets::{BUNDLED_SHAPES, PRESETS};

mod clock;
pub mod description;
mod drag_law;
mod error;
mod lanes;
pub mod sculpt;
mod setup;
mod text;
mod timeline;
pub use drag_law::{DragLawFields, ReplayDragLaw};
pub use error::SceneError;
pub use lanes::{LaneModel, LaneResume, LaneSpec, MAX_BODIES, MAX_LABEL_CHARS};
pub use setup::{MAX_CROSSING_POINTS, Resume, SceneSetup, bundled_shape, load_scene_file};
pub use timeline::{Claim, MAX_CAPTION_CHARS, MAX_STEPS, Step, TimelineSpec, ViewsChange};

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
    /// The scene's own body's name beside the other bodies (`[[bodies]]`) on the overlay, the
    /// plots and the plot data (empty: the scene's name).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub label: String,
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
    /// A lesson's steps (`[[timeline]]`), in increasing simulation time; see `scene::timeline`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub timeline: Vec<TimelineSpec>,
    /// A saved state to go on from (the app's "Save state"), instead of `[initial]` at t = 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resume: Option<ResumeSpec>,
    /// How the saved run got to `[resume]` (`[[replay]]`, written by Save state): the model it
    /// started with at t = 0, then each change made by hand (α, m/m0, the drag law, the
    /// integrator) and each time it was resumed, at the simulation time it took effect. From
    /// the scene's start, [`crate::live::LiveRun::replayed`] runs it again to the saved state,
    /// bit for bit.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub replay: Vec<ReplayEntry>,
    /// More bodies on the same ramp (`[[bodies]]`, at most three): each on a lane of its own,
    /// with its own body, start, m/m0 and drag law; see `scene::lanes`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<LaneSpec>,
}

/// One `[[replay]]` entry: from simulation time `at` on, the run has this model and integrator,
/// the integrator started afresh there (a change made by hand, or a resume). Unknown keys are
/// refused by [`ReplayDragLaw`], which takes the keys this struct does not name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReplayEntry {
    /// Simulation time.
    pub at: f64,
    /// α in radians, as asked for.
    pub alpha_rad: f64,
    /// m/m0 as asked for (0: viscous).
    pub mass_ratio: f64,
    /// Rotational drag γ in units of γ0.
    #[serde(default = "one")]
    pub drag: f64,
    /// The drag law's parameters (none: linear drag).
    #[serde(default, flatten)]
    pub drag_law: ReplayDragLaw,
    /// The integrator, exactly.
    pub integrator: crate::integrate::Method,
    /// The run was resumed from a saved state here: a replay resumes from its own state at
    /// this time as the app did (a fresh run from the state vector), rather than changing the
    /// model of the run in progress, which differs by 1e-15 and grows.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub resumed: bool,
}

impl ReplayEntry {
    /// The entry for `ramp` and `method` from `at` on.
    pub fn of(at: f64, ramp: &crate::dynamics::Ramp, method: crate::integrate::Method) -> Self {
        Self {
            at,
            alpha_rad: ramp.alpha_rad,
            mass_ratio: ramp.mass_ratio,
            drag: ramp.drag,
            drag_law: ReplayDragLaw(DragLawFields::from(&ramp.drag_law)),
            integrator: method,
            resumed: false,
        }
    }

    /// The ramp it asks for, or why it is not one.
    pub fn ramp(&self) -> Result<crate::dynamics::Ramp, SceneError> {
        let law = self
            .drag_law
            .0
            .law()
            .map_err(|e| error::invalid(e.to_string()))?;
        Ok(
            crate::dynamics::Ramp::with_drag(self.alpha_rad, self.mass_ratio, self.drag)
                .map_err(|e| error::invalid(e.to_string()))?
                .with_drag_law(law),
        )
    }
}

/// Where a saved run goes on from (`[resume]`, written by the app's Save state): the time, the
/// model's whole state vector at that time (pose, velocity, position on the ramp, drag work),
/// and the points of the sweep plots collected so far. The model (α, m/m0) is the scene's.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResumeSpec {
    /// Simulation time of the saved state.
    pub t: f64,
    /// The state vector: 2D viscous [θ, x_c]; 2D inertial [θ, θ̇, x_c, W]; 3D viscous
    /// [q_w, q_x, q_y, q_z, x, y]; 3D inertial [q, ω_x, ω_y, ω_z, x, y, W].
    pub state: Vec<f64>,
    /// The 1/T plot's points: [α, 1/T, m/m0, +1 when α was increasing or −1 decreasing].
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "exact_points"
    )]
    pub alpha_sweep: Vec<[f64; 4]>,
    /// The crossing plot's points: [m/m0, polar angle of the ∂Ω crossing].
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "exact_points"
    )]
    pub crossings: Vec<[f64; 2]>,
    /// The drag law each `alpha_sweep` point was measured under, in its order, as
    /// sweep-alpha.csv's drag column words it ("linear drag", "drag_exponent = 1.5"); absent:
    /// the scene's law for every point (files saved before this was written).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub alpha_sweep_drag: Vec<String>,
    /// The drag law each `crossings` point was measured under, in its order, as
    /// crossings.csv's drag column words it; absent: the scene's law for every point.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub crossings_drag: Vec<String>,
}

/// Points of `N` numbers each, exactly: a point with a number too many is refused, not cut
/// to `N` (TOML's reading of a fixed array took `[0.25, 0.1, 0.0, 1.0, 5.0]` as its first four).
pub(crate) fn exact_points<'de, D, const N: usize>(d: D) -> Result<Vec<[f64; N]>, D::Error>
where
    D: serde::Deserializer<'de>,
{
    use serde::de::Error;
    let points = Vec::<Vec<f64>>::deserialize(d)?;
    points
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            <[f64; N]>::try_from(p.as_slice()).map_err(|_| {
                D::Error::custom(format!("point {i} has {} numbers, not {N}: {p:?}", p.len()))
            })
        })
        .collect()
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

/// Ramp angle (one of `alpha_rad`, `alpha_over_critical`), mass ratio and drag, with the drag
/// law's parameters by their registered keys. Unknown fields are
/// refused by [`DragLawFields`], which takes the keys this struct does not name.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ModelSpec {
    /// The registered model the scene starts with ("sphere-inertial", …), when it names one:
    /// checked against the body and `mass_ratio` by the one rule (`ModelKind::named_for`).
    /// Without it the model follows from them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
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
    /// The surface's coefficient of static friction μ: the overlay says when rolling needs
    /// more (the body would slip). Without it only lift-off (N ≤ 0) is flagged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// The drag law's parameters (none: the paper's linear drag).
    #[serde(flatten)]
    pub drag_law: DragLawFields,
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

/// Integrator names as written in scenes: the core's one list ([`crate::integrate::MethodKind`]).
pub use crate::integrate::MethodKind as MethodName;

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
    /// Simulation time where the scene ends, if it has an end (a lesson): `--frames all`
    /// renders up to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_time: Option<f64>,
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
            end_time: None,
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
    /// The plot a lesson talks about: presentation (F5) and class (C) modes show it large
    /// beside the 3D view.
    #[serde(default, skip_serializing_if = "LessonPlot::is_none")]
    pub plot: LessonPlot,
    /// The scene's other bodies (`[[bodies]]`) on their lanes. They run whether shown or not,
    /// so a lesson step that shows them shows runs as long as the scene's own.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub lanes: bool,
}

fn is_true(b: &bool) -> bool {
    *b
}

/// The plot a lesson step talks about ([`ViewsSpec::plot`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LessonPlot {
    /// None.
    #[default]
    None,
    /// 1/T against α, the sweep's branches up and down (and the √ law on a viscous cylinder).
    InversePeriod,
    /// The settled crossings of ∂Ω against m/m0 (3D): the orbit diagram as the sweep draws it.
    Crossings,
}

impl LessonPlot {
    /// Whether no plot is named.
    pub fn is_none(&self) -> bool {
        *self == LessonPlot::None
    }

    /// Its title, as the large plot shows it.
    pub fn title(&self) -> &'static str {
        match self {
            LessonPlot::None => "",
            LessonPlot::InversePeriod => "1/T against α",
            LessonPlot::Crossings => "Crossings of ∂Ω against m/m0",
        }
    }
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
            plot: LessonPlot::None,
            lanes: true,
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
