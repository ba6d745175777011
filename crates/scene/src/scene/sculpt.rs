//! A sculpting session on a scene's body: the bodies its strokes made (undo and redo), what each
//! offers (α*, convexity, the smallest radius of curvature at the print scale), and the scene
//! that runs the sculpted body from the same contact. The stroke itself is the core's
//! ([`crate::geometry::sculpt`]): a sculpted body is a body of the model's family, saved inline
//! in the scene in the shape-file schema, so it goes through the same checks, runs and verdicts
//! as one loaded from disk, and a scene holding it saves and loads exactly.

use std::path::Path;

use crate::analysis::design::Printability;
use crate::analysis::rest::critical_angle::critical_angle;
use crate::geometry::Body;
use crate::geometry::sculpt::{SculptError, Stroke, sculpt};

use super::{BodySpec, InitialSpec, Scene, SceneError, SceneSetup};

/// The most bodies a session keeps to go back to: far more strokes than a lesson's ten minutes
/// make, and a few megabytes at most.
pub const MAX_UNDO: usize = 200;

/// What a body offers, shown beside it as it is sculpted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SculptReadout {
    /// α* (rad).
    pub alpha_star: f64,
    /// Convexity and the print's smallest radius of curvature.
    pub print: Printability,
    /// The print scale (mm per ⟨r⟩) the radius is given at.
    pub scale_mm: f64,
}

impl SculptReadout {
    /// Measures `body` at `scale_mm` per ⟨r⟩.
    ///
    /// # Example
    /// ```
    /// use rollphase_scene::geometry::Body;
    /// use rollphase_scene::scene::sculpt::SculptReadout;
    /// let r = SculptReadout::of(&Body::random_sphere(1, 0.0, 3)?, 20.0);
    /// // A round ball: α* = 0 and a radius of curvature of 20 mm everywhere.
    /// assert!(r.alpha_star < 1e-12 && (r.print.smallest_radius_mm - 20.0).abs() < 1e-9);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of(body: &Body, scale_mm: f64) -> Self {
        Self {
            alpha_star: critical_angle(body).alpha_star,
            print: Printability::of(body, scale_mm),
            scale_mm,
        }
    }
}

/// The bodies of a sculpting session, newest last, and which one is shown.
#[derive(Debug, Clone)]
pub struct Sculptor {
    bodies: Vec<Body>,
    at: usize,
}

impl Sculptor {
    /// A session starting from `body`.
    pub fn new(body: Body) -> Self {
        Self {
            bodies: vec![body],
            at: 0,
        }
    }

    /// The body now.
    pub fn body(&self) -> &Body {
        &self.bodies[self.at]
    }

    /// Applies `stroke` to the body now: the new body, or why it was refused (the body and the
    /// history unchanged). A stroke after an undo drops the bodies that were undone.
    ///
    /// # Example
    /// ```
    /// use rollphase_scene::geometry::Body;
    /// use rollphase_scene::geometry::sculpt::{Stroke, StrokePoint};
    /// use rollphase_scene::scene::sculpt::Sculptor;
    /// let mut s = Sculptor::new(Body::random_disk(1, 0.1, 5)?);
    /// let dent = Stroke { at: StrokePoint::Disk { theta: 0.5 }, width: 0.3, height: -0.02 };
    /// s.stroke(&dent)?;
    /// assert!(s.undo() && !s.undo() && s.redo() && !s.redo());
    /// // Far too deep: refused with why, and nothing changes.
    /// let e = s.stroke(&Stroke { height: -0.3, width: 0.05, ..dent }).unwrap_err();
    /// assert!(e.to_string().contains("strictly convex"));
    /// assert!(s.can_undo() && !s.can_redo());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn stroke(&mut self, stroke: &Stroke) -> Result<&Body, SculptError> {
        let next = sculpt(self.body(), stroke)?;
        self.push(next);
        Ok(self.body())
    }

    /// Takes `body` (the mode panel's edit of the body now) as the next one, if it is strictly
    /// convex; refused with why otherwise.
    pub fn set_body(&mut self, body: Body) -> Result<&Body, SculptError> {
        // Through the shape file's own checks first: finite values, phases and degrees in
        // range (a NaN amplitude would otherwise pass a curvature search).
        let body = Body::from_shape(&body.to_shape()).map_err(SculptError::NotABody)?;
        body.check_convex().map_err(SculptError::NotConvex)?;
        self.push(body);
        Ok(self.body())
    }

    /// Drops the newest body if it is the one shown (its run could not be set up): the
    /// session is as before that stroke.
    pub fn drop_newest(&mut self) {
        if self.at > 0 && self.at + 1 == self.bodies.len() {
            self.bodies.pop();
            self.at -= 1;
        }
    }

    fn push(&mut self, body: Body) {
        self.bodies.truncate(self.at + 1);
        self.bodies.push(body);
        if self.bodies.len() > MAX_UNDO + 1 {
            self.bodies.remove(0);
        }
        self.at = self.bodies.len() - 1;
    }

    /// Whether there is a body to go back to.
    pub fn can_undo(&self) -> bool {
        self.at > 0
    }

    /// Whether there is an undone body to go forward to.
    pub fn can_redo(&self) -> bool {
        self.at + 1 < self.bodies.len()
    }

    /// Back to the body before; false where there is none.
    pub fn undo(&mut self) -> bool {
        let can = self.can_undo();
        self.at -= usize::from(can);
        can
    }

    /// Forward to the body undone last; false where there is none.
    pub fn redo(&mut self) -> bool {
        let can = self.can_redo();
        self.at += usize::from(can);
        can
    }

    /// How many strokes the body now is from the session's first.
    pub fn strokes(&self) -> usize {
        self.at
    }
}

