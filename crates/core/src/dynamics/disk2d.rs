//! 2D rolling of a disk r(θ) on a ramp (SI §1A).
//!
//! Viscous model (SI eq. "viscous limit"), state [θ, x_c]:
//!   θ̇ = (F/γ) r (r sin α − r' cos α) / ((r² + r'²) κ),   ẋ_c = √(r² + r'²) θ̇,
//! with x_c the arc length rolled (the contact point's position on the ramp).
//!
//! Inertial model, state [θ, θ̇, x_c, W] (W = work done by drag). We derive it from the
//! Lagrangian rather than transcribe the paper's θ̈: rolling in 2D is holonomic, the body turns by
//! ψ̇ = −s(θ) θ̇ with s = √(r² + r'²) κ, the centre moves at speed |ψ̇| r, so
//!   T = ½ J(θ) θ̇²,  J = (I + m r²) s²,   V = −F sin α x_cm + F cos α h,
//!   dx_cm/dθ = κ r²,  h = r²/√(r² + r'²),  dh/dθ = κ r r',   drag force −γ s² θ̇,
//! and Lagrange's equation gives
//!   θ̈ = [F κ r (r sin α − r' cos α) − γ s² θ̇] / J − (m r r'/(I + m r²) + s'/s) θ̇².
//! The first term equals the paper's (SI eq. for θ̈: F r (r sin α − r' cos α)/(κ (r² + r'²)) over
//! I + m r²) exactly. The θ̇² coefficient is ½J'/J, which makes E = ½Jθ̇² + V + W constant along
//! solutions. `tests/physics/paper_equations.rs` evaluates the paper's bracket as printed and finds it
//! equal to ½J'/J (to 1e-9, the accuracy of its finite-difference κ'): the paper's 2D equation is
//! right; we keep the shorter Lagrangian form because it needs no κ'. Dimensionless: F = γ = ⟨r⟩ = 1, I = m/2 (m = m/m0).
//!
//! Drawing: ψ = 3π/2 + Δθ − θ with tan Δθ = r'/r (continuous with an unwrapped θ), the centre at
//! x_cm = x_c − r r'/√(r² + r'²) downhill and height h above the ramp.
//!
//! **A dented body rolls on its convex hull** ([`crate::geometry::hull`], issue 34): on the
//! curve where the curve is on the hull, by the equations above; a contact angle inside a
//! bridge's span means the body lies on that bridge, on both ends, at rest (θ is kept in the
//! middle of the span, x_c at the uphill end P_a). When the contact reaches a bridge end (the
//! switching function [`RollingModel::switching`] passes zero) the body either **tips** across
//! to the far end or **comes to rest** on the bridge ([`RollingModel::switch`]):
//! - viscous: it tips if the weight's torque about the far end turns it onward (the viscous
//!   rate at the far end has the direction of travel), instantly (θ jumps across the span, x_c
//!   by the bridge's length L); otherwise it rests;
//! - inertial: the far end strikes the ramp, an impact that keeps the angular momentum about
//!   the far end (the rimless wheel's law): ψ̇⁺ = ψ̇⁻ (I + m P_a·P_b)/(I + m |P_far|²), the
//!   kinetic energy lost added to W (so E + W stays constant). Repeated rocking across one bridge
//!   loses energy geometrically; once the speed after an impact is below [`REST_RATE`] and the
//!   weight's line falls between the two ends, the body rests.
//!
//! Just past a bridge end (a step's overshoot, within a quarter of the span) the equations are
//! those of the end itself, so an integrator step across the end sees a continuous right-hand
//! side until the switch is located.

use std::f64::consts::{PI, TAU};

use glam::{DQuat, DVec3};

use super::{
    ContactForce, DragLaw, ModelHealth, ModelKind, Observation, Observe, Pose, Ramp, RollingModel,
    Switched,
};
use crate::geometry::hull::Bridge;
use crate::geometry::{Disk, RadiusJet};

