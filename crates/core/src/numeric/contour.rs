//! Level sets on a grid: marching squares, giving the segments where a sampled function
//! crosses a level (the halting loops Q = tan α on a body's (θ, φ) grid).

/// Marching squares on Q − level over a (θ, φ) grid: segments in (φ, θ).
///
/// # Example
/// ```
/// use rollphase_core::numeric::contour::level_set;
/// // Q = θ on a 3 × 3 grid: the level 0.5 is the line θ = 0.5, crossed by two cells.
/// let (thetas, phis) = ([0.0, 1.0, 2.0], [0.0, 1.0, 2.0]);
/// let q: Vec<Vec<f64>> = thetas.iter().map(|&t| vec![t; 3]).collect();
/// let segments = level_set(&q, &thetas, &phis, 0.5);
/// assert_eq!(segments.len(), 2);
/// assert!(segments.iter().all(|((_, t0), (_, t1))| *t0 == 0.5 && *t1 == 0.5));
/// ```
pub fn level_set(
    q: &[Vec<f64>],
    thetas: &[f64],
    phis: &[f64],
    level: f64,
) -> Vec<((f64, f64), (f64, f64))> {
    let mut out = Vec::new();
    let interp = |(t0, p0, v0): (f64, f64, f64), (t1, p1, v1): (f64, f64, f64)| {
        let s = (level - v0) / (v1 - v0);
        (p0 + s * (p1 - p0), t0 + s * (t1 - t0))
    };
    for i in 0..thetas.len() - 1 {
        for j in 0..phis.len() - 1 {
            let corners = [
                (thetas[i], phis[j], q[i][j]),
                (thetas[i], phis[j + 1], q[i][j + 1]),
                (thetas[i + 1], phis[j + 1], q[i + 1][j + 1]),
                (thetas[i + 1], phis[j], q[i + 1][j]),
            ];
            let mut pts = Vec::new();
            for k in 0..4 {
                let (a, b) = (corners[k], corners[(k + 1) % 4]);
                if (a.2 - level) * (b.2 - level) < 0.0 {
                    pts.push(interp(a, b));
                }
            }
            if pts.len() == 2 {
                out.push((pts[0], pts[1]));
            } else if pts.len() == 4 {
                out.push((pts[0], pts[1]));
                out.push((pts[2], pts[3]));
            }
        }
    }
    out
}
