//! Power-law drag: torque −γ |ω|^(n−1) ω, so g(s) = sⁿ (n = 1 is the paper's linear drag).
//!
//! The Materials and Methods say the rubber's effective viscous resistance "can depend on the
//! rolling speed"; a power law is the one-parameter family that keeps the model's scaling
//! (no new time scale). Exact consequences, checked in `tests/physics/drag_laws.rs`: a perfect
//! disk or sphere in the viscous limit rolls at ω = (sin α/γ)^(1/n); near α* a 2D body's
//! period diverges as T ∝ (α − α*)^(1/2 − 1/n), because the viscous rate near the bottleneck is
//! the linear one to the power 1/n.
//!
//! Range 0.25 ≤ n ≤ 4: below, the viscous rate (τ/γ)^(1/n) spans more than 4 decades for
//! torques between 0.1 and 1 and the inertial drag's slope n sⁿ⁻¹ diverges at rest faster than
//! an adaptive step can follow; above, the mirror image (a drag that vanishes as s⁴).

use super::DragParameter;

/// The exponent n, registered as `drag_exponent`.
pub const EXPONENT: DragParameter = DragParameter {
    key: "drag_exponent",
    flag: "drag-exponent",
    help: "Drag law exponent n: the drag torque is −γ |ω|^(n−1) ω (1 is the paper's linear \
           drag; 0.25 ≤ n ≤ 4)",
    default: 1.0,
    min: 0.25,
    max: 4.0,
    map: |n, s| s.powf(n),
    inverse: |n, t| t.powf(1.0 / n),
    slope: |n, s| n * s.powf(n - 1.0),
};

#[cfg(test)]
mod tests {
    use super::super::DragLaw;

    #[test]
    fn the_exponent_is_a_power() {
        let square = DragLaw::LINEAR.with("drag_exponent", 2.0).unwrap();
        assert_eq!(square.torque(3.0), 9.0);
        assert_eq!(square.slope(3.0), 6.0);
        assert_eq!(square.viscous_rate(-0.25), -0.5);
        assert_eq!(square.torque_per_speed(0.5), 0.5);
        let root = DragLaw::LINEAR.with("drag_exponent", 0.5).unwrap();
        assert!((root.speed_for(0.3) - 0.09).abs() < 1e-16);
        assert!(DragLaw::LINEAR.with("drag_exponent", 0.2).is_err());
        assert!(DragLaw::LINEAR.with("drag_exponent", 4.5).is_err());
    }
}