/// Below this |θ̇| after an impact, a body whose weight falls between a bridge's ends rests on
/// it: the rocking that is left would take infinitely many ever smaller impacts (a Zeno
/// sequence) whose total time is finite and whose energy is below 1e-18 of F⟨r⟩.
pub const REST_RATE: f64 = 1e-9;

/// Where a contact angle stands on the hull of a disk.
#[derive(Debug, Clone, Copy, PartialEq)]
enum OnHull {
    /// On the curve: θ itself.
    Curve(f64),
    /// Just past a bridge end (a step's overshoot): the end's angle, unwrapped near θ.
    PastEnd(f64),
    /// Resting on a bridge: its uphill end θ_a, unwrapped near θ (the body lies as there).
    Resting(f64),
}

impl OnHull {
    fn of(disk: &Disk, theta: f64) -> Self {
        match disk.hull().bridge_at(theta) {
            None => OnHull::Curve(theta),
            Some(b) => {
                let span = b.theta_b - b.theta_a;
                let t = (theta - b.theta_a).rem_euclid(TAU);
                let a = theta - t;
                if t < 0.25 * span {
                    OnHull::PastEnd(a)
                } else if t > 0.75 * span {
                    OnHull::PastEnd(a + span)
                } else {
                    OnHull::Resting(a)
                }
            }
        }
    }

    /// The contact angle whose geometry the body has.
    fn geometry(self) -> f64 {
        match self {
            OnHull::Curve(t) | OnHull::PastEnd(t) | OnHull::Resting(t) => t,
        }
    }
}

/// The switching function of a dented disk: the angle from θ to the nearest bridge end, negative
/// inside a bridge's span; `None` for a convex disk.
fn hull_switching(disk: &Disk, theta: f64) -> Option<f64> {
    let bridges = disk.hull().bridges();
    if bridges.is_empty() {
        return None;
    }
    Some(match disk.hull().bridge_at(theta) {
        Some(b) => {
            let t = (theta - b.theta_a).rem_euclid(TAU);
            -t.min(b.theta_b - b.theta_a - t)
        }
        None => bridges
            .iter()
            .map(|b| {
                (b.theta_a - theta)
                    .rem_euclid(TAU)
                    .min((theta - b.theta_b).rem_euclid(TAU))
            })
            .fold(f64::INFINITY, f64::min),
    })
}

/// Which end of a bridge θ is at (to 1e-6 rad), with the end's angle unwrapped near θ: `true`
/// for the uphill end θ_a.
fn bridge_end(disk: &Disk, theta: f64) -> Option<(Bridge, bool, f64)> {
    let near = |to: f64| (theta - to + PI).rem_euclid(TAU) - PI;
    disk.hull().bridges().iter().find_map(|b| {
        let (da, db) = (near(b.theta_a), near(b.theta_b));
        if da.abs() < 1e-6 {
            Some((*b, true, theta - da))
        } else if db.abs() < 1e-6 {
            Some((*b, false, theta - db))
        } else {
            None
        }
    })
}

/// A start θ0 inside a flat's span, placed as the body lies (see [`RollingModel::placed`]): on
/// the flat (θ at the span's middle, x_c at P_a) if `rate(θ_a) ≥ 0 ≥ rate(θ_b)` (the weight's
/// line between the ends), else at the end it leans towards, with x_c there; `moving` (an
/// inertial start's θ̇ ≠ 0) puts it at the end it moves towards. Returns (θ, Δx_c).
fn placed_on_flat(
    disk: &Disk,
    theta: f64,
    moving: f64,
    rate: impl Fn(f64) -> f64,
) -> Option<(f64, f64)> {
    let b = disk.hull().bridge_at(theta)?;
    let span = b.theta_b - b.theta_a;
    let a = theta - (theta - b.theta_a).rem_euclid(TAU);
    Some(if moving > 0.0 || (moving == 0.0 && rate(a + span) > 0.0) {
        (a + span, b.length)
    } else if moving < 0.0 || rate(a) < 0.0 {
        (a, 0.0)
    } else {
        (a + 0.5 * span, 0.0)
    })
}

