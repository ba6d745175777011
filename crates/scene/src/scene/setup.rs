//! Validation of a scene into a [`SceneSetup`]: the body built, α resolved (also from
//! `alpha_over_critical`), the integrator and the start checked. Every error names the field,
//! the value and what is allowed.

use crate::analysis::rest::critical_angle::critical_angle;
use crate::dynamics::{ModelKind, Ramp};
use crate::geometry::shape_file::{MAX_INPUT_FILE_BYTES, read_text_capped};
use crate::geometry::{Body, Disk, ShapeFile, Sphere, random_disk, random_sphere};
use crate::integrate::{Method, Preset};
use crate::simulate::start::{Spelling, StartField, StartRequest, check_start};
use crate::simulate::{ContactLimits, OnViolation};
use crate::simulate::{InitialState, ModelState, Start, choose_model};
use std::path::Path;

use super::error::{SceneError, check_speed, invalid};
use super::timeline::Step;
use super::{
    BodySpec, InitialSpec, IntegratorSpec, MethodName, PerfectBody, PlaybackSpec, PoincareSpec,
    Scene, ViewsSpec,
};
use crate::assets::{BUNDLED_SHAPES, PRESETS};

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
    /// The body paired with its start.
    pub start: Start,
    /// The lesson's steps, validated (empty for an ordinary scene).
    pub timeline: Vec<Step>,
    /// The surface the run is checked against (lift-off always, slip with `model.friction`);
    /// the app and headless frames report a violation and go on.
    pub limits: ContactLimits,
    /// The saved state the run goes on from (`[resume]`), checked; `None`: from `start` at 0.
    pub resume: Option<Resume>,
    /// The other bodies on the ramp (`[[bodies]]`), each validated as a scene of its own into
    /// the setup of its run (`scene::lanes`); empty for one body.
    pub lanes: Vec<SceneSetup>,
}

/// A checked `[resume]`: the run goes on at `t` from `state`.
#[derive(Debug, Clone)]
pub struct Resume {
    /// Simulation time.
    pub t: f64,
    /// The model at that time.
    pub state: ModelState,
}

impl Scene {
    /// Parses TOML text.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        Ok(toml::from_str(text)?)
    }

    /// TOML text of the scene, or why it cannot be written (never an empty text that would be
    /// saved as a scene).
    pub fn to_toml(&self) -> Result<String, SceneError> {
        toml::to_string(self)
            .map_err(|e| SceneError::Invalid(format!("cannot write the scene as TOML: {e}")))
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
        let mut setup = self.setup_with_body(self.body.build(base)?)?;
        setup.lanes = self.lane_setups(base, &setup)?;
        Ok(setup)
    }

    /// [`Self::setup`] for `body`, already built from the scene's `[body]`.
    fn setup_with_body(&self, body: Body) -> Result<SceneSetup, SceneError> {
        // A dented cylinder rolls on its convex hull; a sphere must be convex.
        body.check_rollable()?;
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
        let law = m
            .drag_law
            .law()
            .map_err(|e| invalid(format!("model.{e}")))?;
        let ramp = Ramp::with_drag(alpha, m.mass_ratio, m.drag)?.with_drag_law(law);
        if let Some(name) = &m.kind {
            ModelKind::named_for(name, body.dimension(), &ramp)
                .map_err(|e| invalid(format!("model.kind = \"{name}\": {e}")))?;
        }
        let limits = ContactLimits {
            friction: m.friction,
            on_violation: OnViolation::Warn,
        };
        limits
            .validate()
            .map_err(|e| invalid(format!("model.{e}")))?;
        let method = self.integrator.method()?;
        let choice = choose_model(&body, ramp, method).map_err(|e| invalid(e.to_string()))?;
        let start = Start::new(&body, self.initial.build(&body, m.mass_ratio)?)
            .map_err(|e| invalid(e.to_string()))?;
        self.playback.validate()?;
        self.check_step_fits_a_frame(method)?;
        self.views.validate(&body, &choice.ramp)?;
        self.poincare.validate()?;
        let timeline = super::timeline::resolve(self, &body, alpha_star, choice.ramp, method)?;
        let resume = match &self.resume {
            Some(r) => Some(r.check(&start, &choice.ramp)?),
            None => None,
        };
        self.check_replay()?;
        Ok(SceneSetup {
            scene: self.clone(),
            body,
            alpha_star,
            ramp: choice.ramp,
            model_note: choice.note,
            method,
            start,
            timeline,
            limits,
            resume,
            lanes: Vec::new(),
        })
    }
}

