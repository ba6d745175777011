//! 3D rolling of a body r(u) on a ramp (SI §2A–2C), lab frame x downhill, z the ramp's normal:
//! F = (sin α, 0, −cos α), the plane z = 0, the body's outward normal at the contact (0, 0, −1).
//!
//! Orientation: unit quaternion q (Hamilton), body-to-lab, r = q r₀ q̄, q̇ = ½ ω q (SI §2B).
//!
//! Contact: *recovered from q*, not integrated. For a strictly convex body the contact is the
//! support point whose body-frame outward normal is d = q̄ (0, 0, −1) q
//! ([`Sphere::support_point`], Newton warm-started from the previous contact). So the constraint
//! "normal at the contact is (0, 0, −1)" holds to the Newton tolerance (~1e-15) at every instant
//! and cannot drift, unlike the paper's integrated (θ, φ), which needed re-projection every 50
//! time units and is singular at the chart's poles. The paper's (θ̇, φ̇) equation (SI §2C) is the
//! derivative of the same condition: in Cartesian form ṗ = S⁻¹ ḋ with S the shape operator.
//!
//! Viscous, state [q, x, y]: ω = −r × F / γ, centre velocity v = −ω × r (no slip).
//! Inertial, state [q, ω, x, y, W] with I = 2m/5 (SI eq. 34):
//!   (I + m r²) ω̇ = −r × F − γ ω − (mγ/I)(r·ω) r − m r × (ω × ṙ),
//!   ṙ = ω × r + q (S⁻¹ ḋ) q̄,  ḋ = −ω_body × d,
//! where ṙ is the full derivative of the contact vector, the contact's motion over the body
//! included. This equation conserves E = ½Iω² + ½m|v|² − F·x_cm up to the drag work
//! W = ∫γ|ω|² dt (checked in `tests/physics/energy_balance.rs`); we found no error in it.
//! The height z of the centre is −r_z (the support function), so only x, y are integrated.

use std::cell::Cell;

use glam::{DQuat, DVec3};

use super::{
    ContactForce, DragLaw, ModelHealth, ModelKind, Observation, Observe, Pose, Ramp, RollingModel,
};
use crate::geometry::{Sphere, SurfacePoint};
use crate::integrate::OdeSystem;
use crate::integrate::lie::quat_at;

/// The lab's downward direction: the contact normal.
pub const DOWN: DVec3 = DVec3::new(0.0, 0.0, -1.0);

/// Shared contact tracking: finds the contact for an orientation, warm-started.
struct ContactTracker<'a> {
    body: &'a Sphere,
    last: Cell<Option<SurfacePoint>>,
}

impl<'a> ContactTracker<'a> {
    fn new(body: &'a Sphere) -> Self {
        Self {
            body,
            last: Cell::new(None),
        }
    }

    /// The contact geometry for orientation q (normalised here), or `None` if Newton fails;
    /// the next search starts from it.
    fn contact(&self, q: DQuat) -> Option<SurfacePoint> {
        let found = self.look_up(q);
        if found.is_some() {
            self.last.set(found);
        }
        found
    }

    /// The warm start as numbers ([`OdeSystem::memory`]): empty before the first look-up.
    fn memory(&self) -> Vec<f64> {
        let Some(sp) = self.last.get() else {
            return Vec::new();
        };
        let mut m = Vec::with_capacity(22);
        for v in [sp.u, sp.p, sp.grad_s, sp.normal, sp.tangent.0, sp.tangent.1] {
            m.extend(v.to_array());
        }
        m.push(sp.r);
        m.extend(sp.shape_in_tangent);
        m
    }

    /// Restores [`Self::memory`]; anything but its 22 numbers (or none) clears the warm start.
    fn restore_memory(&self, m: &[f64]) {
        let v = |k: usize| DVec3::new(m[3 * k], m[3 * k + 1], m[3 * k + 2]);
        self.last.set((m.len() == 22).then(|| SurfacePoint {
            u: v(0),
            p: v(1),
            grad_s: v(2),
            normal: v(3),
            tangent: (v(4), v(5)),
            r: m[18],
            shape_in_tangent: [m[19], m[20], m[21]],
        }));
    }