/// The body point at contact angle θ, body frame.
fn body_point(disk: &Disk, theta: f64) -> [f64; 2] {
    let r = disk.jet(theta).r;
    [r * theta.cos(), r * theta.sin()]
}
use crate::integrate::OdeSystem;

/// Viscous 2D model; state [θ, x_c].
pub struct DiskViscous<'a> {
    disk: &'a Disk,
    sin_a: f64,
    cos_a: f64,
    drag: f64,
    /// The drag law when it is not linear (the linear equations run untouched otherwise).
    law: Option<DragLaw>,
}

impl<'a> DiskViscous<'a> {
    /// The model for `disk` on `ramp` (mass ignored).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{DiskViscous, Ramp};
    /// use rollphase_core::geometry::Disk;
    /// let disk = Disk::perfect();
    /// let model = DiskViscous::new(&disk, &Ramp::new(0.3, 0.0)?);
    /// assert!((model.theta_dot(1.0) - 0.3f64.sin()).abs() < 1e-15);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn new(disk: &'a Disk, ramp: &Ramp) -> Self {
        Self {
            disk,
            sin_a: ramp.alpha_rad.sin(),
            cos_a: ramp.alpha_rad.cos(),
            drag: if ramp.drag > 0.0 { ramp.drag } else { 1.0 },
            law: ramp.drag_law.if_nonlinear(),
        }
    }

    /// The viscous rate with the drag law: the linear rate θ̇₁ turns the body at s θ̇₁, which
    /// is the torque over γ the weight balances, so the body turns at g⁻¹(s |θ̇₁|) instead
    /// ([`crate::dynamics::drag`]).
    fn with_law(&self, j: &RadiusJet, linear: f64) -> f64 {
        match self.law {
            None => linear,
            Some(law) => {
                let s = j.turn_rate();
                law.viscous_rate(s * linear) / s
            }
        }
    }

    /// θ̇(θ) = r (r sin α − r' cos α) / ((r² + r'²) κ) / γ (linear drag; with a drag law the
    /// body turns at g⁻¹ of the linear rate's turning speed).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{DiskViscous, Ramp};
    /// use rollphase_core::geometry::Body;
    /// // Below α* the flow has a zero (a rest point); above it θ̇ never vanishes.
    /// let Body::Disk(disk) = Body::random_disk(2, 0.3, 5)? else { unreachable!() };
    /// let alpha_star = Body::Disk(disk.clone()).alpha_star();
    /// let min_rate = |alpha: f64| -> Result<f64, rollphase_core::dynamics::ModelError> {
    ///     let model = DiskViscous::new(&disk, &Ramp::new(alpha, 0.0)?);
    ///     Ok((0..2000).map(|i| model.theta_dot(i as f64 * 0.00314159)).fold(f64::INFINITY, f64::min))
    /// };
    /// assert!(min_rate(0.5 * alpha_star)? < 0.0 && min_rate(1.5 * alpha_star)? > 0.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn theta_dot(&self, theta: f64) -> f64 {
        match OnHull::of(self.disk, theta) {
            OnHull::Resting(_) => 0.0,
            on => {
                let j = self.disk.jet(on.geometry());
                self.with_law(
                    &j,
                    theta_dot_viscous(&j, self.sin_a, self.cos_a) / self.drag,
                )
            }
        }
    }
}

pub(crate) fn theta_dot_viscous(j: &RadiusJet, sin_a: f64, cos_a: f64) -> f64 {
    // (r² + r'²) κ = convexity / √(r² + r'²)
    j.r * (j.r * sin_a - j.r1 * cos_a) * j.arc_rate() / j.convexity()
}