impl Scene {
    /// `[[replay]]` as a saved state writes it: with a `[resume]`, from t = 0, in order of
    /// time, none after the saved time, each a ramp and an integrator the app runs.
    fn check_replay(&self) -> Result<(), SceneError> {
        let Some(first) = self.replay.first() else {
            return Ok(());
        };
        let Some(resume) = &self.resume else {
            return Err(invalid(
                "[[replay]] without [resume]: a replay leads to a saved state; Save state writes \
                 both, Save scene neither",
            ));
        };
        let t = crate::integrate::readable;
        if first.at != 0.0 {
            return Err(invalid(format!(
                "the first [[replay]] entry is at t = {} (needs t = 0: the model the run started \
                 with)",
                t(first.at)
            )));
        }
        let mut before = 0.0;
        for (i, e) in self.replay.iter().enumerate() {
            let entry = format!("[[replay]] entry {} (at t = {})", i + 1, t(e.at));
            if !(e.at.is_finite() && e.at >= before && e.at <= resume.t) {
                return Err(invalid(format!(
                    "{entry} is not allowed (needs times in order from 0 to the saved t = {}; \
                     the entry before is at {})",
                    t(resume.t),
                    t(before)
                )));
            }
            before = e.at;
            e.ramp().map_err(|err| invalid(format!("{entry}: {err}")))?;
            e.integrator
                .validate()
                .map_err(|err| invalid(format!("{entry}: {err}")))?;
            // The same rule as [integrator]'s: the app never ran a coarser step.
            self.check_step_fits_a_frame(e.integrator)
                .map_err(|err| invalid(format!("{entry}: {err}")))?;
        }
        Ok(())
    }
}

impl SceneSetup {
    /// The run a saved state's `[[replay]]` starts from: this scene at t = 0 with the model
    /// of its first entry (the one the saved run started with). `None` without a replay.
    ///
    /// # Errors
    /// The first entry's model or integrator cannot be written as the scene's (the check that
    /// the replay starts where the saved run did, to the bit).
    pub fn replay_start(&self) -> Result<Option<SceneSetup>, SceneError> {
        match self.scene.replay.first() {
            Some(first) => self.replay_setup(first, None).map(Some),
            None => Ok(None),
        }
    }

    /// This scene with the model of `entry`, from its start, or (`resume`: a time and a state
    /// vector) resumed there as the app resumes a saved state: what a replay runs from each
    /// entry that was a resume (`ReplayEntry::resumed`).
    ///
    /// # Errors
    /// The entry's model, integrator or state does not fit the scene.
    pub fn replay_setup(
        &self,
        entry: &super::ReplayEntry,
        resume: Option<(f64, Vec<f64>)>,
    ) -> Result<SceneSetup, SceneError> {
        let mut scene = self.scene.clone();
        scene.resume = resume.map(|(t, state)| super::ResumeSpec {
            t,
            state,
            ..Default::default()
        });
        scene.replay.clear();
        // A replay checks the scene's own body: the other bodies' states are saved, not
        // replayed (`[[bodies]]` resume).
        scene.bodies.clear();
        scene.model.alpha_rad = Some(entry.alpha_rad);
        scene.model.alpha_over_critical = None;
        scene.model.mass_ratio = entry.mass_ratio;
        scene.model.drag = entry.drag;
        scene.model.drag_law = entry.drag_law.0.clone();
        scene.model.kind = None;
        scene.integrator = IntegratorSpec::of(&entry.integrator);
        let setup = scene.setup_with_body(self.body.clone())?;
        if setup.method != entry.integrator {
            return Err(invalid(format!(
                "the replay's integrator at t = {} ({}) cannot be written as a scene's",
                crate::integrate::readable(entry.at),
                entry.integrator
            )));
        }
        Ok(setup)
    }
}

/// The latest time a saved state may be at: a billion t0 (a day at the app's fastest speed is
/// 9e7), where a frame's time step still has 8 digits.
pub const MAX_RESUME_T: f64 = 1e9;

/// The most points `[resume]` may carry in each plot (the app keeps 5000 crossings).
const MAX_RESUME_POINTS: usize = 100_000;

/// The most settled crossings the crossings plot keeps (the newest; a run held at one m/m0
/// adds no more once its cycle's points are in): what Save state writes at most, and what
/// `[resume]` may give.
pub const MAX_CROSSING_POINTS: usize = 5000;