    /// [`Self::contact`] that leaves the warm start alone: for observers (the contact-force
    /// watch, the sampled rows, the health, a rest test), whose look-ups must not move where
    /// the integrator's next Newton search starts, and so its last bits: a run that records
    /// is bit for bit one that does not.
    fn peek(&self, q: DQuat) -> Option<SurfacePoint> {
        self.look_up(q)
    }

    fn look_up(&self, q: DQuat) -> Option<SurfacePoint> {
        let q = q.normalize();
        let d = q.conjugate() * DOWN;
        let found = match self.last.get() {
            Some(last) if last.normal.dot(d) > 0.5 => self.body.support_point_from(d, last),
            _ => self.body.support_point(d, d),
        };
        found.ok()
    }
}

/// The orientation that puts the surface point above body direction `u` in contact with the
/// ramp, then spins the body on the spot by `spin_rad` about the lab's +z axis (SI §2F).
///
/// # Example
/// ```
/// use rollphase_core::dynamics::sphere3d::orientation_touching;
/// use rollphase_core::dynamics::{Ramp, SphereViscous};
/// use rollphase_core::geometry::random_sphere;
/// use rollphase_core::glam::DVec3;
/// let body = random_sphere(1, 0.2, 4)?;
/// let u = DVec3::new(0.3, 0.4, -0.5).normalize();
/// let q = orientation_touching(&body, u, 0.7);
/// let model = SphereViscous::new(&body, &Ramp::new(0.2, 0.0)?);
/// let seen = model.observe(&SphereViscous::initial_state(q));
/// assert!((seen.contact_dir - u).length() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn orientation_touching(body: &Sphere, u: DVec3, spin_rad: f64) -> DQuat {
    let n0 = body.surface(u).normal;
    let tilt = DQuat::from_rotation_arc(n0, DOWN);
    (DQuat::from_rotation_z(spin_rad) * tilt).normalize()
}

/// Everything a sampled 3D state shows.
#[derive(Debug, Clone, Copy)]
pub struct SphereObservation {
    /// Orientation as stored (not renormalised).
    pub q: DQuat,
    /// Contact point as a unit vector in the body frame.
    pub contact_dir: DVec3,
    /// Lab angular velocity.
    pub omega: DVec3,
    /// Centre of mass in the lab.
    pub centre: DVec3,
    /// ||q| − 1|.
    pub quat_norm_error: f64,
    /// |q n₀ q̄ − (0, 0, −1)| with the stored q, so |q| drift counts too.
    pub contact_normal_error: f64,
}

fn observe(
    tracker: &ContactTracker,
    q: DQuat,
    omega_of: impl Fn(DVec3) -> DVec3,
    x: f64,
    y: f64,
) -> SphereObservation {
    let nan = DVec3::splat(f64::NAN);
    // An observation is an observer's (rows, health, a rest test): its look-up must not move
    // where the integrator's next Newton search starts, or recording would move the run.
    let Some(sp) = tracker.peek(q) else {
        return SphereObservation {
            q,
            contact_dir: nan,
            omega: nan,
            centre: nan,
            quat_norm_error: f64::NAN,
            contact_normal_error: f64::NAN,
        };
    };
    let qn = q.normalize();
    let r = qn * sp.p;
    let n_lab = q * DQuat::from_xyzw(sp.normal.x, sp.normal.y, sp.normal.z, 0.0) * q.conjugate();
    SphereObservation {
        q,
        contact_dir: sp.u,
        omega: omega_of(r),
        centre: DVec3::new(x, y, -r.z),
        quat_norm_error: (q.length() - 1.0).abs(),
        contact_normal_error: (DVec3::new(n_lab.x, n_lab.y, n_lab.z) - DOWN).length(),
    }
}

fn pure(v: DVec3) -> DQuat {
    DQuat::from_xyzw(v.x, v.y, v.z, 0.0)
}

