//! The classical fourth-order Runge–Kutta step, on its own: the fixed-step stepper
//! ([`super::rk4`]) takes it for RK4, and the Lie-group CF4 step ([`super::lie`]) for the
//! components that are not the quaternion (a file of its own, so that neither of those two
//! imports the other back).

use super::OdeSystem;

/// One classical RK4 step from (t, y) with y' = f already known at the start.
pub(crate) fn rk4_step<S: OdeSystem<N>, const N: usize>(
    system: &S,
    t: f64,
    y: &[f64; N],
    k1: &[f64; N],
    h: f64,
) -> [f64; N] {
    let y2: [f64; N] = std::array::from_fn(|i| y[i] + 0.5 * h * k1[i]);
    let k2 = system.rhs(t + 0.5 * h, &y2);
    let y3: [f64; N] = std::array::from_fn(|i| y[i] + 0.5 * h * k2[i]);
    let k3 = system.rhs(t + 0.5 * h, &y3);
    let y4: [f64; N] = std::array::from_fn(|i| y[i] + h * k3[i]);
    let k4 = system.rhs(t + h, &y4);
    std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}
