//! The registry of rolling models: every model there is, what it is called, which bodies it
//! rolls, whether it carries inertia, and the one rule that picks the model a run asks for.
//!
//! Everything that lists, names, parses or shows a model (the command line's help and JSON,
//! the CSV and summaries, scenes, the app's overlay, Python's `models()`, tests that iterate
//! over models) reads [`REGISTERED`]; everything that must pick one asks [`ModelKind::of`] or
//! [`ModelKind::for_dimension`], never `m/m0 == 0` itself (an architecture test refuses that
//! outside `dynamics`). A new model is its own file (its equations, implementing
//! [`super::RollingModel`]) plus one entry in `with_registered_models!` here: its
//! [`ModelKind`], its [`REGISTERED`] entry and its `simulate::ModelState` variant, with every
//! match over the models there, are made from that entry.

use super::Ramp;

/// The one registration of every model, 2D first, viscous before inertial: each entry names
/// its kind, its type (its own file: the equations, [`super::RollingModel`] and an inherent
/// `new(&body, &Ramp)`), its state's length, the [`crate::geometry::Body`] variant it rolls,
/// and what [`ModelEntry`] says of it. Calls `$then!` with the list: [`ModelKind`] and
/// [`REGISTERED`] are made from it here, `simulate::ModelState` and its dispatch there, so that
/// adding a model is its file plus one entry, and no `match` over the models is written by hand.
macro_rules! with_registered_models {
    ($then:ident) => {
        $then! {
            DiskViscous {
                model: $crate::dynamics::disk2d::DiskViscous<'_>,
                state_len: 2,
                body: Disk,
                name: "disk-viscous",
                dimension: 2,
                inertial: false,
                about: "a cylinder in the viscous limit (m/m0 = 0): θ̇ from the torque balance (SI §1A)",
                state: "theta, x_c",
            },
            DiskInertial {
                model: $crate::dynamics::disk2d::DiskInertial<'_>,
                state_len: 4,
                body: Disk,
                name: "disk-inertial",
                dimension: 2,
                inertial: true,
                about: "a cylinder with inertia (m/m0 > 0): θ̈ from the Lagrangian, drag a torque (SI §1B)",
                state: "theta, theta_dot, x_c, drag_work",
            },
            SphereViscous {
                model: $crate::dynamics::sphere3d::SphereViscous<'_>,
                state_len: 6,
                body: Sphere,
                name: "sphere-viscous",
                dimension: 3,
                inertial: false,
                about: "a sphere in the viscous limit (m/m0 = 0): ω = −r × F/γ (SI §2B)",
                state: "qw, qx, qy, qz, x, y",
            },
            SphereInertial {
                model: $crate::dynamics::sphere3d::SphereInertial<'_>,
                state_len: 10,
                body: Sphere,
                name: "sphere-inertial",
                dimension: 3,
                inertial: true,
                about: "a sphere with inertia (m/m0 > 0): the ω̇ equation about the contact (SI §2A)",
                state: "qw, qx, qy, qz, wx, wy, wz, x, y, drag_work",
            },
        }
    };
}
pub(crate) use with_registered_models;

/// [`ModelKind`] and [`REGISTERED`] from the registration.
macro_rules! define_model_kinds {
    ($($kind:ident {
        model: $model:ty,
        state_len: $n:literal,
        body: $body:ident,
        name: $name:literal,
        dimension: $dimension:literal,
        inertial: $inertial:literal,
        about: $about:literal,
        state: $state:literal,
    },)*) => {
        /// Which model runs. Its [`Display`](std::fmt::Display) and serde name
        /// ("sphere-viscous", …) is its [`ModelEntry::name`], the one name used everywhere:
        /// command line, CSV, JSON, overlay, UI and Python.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        #[serde(rename_all = "kebab-case")]
        pub enum ModelKind {
            $(
                #[doc = $about]
                $kind,
            )*
        }

        /// Every model there is, in the registration's order.
        pub const REGISTERED: &[ModelEntry] = &[
            $(
                ModelEntry {
                    kind: ModelKind::$kind,
                    name: $name,
                    dimension: $dimension,
                    inertial: $inertial,
                    about: $about,
                    state: $state,
                },
            )*
        ];
    };
}
with_registered_models!(define_model_kinds);

