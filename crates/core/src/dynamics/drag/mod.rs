//! The rotational drag as a part: the registry of drag laws and the law a run uses.
//!
//! The paper's drag is linear, a torque −γ ω (SI eq. 1). Its Materials and Methods note that
//! the rubber's resistance "can depend on the rolling speed", so the drag is a law
//! τ_drag = −γ g(|ω|) ω̂ with g monotone increasing, g(0) = 0. A registered law is a
//! monotone map of the speed with one parameter, at whose default value the map is the
//! identity; the run's g is the composition of every registered law at its value, so laws
//! compose and the linear drag is every law at its default. Each law is its own file (its
//! map, inverse and slope) plus one line in [`REGISTERED`]; everything that lists, parses,
//! saves or shows a drag parameter (command-line flags, scene keys, Python keywords, JSON
//! fields, the app's controls) iterates over [`REGISTERED`], never over a named law.
//!
//! The models use the law in three ways:
//! - viscous: the torque balance γ g(|ω|) = |r × F| gives |ω| = g⁻¹(|r × F|/γ)
//!   ([`DragLaw::speed_for`]);
//! - inertial: the torque γ g(|ω|) ω̂ ([`DragLaw::torque`]) and its power γ g(|ω|) |ω|;
//! - the stiff-corner policy: the relaxation time uses the law's slope γ g'(|ω|)
//!   ([`DragLaw::slope`]).
//!
//! Pure math, imports nothing but serde.

pub mod power_law;

use serde::ser::SerializeMap;

/// One registered drag law: its parameter and its speed map.
#[derive(Debug)]
pub struct DragParameter {
    /// Its name in scenes, JSON, CSV headers and Python keywords (snake_case).
    pub key: &'static str,
    /// Its command-line flag without the leading dashes (kebab-case).
    pub flag: &'static str,
    /// What it means, for `--help`, scene docs and the app's tooltip.
    pub help: &'static str,
    /// The value at which the law is today's linear drag (its map is the identity).
    pub default: f64,
    /// The smallest value allowed.
    pub min: f64,
    /// The largest value allowed.
    pub max: f64,
    /// g(speed) for a parameter value: the drag torque over γ at angular speed `speed` ≥ 0.
    pub map: fn(value: f64, speed: f64) -> f64,
    /// g⁻¹: the speed at which the torque over γ is `torque` ≥ 0.
    pub inverse: fn(value: f64, torque: f64) -> f64,
    /// g'(speed), the torque's rate of change with speed (over γ).
    pub slope: fn(value: f64, speed: f64) -> f64,
}

/// The registry: every drag law there is. A new law is its own file and one entry here.
pub const REGISTERED: &[&DragParameter] = &[&power_law::EXPONENT];

/// A bad drag-law parameter.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum DragLawError {
    /// A value outside its law's range.
    #[error(
        "{key} = {value} is not allowed (needs a finite {min} ≤ {key} ≤ {max}; {default} is the \
         paper's linear drag)"
    )]
    OutOfRange {
        /// The parameter's key.
        key: &'static str,
        /// The value given.
        value: f64,
        /// Its smallest allowed value.
        min: f64,
        /// Its largest allowed value.
        max: f64,
        /// Its default.
        default: f64,
    },
    /// A name that is no registered parameter.
    #[error("there is no drag parameter {0:?} (the parameters are: {known})", known = known_keys())]
    Unknown(String),
}

fn known_keys() -> String {
    REGISTERED
        .iter()
        .map(|p| p.key)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The drag law of a run: one value per registered parameter, in [`REGISTERED`]'s order.
/// Serialised as a map from each key to its value, so JSON summaries carry every parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragLaw {
    values: [f64; REGISTERED.len()],
}

impl Default for DragLaw {
    fn default() -> Self {
        Self::LINEAR
    }
}

impl DragLaw {
    /// The paper's linear drag: every parameter at its default.
    pub const LINEAR: DragLaw = DragLaw {
        values: default_values(),
    };