fn force(alpha_rad: f64) -> DVec3 {
    DVec3::new(alpha_rad.sin(), 0.0, -alpha_rad.cos())
}

/// Viscous 3D model; state [qw, qx, qy, qz, x, y].
pub struct SphereViscous<'a> {
    tracker: ContactTracker<'a>,
    force: DVec3,
    drag: f64,
    /// The drag law when it is not linear.
    law: Option<DragLaw>,
}

impl<'a> SphereViscous<'a> {
    /// The model for `body` on `ramp` (mass ignored).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{Ramp, SphereViscous};
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::DQuat;
    /// let ball = Sphere::perfect();
    /// let model = SphereViscous::new(&ball, &Ramp::new(0.3, 0.0)?);
    /// let seen = model.observe(&SphereViscous::initial_state(DQuat::IDENTITY));
    /// // The unit ball rolls at |ω| = sin α / γ about the horizontal axis across the slope.
    /// assert!((seen.omega.length() - 0.3f64.sin()).abs() < 1e-12 && seen.omega.x.abs() < 1e-12);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn new(body: &'a Sphere, ramp: &Ramp) -> Self {
        Self {
            tracker: ContactTracker::new(body),
            force: force(ramp.alpha_rad),
            drag: if ramp.drag > 0.0 { ramp.drag } else { 1.0 },
            law: ramp.drag_law.if_nonlinear(),
        }
    }

    /// Initial state for orientation q at the origin.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::SphereViscous;
    /// use rollphase_core::glam::DQuat;
    /// let y = SphereViscous::initial_state(DQuat::IDENTITY);
    /// assert_eq!(y, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    /// ```
    pub fn initial_state(q: DQuat) -> [f64; 6] {
        [q.w, q.x, q.y, q.z, 0.0, 0.0]
    }

    /// ω = −r × F / γ for lab contact vector r (linear drag); with a drag law the same
    /// direction at speed g⁻¹(|r × F|/γ).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{Ramp, SphereViscous};
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::DVec3;
    /// let ball = Sphere::perfect();
    /// let model = SphereViscous::new(&ball, &Ramp::new(0.3, 0.0)?);
    /// let r = DVec3::new(0.0, 0.0, -1.0);
    /// let omega = model.omega(r);
    /// // ω is perpendicular to the contact vector, with |ω| = sin α / γ on the unit ball.
    /// assert!(omega.dot(r).abs() < 1e-15 && (omega.length() - 0.3f64.sin()).abs() < 1e-15);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn omega(&self, r: DVec3) -> DVec3 {
        let linear = -r.cross(self.force) / self.drag;
        match self.law {
            None => linear,
            Some(law) => {
                let speed = linear.length();
                if speed == 0.0 {
                    linear
                } else {
                    linear * (law.speed_for(speed) / speed)
                }
            }
        }
    }

    /// What the state shows.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{Ramp, SphereViscous};
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::{DQuat, DVec3};
    /// let ball = Sphere::perfect();
    /// let model = SphereViscous::new(&ball, &Ramp::new(0.3, 0.0)?);
    /// let seen = model.observe(&SphereViscous::initial_state(DQuat::IDENTITY));
    /// assert!((seen.centre - DVec3::new(0.0, 0.0, 1.0)).length() < 1e-12);
    /// assert!(seen.quat_norm_error == 0.0 && seen.contact_normal_error < 1e-12);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn observe(&self, y: &[f64; 6]) -> SphereObservation {
        observe(&self.tracker, quat_at(y, 0), |r| self.omega(r), y[4], y[5])
    }
}

impl SphereViscous<'_> {
    /// The right-hand side with the contact from `look_up` (the tracker's, moving its warm
    /// start or not).
    fn rhs_with(&self, y: &[f64; 6], look_up: impl Fn(DQuat) -> Option<SurfacePoint>) -> [f64; 6] {
        let q = quat_at(y, 0);
        let Some(sp) = look_up(q) else {
            return [f64::NAN; 6];
        };
        let r = q.normalize() * sp.p;
        let omega = self.omega(r);
        let qdot = pure(omega) * q * 0.5;
        let v = -omega.cross(r);
        [qdot.w, qdot.x, qdot.y, qdot.z, v.x, v.y]
    }
}