impl OdeSystem<2> for DiskViscous<'_> {
    fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
        let on = OnHull::of(self.disk, y[0]);
        if let OnHull::Resting(_) = on {
            return [0.0, 0.0];
        }
        let j = self.disk.jet(on.geometry());
        let td = self.with_law(
            &j,
            theta_dot_viscous(&j, self.sin_a, self.cos_a) / self.drag,
        );
        [td, j.arc_rate() * td]
    }
}

impl Observe<2> for DiskViscous<'_> {
    fn energy_balance(&self, _y: &[f64; 2]) -> Option<f64> {
        None
    }
}

/// Inertial 2D model; state [θ, θ̇, x_c, W].
pub struct DiskInertial<'a> {
    disk: &'a Disk,
    sin_a: f64,
    cos_a: f64,
    mass: f64,
    drag: f64,
    /// The drag law when it is not linear.
    law: Option<DragLaw>,
}

impl<'a> DiskInertial<'a> {
    /// The model for `disk` on `ramp`; needs m/m0 > 0.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{DiskInertial, Ramp};
    /// use rollphase_core::geometry::Disk;
    /// let disk = Disk::perfect();
    /// let model = DiskInertial::new(&disk, &Ramp::new(0.3, 2.0)?);
    /// // At the viscous rate sin α the drag balances gravity: no acceleration.
    /// assert!(model.theta_ddot(0.5, 0.3f64.sin()).abs() < 1e-14);
    /// assert!(model.theta_ddot(0.5, 0.0) > 0.0);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn new(disk: &'a Disk, ramp: &Ramp) -> Self {
        Self {
            disk,
            sin_a: ramp.alpha_rad.sin(),
            cos_a: ramp.alpha_rad.cos(),
            mass: ramp.mass_ratio,
            drag: ramp.drag,
            law: ramp.drag_law.if_nonlinear(),
        }
    }

    /// The drag's generalised force over θ̇, γ s² (linear), or γ s² g(s|θ̇|)/(s|θ̇|) with a drag
    /// law: the torque γ g(|ψ̇|) against ψ̇ = −s θ̇, times dψ/dθ = −s.
    fn drag_per_rate(&self, s: f64, td: f64) -> f64 {
        match self.law {
            None => self.drag * s * s,
            Some(law) => self.drag * s * s * law.torque_per_speed(s * td.abs()),
        }
    }

    /// θ̈ from the Lagrangian form above.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{DiskInertial, Ramp};
    /// use rollphase_core::geometry::Disk;
    /// let disk = Disk::perfect();
    /// let model = DiskInertial::new(&disk, &Ramp::new(0.3, 2.0)?);
    /// // Faster than terminal: it slows down.
    /// assert!(model.theta_ddot(0.0, 1.0) < 0.0);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn theta_ddot(&self, theta: f64, theta_dot: f64) -> f64 {
        let j = self.disk.jet(theta);
        self.theta_ddot_jet(&j, theta_dot)
    }

    fn theta_ddot_jet(&self, j: &RadiusJet, td: f64) -> f64 {
        let s = j.turn_rate();
        let inertia = self.mass * (0.5 + j.r * j.r); // I + m r², I = m/2
        let drive = j.curvature() * j.r * (j.r * self.sin_a - j.r1 * self.cos_a);
        let accel = (drive - self.drag_per_rate(s, td) * td) / (inertia * s * s);
        accel - (self.mass * j.r * j.r1 / inertia + j.turn_rate_d1() / s) * td * td
    }

    /// The ramp's force on the body at contact angle θ and rate θ̇: f = m a_cm − F, with the
    /// centre's acceleration from the exact θ-derivatives of its position. The centre moves by
    /// dx_cm/dθ = g = κ r² = s h and dh/dθ = k = −s c (c the centre's downhill offset), so
    ///   a = (g' θ̇² + g θ̈, k' θ̇² + k θ̈),  g' = s' h − s² c,  k' = −s' c − s (g − √(r² + r'²)).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{DiskInertial, Ramp};
    /// use rollphase_core::geometry::Disk;
    /// // A uniform disk rolling freely (no drag) accelerates at (2/3) g sin α, so the ramp
    /// // holds it back with (1/3) F sin α and presses with F cos α.
    /// let disk = Disk::perfect();
    /// let model = DiskInertial::new(&disk, &Ramp::with_drag(0.3, 2.0, 0.0)?);
    /// let f = model.contact_force_at(0.4, 0.7);
    /// assert!((f.normal - 0.3f64.cos()).abs() < 1e-14);
    /// assert!((f.friction[0] + 0.3f64.sin() / 3.0).abs() < 1e-14);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn contact_force_at(&self, theta: f64, theta_dot: f64) -> ContactForce {
        let theta = match OnHull::of(self.disk, theta) {
            // At rest on two points: the ramp holds the whole weight.
            OnHull::Resting(_) => {
                return ContactForce {
                    normal: self.cos_a,
                    friction: [-self.sin_a, 0.0],
                };
            }
            on => on.geometry(),
        };
        let j = self.disk.jet(theta);
        let accel = self.theta_ddot_jet(&j, theta_dot);
        let (s, s1) = (j.turn_rate(), j.turn_rate_d1());
        let (h, c, rho) = (j.height(), j.centre_offset(), j.arc_rate());
        let g = s * h;
        let k = -s * c;
        let g1 = s1 * h - s * s * c;
        let k1 = -s1 * c - s * (g - rho);
        let v2 = theta_dot * theta_dot;
        let a_x = g1 * v2 + g * accel;
        let a_y = k1 * v2 + k * accel;
        ContactForce {
            normal: self.mass * a_y + self.cos_a,
            friction: [self.mass * a_x - self.sin_a, 0.0],
        }
    }

    /// Moment J(θ) = (I + m r²) s² of the reduced one-degree-of-freedom system.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{DiskInertial, Ramp};
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// // The perfect disk's moment is the same at every contact angle; a bumpy one's is not.
    /// let round = Disk::perfect();
    /// let m = DiskInertial::new(&round, &Ramp::new(0.3, 2.0)?);
    /// assert!((m.reduced_inertia(0.1) - m.reduced_inertia(2.0)).abs() < 1e-14);
    /// let bumpy = Disk::new(vec![DiskMode { l: 2, a: 0.5, phase: 0.0 }]);
    /// let b = DiskInertial::new(&bumpy, &Ramp::new(0.3, 2.0)?);
    /// assert!((b.reduced_inertia(0.1) - b.reduced_inertia(1.0)).abs() > 1e-3);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn reduced_inertia(&self, theta: f64) -> f64 {
        let j = self.disk.jet(theta);
        let s = j.turn_rate();
        self.mass * (0.5 + j.r * j.r) * s * s
    }

    /// Potential V = −F sin α x_cm + F cos α h for contact angle θ and rolled arc x_c.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{DiskInertial, Ramp};
    /// use rollphase_core::geometry::Disk;
    /// let disk = Disk::perfect();
    /// let model = DiskInertial::new(&disk, &Ramp::new(0.3, 2.0)?);
    /// // The unit disk's centre stays at height 1: V = −sin α x + cos α.
    /// let v = model.potential(0.7, 5.0);
    /// assert!((v - (-0.3f64.sin() * 5.0 + 0.3f64.cos())).abs() < 1e-14);
    /// # Ok::<(), rollphase_core::dynamics::ModelError>(())
    /// ```
    pub fn potential(&self, theta: f64, x_c: f64) -> f64 {
        let j = self.disk.jet(theta);
        -self.sin_a * (x_c + j.centre_offset()) + self.cos_a * j.height()
    }
}

