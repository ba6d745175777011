//! More bodies on the scene's ramp (`[[bodies]]`): up to three beside the scene's own, each on
//! a lane of its own, with its own body, start, m/m0 and drag law, sharing the ramp's α, the
//! integrator and the clock.
//!
//! Each entry is validated as a scene of its own would be: the scene with the entry's body,
//! `[model]` (α the scene's) and `[initial]` put in, through the same [`Scene::setup`], so a
//! body on a lane passes every check a body from a file does and runs the same run. An entry
//! that leaves a table out takes the scene's.
//!
//! ```toml
//! [[bodies]]
//! label = "m/m0 = 4.5"          # its name on the overlay and in the plot data
//! [bodies.model]                # optional: m/m0, drag, friction, the drag law's keys (no α)
//! mass_ratio = 4.5
//! # [bodies.body] shape = "…"   # optional: another body (the same dimension)
//! # [bodies.initial] …          # optional: another start
//! ```

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::error::invalid;
use super::setup::SceneSetup;
use super::text::{as_shown, check_characters};
use super::{BodySpec, InitialSpec, LessonPlot, ModelSpec, Scene, SceneError, ViewsSpec};

/// The most bodies one ramp holds, the scene's own included.
pub const MAX_BODIES: usize = 4;

/// Longest label of a body, in characters.
pub const MAX_LABEL_CHARS: usize = 40;

/// One more body on the ramp (`[[bodies]]`); a table left out is the scene's.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LaneSpec {
    /// Its name on the overlay, the plots and the plot data (empty: "body N").
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub label: String,
    /// Its body (absent: the scene's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<BodySpec>,
    /// Its m/m0, drag, friction and drag law, each field it leaves out the scene's (absent: all
    /// the scene's). α is the ramp's, the scene's `[model]`'s: an entry may not give one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<LaneModel>,
    /// Its start (absent: the scene's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<InitialSpec>,
    /// Its saved state, at the scene's `[resume]` time (Save state writes it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resume: Option<LaneResume>,
}

/// The `[bodies.model]` fields besides the drag law's, for the unknown-field message (α is
/// the ramp's; an entry that gives it is refused by name at validation).
const LANE_MODEL_FIELDS: [&str; 4] = ["kind", "mass_ratio", "drag", "friction"];

/// An entry's `[bodies.model]`: the fields it gives, each over the scene's `[model]`, so
/// `friction = 0.3` alone is the scene's model with that friction, not a default model (m/m0
/// = 0) with it. Read as `[model]` is (the same types and ranges), but an unknown key is refused
/// with the fields an entry may give: `[model]`'s message would offer `alpha_rad`, which an entry
/// may not give.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
#[serde(transparent)]
pub struct LaneModel(toml::Table);

impl LaneModel {
    /// Every field of `model` (what Save scene pins for a body as it runs).
    pub fn whole(model: &ModelSpec) -> Self {
        LaneModel(toml::Table::try_from(model).unwrap_or_default())
    }

    /// Whether the entry gives `key`.
    pub fn gives(&self, key: &str) -> bool {
        self.0.contains_key(key)
    }

    /// The model of the body: `scene`'s, with each field this gives put over it. An m/m0 given
    /// without a `kind` drops the scene's `kind`, which names the scene's own m/m0's model.
    pub fn over(&self, scene: &ModelSpec) -> Result<ModelSpec, String> {
        let mut table = toml::Table::try_from(scene).map_err(|e| e.to_string())?;
        if self.gives("mass_ratio") && !self.gives("kind") {
            table.remove("kind");
        }
        table.extend(self.0.iter().map(|(k, v)| (k.clone(), v.clone())));
        ModelSpec::deserialize(table).map_err(|e| format!("[bodies.model]: {}", e.message()))
    }
}

impl<'de> Deserialize<'de> for LaneModel {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let table = toml::Table::deserialize(d)?;
        let alpha = ["alpha_rad", "alpha_over_critical"];
        if let Some(key) = table.keys().find(|k| {
            !LANE_MODEL_FIELDS.contains(&k.as_str())
                && !alpha.contains(&k.as_str())
                && !crate::scene::drag_law::is_registered_key(k)
        }) {
            let fields: Vec<_> = LANE_MODEL_FIELDS.iter().map(|f| format!("`{f}`")).collect();
            return Err(D::Error::custom(format!(
                "[bodies.model] has an unknown field `{key}`: expected one of {} or a drag-law \
                 parameter ({}) (α is the ramp's, the scene's [model])",
                fields.join(", "),
                crate::scene::drag_law::registered_keys()
            )));
        }
        // The types, as [model] takes them, checked as the file is read.
        ModelSpec::deserialize(table.clone())
            .map_err(|e| D::Error::custom(format!("[bodies.model]: {}", e.message())))?;
        Ok(LaneModel(table))
    }
}

