//! The one model abstraction: what every rolling model offers the code above it
//! ([`RollingModel`]: its name, its trajectory's columns, a sample row, the health it can
//! measure, its Poincaré section, and what its state looks like as an [`Observation`]), and the
//! visitor through which that code reaches the model of a run without naming the models
//! ([`ModelVisitor`], dispatched once, in `simulate::ModelState::visit`).
//!
//! A fifth model implements [`RollingModel`] in its own file (with [`Pose`], how its state
//! carries over from and to the other models of its dimension) and gets one entry in
//! `dynamics::models::with_registered_models`, from which its `ModelKind`, its registry entry and
//! its `ModelState` variant are made; `simulate::run`, the live run, the CSV columns, the
//! overlay, the health plot, `--help` and Python's `models()` ask the model or the registry and
//! need no change. What still names models: an analysis with its own algorithm per model (the
//! viscous and inertial sphere's orbit solvers) picks by `ModelKind`, and a model with the
//! (dimension, inertia) of a registered one would need a way to be asked for.

use glam::{DQuat, DVec3};

use super::{ModelKind, Observe};

/// The numerical health a model can measure at a state; `None` where it does not apply (|q|
/// for a cylinder, energy for a viscous model).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ModelHealth {
    /// ||q| − 1| (3D).
    pub quat_norm_error: Option<f64>,
    /// |n_lab − (0, 0, −1)|, the contact normal's error (3D).
    pub contact_normal_error: Option<f64>,
    /// E + W, energy plus the work done by drag (inertial models).
    pub energy: Option<f64>,
}

/// What a state looks like in the ramp frame (x downhill, z the ramp's normal), for drawing
/// and the overlay.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    /// Body-to-ramp rotation, unit.
    pub rotation: DQuat,
    /// Centre of mass.
    pub centre: DVec3,
    /// The contact point on the ramp (z = 0).
    pub contact_on_ramp: DVec3,
    /// The contact point in the body frame (a cylinder's on its mid-plane).
    pub contact_in_body: DVec3,
    /// The orientation as integrated (3D; not renormalised), for the SO(3) ball.
    pub orientation: Option<DQuat>,
    /// |ω| (3D) or |θ̇| (2D).
    pub angular_speed: f64,
    /// |r × F|, the torque of the weight about the contact that nothing balances (units of
    /// F⟨r⟩): zero at an equilibrium and for a dented cylinder resting on a flat of its hull.
    /// With `angular_speed` it is what `analysis::verdict::at_rest` decides a rest by: a heavy
    /// body released from rest above α* is still but pushed.
    pub ramp_torque: f64,
    /// The contact angle θ (2D).
    pub theta: Option<f64>,
    /// θ̇ (2D).
    pub theta_dot: Option<f64>,
    /// Its health.
    pub health: ModelHealth,
}

/// The force the ramp exerts on the body at the contact, in units of the weight F, in the ramp
/// frame (x downhill, y across, z the ramp's normal): f = m a_cm − F, Newton's law for the centre
/// of mass with the model's own acceleration (the drag is a pure torque, SI eq. 1), so it is exact
/// for the motion the model computes. In the viscous limit m → 0 it is −F: N = cos α and the
/// friction needed is tan α.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactForce {
    /// The normal force N (> 0 pushes the body off the ramp; ≤ 0 means the ramp would have to
    /// pull: the body leaves it).
    pub normal: f64,
    /// The tangential (friction) force (f_x, f_y); f_x < 0 points uphill.
    pub friction: [f64; 2],
}

impl ContactForce {
    /// The coefficient of static friction rolling needs, |f_t|/N; infinite where N ≤ 0 (no
    /// friction holds a body the ramp does not press).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ContactForce;
    /// let f = ContactForce { normal: 0.5, friction: [-0.3, 0.4] };
    /// assert!((f.friction_needed() - 1.0).abs() < 1e-15);
    /// let off = ContactForce { normal: -0.1, friction: [0.0, 0.0] };
    /// assert!(off.friction_needed().is_infinite());
    /// ```
    pub fn friction_needed(&self) -> f64 {
        if self.normal > 0.0 {
            self.friction[0].hypot(self.friction[1]) / self.normal
        } else {
            f64::INFINITY
        }
    }