impl super::ResumeSpec {
    /// Checks the saved state against the scene's model, and the plots' points.
    fn check(&self, start: &Start, ramp: &Ramp) -> Result<Resume, SceneError> {
        if !(self.t.is_finite() && (0.0..=MAX_RESUME_T).contains(&self.t)) {
            return Err(invalid(format!(
                "resume.t = {} is not allowed (needs a time from 0 to {MAX_RESUME_T:e}: past it a \
                 frame's step is lost in the time's rounding, and at 1e307 the frame clock \
                 never advanced)",
                crate::integrate::readable(self.t)
            )));
        }
        let state = ModelState::new(start, ramp)
            .with_vector(&self.state)
            .map_err(|e| invalid(format!("resume.state: {e}")))?;
        if self.alpha_sweep.len() > MAX_RESUME_POINTS || self.crossings.len() > MAX_RESUME_POINTS {
            return Err(invalid(format!(
                "resume: at most {MAX_RESUME_POINTS} points a plot (alpha_sweep has {}, \
                 crossings {})",
                self.alpha_sweep.len(),
                self.crossings.len()
            )));
        }
        for (field, labels, points) in [
            (
                "alpha_sweep",
                &self.alpha_sweep_drag,
                self.alpha_sweep.len(),
            ),
            ("crossings", &self.crossings_drag, self.crossings.len()),
        ] {
            if !labels.is_empty() && labels.len() != points {
                return Err(invalid(format!(
                    "resume.{field}_drag has {} label(s) for {points} {field} point(s) (needs \
                     one per point; left out or empty, every point is the scene's law)",
                    labels.len()
                )));
            }
            for (i, label) in labels.iter().enumerate() {
                let at = format!("resume.{field}_drag[{i}] =");
                let chars = label.chars().count();
                if chars > 200 {
                    let start: String = label.chars().take(40).collect();
                    return Err(invalid(format!(
                        "{at} {start:?}… ({chars} characters) is not a drag law's words (needs \
                         1 to 200 characters, as the plot's CSV words its drag column)"
                    )));
                }
                super::text::check_characters(label, &at)?;
                if super::text::as_shown(label).is_empty() {
                    return Err(invalid(format!(
                        "{at} {label:?} is not a drag law's words: it has no visible character \
                         (needs 1 to 200 characters, as the plot's CSV words its drag column)"
                    )));
                }
            }
        }
        // A point is one the app could have measured: a ramp it runs (α and m/m0 as `Ramp`
        // takes them), a finite 1/T ≥ 0, a polar angle on the ball (0 to π).
        let a_ramp = |alpha: f64, mass: f64| Ramp::new(alpha, mass).is_ok();
        for (i, p) in self.alpha_sweep.iter().enumerate() {
            let [alpha, rate, mass, dir] = *p;
            let ok = a_ramp(alpha, mass)
                && rate.is_finite()
                && rate >= 0.0
                && (dir == 1.0 || dir == -1.0);
            if !ok {
                return Err(invalid(format!(
                    "resume.alpha_sweep[{i}] = {p:?} is not a point (needs [α in [1e-9, π/2), \
                     1/T ≥ 0, m/m0 ≥ 0, +1 or −1], all finite)"
                )));
            }
        }
        if self.crossings.len() > MAX_CROSSING_POINTS {
            return Err(invalid(format!(
                "resume.crossings has {} points, but the crossings plot keeps at most \
                 {MAX_CROSSING_POINTS} (the newest; Save state writes no more): leave out the \
                 oldest {}",
                self.crossings.len(),
                self.crossings.len() - MAX_CROSSING_POINTS
            )));
        }
        if matches!(start, Start::Disk { .. }) && !self.crossings.is_empty() {
            return Err(invalid(format!(
                "resume.crossings has {} points, but the body is a cylinder: crossings of ∂Ω \
                 are a sphere's (a cylinder's plots keep alpha_sweep only); leave them out",
                self.crossings.len()
            )));
        }
        if let Some(i) = self.crossings.iter().position(|&[mass, polar]| {
            !(a_ramp(0.1, mass) && (0.0..=std::f64::consts::PI).contains(&polar))
        }) {
            return Err(invalid(format!(
                "resume.crossings[{i}] = {:?} is not a point (needs [m/m0 ≥ 0, a polar angle \
                 from 0 to π], both finite)",
                self.crossings[i]
            )));
        }
        Ok(Resume { t: self.t, state })
    }
}