/// A body's saved state on its lane: the time (the scene's `[resume]` time), the model's
/// state vector, and its points in the sweep plots, as `[resume]` keeps the scene's own body's
/// (checked by the same rules).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LaneResume {
    /// Simulation time of the saved state.
    pub t: f64,
    /// The state vector, as `[resume]` writes it.
    pub state: Vec<f64>,
    /// Its 1/T points: [α, 1/T, m/m0, +1 when α was increasing or −1 decreasing].
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "super::exact_points"
    )]
    pub alpha_sweep: Vec<[f64; 4]>,
    /// Its settled crossings: [m/m0, polar angle of the ∂Ω crossing].
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "super::exact_points"
    )]
    pub crossings: Vec<[f64; 2]>,
    /// The drag law of each `alpha_sweep` point, as `[resume]`'s.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub alpha_sweep_drag: Vec<String>,
    /// The drag law of each `crossings` point, as `[resume]`'s.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub crossings_drag: Vec<String>,
}

impl From<super::ResumeSpec> for LaneResume {
    /// A body's `[resume]` as its lane keeps it (the same fields).
    fn from(r: super::ResumeSpec) -> Self {
        LaneResume {
            t: r.t,
            state: r.state,
            alpha_sweep: r.alpha_sweep,
            crossings: r.crossings,
            alpha_sweep_drag: r.alpha_sweep_drag,
            crossings_drag: r.crossings_drag,
        }
    }
}

impl LaneSpec {
    /// Its name: the label, or "body N" for the `n`-th body on the ramp (the scene's own is 1).
    pub fn name(&self, n: usize) -> String {
        if self.label.is_empty() {
            format!("body {n}")
        } else {
            self.label.clone()
        }
    }
}

/// A body's name as the overlay shows it: at most [`MAX_LABEL_CHARS`] characters, on one line.
fn check_label(label: &str, field: &str) -> Result<(), SceneError> {
    let chars = label.chars().count();
    if chars > MAX_LABEL_CHARS {
        return Err(invalid(format!(
            "{field} {label:?} is not allowed (needs at most {MAX_LABEL_CHARS} characters on one \
             line; it has {chars})"
        )));
    }
    check_characters(label, field)?;
    if !label.is_empty() && as_shown(label).is_empty() {
        return Err(invalid(format!(
            "{field} {label:?} is not allowed: it has no visible character (leave it out for the \
             body's number, \"body N\")"
        )));
    }
    Ok(())
}

impl SceneSetup {
    /// The shape files the scene's bodies are read from, as the scene names them (relative to
    /// its folder): its own body's, then each `[[bodies]]` entry's. Inputs: no output may
    /// overwrite one.
    pub fn shape_paths(&self) -> Vec<&Path> {
        std::iter::once(self)
            .chain(&self.lanes)
            .filter_map(|s| s.scene.body.shape.as_deref())
            .collect()
    }
}

impl Scene {
    /// The scene `entry` makes: this one with its body, model and start put in, the ramp's α
    /// (`alpha_rad`, as resolved for the scene's own body) given, and none of a lesson's
    /// steps, the other bodies, the plots or a replay: a plain run on the same ramp.
    fn lane_scene(&self, entry: &LaneSpec, n: usize, alpha_rad: f64) -> Result<Scene, String> {
        let mut model = match &entry.model {
            Some(given) => given.over(&self.model)?,
            None => self.model.clone(),
        };
        model.alpha_rad = Some(alpha_rad);
        model.alpha_over_critical = None;
        Ok(Scene {
            name: entry.name(n),
            description: String::new(),
            label: String::new(),
            body: entry.body.clone().unwrap_or_else(|| self.body.clone()),
            model,
            initial: entry
                .initial
                .clone()
                .unwrap_or_else(|| self.initial.clone()),
            integrator: self.integrator.clone(),
            playback: self.playback.clone(),
            views: ViewsSpec {
                body: true,
                // (Its path in the scene's SO(3) ball is followed by the scene's run:
                // `LiveRun::set_views`.)
                ball: false,
                poincare: false,
                overlay: true,
                plot: LessonPlot::None,
                lanes: true,
            },
            poincare: self.poincare.clone(),
            timeline: Vec::new(),
            resume: entry.resume.as_ref().map(|r| super::ResumeSpec {
                t: r.t,
                state: r.state.clone(),
                alpha_sweep: r.alpha_sweep.clone(),
                crossings: r.crossings.clone(),
                alpha_sweep_drag: r.alpha_sweep_drag.clone(),
                crossings_drag: r.crossings_drag.clone(),
            }),
            replay: Vec::new(),
            bodies: Vec::new(),
        })
    }

