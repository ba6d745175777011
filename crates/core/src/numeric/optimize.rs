//! One-dimensional maximisation: golden-section search on a bracket.
//!
//! Why our own: ten lines, no allocation, and the callers (α*'s refinement, the lag-time fit)
//! need exactly a bracketed unimodal maximum (and a run's contact-force extremes, on a step's
//! dense output, which is why f may keep state).

/// Golden-section search for the maximiser of a unimodal f on [a, b], to an interval of `tol`.
///
/// # Example
/// ```
/// use rollphase_core::numeric::optimize::golden_max;
/// let x = golden_max(&|x: f64| x.sin(), 0.0, 3.0, 1e-9);
/// // To about √ε, not to the 1e-9 asked: at a maximum, f is flat to ε over that width.
/// assert!((x - std::f64::consts::FRAC_PI_2).abs() < 1e-7);
/// ```
pub fn golden_max(mut f: impl FnMut(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> f64 {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    while (b - a).abs() > tol {
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}