impl OdeSystem<6> for SphereViscous<'_> {
    fn memory(&self) -> Vec<f64> {
        self.tracker.memory()
    }
    fn restore_memory(&self, memory: &[f64]) {
        self.tracker.restore_memory(memory);
    }
    fn rhs(&self, _t: f64, y: &[f64; 6]) -> [f64; 6] {
        self.rhs_with(y, |q| self.tracker.contact(q))
    }
    fn rhs_aside(&self, _t: f64, y: &[f64; 6]) -> [f64; 6] {
        self.rhs_with(y, |q| self.tracker.peek(q))
    }
    fn quaternion_slot(&self) -> Option<usize> {
        Some(0)
    }
}

impl Observe<6> for SphereViscous<'_> {
    fn energy_balance(&self, _y: &[f64; 6]) -> Option<f64> {
        None
    }
}

/// Inertial 3D model; state [qw, qx, qy, qz, ωx, ωy, ωz, x, y, W].
pub struct SphereInertial<'a> {
    tracker: ContactTracker<'a>,
    force: DVec3,
    mass: f64,
    inertia: f64,
    drag: f64,
    /// The drag law when it is not linear.
    law: Option<DragLaw>,
}

impl<'a> SphereInertial<'a> {
    /// The model for `body` on `ramp`; needs m/m0 > 0.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{Ramp, SphereInertial};
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::{DQuat, DVec3};
    /// let ball = Sphere::perfect();
    /// let model = SphereInertial::new(&ball, &Ramp::new(0.3, 2.0)?);
    /// let omega = DVec3::new(0.0, 0.2, 0.0);
    /// let seen = model.observe(&SphereInertial::initial_state(DQuat::IDENTITY, omega));
    /// assert!((seen.omega - omega).length() < 1e-15);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn new(body: &'a Sphere, ramp: &Ramp) -> Self {
        Self {
            tracker: ContactTracker::new(body),
            force: force(ramp.alpha_rad),
            mass: ramp.mass_ratio,
            inertia: 0.4 * ramp.mass_ratio,
            drag: ramp.drag,
            law: ramp.drag_law.if_nonlinear(),
        }
    }

    /// Initial state for orientation q and lab angular velocity ω at the origin.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::SphereInertial;
    /// use rollphase_core::glam::{DQuat, DVec3};
    /// let y = SphereInertial::initial_state(DQuat::IDENTITY, DVec3::new(0.1, 0.2, 0.3));
    /// assert_eq!(y.len(), 10);
    /// assert_eq!(&y[..4], &[1.0, 0.0, 0.0, 0.0]);
    /// ```
    pub fn initial_state(q: DQuat, omega: DVec3) -> [f64; 10] {
        [q.w, q.x, q.y, q.z, omega.x, omega.y, omega.z, 0.0, 0.0, 0.0]
    }

    /// What the state shows.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{Ramp, SphereInertial};
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::{DQuat, DVec3};
    /// let ball = Sphere::perfect();
    /// let model = SphereInertial::new(&ball, &Ramp::new(0.3, 2.0)?);
    /// let seen = model.observe(&SphereInertial::initial_state(DQuat::IDENTITY, DVec3::ZERO));
    /// assert!((seen.centre.z - 1.0).abs() < 1e-12 && seen.omega == DVec3::ZERO);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn observe(&self, y: &[f64; 10]) -> SphereObservation {
        let omega = DVec3::new(y[4], y[5], y[6]);
        observe(&self.tracker, quat_at(y, 0), |_| omega, y[7], y[8])
    }

    /// The ramp's force on the body at state `y`: f = m a_cm − F with the centre's
    /// acceleration a = −ω̇ × r − ω × ṙ (the derivative of the rolling condition v = −ω × r,
    /// ṙ including the contact's motion over the body); NaN where the contact is not found.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{Ramp, SphereInertial};
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::{DQuat, DVec3};
    /// // A uniform ball rolling freely accelerates at (5/7) g sin α: the ramp holds it back
    /// // with (2/7) F sin α and presses with F cos α.
    /// let ball = Sphere::perfect();
    /// let model = SphereInertial::new(&ball, &Ramp::with_drag(0.3, 2.0, 0.0)?);
    /// let y = SphereInertial::initial_state(DQuat::IDENTITY, DVec3::new(0.0, 0.5, 0.0));
    /// let f = model.contact_force_at(&y);
    /// assert!((f.normal - 0.3f64.cos()).abs() < 1e-12);
    /// assert!((f.friction[0] + 2.0 / 7.0 * 0.3f64.sin()).abs() < 1e-12);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn contact_force_at(&self, y: &[f64; 10]) -> ContactForce {
        let q = quat_at(y, 0);
        let Some(sp) = self.tracker.peek(q) else {
            return ContactForce {
                normal: f64::NAN,
                friction: [f64::NAN; 2],
            };
        };
        let omega = DVec3::new(y[4], y[5], y[6]);
        let (omega_dot, r, r_dot) = self.omega_dot(q.normalize(), &sp, omega);
        let a = -omega_dot.cross(r) - omega.cross(r_dot);
        let f = self.mass * a - self.force;
        ContactForce {
            normal: f.z,
            friction: [f.x, f.y],
        }
    }

    /// |r × F|, the torque of the body's weight about the contact (units of F⟨r⟩): zero only
    /// where the body can rest; NaN where the contact is not found.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{Ramp, SphereInertial};
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::glam::{DQuat, DVec3};
    /// // The unit ball: the weight's torque about the contact is sin α, wherever it is turned.
    /// let ball = Sphere::perfect();
    /// let model = SphereInertial::new(&ball, &Ramp::new(0.3, 2.0)?);
    /// let y = SphereInertial::initial_state(DQuat::IDENTITY, DVec3::ZERO);
    /// assert!((model.ramp_torque(&y) - 0.3f64.sin()).abs() < 1e-12);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn ramp_torque(&self, y: &[f64; 10]) -> f64 {
        let q = quat_at(y, 0);
        self.tracker.peek(q).map_or(f64::NAN, |sp| {
            (q.normalize() * sp.p).cross(self.force).length()
        })
    }

    /// The drag torque's magnitude-and-direction γ g(|ω|) ω̂ (γ ω for linear drag); the
    /// torque on the body is its negative.
    fn drag_torque(&self, omega: DVec3) -> DVec3 {
        match self.law {
            None => self.drag * omega,
            Some(law) => self.drag * law.torque_per_speed(omega.length()) * omega,
        }
    }

    /// ω̇, the lab contact vector r and its full derivative ṙ for contact `sp`, orientation q
    /// (unit) and ω (SI eq. 34).
    fn omega_dot(&self, q: DQuat, sp: &SurfacePoint, omega: DVec3) -> (DVec3, DVec3, DVec3) {
        let r = q * sp.p;
        let d = q.conjugate() * DOWN;
        let omega_body = q.conjugate() * omega;
        let p_dot_body = sp.solve_shape(-omega_body.cross(d));
        let r_dot = omega.cross(r) + q * p_dot_body;
        let m = self.mass;
        // The linear drag's terms as written before the drag laws, so linear runs keep their
        // numbers bit for bit.
        let (drag, drag_along_r) = match self.law {
            None => (
                self.drag * omega,
                (m * self.drag / self.inertia) * r.dot(omega) * r,
            ),
            Some(_) => {
                let drag = self.drag_torque(omega);
                (drag, (m / self.inertia) * r.dot(drag) * r)
            }
        };
        let rhs = -r.cross(self.force) - drag - drag_along_r - m * r.cross(omega.cross(r_dot));
        (rhs / (self.inertia + m * r.length_squared()), r, r_dot)
    }
}