/// `scene` with `body` in place of its own (inline, in the shape-file schema, with the print
/// scale `scale_mm`), started from `initial` at t = 0 (the same contact as the run before, for a
/// restart: a saved state's `[resume]` and `[[replay]]` are the old body's and are dropped), and
/// its setup: the same checks as a body loaded from disk. A lesson (a scene with a timeline) is
/// refused: its captions are about its own body.
///
/// # Example
/// ```
/// use rollphase_scene::geometry::sculpt::{Stroke, StrokePoint};
/// use rollphase_scene::scene::{InitialSpec, Scene};
/// use rollphase_scene::scene::sculpt::{Sculptor, sculpted_scene};
/// let scene = Scene::preset("sphere-cruising")?;
/// let setup = scene.setup(None)?;
/// let mut s = Sculptor::new(setup.body.clone());
/// let u = rollphase_scene::glam::DVec3::Z;
/// s.stroke(&Stroke { at: StrokePoint::Sphere { u }, width: 0.4, height: 0.02 })?;
/// let (edited, new_setup) = sculpted_scene(&scene, s.body(), InitialSpec::default(), (None, Some(20.0)))?;
/// // Saved and loaded, the scene holds the same body to the bit.
/// let again = Scene::from_toml(&edited.to_toml()?)?.setup(None)?;
/// assert_eq!(again.body.to_shape(), new_setup.body.to_shape());
/// assert_eq!(again.alpha_star, new_setup.alpha_star);
/// // A lesson's captions are about its own body: refused.
/// let lesson = Scene::preset("lesson-period-doubling")?;
/// assert!(sculpted_scene(&lesson, s.body(), InitialSpec::default(), (None, None)).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sculpted_scene(
    scene: &Scene,
    body: &Body,
    initial: InitialSpec,
    (base, scale_mm): (Option<&Path>, Option<f64>),
) -> Result<(Scene, SceneSetup), SceneError> {
    if !scene.timeline.is_empty() {
        return Err(SceneError::Invalid(format!(
            "{} is a lesson: its captions are about its own body, so it is not sculpted or \
             designed (load a scene, or a preset that is not a lesson)",
            scene.name
        )));
    }
    let mut edited = scene.clone();
    // The other bodies on the ramp are not sculpted: each keeps the body and start it had
    // (an entry without its own took the scene's), and goes from t = 0 with the scene.
    for entry in &mut edited.bodies {
        entry.body.get_or_insert_with(|| scene.body.clone());
        entry.initial.get_or_insert_with(|| scene.initial.clone());
        entry.resume = None;
    }
    edited.body = BodySpec {
        inline: Some(body.to_shape().with_scale_mm(scale_mm)),
        ..BodySpec::default()
    };
    edited.initial = initial;
    edited.resume = None;
    edited.replay.clear();
    // From t = 0: a scene that skips ahead to a settled orbit would hide the new body's start.
    edited.playback.start_time = 0.0;
    // A scene that named its α relative to α* keeps that ratio on the new body.
    let setup = edited.setup(base)?;
    Ok((edited, setup))
}