    /// The force of the viscous limit, −F: N = cos α, friction (−sin α, 0).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ContactForce;
    /// let f = ContactForce::viscous(0.3);
    /// assert!((f.friction_needed() - 0.3f64.tan()).abs() < 1e-15);
    /// ```
    pub fn viscous(alpha_rad: f64) -> Self {
        ContactForce {
            normal: alpha_rad.cos(),
            friction: [-alpha_rad.sin(), 0.0],
        }
    }
}

/// The trajectory columns of [`ContactForce`] that every model appends to its row
/// (`friction_y` is 0 in 2D; `friction_needed` is `inf` where N ≤ 0).
pub const FORCE_COLUMNS: &str = "normal_force,friction_x,friction_y,friction_needed";

/// What the models of one body share: where it is and how it turns. A start is one; a change
/// of model mid-run (m/m0 turned on or off) carries it from one model's state to the other's
/// ([`RollingModel::pose`], [`RollingModel::state_at`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pose {
    /// A cylinder.
    Disk {
        /// The contact angle θ.
        theta: f64,
        /// θ̇; zero from a viscous state (an inertial model taking it over starts from rest).
        theta_dot: f64,
        /// The contact's distance down the ramp.
        x_c: f64,
    },
    /// A sphere.
    Sphere {
        /// The orientation, body to lab (as integrated).
        q: DQuat,
        /// The lab angular velocity; zero from a viscous state.
        omega: DVec3,
        /// Where it is on the ramp (x downhill, y across), as its state holds it.
        position: [f64; 2],
    },
}

/// A rolling model, as everything above the physics sees it. `N` is the size of its state.
///
/// A model is its own file: its equations ([`crate::integrate::OdeSystem`], [`Observe`]), this
/// trait, and an inherent `new(&body, &Ramp)`; plus its one entry in
/// `dynamics::models::with_registered_models`, from which its [`ModelKind`], its registry
/// entry and its `simulate::ModelState` variant (and every match over the models) are made.
pub trait RollingModel<const N: usize>: Observe<N> {
    /// Its one name.
    const KIND: ModelKind;
    /// Its trajectory's columns, t first (the CSV header).
    const COLUMNS: &'static str;
    /// One sample in [`Self::COLUMNS`] order, t first, written to `out` (cleared first).
    fn row(&self, t: f64, y: &[f64; N], out: &mut Vec<f64>);
    /// The health it can measure at `y`.
    fn health(&self, y: &[f64; N]) -> ModelHealth;
    /// The ramp's force on the body at `y` ([`ContactForce`]), from the equations of motion.
    fn contact_force(&self, y: &[f64; N]) -> ContactForce;
    /// What `y` looks like.
    fn observation(&self, y: &[f64; N]) -> Observation;
    /// Its Poincaré section, a function of the state that passes zero at each crossing: sin(θ/2)
    /// for a cylinder (θ through a multiple of 2π), q_w for a sphere (∂Ω).
    fn section(&self, y: &[f64; N]) -> f64;
    /// Where a crossing of the section is: the boundary point of ∂Ω (3D); `None` in 2D.
    fn section_point(&self, y: &[f64; N]) -> Option<DVec3>;
    /// A function of the state that passes from ≥ 0 to < 0 where the motion switches: a dented
    /// 2D body's contact reaching the end of a bridge of its hull. `None` for a smooth model
    /// (every convex body, every sphere).
    fn switching(&self, _y: &[f64; N]) -> Option<f64> {
        None
    }
    /// A start as the body would lie: a dented body started on a flat of its hull rests there
    /// if its weight falls between the flat's ends, and otherwise tips onto the end it leans
    /// towards at once. The identity for every other model.
    fn placed(&self, y: [f64; N]) -> [f64; N] {
        y
    }
    /// The state right after the switch at `y` (on the switching surface), and what happened
    /// there; `None` if `y` is not at a switch.
    fn switch(&self, _y: &[f64; N]) -> Option<([f64; N], Switched)> {
        None
    }
    /// Its state at `pose`, with no work done by drag yet; `None` for a pose of the other
    /// dimension. A viscous model drops the rate (its rate follows from where it is).
    fn state_at(pose: &Pose) -> Option<[f64; N]>;
    /// Where `y` puts the body, and how it turns (zero for a viscous state).
    fn pose(y: &[f64; N]) -> Pose;
    /// `v` as its state, checked beyond being finite (a resumed file's numbers): a sphere's
    /// quaternion must be of unit length to 1e-6 and is renormalised within that. The identity
    /// for a model with nothing more to check.
    fn checked_state(v: [f64; N]) -> Result<[f64; N], String> {
        Ok(v)
    }
}