impl SphereInertial<'_> {
    /// The right-hand side with the contact from `look_up` (the tracker's, moving its warm
    /// start or not).
    fn rhs_with(
        &self,
        y: &[f64; 10],
        look_up: impl Fn(DQuat) -> Option<SurfacePoint>,
    ) -> [f64; 10] {
        let q = quat_at(y, 0);
        let Some(sp) = look_up(q) else {
            return [f64::NAN; 10];
        };
        let omega = DVec3::new(y[4], y[5], y[6]);
        let (omega_dot, r, _) = self.omega_dot(q.normalize(), &sp, omega);
        let qdot = pure(omega) * q * 0.5;
        let v = -omega.cross(r);
        [
            qdot.w,
            qdot.x,
            qdot.y,
            qdot.z,
            omega_dot.x,
            omega_dot.y,
            omega_dot.z,
            v.x,
            v.y,
            match self.law {
                None => self.drag * omega.length_squared(),
                Some(_) => self.drag_torque(omega).dot(omega),
            },
        ]
    }
}

impl OdeSystem<10> for SphereInertial<'_> {
    fn memory(&self) -> Vec<f64> {
        self.tracker.memory()
    }
    fn restore_memory(&self, memory: &[f64]) {
        self.tracker.restore_memory(memory);
    }
    fn rhs(&self, _t: f64, y: &[f64; 10]) -> [f64; 10] {
        self.rhs_with(y, |q| self.tracker.contact(q))
    }
    fn rhs_aside(&self, _t: f64, y: &[f64; 10]) -> [f64; 10] {
        self.rhs_with(y, |q| self.tracker.peek(q))
    }
    fn quaternion_slot(&self) -> Option<usize> {
        Some(0)
    }
}