impl Scene {
    /// A fixed step longer than one frame's simulated time (playback speed / fps, at the
    /// slowest speed the lesson plays at) would be cut to a frame at every frame, so the run
    /// would not use the step asked for; `simulate` refuses dt > t_end for the same reason.
    fn check_step_fits_a_frame(&self, method: Method) -> Result<(), SceneError> {
        let (Method::Rk4 { dt } | Method::Cf4 { dt }) = method else {
            return Ok(());
        };
        let slowest = self
            .timeline
            .iter()
            .filter_map(|s| s.speed)
            .fold(self.playback.speed, f64::min);
        let frame = slowest / self.playback.fps;
        if dt > frame {
            return Err(invalid(format!(
                "integrator.dt = {} is longer than one frame's simulated time ({} = the slowest \
                 playback speed {} / fps {}): every frame would take one shorter step instead, so \
                 the run would not use the step asked for; use dt ≤ {}",
                crate::integrate::readable(dt),
                crate::integrate::readable(frame),
                crate::integrate::readable(slowest),
                crate::integrate::readable(self.playback.fps),
                crate::integrate::readable(frame)
            )));
        }
        Ok(())
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
            return Ok(Body::from_shape(&file)?);
        }
        if let Some(file) = &self.inline {
            return Ok(Body::from_shape(file)?);
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

/// The scene file's names of the start's fields, for the core's messages.
fn scene_key(f: StartField) -> &'static str {
    match f {
        StartField::Q0 => "initial.q0",
        StartField::Contact => "initial.contact",
        StartField::Spin => "initial.spin",
        StartField::Omega0 => "initial.omega",
        StartField::Theta0 => "initial.theta0",
        StartField::ThetaDot0 => "initial.theta_dot0",
    }
}

impl InitialSpec {
    /// The start, checked by the core as the command line's and Python's are ([`check_start`]):
    /// a key that does not apply to this body is an error, never ignored. The keys default to
    /// 0, so a zero is read as not given. One difference: an initial velocity (`omega`,
    /// `theta_dot0`) with `model.mass_ratio = 0` is kept in the file but not used, because a
    /// scene is edited live: the app saves the scene with the mass slider wherever it is, and
    /// the preset's velocity must not make that file unloadable.
    fn build(&self, body: &Body, mass_ratio: f64) -> Result<InitialState, SceneError> {
        let given = |v: f64| Some(v).filter(|v| *v != 0.0);
        // The velocity of the body's own kind is dropped when viscous; the other kind's is
        // still refused.
        let (sphere, inertial) = (
            body.dimension() == 3,
            crate::dynamics::models::asks_for_inertia(mass_ratio),
        );
        let request = StartRequest {
            q0: self.q0,
            contact: self.contact,
            // A saved scene writes spin = 0.0 beside its q0: here 0 is "not given".
            spin: Some(self.spin).filter(|s| *s != 0.0),
            omega0: Some(self.omega).filter(|w| *w != [0.0; 3] && (inertial || !sphere)),
            theta0: given(self.theta0),
            theta_dot0: given(self.theta_dot0).filter(|_| inertial || sphere),
        };
        let spelling = Spelling {
            field: scene_key,
            mass: "model.mass_ratio",
            viscous: "model.mass_ratio = 0",
            body: "this scene's body",
        };
        let start =
            check_start(body, mass_ratio, &request).map_err(|e| invalid(e.explain(&spelling)))?;
        Ok(start.initial)
    }
}

impl IntegratorSpec {
    /// The spec that names `method`: its preset where it is one, else the method with its
    /// step or tolerance (a DOP853 spec has one tolerance: rtol = atol).
    pub fn of(method: &Method) -> IntegratorSpec {
        if let Some(p) = Preset::ALL.into_iter().find(|p| p.method() == *method) {
            return IntegratorSpec {
                preset: Some(p),
                ..IntegratorSpec::default()
            };
        }
        match *method {
            Method::Dop853 { rtol, .. } => IntegratorSpec {
                method: Some(MethodName::Dop853),
                rtol: Some(rtol),
                ..IntegratorSpec::default()
            },
            Method::Rk4 { dt } => IntegratorSpec {
                method: Some(MethodName::Rk4),
                dt: Some(dt),
                ..IntegratorSpec::default()
            },
            Method::Cf4 { dt } => IntegratorSpec {
                method: Some(MethodName::Cf4),
                dt: Some(dt),
                ..IntegratorSpec::default()
            },
        }
    }

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
            (None, Some(kind)) => {
                kind.with(self.rtol.unwrap_or(1e-8), None, self.dt.unwrap_or(0.01))?
            }
        };
        Ok(method)
    }
}