    /// Each `[[bodies]]` entry validated into the setup of its run, beside `own`, the scene's
    /// own body's: at most [`MAX_BODIES`] in all, each the same dimension as the scene's, α
    /// the ramp's, and a saved state exactly when the scene has one, at its time.
    pub(super) fn lane_setups(
        &self,
        base: Option<&Path>,
        own: &SceneSetup,
    ) -> Result<Vec<SceneSetup>, SceneError> {
        if self.bodies.len() > MAX_BODIES - 1 {
            return Err(invalid(format!(
                "[[bodies]]: {} entries is too many (a ramp holds at most {MAX_BODIES} bodies: \
                 the scene's own and {} more)",
                self.bodies.len(),
                MAX_BODIES - 1
            )));
        }
        check_label(&self.label, "label")?;
        if self.label.is_empty() && !self.bodies.is_empty() {
            let field =
                "name (the scene's own body's name beside the other bodies, as it has no label)";
            check_characters(&self.name, field)?;
            if as_shown(&self.name).is_empty() {
                return Err(invalid(format!(
                    "{field} {:?} is not allowed: it has no visible character (give the scene a \
                     name, or its body a label)",
                    self.name
                )));
            }
        }
        let mut lanes = Vec::with_capacity(self.bodies.len());
        for (i, entry) in self.bodies.iter().enumerate() {
            let n = i + 2;
            let at = format!("[[bodies]] entry {} (body {n})", i + 1);
            check_label(&entry.label, &format!("{at}: label"))?;
            let name = entry.name(n);
            let own_name = if self.label.is_empty() {
                &self.name
            } else {
                &self.label
            };
            let taken = std::iter::once(own_name.clone()).chain(
                self.bodies[..i]
                    .iter()
                    .enumerate()
                    .map(|(j, e)| e.name(j + 2)),
            );
            if let Some(twin) = taken.into_iter().find(|t| as_shown(t) == as_shown(&name)) {
                let same = if twin == name {
                    format!("its name {twin:?} is another body's too")
                } else {
                    format!("its name {name:?} looks the same as another body's, {twin:?}")
                };
                return Err(invalid(format!(
                    "{at}: {same} (the overlay, the plots and the plot data tell the bodies apart \
                     by name: give each its own label)"
                )));
            }
            if let Some(model) = &entry.model
                && (model.gives("alpha_rad") || model.gives("alpha_over_critical"))
            {
                return Err(invalid(format!(
                    "{at}: model gives α, but the bodies share one ramp: α is the scene's \
                     [model] alpha_rad or alpha_over_critical; leave it out of [bodies.model]"
                )));
            }
            match (&self.resume, &entry.resume) {
                (Some(own_resume), Some(r)) if r.t == own_resume.t => {}
                (Some(own_resume), Some(r)) => {
                    return Err(invalid(format!(
                        "{at}: resume.t = {} is not the scene's [resume] t = {} (the bodies were \
                         saved together, at one time)",
                        crate::integrate::readable(r.t),
                        crate::integrate::readable(own_resume.t)
                    )));
                }
                (Some(_), None) => {
                    return Err(invalid(format!(
                        "{at}: the scene goes on from a saved state ([resume]) but this body has \
                         no resume of its own (Save state writes one for every body)"
                    )));
                }
                (None, Some(_)) => {
                    return Err(invalid(format!(
                        "{at}: resume is given but the scene has no [resume]: a body's saved \
                         state goes with the scene's"
                    )));
                }
                (None, None) => {}
            }
            let scene = self
                .lane_scene(entry, n, own.ramp.alpha_rad)
                .map_err(|e| invalid(format!("{at}: {e}")))?;
            let setup = scene
                .setup(base)
                .map_err(|e| invalid(format!("{at}: {e}")))?;
            if setup.body.dimension() != own.body.dimension() {
                return Err(invalid(format!(
                    "{at}: its body is {}D but the scene's is {}D (the bodies on one ramp are all \
                     cylinders or all spheres)",
                    setup.body.dimension(),
                    own.body.dimension()
                )));
            }
            lanes.push(setup);
        }
        Ok(lanes)
    }
}