impl OdeSystem<4> for DiskInertial<'_> {
    fn rhs(&self, _t: f64, y: &[f64; 4]) -> [f64; 4] {
        let on = OnHull::of(self.disk, y[0]);
        if let OnHull::Resting(_) = on {
            return [0.0; 4];
        }
        let j = self.disk.jet(on.geometry());
        let td = y[1];
        let s = j.turn_rate();
        [
            td,
            self.theta_ddot_jet(&j, td),
            j.arc_rate() * td,
            self.drag_per_rate(s, td) * td * td,
        ]
    }
}

impl Observe<4> for DiskInertial<'_> {
    fn energy_balance(&self, y: &[f64; 4]) -> Option<f64> {
        let theta = OnHull::of(self.disk, y[0]).geometry();
        let kinetic = 0.5 * self.reduced_inertia(theta) * y[1] * y[1];
        Some(kinetic + self.potential(theta, y[2]) + y[3])
    }
}

/// What a 2D state looks like in the lab: rotation angle and centre of mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiskPose {
    /// Body-to-lab rotation ψ (radians, continuous when θ is unwrapped).
    pub psi: f64,
    /// Centre of mass downhill along the ramp.
    pub x: f64,
    /// Height of the centre of mass above the ramp.
    pub y: f64,
}