impl Observe<10> for SphereInertial<'_> {
    fn energy_balance(&self, y: &[f64; 10]) -> Option<f64> {
        let q = quat_at(y, 0);
        // An observer's look-up: leaves the integrator's warm start where it was.
        let sp = self.tracker.peek(q)?;
        let r = q.normalize() * sp.p;
        let omega = DVec3::new(y[4], y[5], y[6]);
        let v = -omega.cross(r);
        let centre = DVec3::new(y[7], y[8], -r.z);
        Some(
            0.5 * self.inertia * omega.length_squared() + 0.5 * self.mass * v.length_squared()
                - self.force.dot(centre)
                + y[9],
        )
    }
}

impl RollingModel<6> for SphereViscous<'_> {
    const KIND: ModelKind = ModelKind::SphereViscous;
    const COLUMNS: &'static str = "t,qw,qx,qy,qz,ux,uy,uz,wx,wy,wz,x,y,z";

    fn row(&self, t: f64, y: &[f64; 6], out: &mut Vec<f64>) {
        sphere_row(t, &self.observe(y), out);
    }

    fn health(&self, y: &[f64; 6]) -> ModelHealth {
        let o = self.observe(y);
        ModelHealth {
            quat_norm_error: Some(o.quat_norm_error),
            contact_normal_error: Some(o.contact_normal_error),
            energy: None,
        }
    }

    fn contact_force(&self, _y: &[f64; 6]) -> ContactForce {
        ContactForce {
            normal: -self.force.z,
            friction: [-self.force.x, -self.force.y],
        }
    }

    fn observation(&self, y: &[f64; 6]) -> Observation {
        sphere_observation(self.tracker.body, self.force, &self.observe(y), None)
    }

    fn section(&self, y: &[f64; 6]) -> f64 {
        y[0]
    }

    fn section_point(&self, y: &[f64; 6]) -> Option<DVec3> {
        Some(DVec3::new(y[1], y[2], y[3]).normalize())
    }
    fn state_at(pose: &Pose) -> Option<[f64; 6]> {
        match *pose {
            Pose::Sphere { q, position, .. } => {
                Some([q.w, q.x, q.y, q.z, position[0], position[1]])
            }
            Pose::Disk { .. } => None,
        }
    }

    fn pose(y: &[f64; 6]) -> Pose {
        Pose::Sphere {
            q: quat_at(y, 0),
            omega: DVec3::ZERO,
            position: [y[4], y[5]],
        }
    }

    fn checked_state(v: [f64; 6]) -> Result<[f64; 6], String> {
        unit_quaternion(v)
    }
}