/// What happened at a switch of a hybrid model ([`RollingModel::switch`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Switched {
    /// The body tipped across a bridge onto its far end: instantly in the viscous model; with an
    /// impact in the inertial one, which loses this much kinetic energy (units of F⟨r⟩).
    Tip {
        /// Kinetic energy lost in the impact (0 in the viscous model).
        energy_lost: f64,
    },
    /// The body came to rest on a bridge, on both its ends (it stays there).
    Rest {
        /// Kinetic energy it still had, dissipated in the last, unresolved rocking.
        energy_lost: f64,
    },
}

impl Switched {
    /// The kinetic energy lost.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::Switched;
    /// assert_eq!(Switched::Tip { energy_lost: 0.25 }.energy_lost(), 0.25);
    /// ```
    pub fn energy_lost(&self) -> f64 {
        match self {
            Switched::Tip { energy_lost } | Switched::Rest { energy_lost } => *energy_lost,
        }
    }
}

/// Code that works with any [`RollingModel`] and its state: `simulate::ModelState::visit`
/// calls [`Self::visit`] with the run's model, so the caller never matches on the models.
pub trait ModelVisitor {
    /// What the visit returns.
    type Output;
    /// Works with `model` at state `y`.
    fn visit<const N: usize, M: RollingModel<N>>(self, model: &M, y: &[f64; N]) -> Self::Output;
}

/// [`ModelVisitor`] that may change the state (stepping it).
pub trait ModelVisitorMut {
    /// What the visit returns.
    type Output;
    /// Works with `model`, updating `y`.
    fn visit<const N: usize, M: RollingModel<N>>(self, model: &M, y: &mut [f64; N])
    -> Self::Output;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{DiskViscous, Ramp, SphereInertial, SphereViscous};
    use crate::geometry::Body;

    /// In the viscous limit the drag balances the weight's torque, γ|ω| = |r × F|: the rest
    /// measure a run is halted by is the model's own torque balance, in 2D and 3D.
    #[test]
    fn the_unbalanced_torque_is_the_viscous_drag_and_a_still_heavy_body_is_pushed() {
        let ramp = Ramp::new(0.1, 0.0).unwrap();
        let Body::Disk(disk) = Body::paper_disk(84, 0.12, 5).unwrap() else {
            unreachable!()
        };
        let model = DiskViscous::new(&disk, &ramp);
        for i in 0..50 {
            let theta = i as f64 * 0.125;
            let o = model.observation(&[theta, 0.0]);
            let psi_dot = disk.jet(theta).turn_rate() * model.theta_dot(theta);
            assert!(
                (o.ramp_torque - psi_dot.abs()).abs() < 1e-12,
                "θ = {theta}: torque {} against γ|ψ̇| {}",
                o.ramp_torque,
                psi_dot.abs()
            );
        }
        let Body::Sphere(sphere) = Body::paper_sphere(219, 0.25, 5).unwrap() else {
            unreachable!()
        };
        let model = SphereViscous::new(&sphere, &ramp);
        for i in 0..20 {
            let q = glam::DQuat::from_scaled_axis(glam::DVec3::new(0.3, -0.2, 0.5) * i as f64);
            let o = model.observation(&SphereViscous::initial_state(q));
            assert!((o.ramp_torque - o.angular_speed).abs() < 1e-12);
        }
        // A heavy sphere released from rest above α*: still, and pushed by sin α-ish.
        let heavy = SphereInertial::new(&sphere, &Ramp::new(0.3, 1e10).unwrap());
        let o = heavy.observation(&SphereInertial::initial_state(
            glam::DQuat::IDENTITY,
            glam::DVec3::ZERO,
        ));
        assert_eq!(o.angular_speed, 0.0);
        assert!(o.ramp_torque > 0.1, "{}", o.ramp_torque);
    }
}
