//! Lessons: a scene's `[[timeline]]` steps, each at a simulation time, changing α, m/m0, the
//! playback speed, the views or the integrator preset, and showing a caption. Validated here
//! into [`Step`]s (α resolved from `alpha_over_critical`, each step checked against the values
//! the steps before it leave); applied by `live::LiveRun` when its time reaches a step, so the
//! app and the headless renderer play a lesson the same way.
//!
//! ```toml
//! [[timeline]]
//! at = 0.0                           # simulation time; strictly increasing
//! caption = "Below α* the cylinder finds a resting place"
//! [[timeline]]
//! at = 40.0
//! alpha_over_critical = 1.05         # or alpha_rad
//! mass_ratio = 2.0                   # 0 = viscous model
//! speed = 30.0                       # simulation time per second of video from here on
//! integrator = "precise"             # a preset: fast / balanced / precise
//! views = { ball = true }            # only the views named change
//! caption = ""                       # an empty caption clears it
//! ```
//!
//! Playback speed steps make the video clock piecewise linear in simulation time:
//! [`SceneSetup::frame_time`] walks those pieces, and the app's controller splits a tick at a
//! step the same way, so frame k of a lesson shows the same instant in both.

use serde::{Deserialize, Serialize};

use crate::dynamics::Ramp;
use crate::geometry::Body;
use crate::integrate::{Method, Preset};
use crate::simulate::choose_model;

use super::error::{SceneError, check_speed, invalid};
use super::{Scene, ViewsSpec};

/// Longest caption, in characters (a projector shows about two lines of this).
pub const MAX_CAPTION_CHARS: usize = 240;
/// Most steps in one timeline.
pub const MAX_STEPS: usize = 200;

/// One `[[timeline]]` step as written in TOML: every field but `at` is optional, and only what
/// is given changes.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimelineSpec {
    /// Simulation time at which the step applies.
    pub at: f64,
    /// New α in radians.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_rad: Option<f64>,
    /// New α as a multiple of the body's α*.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_over_critical: Option<f64>,
    /// New m/m0 (0: viscous model).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_ratio: Option<f64>,
    /// New playback speed (simulation time per second of video).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// Views to turn on or off; those not named keep their state.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub views: Option<ViewsChange>,
    /// New integrator preset.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub integrator: Option<Preset>,
    /// Caption shown from this step on ("" clears it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub caption: Option<String>,
    /// What the caption claims the step's plot shows, checked against the step's evidence
    /// (`live::evidence::check_claim`): the app says so under a caption its run does not bear
    /// out, and the tests hold every bundled lesson to its claims.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub claim: Option<Claim>,
}

/// What a lesson step claims its plot shows by the step's end, at the step's α and m/m0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Claim {
    /// The 1/T plot has a point at the step's α, and it is 0: the body halted.
    #[serde(rename = "halted")]
    Halted,
    /// The 1/T plot has a point at the step's α above 0: the body rolls on.
    #[serde(rename = "rolling")]
    Rolling,
    /// The run settled on period 1 at the step's α and m/m0 during the step (its one test of a
    /// repeat, a steady cycle of ∂Ω crossings); the crossings plot shows its crossing. A sphere's.
    #[serde(rename = "period-1")]
    Period1,
    /// The run settled on period 2 at the step's α and m/m0 during the step (a steady cycle of
    /// two ∂Ω crossings); the crossings plot shows its two crossings, alternating. A sphere's.
    #[serde(rename = "period-2")]
    Period2,
    /// The 1/T plot's rolling points near α* (α* < α ≤ 1.05 α*, at least three, at the step's
    /// m/m0) follow T = a/√(α − α*) + b, the viscous cylinder's law near the critical angle
    /// (SI §1B), each within [`SQRT_LAW_FIT_TOL`](crate::live::evidence::SQRT_LAW_FIT_TOL) of
    /// the fit the plot draws.
    #[serde(rename = "sqrt-law")]
    SqrtLaw,
}

impl Claim {
    /// The plot the claim is read from.
    pub fn plot(self) -> super::LessonPlot {
        match self {
            Claim::Halted | Claim::Rolling | Claim::SqrtLaw => super::LessonPlot::InversePeriod,
            Claim::Period1 | Claim::Period2 => super::LessonPlot::Crossings,
        }
    }

    /// The name a scene file gives it.
    pub fn name(self) -> &'static str {
        match self {
            Claim::Halted => "halted",
            Claim::Rolling => "rolling",
            Claim::Period1 => "period-1",
            Claim::Period2 => "period-2",
            Claim::SqrtLaw => "sqrt-law",
        }
    }
}