#[cfg(test)]
mod tests {
    use super::super::Scene;

    /// Two more bodies on the doubling lesson's ramp, as the lesson's comparison step has.
    fn lesson() -> Scene {
        Scene::preset("lesson-period-doubling").unwrap()
    }

    /// An entry's `[bodies.model]` changes the fields it gives and takes the rest from the
    /// scene's `[model]`: friction alone keeps the scene's m/m0 and drag law (it made a viscous
    /// body with the paper's drag, a helper found), and an m/m0 alone drops the scene's `kind`.
    #[test]
    fn a_body_takes_the_scenes_model_fields_it_leaves_out() {
        let base = Scene::preset("sphere-doubling").unwrap().to_toml().unwrap();
        let base = base.replace(
            "mass_ratio = 6.0\ndrag = 1.0",
            "mass_ratio = 6.0\nkind = \"sphere-inertial\"\ndrag = 2.0\ndrag_exponent = 1.5",
        );
        let lanes = |entry: &str| {
            let setup = Scene::from_toml(&format!("{base}\n[[bodies]]\n[bodies.model]\n{entry}\n"))
                .unwrap()
                .setup(None)
                .unwrap();
            let lane = &setup.lanes[0];
            (
                lane.ramp.mass_ratio,
                lane.scene.model.drag,
                lane.ramp.drag_law.label(),
                lane.scene.model.friction,
            )
        };
        let exponent = |n: f64| {
            crate::dynamics::DragLaw::LINEAR
                .with("drag_exponent", n)
                .unwrap()
                .label()
        };
        assert_eq!(
            lanes("friction = 0.3"),
            (6.0, 2.0, exponent(1.5), Some(0.3))
        );
        assert_eq!(
            lanes("drag_exponent = 1.0"),
            (6.0, 2.0, exponent(1.0), None)
        );
        // The viscous limit, though the scene names the inertial model.
        assert_eq!(lanes("mass_ratio = 0.0"), (0.0, 2.0, exponent(1.5), None));
        // Save scene writes the whole model of a body as it runs; it loads as the same.
        let model = Scene::from_toml(&base).unwrap().model;
        let whole = super::LaneModel::whole(&model);
        assert_eq!(
            whole.over(&crate::scene::ModelSpec::default()).unwrap(),
            model
        );
    }

    #[test]
    fn each_body_is_set_up_as_a_scene_of_its_own_on_the_one_ramp() {
        let setup = lesson().setup(None).unwrap();
        assert_eq!(setup.lanes.len(), 2);
        for (lane, m) in setup.lanes.iter().zip([2.0, 4.5]) {
            assert_eq!(lane.ramp.alpha_rad, setup.ramp.alpha_rad, "one ramp");
            assert_eq!(lane.ramp.mass_ratio, m);
            assert_eq!(lane.method, setup.method);
            assert!(lane.timeline.is_empty() && lane.lanes.is_empty());
            // The same body and start as the scene's, where the entry gives none.
            assert_eq!(lane.alpha_star, setup.alpha_star);
            assert_eq!(lane.scene.initial, setup.scene.initial);
            assert_eq!(lane.scene.body, setup.scene.body);
        }
        assert_eq!(setup.lanes[1].scene.name, "m/m0 = 4.5");
        // It writes and reads back as it was.
        let scene = lesson();
        assert_eq!(Scene::from_toml(&scene.to_toml().unwrap()).unwrap(), scene);
    }