impl PlaybackSpec {
    pub(super) fn validate(&self) -> Result<(), SceneError> {
        check_speed("playback.speed", self.speed)?;
        let checks = [
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
        if let Some(end) = self.end_time
            && !(end.is_finite() && end > self.start_time && end <= 1e6)
        {
            return Err(invalid(
                if end.is_finite() && end <= 1e6 && end <= self.start_time {
                    // Either may be the mistake: both are named.
                    format!(
                        "playback.start_time = {} is not before playback.end_time = {end}: the scene \
                     would start past its end (needs start_time < end_time ≤ 1e6)",
                        self.start_time
                    )
                } else {
                    format!(
                        "playback.end_time = {end} is not allowed (needs start_time < end_time ≤ 1e6)"
                    )
                },
            ));
        }
        Ok(())
    }
}

impl ViewsSpec {
    pub(super) fn validate(&self, body: &Body, ramp: &Ramp) -> Result<(), SceneError> {
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
        if matches!(body, Body::Disk(_)) && self.plot == super::LessonPlot::Crossings {
            return Err(invalid(
                "views.plot = \"crossings\" needs a 3D body (the crossings of ∂Ω are a sphere's); \
                 a cylinder's lesson can name \"inverse-period\"",
            ));
        }
        // The map on ∂Ω is the viscous sphere's; every model is named, so a new one is a
        // compile error here until its map is decided.
        let has_map = match ModelKind::of(body, ramp) {
            ModelKind::SphereViscous => true,
            ModelKind::SphereInertial | ModelKind::DiskViscous | ModelKind::DiskInertial => false,
        };
        if self.poincare && !has_map {
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
    use crate::scene::DEFAULT_PRESET;

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
            assert_eq!(Scene::from_toml(&scene.to_toml().unwrap()).unwrap(), scene);
        }
    }

    #[test]
    fn a_scene_may_name_its_model_and_a_name_that_does_not_fit_is_refused() {
        let base = Scene::preset(DEFAULT_PRESET).unwrap().to_toml().unwrap();
        let with = |line: &str| base.replace("[model]\n", &format!("[model]\n{line}\n"));
        // The default preset: a sphere, m/m0 = 0.
        let named = Scene::from_toml(&with("kind = \"sphere-viscous\"")).unwrap();
        assert_eq!(named.setup(None).unwrap().ramp.mass_ratio, 0.0);
        for (line, says) in [
            (
                "kind = \"sphere-inertial\"",
                "m/m0 = 0 asks for sphere-viscous",
            ),
            (
                "kind = \"disk-viscous\"",
                "rolls 2D bodies and this body is 3D",
            ),
            (
                "kind = \"ball\"",
                "the registered models are disk-viscous, disk-inertial",
            ),
        ] {
            let e = Scene::from_toml(&with(line))
                .unwrap()
                .setup(None)
                .unwrap_err();
            assert!(e.to_string().contains(says), "{line}: {e}");
            assert!(e.to_string().starts_with("model.kind = "), "{e}");
        }
    }

    /// A saved state's drag-law labels go one per point, each a law's words, for either plot.
    #[test]
    fn a_saved_states_drag_labels_go_one_per_point() {
        let base = Scene::preset(DEFAULT_PRESET).unwrap().to_toml().unwrap();
        let resumed = |extra: &str| {
            let text = format!(
                "{base}\n[resume]\nt = 1.0\nstate = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]\n\
                 crossings = [[0.0, 1.2], [0.0, 1.3]]\n{extra}"
            );
            Scene::from_toml(&text).unwrap().setup(None).map(|_| ())
        };
        resumed("crossings_drag = [\"linear drag\", \"drag_exponent = 2\"]").unwrap();
        resumed("").unwrap();
        let e = resumed("crossings_drag = [\"linear drag\"]").unwrap_err();
        assert!(
            e.to_string()
                .contains("resume.crossings_drag has 1 label(s) for 2 crossings point(s)"),
            "{e}"
        );
        let e = resumed("crossings_drag = [\"linear drag\", \"\"]").unwrap_err();
        assert!(
            e.to_string()
                .contains("resume.crossings_drag[1] = \"\" is not a drag law's words"),
            "{e}"
        );
        // Blank, a line break, an override that turns the text around: not a law's words.
        for (label, says) in [
            ("   ", "no visible character"),
            ("linear\\ndrag", "control character"),
            ("\\u202Eward", "U+202E"),
        ] {
            let e = resumed(&format!("crossings_drag = [\"linear drag\", \"{label}\"]"))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("resume.crossings_drag[1] =") && e.contains(says),
                "{e}"
            );
        }
        // A label too long is named by its start, not echoed whole.
        let long = "x".repeat(201);
        let e = resumed(&format!("crossings_drag = [\"linear drag\", \"{long}\"]"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("(201 characters)") && e.len() < 400, "{e}");
    }
}