/// The views a step turns on or off.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewsChange {
    /// The body on the ramp.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<bool>,
    /// The SO(3) ball.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ball: Option<bool>,
    /// The Poincaré field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poincare: Option<bool>,
    /// The text overlay.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub overlay: Option<bool>,
    /// The plot the step talks about ("none" to name none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plot: Option<super::LessonPlot>,
    /// The scene's other bodies (`[[bodies]]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lanes: Option<bool>,
}

impl ViewsChange {
    /// `views` with this change made.
    pub fn applied_to(&self, views: &ViewsSpec) -> ViewsSpec {
        ViewsSpec {
            body: self.body.unwrap_or(views.body),
            ball: self.ball.unwrap_or(views.ball),
            poincare: self.poincare.unwrap_or(views.poincare),
            overlay: self.overlay.unwrap_or(views.overlay),
            plot: self.plot.unwrap_or(views.plot),
            lanes: self.lanes.unwrap_or(views.lanes),
        }
    }
}

/// A validated step, α already in radians.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Simulation time at which it applies.
    pub at: f64,
    /// New α, radians.
    pub alpha_rad: Option<f64>,
    /// New m/m0.
    pub mass_ratio: Option<f64>,
    /// New playback speed.
    pub speed: Option<f64>,
    /// Views turned on or off.
    pub views: Option<ViewsChange>,
    /// New integrator.
    pub method: Option<Method>,
    /// New caption (empty: none).
    pub caption: Option<String>,
    /// What the step claims its plot shows (checked: the plot is the one in effect).
    pub claim: Option<Claim>,
}

impl Step {
    /// Whether the step changes the ramp or the integrator (the model must be rebuilt).
    pub fn changes_model(&self) -> bool {
        self.alpha_rad.is_some() || self.mass_ratio.is_some() || self.method.is_some()
    }
}

/// Checks the timeline of `scene` (whose body, α* and starting ramp are already built) and
/// resolves it into steps. Each step is checked against the α, m/m0, views and integrator the
/// steps before it leave, so an error names the step that makes the combination bad.
pub(super) fn resolve(
    scene: &Scene,
    body: &Body,
    alpha_star: f64,
    ramp: Ramp,
    method: Method,
) -> Result<Vec<Step>, SceneError> {
    if scene.timeline.len() > MAX_STEPS {
        return Err(invalid(format!(
            "the timeline has {} steps; at most {MAX_STEPS} are allowed",
            scene.timeline.len()
        )));
    }
    let mut alpha = ramp.alpha_rad;
    let mut mass = ramp.mass_ratio;
    let mut views = scene.views.clone();
    let mut method_now = method;
    let mut previous_at: Option<f64> = None;
    let mut steps = Vec::with_capacity(scene.timeline.len());
    for (i, spec) in scene.timeline.iter().enumerate() {
        let name = format!("timeline[{i}]");
        let at = spec.at;
        if !(at.is_finite() && (0.0..=1e6).contains(&at)) {
            return Err(invalid(format!(
                "{name}.at = {at} is not allowed (needs 0 ≤ at ≤ 1e6, a simulation time)"
            )));
        }
        if let Some(prev) = previous_at
            && at <= prev
        {
            return Err(invalid(format!(
                "{name}.at = {at} is not after the step before it (at = {prev}); steps must be in \
                 strictly increasing time"
            )));
        }
        previous_at = Some(at);
        let alpha_rad = match (spec.alpha_rad, spec.alpha_over_critical) {
            (Some(_), Some(_)) => {
                return Err(invalid(format!(
                    "{name}: give alpha_rad or alpha_over_critical, not both"
                )));
            }
            (Some(a), None) => Some(a),
            (None, Some(f)) => {
                if alpha_star == 0.0 {
                    return Err(invalid(format!(
                        "{name}.alpha_over_critical needs a body with α* > 0; a perfect body has \
                         α* = 0, so give alpha_rad"
                    )));
                }
                if !(f.is_finite() && f > 0.0) {
                    return Err(invalid(format!(
                        "{name}.alpha_over_critical = {f} is not allowed (needs a finite factor > 0)"
                    )));
                }
                Some(f * alpha_star)
            }
            (None, None) => None,
        };
        alpha = alpha_rad.unwrap_or(alpha);
        mass = spec.mass_ratio.unwrap_or(mass);
        let step_ramp = Ramp::with_drag(alpha, mass, ramp.drag)
            .map_err(|e| invalid(format!("{name}: {e}")))?
            .with_drag_law(ramp.drag_law);
        let step_method = spec.integrator.map(Preset::method);
        method_now = step_method.unwrap_or(method_now);
        let choice = choose_model(body, step_ramp, method_now)
            .map_err(|e| invalid(format!("{name}: {e}")))?;
        if let Some(s) = spec.speed {
            check_speed(&format!("{name}.speed"), s)?;
        }
        if let Some(change) = &spec.views {
            views = change.applied_to(&views);
        }
        views
            .validate(body, &choice.ramp)
            .map_err(|e| invalid(format!("{name}: {e}")))?;
        if let Some(c) = &spec.caption
            && c.chars().count() > MAX_CAPTION_CHARS
        {
            return Err(invalid(format!(
                "{name}.caption has {} characters; at most {MAX_CAPTION_CHARS} fit on a projector",
                c.chars().count()
            )));
        }
        if let (Some(claim @ (Claim::Period1 | Claim::Period2)), Body::Disk(_)) = (spec.claim, body)
        {
            // Its advice (the crossings plot) is refused for a cylinder: say what is allowed.
            return Err(invalid(format!(
                "{name}.claim = \"{}\" is a sphere's (a cycle of crossings of ∂Ω); a cylinder's \
                 step can claim \"halted\", \"rolling\" or \"sqrt-law\" on the 1/T plot",
                claim.name()
            )));
        }
        if let Some(claim) = spec.claim
            && views.plot != claim.plot()
        {
            return Err(invalid(format!(
                "{name}.claim = \"{}\" is read from the {} plot, but the plot in effect at this \
                 step is {}: name it in [views] or in this step's views (plot = \"{}\")",
                claim.name(),
                claim.plot().title(),
                if views.plot.is_none() {
                    "none"
                } else {
                    views.plot.title()
                },
                if claim.plot() == super::LessonPlot::Crossings {
                    "crossings"
                } else {
                    "inverse-period"
                }
            )));
        }
        if spec.claim == Some(Claim::SqrtLaw) {
            check_sqrt_law(&name, body, &choice.ramp, alpha_star)?;
        }
        let step = Step {
            at,
            alpha_rad,
            mass_ratio: spec.mass_ratio,
            speed: spec.speed,
            views: spec.views,
            method: step_method,
            caption: spec.caption.clone(),
            claim: spec.claim,
        };
        if !step.changes_model()
            && step.speed.is_none()
            && step.views.is_none()
            && step.caption.is_none()
        {
            return Err(invalid(format!(
                "{name} changes nothing: give at least one of alpha_rad, alpha_over_critical, \
                 mass_ratio, speed, views, integrator, caption"
            )));
        }
        steps.push(step);
    }
    if let (Some(end), Some(last)) = (scene.playback.end_time, steps.last())
        && end < last.at
    {
        return Err(invalid(format!(
            "playback.end_time = {end} comes before the last timeline step (at = {}); the \
             lesson would be cut short",
            last.at
        )));
    }
    Ok(steps)
}