/// One registered model.
#[derive(Debug)]
pub struct ModelEntry {
    /// Which it is.
    pub kind: ModelKind,
    /// Its one name (kebab-case; serde's for [`ModelKind`]).
    pub name: &'static str,
    /// The bodies it rolls: 2 (a cylinder's cross-section r(θ)) or 3 (a sphere-like r(u)).
    pub dimension: u32,
    /// Whether it carries the body's inertia (m/m0 > 0) or is the viscous limit (m/m0 = 0).
    pub inertial: bool,
    /// What it is, for `--help`, Python and the docs.
    pub about: &'static str,
    /// Its integrated state, in order.
    pub state: &'static str,
}

impl ModelKind {
    /// The model a body runs with on `ramp`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// use rollphase_core::geometry::Body;
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// assert_eq!(ModelKind::of(&body, &Ramp::new(0.15, 0.0)?), ModelKind::SphereViscous);
    /// assert_eq!(ModelKind::of(&body, &Ramp::new(0.15, 6.0)?), ModelKind::SphereInertial);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of(body: &crate::geometry::Body, ramp: &Ramp) -> Self {
        Self::for_dimension(body.dimension(), ramp)
    }

    /// The model a body of `dimension` (2 or 3) runs with on `ramp`: the one rule, inertial
    /// exactly when the ramp's m/m0 > 0 ([`asks_for_inertia`]). A dimension with no model gets the 3D one (bodies
    /// are 2D or 3D by construction).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// assert_eq!(ModelKind::for_dimension(2, &Ramp::new(0.1, 2.0)?), ModelKind::DiskInertial);
    /// assert_eq!(ModelKind::for_dimension(3, &Ramp::new(0.1, 0.0)?), ModelKind::SphereViscous);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn for_dimension(dimension: u32, ramp: &Ramp) -> Self {
        let inertial = asks_for_inertia(ramp.mass_ratio);
        REGISTERED
            .iter()
            .find(|m| m.dimension == dimension && m.inertial == inertial)
            .map_or(
                if inertial {
                    ModelKind::SphereInertial
                } else {
                    ModelKind::SphereViscous
                },
                |m| m.kind,
            )
    }

    /// Its registry entry.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::models::{ModelKind, REGISTERED};
    /// for m in REGISTERED {
    ///     assert_eq!(m.kind.entry().name, m.name);
    /// }
    /// ```
    pub fn entry(self) -> &'static ModelEntry {
        REGISTERED
            .iter()
            .find(|m| m.kind == self)
            .expect("every ModelKind is registered (tested)")
    }

    /// The name: "disk-viscous", "disk-inertial", "sphere-viscous" or "sphere-inertial".
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ModelKind;
    /// assert_eq!(ModelKind::DiskInertial.name(), "disk-inertial");
    /// assert_eq!(ModelKind::SphereViscous.to_string(), "sphere-viscous");
    /// ```
    pub fn name(self) -> &'static str {
        self.entry().name
    }

    /// Whether it carries inertia (m/m0 > 0).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ModelKind;
    /// assert!(ModelKind::SphereInertial.is_inertial() && !ModelKind::DiskViscous.is_inertial());
    /// ```
    pub fn is_inertial(self) -> bool {
        self.entry().inertial
    }

    /// The arm of an exhaustive `match` on [`ModelKind::for_dimension`]`(dimension, …)` for the
    /// kinds of another dimension, which it never gives. Analyses match every kind by name
    /// (never `==` one kind and `else` the rest), so a newly registered model is a compile error
    /// in each of them until it is handled; these arms only say which dimension was asked.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// let ramp = Ramp::new(0.1, 0.0)?;
    /// let state_len = match ModelKind::for_dimension(3, &ramp) {
    ///     ModelKind::SphereViscous => 6,
    ///     ModelKind::SphereInertial => 10,
    ///     other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => other.wrong_dimension(3),
    /// };
    /// assert_eq!(state_len, 6);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn wrong_dimension(self, dimension: u32) -> ! {
        unreachable!(
            "ModelKind::for_dimension({dimension}, …) gave {self}, a {}D model",
            self.entry().dimension
        )
    }

    /// The registered model called `name`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ModelKind;
    /// assert_eq!(ModelKind::from_name("disk-viscous"), Some(ModelKind::DiskViscous));
    /// assert_eq!(ModelKind::from_name("sphere"), None);
    /// ```
    pub fn from_name(name: &str) -> Option<Self> {
        REGISTERED.iter().find(|m| m.name == name).map(|m| m.kind)
    }
}