/// ψ and the centre of mass for contact angle θ and rolled arc x_c.
///
/// # Example
/// ```
/// use rollphase_core::dynamics::disk2d::pose;
/// use rollphase_core::geometry::Disk;
/// let p = pose(&Disk::perfect(), 0.4, 2.0);
/// assert_eq!((p.x, p.y), (2.0, 1.0));
/// assert!((p.psi - (1.5 * std::f64::consts::PI - 0.4)).abs() < 1e-15);
/// ```
pub fn pose(disk: &Disk, theta: f64, x_c: f64) -> DiskPose {
    let theta = OnHull::of(disk, theta).geometry();
    let j = disk.jet(theta);
    DiskPose {
        psi: 1.5 * PI + j.normal_offset() - theta,
        x: x_c + j.centre_offset(),
        y: j.height(),
    }
}

impl RollingModel<2> for DiskViscous<'_> {
    const KIND: ModelKind = ModelKind::DiskViscous;
    const COLUMNS: &'static str = "t,theta,theta_dot,psi,x,y";

    fn row(&self, t: f64, y: &[f64; 2], out: &mut Vec<f64>) {
        let p = pose(self.disk, y[0], y[1]);
        out.clear();
        out.extend([t, y[0], self.theta_dot(y[0]), p.psi, p.x, p.y]);
    }

    fn health(&self, _y: &[f64; 2]) -> ModelHealth {
        ModelHealth::default()
    }

    fn contact_force(&self, _y: &[f64; 2]) -> ContactForce {
        ContactForce {
            normal: self.cos_a,
            friction: [-self.sin_a, 0.0],
        }
    }

    fn observation(&self, y: &[f64; 2]) -> Observation {
        disk_observation(
            self.disk,
            (self.sin_a, self.cos_a),
            y[0],
            self.theta_dot(y[0]),
            y[1],
            None,
        )
    }

    fn section(&self, y: &[f64; 2]) -> f64 {
        (y[0] / 2.0).sin()
    }

    fn section_point(&self, _y: &[f64; 2]) -> Option<DVec3> {
        None
    }

    fn switching(&self, y: &[f64; 2]) -> Option<f64> {
        hull_switching(self.disk, y[0])
    }

    fn placed(&self, y: [f64; 2]) -> [f64; 2] {
        let rate = |t: f64| theta_dot_viscous(&self.disk.jet(t), self.sin_a, self.cos_a);
        match placed_on_flat(self.disk, y[0], 0.0, rate) {
            Some((theta, dx)) => [theta, y[1] + dx],
            None => y,
        }
    }

    fn switch(&self, y: &[f64; 2]) -> Option<([f64; 2], Switched)> {
        let (b, uphill_end, theta) = bridge_end(self.disk, y[0])?;
        let span = b.theta_b - b.theta_a;
        let rate = |t: f64| theta_dot_viscous(&self.disk.jet(t), self.sin_a, self.cos_a);
        let rested = Switched::Rest { energy_lost: 0.0 };
        let tipped = Switched::Tip { energy_lost: 0.0 };
        Some(if uphill_end {
            // Rolling forward onto the bridge: on to P_b if the weight turns it onward there.
            if rate(theta + span) > 0.0 {
                ([theta + span, y[1] + b.length], tipped)
            } else {
                ([theta + 0.5 * span, y[1]], rested)
            }
        } else if rate(theta - span) < 0.0 {
            ([theta - span, y[1] - b.length], tipped)
        } else {
            ([theta - 0.5 * span, y[1] - b.length], rested)
        })
    }
    fn state_at(pose: &Pose) -> Option<[f64; 2]> {
        match *pose {
            Pose::Disk { theta, x_c, .. } => Some([theta, x_c]),
            Pose::Sphere { .. } => None,
        }
    }

    fn pose(y: &[f64; 2]) -> Pose {
        Pose::Disk {
            theta: y[0],
            theta_dot: 0.0,
            x_c: y[1],
        }
    }
}