/// Where a step may claim the √ law: a viscous cylinder's under linear drag with a bottleneck
/// (α* > 0). Under drag_exponent n the period goes as (α − α*)^(1/2 − 1/n), and a fit of three
/// points to 2 % cannot tell those laws apart, so the claim is refused where the physics says it
/// does not hold.
fn check_sqrt_law(
    name: &str,
    body: &crate::geometry::Body,
    ramp: &Ramp,
    alpha_star: f64,
) -> Result<(), SceneError> {
    let model = crate::dynamics::ModelKind::of(body, ramp);
    let why_not = if model != crate::dynamics::ModelKind::DiskViscous {
        format!(
            "this step runs {}: its 1/T follows another law (the claim needs a cylinder at \
             m/m0 = 0)",
            model.name()
        )
    } else if !ramp.drag_law.is_linear() {
        format!(
            "this scene's drag is {}: under drag_exponent n the period goes as \
             (α − α*)^(1/2 − 1/n), not as 1/√(α − α*) (the claim needs linear drag)",
            ramp.drag_law.label()
        )
    } else if alpha_star <= 0.0 {
        "this body has no critical angle (α* = 0): it rolls at any slope, with no bottleneck \
         whose time could diverge"
            .to_string()
    } else {
        return Ok(());
    };
    Err(invalid(format!(
        "{name}.claim = \"sqrt-law\" is the viscous cylinder's law near α* under linear drag \
         (SI §1B), but {why_not}"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneSetup;

    const LESSON: &str = r#"
name = "t"
[body]
perfect = "disk"
[model]
alpha_rad = 0.3
[playback]
speed = 6.0
fps = 30.0
start_time = 10.0
end_time = 103.0
[[timeline]]
at = 16.0
speed = 60.0
[[timeline]]
at = 76.0
caption = "x"
[[timeline]]
at = 100.0
speed = 3.0
"#;

    fn setup(text: &str) -> Result<SceneSetup, SceneError> {
        Scene::from_toml(text)?.setup(None)
    }

    #[test]
    fn frame_times_walk_the_speed_steps() {
        let s = setup(LESSON).unwrap();
        let close = |k: u64, t: f64| {
            let got = s.frame_time(k);
            assert!((got - t).abs() < 1e-9, "frame {k}: {got} != {t}");
        };
        close(0, 10.0); // start_time
        close(30, 16.0); // 1 s at speed 6
        close(45, 46.0); // then 0.5 s at 60
        close(60, 76.0); // the caption step does not change the speed
        close(72, 100.0); // 0.4 s more at 60
        close(102, 103.0); // 1 s at 3
        for (video, t) in [(0.0, 10.0), (1.5, 46.0), (2.4, 100.0), (3.4, 103.0)] {
            assert!((s.video_time_at(t) - video).abs() < 1e-12, "t = {t}");
            assert!(
                (s.time_after_video(video) - t).abs() < 1e-9,
                "video {video}"
            );
        }
        assert_eq!(s.frames_to_end(), Some(103));
        assert_eq!(s.speed_at(15.9), 6.0);
        assert_eq!(s.speed_at(16.0), 60.0);
        assert_eq!(s.speed_at(1e5), 3.0);
    }

    #[test]
    fn the_last_frame_shows_the_end_when_frames_do_not_land_on_it() {
        // 93.1 of simulation time after t = 10 at speed 6 then 60 then 3: the end falls 0.3 of a
        // frame step after frame 102, so frame 103 is the last and shows 103.1 exactly, not 103.2.
        let s = setup(&LESSON.replace("end_time = 103.0", "end_time = 103.1")).unwrap();
        assert_eq!(s.frames_to_end(), Some(104));
        assert_eq!(s.frame_time(103), 103.1);
        assert!((s.frame_time(102) - 103.0).abs() < 1e-9);
        // Frames asked for by count go on past the end at the playback speed.
        assert!((s.frame_time(104) - 103.2).abs() < 1e-9);
    }

    #[test]
    fn a_speed_step_before_the_start_time_sets_the_first_speed() {
        let s = setup(&LESSON.replace("start_time = 10.0", "start_time = 50.0")).unwrap();
        assert!((s.frame_time(15) - 80.0).abs() < 1e-9);
    }

    #[test]
    fn without_a_timeline_frames_follow_the_scene_speed() {
        let s = Scene::preset("cylinder-near-critical")
            .unwrap()
            .setup(None)
            .unwrap();
        assert!(s.timeline.is_empty());
        assert_eq!(s.frame_time(0), 0.0);
        assert!((s.frame_time(30) - 30.0).abs() < 1e-12);
        assert_eq!(s.frames_to_end(), None);
    }

    #[test]
    fn bad_timelines_are_refused_by_step_and_field() {
        let cases = [
            ("at = 76.0", "at = 16.0", "timeline[1].at = 16 is not after"),
            (
                "at = 16.0",
                "at = -1.0",
                "timeline[0].at = -1 is not allowed",
            ),
            (
                "speed = 60.0",
                "speed = 0.0",
                "timeline[0].speed = 0 is not allowed (needs 0 < speed",
            ),
            ("caption = \"x\"", "alpha_rad = 2.0", "timeline[1]: "),
            (
                "caption = \"x\"",
                "alpha_over_critical = 1.1",
                "timeline[1].alpha_over_critical needs a body with α* > 0",
            ),
            (
                "caption = \"x\"",
                "views = { ball = true }",
                "timeline[1]: views.ball",
            ),
            ("caption = \"x\"", "mass_ratio = -1.0", "timeline[1]: "),
            (
                "end_time = 103.0",
                "end_time = 90.0",
                "playback.end_time = 90 comes before",
            ),
            (
                "end_time = 103.0",
                "end_time = 5.0",
                "playback.start_time = 10 is not before playback.end_time = 5",
            ),
            (
                "end_time = 103.0",
                "end_time = 2e6",
                "playback.end_time = 2000000 is not allowed",
            ),
            ("caption = \"x\"", "", "timeline[1] changes nothing"),
            (
                "caption = \"x\"",
                &format!("caption = \"{}\"", "a".repeat(MAX_CAPTION_CHARS + 1)),
                "timeline[1].caption has 241 characters",
            ),
            ("caption = \"x\"", "colour = 1", "unknown field `colour`"),
        ];
        for (from, to, expected) in cases {
            let text = LESSON.replacen(from, to, 1);
            let err = setup(&text).map(|_| ()).unwrap_err().to_string();
            assert!(err.contains(expected), "{to}: {err}");
        }
    }

    #[test]
    fn views_changes_keep_what_they_do_not_name() {
        let base = ViewsSpec {
            body: true,
            ball: false,
            poincare: true,
            overlay: true,
            plot: super::super::LessonPlot::InversePeriod,
            lanes: false,
        };
        let changed = ViewsChange {
            ball: Some(true),
            overlay: Some(false),
            ..ViewsChange::default()
        }
        .applied_to(&base);
        assert_eq!(
            changed,
            ViewsSpec {
                body: true,
                ball: true,
                poincare: true,
                overlay: false,
                plot: super::super::LessonPlot::InversePeriod,
                lanes: false,
            }
        );
    }
}
