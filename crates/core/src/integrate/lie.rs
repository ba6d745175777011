//! Commutator-free Lie-group Runge–Kutta of order 4 (CF4) for states that carry a unit
//! quaternion: q advances by exponentials q ← exp(h Ω / 2) q of lab-frame angular velocities, so
//! |q| = 1 holds to round-off with no projection; all other components take the classical RK4
//! step, to which CF4 reduces on a vector space.
//!
//! Scheme (Celledoni, Marthinsen & Owren, *Future Gener. Comput. Syst.* 19 (2003) 341), with
//! Fᵢ the stage derivatives and exp(hF)·y the group action:
//! ```text
//! Y2 = exp(h F1 / 2)·y0        Y3 = exp(h F2 / 2)·y0        Y4 = exp(h F3 − h F1 / 2)·Y2
//! y1 = exp(h(−F1/12 + F2/6 + F3/6 + F4/4)) · exp(h(F1/4 + F2/6 + F3/6 − F4/12)) · y0
//! ```
//! (the right factor acts first). With q̇ = ½ ω q the algebra acts on the left, and this is the
//! order of the two final exponentials that makes the step fourth order; the other order leaves
//! the commutator ½[X, Y] = O(h³) per step, i.e. a second-order method. `tests/physics/integrator_order.rs`
//! measures the order on the 3D model, so a regression here fails CI.
//! The angular velocity of a stage is read back from the system's own q̇ as ω = 2 q̇ q̄ / |q|², so
//! any [`OdeSystem`] with a [`OdeSystem::quaternion_slot`] can use this step unchanged.

use glam::{DQuat, DVec3};

use super::{OdeSystem, classical::rk4_step};

/// Reads q (w, x, y, z) from a state slot.
///
/// # Example
/// ```
/// use rollphase_core::integrate::lie::{quat_at, set_quat};
/// use rollphase_core::glam::DQuat;
/// let mut y = [0.0; 6];
/// let q = DQuat::from_rotation_z(0.5);
/// set_quat(&mut y, 2, q);
/// assert_eq!(quat_at(&y, 2), q);
/// assert_eq!(y[2], q.w); // stored w first
/// ```
pub fn quat_at(y: &[f64], slot: usize) -> DQuat {
    DQuat::from_xyzw(y[slot + 1], y[slot + 2], y[slot + 3], y[slot])
}

/// Writes q (w, x, y, z) into a state slot.
///
/// # Example
/// ```
/// use rollphase_core::integrate::lie::set_quat;
/// use rollphase_core::glam::DQuat;
/// let mut y = [9.0; 4];
/// set_quat(&mut y, 0, DQuat::IDENTITY);
/// assert_eq!(y, [1.0, 0.0, 0.0, 0.0]);
/// ```
pub fn set_quat(y: &mut [f64], slot: usize, q: DQuat) {
    y[slot] = q.w;
    y[slot + 1] = q.x;
    y[slot + 2] = q.y;
    y[slot + 3] = q.z;
}

/// Lab-frame angular velocity ω from q̇ = ½ ω q: ω = 2 (q̇ q̄) / |q|².
fn angular_velocity(y: &[f64], f: &[f64], slot: usize) -> DVec3 {
    let q = quat_at(y, slot);
    let qdot = quat_at(f, slot);
    let w = qdot * q.conjugate();
    2.0 * DVec3::new(w.x, w.y, w.z) / q.length_squared()
}

/// One CF4 step (or plain RK4 when the system has no quaternion).
pub(crate) fn cf4_step<S: OdeSystem<N>, const N: usize>(
    system: &S,
    t: f64,
    y0: &[f64; N],
    f1: &[f64; N],
    h: f64,
) -> [f64; N] {
    let Some(slot) = system.quaternion_slot() else {
        return rk4_step(system, t, y0, f1, h);
    };
    let act = |y: &[f64; N], weights: &[(f64, &[f64; N], &[f64; N])]| -> [f64; N] {
        // Vector part: y + Σ w h f. Quaternion part: exp(Σ w h ω) q.
        let mut out: [f64; N] = std::array::from_fn(|i| {
            y[i] + weights.iter().map(|(w, _, f)| w * h * f[i]).sum::<f64>()
        });
        let rot: DVec3 = weights
            .iter()
            .map(|(w, ys, f)| *w * h * angular_velocity(*ys, *f, slot))
            .sum();
        let q = (DQuat::from_scaled_axis(rot) * quat_at(y, slot)).normalize();
        set_quat(&mut out, slot, q);
        out
    };
    let y2 = act(y0, &[(0.5, y0, f1)]);
    let f2 = system.rhs(t + 0.5 * h, &y2);
    let y3 = act(y0, &[(0.5, &y2, &f2)]);
    let f3 = system.rhs(t + 0.5 * h, &y3);
    let y4 = act(&y2, &[(1.0, &y3, &f3), (-0.5, y0, f1)]);
    let f4 = system.rhs(t + h, &y4);
    let inner = act(
        y0,
        &[
            (0.25, y0, f1),
            (1.0 / 6.0, &y2, &f2),
            (1.0 / 6.0, &y3, &f3),
            (-1.0 / 12.0, &y4, &f4),
        ],
    );
    // The outer exponential acts on the inner result: vector parts add up to the RK4 weights.
    act(
        &inner,
        &[
            (-1.0 / 12.0, y0, f1),
            (1.0 / 6.0, &y2, &f2),
            (1.0 / 6.0, &y3, &f3),
            (0.25, &y4, &f4),
        ],
    )
}
