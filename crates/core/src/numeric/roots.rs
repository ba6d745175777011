//! Root finding on a bracket: Brent's method (inverse quadratic interpolation, secant and
//! bisection), as used by event location and the disk's drive-angle search.
//!
//! Why our own: event location calls it on dense-output polynomials millions of times; it
//! needs no allocation and keeps the caller's f(a), f(b).

/// Brent's root finder on a bracket [a, b] with f(a)·f(b) ≤ 0 (Brent 1973, `zero`).
///
/// # Example
/// ```
/// use rollphase_core::numeric::roots::brent;
/// let f = |x: f64| x * x - 2.0;
/// let root = brent(f, 0.0, 2.0, f(0.0), f(2.0), 1e-14);
/// assert!((root - 2f64.sqrt()).abs() < 1e-13);
/// ```
pub fn brent(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, fa: f64, fb: f64, tol: f64) -> f64 {
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    let mut c = a;
    let mut fc = fa;
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol1 || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qa = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1 * m.signum() };
        fb = f(b);
    }
    b
}
