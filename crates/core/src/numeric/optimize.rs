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
/// // A tolerance finer than the doubles near t = 25 can hold still ends (it once looped).
/// let t = golden_max(|t: f64| -(t - 25.0000001).powi(2), 25.0, 25.000001, 1e-18);
/// assert!((t - 25.0000001).abs() < 1e-12);
/// ```
pub fn golden_max(mut f: impl FnMut(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> f64 {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    // An interval cannot shrink below the spacing of the doubles at its ends: a tolerance under
    // it (a step of 1e-6 at t = 25 asked to 1e-9 of its length) would loop for ever, so it is
    // floored there, and the iterations are capped too (each keeps 0.618 of the interval:
    // 200 take any interval below any tolerance a double can hold, or the input was NaN).
    let tol = tol.max(4.0 * f64::EPSILON * a.abs().max(b.abs()));
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    let mut iterations = 0;
    while (b - a).abs() > tol && iterations < 200 {
        iterations += 1;
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