    #[test]
    fn a_body_that_does_not_fit_the_ramp_is_refused_naming_its_entry() {
        let cases: [(&str, &str); 16] = [
            (
                "[[bodies]]\n[[bodies]]\n[[bodies]]\n[[bodies]]\n",
                "at most 4 bodies",
            ),
            (
                "[[bodies]]\n[bodies.model]\nalpha_rad = 0.2\n",
                "entry 1 (body 2): model gives α",
            ),
            (
                "[[bodies]]\n[bodies.body]\nperfect = \"disk\"\n[bodies.initial]\ntheta0 = 0.0\n",
                "its body is 2D but the scene's is 3D",
            ),
            (
                "[[bodies]]\n[bodies.model]\nmass_ratio = -1.0\n",
                "[[bodies]] entry 1 (body 2): ",
            ),
            (
                "[[bodies]]\nlabel = \"a\\nb\"\n",
                "entry 1 (body 2): label \"a\\nb\" is not allowed: it holds the control character '\\n'",
            ),
            (
                // Shown as "fast ydob": a right-to-left override.
                "[[bodies]]\nlabel = \"fast \\u202Ebody\"\n",
                "entry 1 (body 2): label \"fast \\u{202e}body\" is not allowed: it holds the \
                 invisible character U+202E",
            ),
            (
                "[[bodies]]\nlabel = \"two\\u2028lines\"\n",
                "it holds the invisible character U+2028, which breaks the line",
            ),
            (
                "[[bodies]]\nlabel = \" \\u3000\\u200D \"\n",
                "it has no visible character",
            ),
            (
                // Looks like the scene's own name, and the first entry's.
                "[[bodies]]\nlabel = \"twin\"\n[[bodies]]\nlabel = \" twin\\uFE0F \"\n",
                "entry 2 (body 3): its name \" twin\\u{fe0f} \" looks the same as another \
                 body's, \"twin\"",
            ),
            (
                "[[bodies]]\nlabel = \"twin\"\n[[bodies]]\nlabel = \"twin\"\n",
                "entry 2 (body 3): its name \"twin\" is another body's too",
            ),
            (
                "[[bodies]]\nlabel = \"sphere-cruising\"\n",
                "its name \"sphere-cruising\" is another body's too",
            ),
            (
                "[[bodies]]\n[bodies.resume]\nt = 1.0\nstate = [1.0]\n",
                "the scene has no [resume]",
            ),
            (
                "[[bodies]]\n[bodies.initial]\ncontact = [1.0, nan]\n",
                "[[bodies]] entry 1 (body 2): ",
            ),
            (
                // The entry's own fields are offered, not α, which it may not give.
                "[[bodies]]\n[bodies.model]\nmass_ration = 2.0\n",
                "[bodies.model] has an unknown field `mass_ration`: expected one of `kind`, \
                 `mass_ratio`, `drag`, `friction` or a drag-law parameter (`drag_exponent`) (α is \
                 the ramp's, the scene's [model])",
            ),
            (
                "[[bodies]]\n[bodies.model]\nmass_ratio = \"heavy\"\n",
                "[bodies.model]: invalid type: string \"heavy\", expected f64",
            ),
            (
                "[[bodies]]\n[bodies.model]\nalpha_over_critical = 1.1\n",
                "entry 1 (body 2): model gives α",
            ),
        ];
        let base = Scene::preset("sphere-cruising").unwrap().to_toml().unwrap();
        for (extra, expected) in cases {
            let text = format!("{base}\n{extra}");
            let err = Scene::from_toml(&text)
                .and_then(|s| s.setup(None))
                .map(|_| ())
                .unwrap_err()
                .to_string();
            assert!(err.contains(expected), "{extra}: {err}");
        }
    }