impl ModelKind {
    /// The registered model called `name`, checked against what a body of `dimension` on
    /// `ramp` runs by the one rule ([`Self::for_dimension`]): a scene may name its model, and a
    /// name that is not registered, rolls the other dimension, or disagrees with m/m0 is
    /// refused with what would fit.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// let heavy = Ramp::new(0.15, 6.0)?;
    /// assert_eq!(ModelKind::named_for("sphere-inertial", 3, &heavy), Ok(ModelKind::SphereInertial));
    /// let e = ModelKind::named_for("sphere-viscous", 3, &heavy).unwrap_err();
    /// assert!(e.contains("m/m0 = 6 asks for sphere-inertial"), "{e}");
    /// assert!(ModelKind::named_for("disk-inertial", 3, &heavy).unwrap_err().contains("2D"));
    /// assert!(ModelKind::named_for("sphere", 3, &heavy).unwrap_err().contains("sphere-viscous"));
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn named_for(name: &str, dimension: u32, ramp: &Ramp) -> Result<Self, String> {
        let names = |keep: &dyn Fn(&ModelEntry) -> bool| {
            REGISTERED
                .iter()
                .filter(|m| keep(m))
                .map(|m| m.name)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let Some(kind) = Self::from_name(name) else {
            return Err(format!(
                "no model is called \"{name}\"; the registered models are {}",
                names(&|_| true)
            ));
        };
        let entry = kind.entry();
        if entry.dimension != dimension {
            return Err(format!(
                "{name} rolls {}D bodies and this body is {dimension}D (its models: {})",
                entry.dimension,
                names(&|m| m.dimension == dimension)
            ));
        }
        let asked = Self::for_dimension(dimension, ramp);
        if asked != kind {
            return Err(format!(
                "{name} {}, and m/m0 = {} asks for {asked}: name {asked}, or set m/m0 {}",
                if entry.inertial {
                    "carries the body's inertia"
                } else {
                    "is the viscous limit"
                },
                ramp.mass_ratio,
                if entry.inertial { "> 0" } else { "= 0" }
            ));
        }
        Ok(kind)
    }
}

impl std::fmt::Display for ModelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The one rule that says which kind of model a run asks for: viscous exactly at m/m0 = 0 (the
/// paper's viscous limit), inertial otherwise. Everything that picks a model goes through here
/// ([`ModelKind::for_dimension`], the typed API's `Model`, a start's checks, the scene). A
/// negative or NaN m/m0 asks for inertia, so that the ramp's check refuses it by its value
/// rather than a viscous model taking it.
///
/// # Example
/// ```
/// use rollphase_core::dynamics::models::asks_for_inertia;
/// assert!(!asks_for_inertia(0.0) && asks_for_inertia(1e-12) && asks_for_inertia(6.0));
/// assert!(asks_for_inertia(-1.0) && asks_for_inertia(f64::NAN));
/// ```
pub fn asks_for_inertia(mass_ratio: f64) -> bool {
    mass_ratio != 0.0
}

/// The registered models, one line each ("disk-viscous: …"), for `--help` and the docs.
///
/// # Example
/// ```
/// use rollphase_core::dynamics::models::{REGISTERED, listing};
/// assert_eq!(listing().lines().count(), REGISTERED.len());
/// ```
pub fn listing() -> String {
    REGISTERED
        .iter()
        .map(|m| format!("{}: {} [state: {}]", m.name, m.about, m.state))
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::RollingModel;

    #[test]
    fn every_model_is_registered_once_with_its_serde_name() {
        for kind in REGISTERED.iter().map(|m| m.kind) {
            assert_eq!(REGISTERED.iter().filter(|m| m.kind == kind).count(), 1);
            let serde_name = serde_json::to_string(&kind).unwrap();
            assert_eq!(serde_name, format!("\"{}\"", kind.name()));
        }
        // Each (dimension, inertia) pair picks exactly one model.
        for d in [2, 3] {
            for inertial in [false, true] {
                let n = REGISTERED
                    .iter()
                    .filter(|m| m.dimension == d && m.inertial == inertial)
                    .count();
                assert_eq!(n, 1, "dimension {d}, inertial {inertial}");
            }
        }
    }

    #[test]
    fn each_models_own_kind_is_its_registration() {
        assert_eq!(
            <crate::dynamics::DiskViscous<'_> as RollingModel<2>>::KIND
                .entry()
                .state
                .split(", ")
                .count(),
            2
        );
        assert_eq!(
            <crate::dynamics::SphereInertial<'_> as RollingModel<10>>::KIND
                .entry()
                .state
                .split(", ")
                .count(),
            10
        );
        assert_eq!(ModelKind::DiskInertial.entry().state.split(", ").count(), 4);
        assert_eq!(
            ModelKind::SphereViscous.entry().state.split(", ").count(),
            6
        );
    }
}
