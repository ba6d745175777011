//! Least-squares fits used by the figures: straight lines with standard errors, and power laws
//! y = c·x^β as lines in log–log coordinates, and the viscous period law near α*.

use serde::Serialize;

/// A fitted straight line y = intercept + slope·x.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LineFit {
    /// Slope.
    pub slope: f64,
    /// Standard error of the slope (from the residuals; NaN with fewer than 3 points).
    pub slope_stderr: f64,
    /// Intercept.
    pub intercept: f64,
    /// Coefficient of determination R².
    pub r2: f64,
    /// Residual sum of squares.
    pub rss: f64,
    /// Number of points.
    pub n: usize,
}

/// Ordinary least squares through (x, y); `None` with fewer than 2 distinct x.
///
/// # Example
/// ```
/// use rollphase_core::analysis::fit::line;
/// let fit = line(&[(0.0, 1.0), (1.0, 3.0), (2.0, 5.0)]).unwrap();
/// assert!((fit.slope - 2.0).abs() < 1e-12 && (fit.intercept - 1.0).abs() < 1e-12);
/// assert!(line(&[(1.0, 1.0), (1.0, 2.0)]).is_none()); // one distinct x
/// ```
pub fn line(points: &[(f64, f64)]) -> Option<LineFit> {
    let n = points.len();
    if n < 2 {
        return None;
    }
    let nf = n as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / nf;
    let my = points.iter().map(|p| p.1).sum::<f64>() / nf;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = points.iter().map(|p| (p.1 - my).powi(2)).sum();
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let rss: f64 = points
        .iter()
        .map(|p| (p.1 - intercept - slope * p.0).powi(2))
        .sum();
    let slope_stderr = if n > 2 {
        (rss / (nf - 2.0) / sxx).sqrt()
    } else {
        f64::NAN
    };
    let r2 = if syy > 0.0 { 1.0 - rss / syy } else { 1.0 };
    Some(LineFit {
        slope,
        slope_stderr,
        intercept,
        r2,
        rss,
        n,
    })
}

/// y = c·x^β fitted as a line through (ln x, ln y); points with x ≤ 0 or y ≤ 0 are skipped.
/// Returns the line fit (slope = β, intercept = ln c).
///
/// # Example
/// ```
/// use rollphase_core::analysis::fit::power_law;
/// // T = 3·δα^(−1/2), the saddle-node law.
/// let points: Vec<(f64, f64)> = [1e-6, 1e-5, 1e-4].iter().map(|&d: &f64| (d, 3.0 * d.powf(-0.5))).collect();
/// let fit = power_law(&points).unwrap();
/// assert!((fit.slope + 0.5).abs() < 1e-12 && (fit.intercept.exp() - 3.0).abs() < 1e-10);
/// ```
pub fn power_law(points: &[(f64, f64)]) -> Option<LineFit> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    line(&logs)
}

/// How far above α* the √ law is fitted ([`sqrt_law`]): α ≤ SQRT_LAW_REACH · α*. The law is
/// asymptotic, and its next order shows as a trend in the residuals further out: on the
/// critical-angle lesson's cylinder the fit through 1.003, 1.01 and 1.03 α* holds each point to
/// 0.4 % of T, while one reaching out to 1.2 α* missed 1.1 α* by 2.9 % (+0.4, −1.1, −1.4, +2.9 %:
/// curvature, not noise), which on the lesson's plot is a point a marker's width off the curve.
pub const SQRT_LAW_REACH: f64 = 1.05;

/// The period law near the critical angle, T = a/√(α − α*) + b (SI §1B: the bottleneck time
/// diverges like (α − α*)^−½, the rest of a turn stays finite), fitted by least squares in
/// (1/√(α − α*), T) to the rolling points (α, 1/T) with α* < α ≤ [`SQRT_LAW_REACH`] α* (further
/// out the bottleneck no longer dominates a turn). Returns (a, b);
/// `None` with fewer than 3 such points or a fit that does not diverge (a ≤ 0).
///
/// ```
/// use rollphase_core::analysis::fit::sqrt_law;
/// // Points of T = 2/√(α − 0.1) + 5 exactly.
/// let points: Vec<[f64; 2]> = [0.1003, 0.101, 0.102, 0.103, 0.104]
///     .iter()
///     .map(|&a| [a, 1.0 / (2.0 / (a - 0.1f64).sqrt() + 5.0)])
///     .collect();
/// let (a, b) = sqrt_law(&points, 0.1).unwrap();
/// assert!((a - 2.0).abs() < 1e-9 && (b - 5.0).abs() < 1e-7);
/// ```
pub fn sqrt_law(points: &[[f64; 2]], alpha_star: f64) -> Option<(f64, f64)> {
    let pairs: Vec<(f64, f64)> = points
        .iter()
        .filter(|[alpha, rate]| {
            *alpha > alpha_star && *alpha <= SQRT_LAW_REACH * alpha_star && *rate > 0.0
        })
        .map(|[alpha, rate]| (1.0 / (alpha - alpha_star).sqrt(), 1.0 / rate))
        .collect();
    if pairs.len() < 3 {
        return None;
    }
    let fit = line(&pairs)?;
    (fit.slope > 0.0).then_some((fit.slope, fit.intercept))
}

/// `n` logarithmically spaced values from `a` to `b` inclusive.
///
/// # Example
/// ```
/// use rollphase_core::analysis::fit::logspace;
/// let v = logspace(1e-6, 1e-2, 5);
/// assert_eq!(v.len(), 5);
/// assert!((v[2] - 1e-4).abs() < 1e-18);
/// ```
pub fn logspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    if n == 1 {
        return vec![a];
    }
    (0..n)
        .map(|i| (a.ln() + (b.ln() - a.ln()) * i as f64 / (n - 1) as f64).exp())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_an_exact_power_law_and_a_noisy_slope_error() {
        let pts: Vec<(f64, f64)> = logspace(1e-6, 1e-2, 9)
            .into_iter()
            .map(|x| (x, 3.0 * x.powf(-0.5)))
            .collect();
        let f = power_law(&pts).unwrap();
        assert!((f.slope + 0.5).abs() < 1e-12 && (f.intercept.exp() - 3.0).abs() < 1e-10);
        assert!(f.slope_stderr < 1e-12 && (f.r2 - 1.0).abs() < 1e-12);
        // y = x + alternating ±0.1: slope 1, stderr from the textbook formula.
        let noisy: Vec<(f64, f64)> = (0..10)
            .map(|i| (i as f64, i as f64 + if i % 2 == 0 { 0.1 } else { -0.1 }))
            .collect();
        let g = line(&noisy).unwrap();
        let sxx: f64 = (0..10).map(|i| (i as f64 - 4.5).powi(2)).sum();
        assert!((g.slope_stderr - (g.rss / 8.0 / sxx).sqrt()).abs() < 1e-15);
        assert!((g.slope - 1.0).abs() < 0.05);
    }
}