    /// This law with parameter `key` set to `value`, checked against its range.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::{DragLaw, DragLawError, REGISTERED};
    /// for p in REGISTERED {
    ///     let law = DragLaw::LINEAR.with(p.key, p.max)?;
    ///     assert_eq!(law.get(p.key), Some(p.max));
    ///     assert!(!law.is_linear());
    ///     assert!(matches!(law.with(p.key, f64::NAN), Err(DragLawError::OutOfRange { .. })));
    /// }
    /// assert!(matches!(DragLaw::LINEAR.with("drag_colour", 1.0), Err(DragLawError::Unknown(_))));
    /// # Ok::<(), DragLawError>(())
    /// ```
    pub fn with(self, key: &str, value: f64) -> Result<Self, DragLawError> {
        let index = REGISTERED
            .iter()
            .position(|p| p.key == key)
            .ok_or_else(|| DragLawError::Unknown(key.to_string()))?;
        let p = REGISTERED[index];
        if !(value.is_finite() && (p.min..=p.max).contains(&value)) {
            return Err(DragLawError::OutOfRange {
                key: p.key,
                value,
                min: p.min,
                max: p.max,
                default: p.default,
            });
        }
        let mut values = self.values;
        values[index] = value;
        Ok(Self { values })
    }

    /// The value of parameter `key`, if there is one.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::{DragLaw, REGISTERED};
    /// for p in REGISTERED {
    ///     assert_eq!(DragLaw::LINEAR.get(p.key), Some(p.default));
    /// }
    /// assert_eq!(DragLaw::LINEAR.get("nothing"), None);
    /// ```
    pub fn get(&self, key: &str) -> Option<f64> {
        REGISTERED
            .iter()
            .position(|p| p.key == key)
            .map(|i| self.values[i])
    }