impl RollingModel<4> for DiskInertial<'_> {
    const KIND: ModelKind = ModelKind::DiskInertial;
    const COLUMNS: &'static str = "t,theta,theta_dot,psi,x,y";

    fn row(&self, t: f64, y: &[f64; 4], out: &mut Vec<f64>) {
        let p = pose(self.disk, y[0], y[2]);
        out.clear();
        out.extend([t, y[0], y[1], p.psi, p.x, p.y]);
    }

    fn health(&self, y: &[f64; 4]) -> ModelHealth {
        ModelHealth {
            energy: self.energy_balance(y),
            ..ModelHealth::default()
        }
    }

    fn contact_force(&self, y: &[f64; 4]) -> ContactForce {
        self.contact_force_at(y[0], y[1])
    }

    fn observation(&self, y: &[f64; 4]) -> Observation {
        disk_observation(
            self.disk,
            (self.sin_a, self.cos_a),
            y[0],
            y[1],
            y[2],
            self.energy_balance(y),
        )
    }

    fn section(&self, y: &[f64; 4]) -> f64 {
        (y[0] / 2.0).sin()
    }

    fn section_point(&self, _y: &[f64; 4]) -> Option<DVec3> {
        None
    }

    fn switching(&self, y: &[f64; 4]) -> Option<f64> {
        hull_switching(self.disk, y[0])
    }

    fn placed(&self, y: [f64; 4]) -> [f64; 4] {
        let rate = |t: f64| theta_dot_viscous(&self.disk.jet(t), self.sin_a, self.cos_a);
        match placed_on_flat(self.disk, y[0], y[1], rate) {
            // On the flat: at rest, whatever rate was given.
            Some((theta, dx)) if self.disk.hull().bridge_at(theta).is_some() => {
                [theta, 0.0, y[2] + dx, y[3]]
            }
            Some((theta, dx)) => [theta, y[1], y[2] + dx, y[3]],
            None => y,
        }
    }

    fn switch(&self, y: &[f64; 4]) -> Option<([f64; 4], Switched)> {
        let (b, uphill_end, theta) = bridge_end(self.disk, y[0])?;
        let span = b.theta_b - b.theta_a;
        let (from, to) = if uphill_end {
            (theta, theta + span)
        } else {
            (theta, theta - span)
        };
        let (p_from, p_to) = (body_point(self.disk, from), body_point(self.disk, to));
        let inertia = 0.5 * self.mass;
        let moment = |p: [f64; 2]| inertia + self.mass * (p[0] * p[0] + p[1] * p[1]);
        let dot = p_from[0] * p_to[0] + p_from[1] * p_to[1];
        // ψ̇ = −s θ̇ on the curve; the impact keeps the angular momentum about the far end.
        let psi_before = -self.disk.jet(from).turn_rate() * y[1];
        let psi_after = psi_before * (inertia + self.mass * dot) / moment(p_to);
        let theta_dot_after = -psi_after / self.disk.jet(to).turn_rate();
        let before = 0.5 * moment(p_from) * psi_before * psi_before;
        let after = 0.5 * moment(p_to) * psi_after * psi_after;
        let moving_in = if uphill_end { y[1] > 0.0 } else { y[1] < 0.0 };
        let onward = theta_dot_viscous(&self.disk.jet(to), self.sin_a, self.cos_a);
        let weight_onward = if uphill_end {
            onward > 0.0
        } else {
            onward < 0.0
        };
        let x_at_a = if uphill_end { y[2] } else { y[2] - b.length };
        if !moving_in || (theta_dot_after.abs() < REST_RATE && !weight_onward) {
            // The last rocking, or a start on the end itself moving out: at rest on both ends.
            let mid = if uphill_end {
                theta + 0.5 * span
            } else {
                theta - 0.5 * span
            };
            return Some((
                [mid, 0.0, x_at_a, y[3] + before],
                Switched::Rest {
                    energy_lost: before,
                },
            ));
        }
        let x = if uphill_end {
            y[2] + b.length
        } else {
            y[2] - b.length
        };
        Some((
            [to, theta_dot_after, x, y[3] + (before - after)],
            Switched::Tip {
                energy_lost: before - after,
            },
        ))
    }
    fn state_at(pose: &Pose) -> Option<[f64; 4]> {
        match *pose {
            Pose::Disk {
                theta,
                theta_dot,
                x_c,
            } => Some([theta, theta_dot, x_c, 0.0]),
            Pose::Sphere { .. } => None,
        }
    }

    fn pose(y: &[f64; 4]) -> Pose {
        Pose::Disk {
            theta: y[0],
            theta_dot: y[1],
            x_c: y[2],
        }
    }
}

