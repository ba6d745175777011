//! The file written beside a plot-data folder's CSVs ([`PLOT_META_FILE`]): the scene, each
//! body's shape, start, model, m/m0, drag law and fate, and each file's columns, so the CSVs can
//! be read without the app that wrote them; and the names of the other bodies' files.

use std::collections::BTreeMap;

use super::super::Snapshot;
use super::PlotData;

/// The file written beside the CSVs: what they were taken from.
pub const PLOT_META_FILE: &str = "plot-data.json";

/// What a plot-data folder was taken from ([`PLOT_META_FILE`]), so the CSVs can be read
/// without the app that wrote them.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PlotMeta {
    /// The program and its version.
    pub written_by: String,
    /// The scene's name and description.
    pub scene: String,
    /// As the scene describes it.
    pub description: String,
    /// The body as the scene gives it (a shape file, inline coefficients, a generator).
    pub body: serde_json::Value,
    /// Its start as the scene gives it (`[initial]`).
    pub initial: serde_json::Value,
    /// The model (disk-viscous, …).
    pub model: String,
    /// The ramp angle now, rad.
    pub alpha_rad: f64,
    /// The body's critical angle, rad.
    pub alpha_star: f64,
    /// m/m0 now (0: the viscous model).
    pub mass_ratio: f64,
    /// The drag law now: one field per registered parameter, named by its key (the linear
    /// drag's defaults included).
    #[serde(flatten)]
    pub drag_law: crate::dynamics::DragLaw,
    /// The drag law in words ("linear drag", "drag_exponent = 2").
    pub drag: String,
    /// The rotational drag γ in units of γ0 (`[model] drag`).
    pub drag_gamma: f64,
    /// The surface's coefficient of static friction μ, when the scene gives one.
    pub friction: Option<f64>,
    /// The integrator setting.
    pub integrator: String,
    /// The simulation time when the data were written.
    pub t: f64,
    /// The scene's own body's name (its `label`, else the scene's name).
    pub label: String,
    /// The scene's own body's fate then, in the verdict's words.
    pub fate: String,
    /// Simulation time between two samples of the time series.
    pub sample_dt: f64,
    /// Each file and its columns.
    pub files: BTreeMap<&'static str, &'static str>,
    /// The scene's other bodies (`[[bodies]]`), body 2 on: each one's run and its files.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<BodyMeta>,
}

/// One of the scene's other bodies in [`PlotMeta`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct BodyMeta {
    /// Its number on the ramp (the scene's own body is 1).
    pub body: usize,
    /// Its name (the entry's label, or "body N").
    pub label: String,
    /// Its model.
    pub model: String,
    /// Its critical angle, rad.
    pub alpha_star: f64,
    /// Its m/m0.
    pub mass_ratio: f64,
    /// The body as its entry gives it, or the scene's when it gives none (a shape file,
    /// inline coefficients, a generator). (`shape`, as `body` is its number.)
    pub shape: serde_json::Value,
    /// Its start as its entry gives it, or the scene's.
    pub initial: serde_json::Value,
    /// Its drag law: one field per registered parameter, as the scene's own body's.
    #[serde(flatten)]
    pub drag_law: crate::dynamics::DragLaw,
    /// Its drag law in words.
    pub drag: String,
    /// Its rotational drag γ in units of γ0.
    pub drag_gamma: f64,
    /// Its surface's μ, when its model gives one.
    pub friction: Option<f64>,
    /// Its fate when the data were written, in the verdict's words.
    pub fate: String,
    /// Its time series ([`PlotData::Series`]'s columns), contact force ([`PlotData::Forces`]'s),
    /// settled crossings ([`PlotData::Crossings`]'s) and 1/T points ([`PlotData::AlphaSweep`]'s).
    pub files: [String; 4],
}

/// The data sets each other body has a file of, in [`body_files`]' order: every plot's but the
/// health's, whose quantities are the scene's own model's.
pub(super) const BODY_DATA: [PlotData; 4] = [
    PlotData::Series,
    PlotData::Forces,
    PlotData::Crossings,
    PlotData::AlphaSweep,
];

/// The files of body `n` (2 on): its series, contact force, settled crossings and 1/T points,
/// named as the scene's own body's with `-body-N`.
pub(super) fn body_files(n: usize) -> [String; 4] {
    BODY_DATA.map(|d| d.file_name().replace(".csv", &format!("-body-{n}.csv")))
}

impl PlotMeta {
    /// The metadata of the run `snapshot` shows, of the scene `setup`, integrated by `method`.
    pub fn of(
        snapshot: &Snapshot,
        setup: &crate::scene::SceneSetup,
        method: crate::integrate::Method,
    ) -> Self {
        Self {
            written_by: format!("rollphase {}", env!("CARGO_PKG_VERSION")),
            scene: setup.scene.name.clone(),
            // The scene's own words: a saved scene's "Saved from the app at α = …" names the α
            // it was saved at, which `alpha_rad` here may no longer be.
            description: crate::scene::description::original_description(&setup.scene.description)
                .to_string(),
            body: json(&setup.scene.body),
            initial: json(&setup.scene.initial),
            model: snapshot.model.to_string(),
            alpha_rad: snapshot.alpha_rad,
            alpha_star: snapshot.alpha_star,
            mass_ratio: snapshot.mass_ratio,
            drag_law: snapshot.drag_law,
            drag: snapshot.drag_law.label(),
            drag_gamma: snapshot.drag_gamma,
            friction: snapshot.contact.friction,
            integrator: method.to_string(),
            t: snapshot.t,
            label: snapshot.label.clone(),
            fate: snapshot.fate(),
            sample_dt: super::super::PLOT_SAMPLE_DT,
            files: PlotData::ALL
                .iter()
                .map(|d| (d.file_name(), d.columns()))
                .collect(),
            bodies: snapshot
                .lanes
                .iter()
                .enumerate()
                .map(|(i, lane)| {
                    let entry = setup.scene.bodies.get(i);
                    let shape = entry.and_then(|e| e.body.as_ref());
                    let initial = entry.and_then(|e| e.initial.as_ref());
                    BodyMeta {
                        body: i + 2,
                        label: lane.label.clone(),
                        model: lane.model.to_string(),
                        alpha_star: lane.alpha_star,
                        mass_ratio: lane.mass_ratio,
                        shape: json(shape.unwrap_or(&setup.scene.body)),
                        initial: json(initial.unwrap_or(&setup.scene.initial)),
                        drag_law: lane.drag_law,
                        drag: lane.drag_law.label(),
                        drag_gamma: lane.drag_gamma,
                        friction: lane.contact.friction,
                        fate: lane.fate(),
                        files: body_files(i + 2),
                    }
                })
                .collect(),
        }
    }
}

/// A scene table as plot-data JSON (`null` if it could not be written, which a table of
/// numbers and strings never is).
fn json<T: serde::Serialize>(value: &T) -> serde_json::Value {
    serde_json::to_value(value).unwrap_or(serde_json::Value::Null)
}
