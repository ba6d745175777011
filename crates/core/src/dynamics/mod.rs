//! The four rolling models of the paper (SI §1A, §2A–2C), as [`OdeSystem`]s on fixed-size
//! states, plus what is observed on them (contact point, centre of mass, energy).
//! Pure math: imports `geometry`, `integrate`, `glam`.
//!
//! Units throughout: F = γ = ⟨r⟩ = 1 by default, time in t0 = γ/(F⟨r⟩), mass as m/m0 with
//! m0 = γ²/(F⟨r⟩³). The drag γ can be set to 0 (conservative tests) for inertial models only.

pub mod disk2d;
pub mod drag;
pub mod model;
pub mod models;
pub mod sphere3d;
pub mod validity;

use thiserror::Error;

use crate::integrate::OdeSystem;

pub use disk2d::{DiskInertial, DiskViscous};
pub use drag::{DragLaw, DragLawError};
pub use model::{
    ContactForce, FORCE_COLUMNS, ModelHealth, ModelVisitor, ModelVisitorMut, Observation, Pose,
    RollingModel, Switched,
};
pub use models::ModelKind;
pub use sphere3d::{SphereInertial, SphereViscous};

/// The ramp and the body's dynamical constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    /// Tilt α in radians, [`MIN_ALPHA`] ≤ α < π/2.
    pub alpha_rad: f64,
    /// m/m0; 0 asks for the viscous model ([`ModelKind::for_dimension`] decides).
    pub mass_ratio: f64,
    /// Rotational drag γ in units of γ0 (1 by default; 0 only for inertial models).
    pub drag: f64,
    /// How the drag torque grows with the speed ([`drag`]): linear unless a registered law's
    /// parameter says otherwise.
    pub drag_law: DragLaw,
}

/// A bad model parameter.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ModelError {
    /// α outside [[`MIN_ALPHA`], π/2).
    #[error("{}", bad_alpha_text(*.0))]
    BadAlpha(f64),
    /// Negative or non-finite mass ratio.
    #[error(
        "mass ratio m/m0 = {} is not allowed (needs a finite m/m0 ≥ 0; 0 means the viscous model)",
        crate::integrate::readable(*.0)
    )]
    BadMass(f64),
    /// Negative or non-finite drag, or zero drag in a viscous model.
    #[error(
        "drag gamma = {} is not allowed (needs a finite gamma ≥ 0, and > 0 when m/m0 = 0)",
        crate::integrate::readable(*.0)
    )]
    BadDrag(f64),
    /// A drag-law parameter out of its range, or no such parameter.
    #[error(transparent)]
    BadDragLaw(#[from] DragLawError),
}

/// [`ModelError::BadAlpha`]'s message: why a tiny angle is refused only where it is tiny.
fn bad_alpha_text(alpha: f64) -> String {
    let shown = crate::integrate::readable(alpha);
    if alpha > 0.0 && alpha < MIN_ALPHA {
        format!(
            "alpha = {shown} rad is not allowed (needs 1e-9 ≤ alpha < π/2 ≈ 1.5708, in radians): \
             below 1e-9 rad the tilt's pull is within a few million round-offs of the contact \
             geometry's forces, and near 1e-14 the computed motion is round-off alone"
        )
    } else {
        format!(
            "alpha = {shown} rad is not allowed (needs 1e-9 ≤ alpha < π/2 ≈ 1.5708, in radians)"
        )
    }
}

/// The smallest ramp angle (rad). The tilt's pull is F sin α, the geometry's forces are of
/// order F with round-off 1e-16: on the perfect sphere the computed motion is round-off alone
/// below α ≈ 1e-14 (at 1e-16 it rolls uphill; from 1e-20 down it goes 1,689 times too far), so
/// 1e-9 keeps every answer to about 1e-7 of itself. No body of the paper does anything at such
/// a tilt but rest (α* ≥ 1e-3 for any irregular one).
pub const MIN_ALPHA: f64 = 1e-9;

impl Ramp {
    /// A ramp with unit drag.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelError, Ramp};
    /// let ramp = Ramp::new(0.15, 6.0)?;
    /// assert_eq!((ramp.drag, ramp.mass_ratio), (1.0, 6.0));
    /// assert_eq!(Ramp::new(2.0, 0.0), Err(ModelError::BadAlpha(2.0)));
    /// // Below 1e-9 rad the tilt is lost in round-off.
    /// assert_eq!(Ramp::new(1e-16, 0.0), Err(ModelError::BadAlpha(1e-16)));
    /// assert!(Ramp::new(0.15, f64::NAN).is_err());
    /// # Ok::<(), ModelError>(())
    /// ```
    pub fn new(alpha_rad: f64, mass_ratio: f64) -> Result<Self, ModelError> {
        Self::with_drag(alpha_rad, mass_ratio, 1.0)
    }

    /// A ramp with the given drag, validated.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelError, Ramp};
    /// // No drag: allowed with inertia (free rolling), not in the viscous model.
    /// assert!(Ramp::with_drag(0.15, 1.0, 0.0).is_ok());
    /// assert_eq!(Ramp::with_drag(0.15, 0.0, 0.0), Err(ModelError::BadDrag(0.0)));
    /// // m/m0 = −0 is 0.
    /// assert!(Ramp::with_drag(0.15, -0.0, 1.0).unwrap().mass_ratio.is_sign_positive());
    /// ```
    pub fn with_drag(alpha_rad: f64, mass_ratio: f64, drag: f64) -> Result<Self, ModelError> {
        if !(MIN_ALPHA..std::f64::consts::FRAC_PI_2).contains(&alpha_rad) {
            return Err(ModelError::BadAlpha(alpha_rad));
        }
        if !(mass_ratio.is_finite() && mass_ratio >= 0.0) {
            return Err(ModelError::BadMass(mass_ratio));
        }
        if !(drag.is_finite() && drag >= 0.0) || (mass_ratio == 0.0 && drag == 0.0) {
            return Err(ModelError::BadDrag(drag));
        }
        Ok(Self {
            alpha_rad,
            // −0 is the viscous model's 0: not "m/m0 = -0" on any surface.
            mass_ratio: mass_ratio + 0.0,
            drag,
            drag_law: DragLaw::LINEAR,
        })
    }

    /// This ramp with drag law `law` (already checked when it was built).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{DragLaw, Ramp};
    /// let ramp = Ramp::new(0.2, 0.0)?.with_drag_law(DragLaw::LINEAR);
    /// assert!(ramp.drag_law.is_linear());
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn with_drag_law(self, law: DragLaw) -> Self {
        Self {
            drag_law: law,
            ..self
        }
    }
}

/// Implemented by every model: what a sampled state means physically.
pub trait Observe<const N: usize>: OdeSystem<N> {
    /// Total energy E = kinetic − F·x_cm plus the work already dissipated by drag, which stays
    /// constant along exact solutions; `None` for viscous models (no kinetic energy).
    fn energy_balance(&self, y: &[f64; N]) -> Option<f64>;
}