/// 2D: the cross-section lies in the ramp's (x, z) plane; ψ turns it about the y axis (the
/// body point at angle θ sits at r(θ)(cos θ, 0, sin θ) in the body frame, as in
/// [`crate::geometry::mesh::disk_mesh`]). Contact points are on the mid-plane y = 0; where a
/// cylinder of some length is drawn is the view's business.
fn disk_observation(
    d: &Disk,
    (sin_a, cos_a): (f64, f64),
    theta: f64,
    theta_dot: f64,
    x_c: f64,
    energy: Option<f64>,
) -> Observation {
    let p = pose(d, theta, x_c);
    // The weight (sin α, −cos α) about the contact (x_c, 0); none on a flat of the hull, where
    // the body rests on both of its ends.
    let ramp_torque = if d.hull().bridge_at(theta).is_some() {
        0.0
    } else {
        ((p.x - x_c) * cos_a + p.y * sin_a).abs()
    };
    let theta = OnHull::of(d, theta).geometry();
    let r = d.jet(theta).r;
    // Lab 2D (x downhill, y up) maps to ramp 3D (x, z); a counter-clockwise turn ψ in that plane
    // is a rotation by −ψ about +y.
    Observation {
        rotation: DQuat::from_rotation_y(-p.psi),
        centre: DVec3::new(p.x, 0.0, p.y),
        contact_on_ramp: DVec3::new(x_c, 0.0, 0.0),
        contact_in_body: DVec3::new(r * theta.cos(), 0.0, r * theta.sin()),
        orientation: None,
        angular_speed: theta_dot.abs(),
        ramp_torque,
        theta: Some(theta),
        theta_dot: Some(theta_dot),
        health: ModelHealth {
            energy,
            ..ModelHealth::default()
        },
    }
}