impl RollingModel<10> for SphereInertial<'_> {
    const KIND: ModelKind = ModelKind::SphereInertial;
    const COLUMNS: &'static str = "t,qw,qx,qy,qz,ux,uy,uz,wx,wy,wz,x,y,z";

    fn row(&self, t: f64, y: &[f64; 10], out: &mut Vec<f64>) {
        sphere_row(t, &self.observe(y), out);
    }

    fn health(&self, y: &[f64; 10]) -> ModelHealth {
        let o = self.observe(y);
        ModelHealth {
            quat_norm_error: Some(o.quat_norm_error),
            contact_normal_error: Some(o.contact_normal_error),
            energy: self.energy_balance(y),
        }
    }

    fn contact_force(&self, y: &[f64; 10]) -> ContactForce {
        self.contact_force_at(y)
    }

    fn observation(&self, y: &[f64; 10]) -> Observation {
        let o = self.observe(y);
        sphere_observation(self.tracker.body, self.force, &o, self.energy_balance(y))
    }

    fn section(&self, y: &[f64; 10]) -> f64 {
        y[0]
    }

    fn section_point(&self, y: &[f64; 10]) -> Option<DVec3> {
        Some(DVec3::new(y[1], y[2], y[3]).normalize())
    }
    fn state_at(pose: &Pose) -> Option<[f64; 10]> {
        match *pose {
            Pose::Sphere { q, omega, position } => Some([
                q.w,
                q.x,
                q.y,
                q.z,
                omega.x,
                omega.y,
                omega.z,
                position[0],
                position[1],
                0.0,
            ]),
            Pose::Disk { .. } => None,
        }
    }

    fn pose(y: &[f64; 10]) -> Pose {
        Pose::Sphere {
            q: quat_at(y, 0),
            omega: DVec3::new(y[4], y[5], y[6]),
            position: [y[7], y[8]],
        }
    }

    fn checked_state(v: [f64; 10]) -> Result<[f64; 10], String> {
        unit_quaternion(v)
    }
}

/// A sphere's state whose orientation (its first four numbers) is of unit length to 1e-6,
/// renormalised; refused otherwise.
fn unit_quaternion<const N: usize>(mut v: [f64; N]) -> Result<[f64; N], String> {
    let norm = v[..4].iter().map(|x| x * x).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > 1e-6 {
        return Err(format!(
            "the orientation quaternion (the first 4 numbers) has length {norm}, not 1"
        ));
    }
    v[..4].iter_mut().for_each(|x| *x /= norm);
    Ok(v)
}

/// The sample row of a sphere: t, q, contact direction, ω, centre of mass.
fn sphere_row(t: f64, o: &SphereObservation, out: &mut Vec<f64>) {
    out.clear();
    out.extend([
        t,
        o.q.w,
        o.q.x,
        o.q.y,
        o.q.z,
        o.contact_dir.x,
        o.contact_dir.y,
        o.contact_dir.z,
        o.omega.x,
        o.omega.y,
        o.omega.z,
        o.centre.x,
        o.centre.y,
        o.centre.z,
    ]);
}

fn sphere_observation(
    s: &Sphere,
    weight: DVec3,
    o: &SphereObservation,
    energy: Option<f64>,
) -> Observation {
    let q = o.q.normalize();
    let in_body = o.contact_dir * s.radius(o.contact_dir);
    let on_ramp = o.centre + q * in_body;
    Observation {
        rotation: q,
        centre: o.centre,
        contact_on_ramp: DVec3::new(on_ramp.x, on_ramp.y, 0.0),
        contact_in_body: in_body,
        orientation: Some(q),
        angular_speed: o.omega.length(),
        ramp_torque: (q * in_body).cross(weight).length(),
        theta: None,
        theta_dot: None,
        health: ModelHealth {
            quat_norm_error: Some(o.quat_norm_error),
            contact_normal_error: Some(o.contact_normal_error),
            energy,
        },
    }
}