    /// Every registered parameter with its value here.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::{DragLaw, REGISTERED};
    /// assert_eq!(DragLaw::LINEAR.parameters().count(), REGISTERED.len());
    /// ```
    pub fn parameters(&self) -> impl Iterator<Item = (&'static DragParameter, f64)> + '_ {
        REGISTERED.iter().copied().zip(self.values.iter().copied())
    }

    /// The law in a few words, for a status line or a saved description: "linear drag" for
    /// the paper's, else its parameters away from their defaults ("drag_exponent = 2").
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::DragLaw;
    /// assert_eq!(DragLaw::LINEAR.label(), "linear drag");
    /// assert_eq!(DragLaw::LINEAR.with("drag_exponent", 2.0)?.label(), "drag_exponent = 2");
    /// # Ok::<(), rollphase_core::dynamics::drag::DragLawError>(())
    /// ```
    pub fn label(&self) -> String {
        if self.is_linear() {
            return "linear drag".to_string();
        }
        self.parameters()
            .filter(|(p, v)| *v != p.default)
            .map(|(p, v)| format!("{} = {v}", p.key))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Whether this is the paper's linear drag (the models then run their linear equations
    /// untouched, bit for bit).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::DragLaw;
    /// assert!(DragLaw::default().is_linear());
    /// ```
    pub fn is_linear(&self) -> bool {
        self.parameters().all(|(p, v)| v == p.default)
    }

    /// g(speed): the drag torque over γ at angular speed `speed` ≥ 0.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::{DragLaw, REGISTERED};
    /// assert_eq!(DragLaw::LINEAR.torque(3.0), 3.0);
    /// for p in REGISTERED {
    ///     // Every law makes the torque grow with the speed.
    ///     let law = DragLaw::LINEAR.with(p.key, p.max)?;
    ///     assert!(law.torque(2.0) > law.torque(1.0) && law.torque(0.0) == 0.0);
    /// }
    /// # Ok::<(), rollphase_core::dynamics::drag::DragLawError>(())
    /// ```
    pub fn torque(&self, speed: f64) -> f64 {
        self.parameters()
            .filter(|(p, v)| *v != p.default)
            .fold(speed, |s, (p, v)| (p.map)(v, s))
    }

    /// g⁻¹(torque): the speed at which the drag torque over γ is `torque` ≥ 0.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::{DragLaw, REGISTERED};
    /// for p in REGISTERED {
    ///     let law = DragLaw::LINEAR.with(p.key, p.min)?;
    ///     assert!((law.torque(law.speed_for(0.3)) - 0.3).abs() < 1e-15);
    /// }
    /// # Ok::<(), rollphase_core::dynamics::drag::DragLawError>(())
    /// ```
    pub fn speed_for(&self, torque: f64) -> f64 {
        // The maps undone in reverse order; no allocation, as the viscous models call this
        // on every right-hand-side evaluation.
        REGISTERED
            .iter()
            .zip(self.values.iter())
            .rev()
            .filter(|(p, v)| **v != p.default)
            .fold(torque, |t, (p, v)| (p.inverse)(*v, t))
    }

    /// g'(speed), by the chain rule through the composed laws.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::{DragLaw, REGISTERED};
    /// assert_eq!(DragLaw::LINEAR.slope(3.0), 1.0);
    /// for p in REGISTERED {
    ///     let law = DragLaw::LINEAR.with(p.key, p.max)?;
    ///     let numeric = (law.torque(1.0 + 1e-6) - law.torque(1.0 - 1e-6)) / 2e-6;
    ///     assert!((law.slope(1.0) - numeric).abs() < 1e-6);
    /// }
    /// # Ok::<(), rollphase_core::dynamics::drag::DragLawError>(())
    /// ```
    pub fn slope(&self, speed: f64) -> f64 {
        let mut s = speed;
        let mut slope = 1.0;
        for (p, v) in self.parameters().filter(|(p, v)| *v != p.default) {
            slope *= (p.slope)(v, s);
            s = (p.map)(v, s);
        }
        slope
    }

    /// This law if it is not the linear one (the models then run their linear equations).
    pub(crate) fn if_nonlinear(self) -> Option<DragLaw> {
        (!self.is_linear()).then_some(self)
    }

    /// The viscous angular velocity for the linear one, `linear` = τ/γ: the same direction,
    /// speed g⁻¹(|τ|/γ).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::DragLaw;
    /// assert_eq!(DragLaw::LINEAR.viscous_rate(-0.25), -0.25);
    /// assert_eq!(DragLaw::LINEAR.viscous_rate(0.0), 0.0);
    /// ```
    pub fn viscous_rate(&self, linear: f64) -> f64 {
        if linear == 0.0 {
            return 0.0;
        }
        self.speed_for(linear.abs()).copysign(linear)
    }

    /// The factor g(|ω|)/|ω| that turns ω into the drag torque over γ (0 at rest).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::drag::DragLaw;
    /// assert_eq!(DragLaw::LINEAR.torque_per_speed(0.5), 1.0);
    /// assert_eq!(DragLaw::LINEAR.torque_per_speed(0.0), 0.0);
    /// ```
    pub fn torque_per_speed(&self, speed: f64) -> f64 {
        if speed == 0.0 {
            // The limit g(s)/s as s → 0: g'(0), which is 0 for an exponent > 1 and infinite
            // below; at rest the torque itself is 0 either way.
            return 0.0;
        }
        self.torque(speed) / speed
    }
}

const fn default_values() -> [f64; REGISTERED.len()] {
    let mut values = [0.0; REGISTERED.len()];
    let mut i = 0;
    while i < REGISTERED.len() {
        values[i] = REGISTERED[i].default;
        i += 1;
    }
    values
}

impl serde::Serialize for DragLaw {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(REGISTERED.len()))?;
        for (p, v) in self.parameters() {
            map.serialize_entry(p.key, &v)?;
        }
        map.end()
    }
}