    #[test]
    fn names_keep_what_spelling_needs_and_refuse_what_hides_text() {
        let with = |label: &str| {
            let mut scene = Scene::preset("which-one-stops").unwrap();
            scene.bodies[0].label = label.into();
            scene.setup(None).map(|_| ()).map_err(|e| e.to_string())
        };
        // Persian with a zero-width non-joiner, an emoji sequence, Hebrew with a mark.
        for fine in [
            "می\u{200C}خواهم",
            "👨\u{200D}👩\u{200D}👧",
            "גוף\u{200F} 2",
            "smooth 2",
        ] {
            assert_eq!(with(fine), Ok(()), "{fine:?}");
        }
        // A blank Braille pattern draws as nothing: it looks like the scene's own body's label.
        let err = with("α* = 10°\u{2800}").unwrap_err();
        assert!(
            err.contains("looks the same as another body's, \"α* = 10°\""),
            "{err}"
        );
        assert!(
            with("\u{2800}")
                .unwrap_err()
                .contains("no visible character")
        );
        // The scene's own body has no label: its name names it beside the others.
        let mut unnamed = Scene::preset("which-one-stops").unwrap();
        unnamed.label = String::new();
        unnamed.name = "\u{200D}".into();
        let err = unnamed.setup(None).unwrap_err().to_string();
        assert!(err.contains("it has no visible character"), "{err}");
        let mut scene = Scene::preset("which-one-stops").unwrap();
        scene.label = String::new();
        scene.name = "fast \u{202E}body".into();
        let err = scene.setup(None).unwrap_err().to_string();
        assert!(
            err.contains(
                "name (the scene's own body's name beside the other bodies, as it has no \
                          label) \"fast \\u{202e}body\" is not allowed"
            ),
            "{err}"
        );
        // Composed and decomposed, the Ohm sign and omega: one name as drawn, so refused as a
        // second body's; a superscript is not a digit, so "x²" beside "x2" is two names.
        let pair = |own: &str, other: &str| {
            let mut scene = Scene::preset("which-one-stops").unwrap();
            scene.label = own.into();
            scene.bodies[0].label = other.into();
            scene.setup(None).map(|_| ()).map_err(|e| e.to_string())
        };
        for (own, other) in [("café", "cafe\u{301}"), ("\u{2126} = 1", "\u{3a9} = 1")] {
            let err = pair(own, other).unwrap_err();
            assert!(err.contains("looks the same as another body's"), "{err}");
        }
        assert_eq!(pair("x²", "x2"), Ok(()));
    }

    #[test]
    fn a_saved_state_needs_every_body_saved_at_its_time() {
        let mut scene = Scene::preset("sphere-cruising").unwrap();
        let setup = scene.setup(None).unwrap();
        let state = crate::simulate::ModelState::new(&setup.start, &setup.ramp)
            .vector()
            .to_vec();
        scene.resume = Some(super::super::ResumeSpec {
            t: 5.0,
            state: state.clone(),
            ..Default::default()
        });
        scene.bodies = vec![super::LaneSpec::default()];
        let err = scene.setup(None).unwrap_err().to_string();
        assert!(err.contains("has no resume of its own"), "{err}");
        scene.bodies[0].resume = Some(super::LaneResume {
            t: 4.0,
            state: state.clone(),
            ..Default::default()
        });
        let err = scene.setup(None).unwrap_err().to_string();
        assert!(err.contains("is not the scene's [resume] t = 5"), "{err}");
        scene.bodies[0].resume = Some(super::LaneResume {
            t: 5.0,
            state,
            ..Default::default()
        });
        let setup = scene.setup(None).unwrap();
        assert_eq!(setup.lanes[0].resume.as_ref().map(|r| r.t), Some(5.0));
    }

    /// Sculpting the scene's own body leaves the others as they were: an entry that took the
    /// scene's body and start keeps the old ones, pinned, and the saved scene loads as it ran.
    #[test]
    fn sculpting_the_own_body_leaves_the_others_theirs() {
        use crate::geometry::sculpt::{Stroke, StrokePoint};
        use crate::scene::sculpt::{Sculptor, sculpted_scene};
        let mut scene = Scene::preset("sphere-cruising").unwrap();
        scene.bodies = vec![super::LaneSpec {
            label: "as it was".into(),
            ..Default::default()
        }];
        let setup = scene.setup(None).unwrap();
        let mut s = Sculptor::new(setup.body.clone());
        s.stroke(&Stroke {
            at: StrokePoint::Sphere {
                u: [0.0, 0.0, 1.0].into(),
            },
            width: 0.4,
            height: 0.03,
        })
        .unwrap();
        let initial = crate::scene::InitialSpec {
            contact: Some([0.5, 0.5]),
            ..Default::default()
        };
        let (edited, new_setup) = sculpted_scene(&scene, s.body(), initial, (None, None)).unwrap();
        assert_ne!(
            new_setup.alpha_star, setup.alpha_star,
            "the own body changed"
        );
        assert_eq!(
            new_setup.lanes[0].alpha_star, setup.alpha_star,
            "the other did not"
        );
        assert_eq!(new_setup.lanes[0].scene.initial, setup.scene.initial);
        let again = Scene::from_toml(&edited.to_toml().unwrap())
            .unwrap()
            .setup(None)
            .unwrap();
        assert_eq!(again.lanes[0].body.to_shape(), setup.body.to_shape());
    }
}
