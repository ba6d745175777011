//! The mismatch of a track with itself shifted, at every whole shift at once: the track as one
//! complex signal less its line ([`Detrended`]), E(τ) by prefix sums and one FFT's
//! autocorrelation ([`Curve`]), evaluated between whole shifts too, and its cumulative-mean
//! normalisation d′ (YIN). The period search ([`super::period`]) and its check against chance
//! ([`super::surrogates`]) read the same curve.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;

use super::CleanTrack;

/// The track as z = down + i·across less its least-squares line.
pub(super) struct Detrended {
    pub(super) z: Vec<Complex64>,
    /// The line's slope (per frame), added back to the mean displacement.
    pub(super) slope: Complex64,
}

impl Detrended {
    pub(super) fn of(track: &CleanTrack) -> Self {
        let z: Vec<Complex64> = track
            .down
            .iter()
            .zip(&track.across)
            .map(|(&d, &a)| Complex64::new(d, a))
            .collect();
        Self::of_signal(z)
    }

    pub(super) fn of_signal(mut z: Vec<Complex64>) -> Self {
        let n = z.len() as f64;
        let mid = (n - 1.0) / 2.0;
        let mean = z.iter().sum::<Complex64>() / n;
        let (mut sxy, mut sxx) = (Complex64::new(0.0, 0.0), 0.0);
        for (i, v) in z.iter().enumerate() {
            let x = i as f64 - mid;
            sxy += (v - mean) * x;
            sxx += x * x;
        }
        let slope = if sxx > 0.0 { sxy / sxx } else { sxy * 0.0 };
        for (i, v) in z.iter_mut().enumerate() {
            *v -= mean + slope * (i as f64 - mid);
        }
        Detrended { z, slope }
    }

    /// Twice the variance: the mismatch of unrelated points.
    pub(super) fn scale(&self) -> f64 {
        2.0 * self.z.iter().map(Complex64::norm_sqr).sum::<f64>() / self.z.len() as f64
    }

    /// E(τ) (unnormalised) and the mean displacement over τ for a whole shift, directly: the
    /// FFT curve's check.
    #[cfg(test)]
    pub(super) fn mismatch_at(&self, tau: usize) -> (f64, Complex64) {
        let n = self.z.len();
        let count = n - tau;
        let (mut sum, mut sq) = (Complex64::new(0.0, 0.0), 0.0);
        for i in 0..count {
            let d = self.z[i + tau] - self.z[i];
            sum += d;
            sq += d.norm_sqr();
        }
        let c = count as f64;
        let mean = sum / c;
        ((sq / c - mean.norm_sqr()).max(0.0), mean)
    }
}

pub(super) fn next_pow2(n: usize) -> usize {
    n.max(2).next_power_of_two()
}

/// The mismatch at every whole shift, and what evaluates it between whole shifts.
pub(super) struct Curve {
    /// E(τ) (unnormalised) at τ = 0 … max_tau.
    pub(super) e: Vec<f64>,
    /// The mean displacement D(τ).
    pub(super) displacement: Vec<Complex64>,
    /// Σ|z(t + τ)|² + Σ|z(t)|² over the n − τ pairs.
    pub(super) squares: Vec<f64>,
    /// The power spectrum folded onto |frequency| (P_j + P_{m−j}), for the autocorrelation
    /// between whole shifts.
    pub(super) folded_power: Vec<f64>,
    /// The FFT length.
    pub(super) m: usize,
    /// The track's length.
    pub(super) len: usize,
}

impl Curve {
    /// E(τ) for every whole shift τ = 0 … `max_tau` (unnormalised): Σ|z|² sums by prefix sums,
    /// the autocorrelation by one FFT pair of length ≥ 2n (no wrap-around).
    pub(super) fn of(z: &[Complex64], max_tau: usize, planner: &mut FftPlanner<f64>) -> Curve {
        let n = z.len();
        let m = next_pow2(2 * n);
        let mut buf = vec![Complex64::new(0.0, 0.0); m];
        buf[..n].copy_from_slice(z);
        planner.plan_fft_forward(m).process(&mut buf);
        let power: Vec<f64> = buf.iter().map(Complex64::norm_sqr).collect();
        let mut folded_power = Vec::with_capacity(m / 2 + 1);
        folded_power.push(power[0]);
        for j in 1..m / 2 {
            folded_power.push(power[j] + power[m - j]);
        }
        folded_power.push(power[m / 2]);
        for (b, p) in buf.iter_mut().zip(&power) {
            *b = Complex64::new(*p, 0.0);
        }
        planner.plan_fft_inverse(m).process(&mut buf);
        let mut s1 = vec![Complex64::new(0.0, 0.0); n + 1];
        let mut s2 = vec![0.0; n + 1];
        for (i, v) in z.iter().enumerate() {
            s1[i + 1] = s1[i] + v;
            s2[i + 1] = s2[i] + v.norm_sqr();
        }
        let top = max_tau.min(n - 1);
        let mut e = Vec::with_capacity(top + 1);
        let mut displacement = Vec::with_capacity(top + 1);
        let mut squares = Vec::with_capacity(top + 1);
        for tau in 0..=top {
            let count = n - tau;
            let c = count as f64;
            // Σ_{t<count} |z(t+τ) − z(t)|² = Σ|z(t+τ)|² + Σ|z(t)|² − 2 Re Σ conj(z(t)) z(t+τ).
            let auto = buf[tau].re / m as f64;
            let sq = (s2[n] - s2[tau]) + s2[count];
            let mean = ((s1[n] - s1[tau]) - s1[count]) / c;
            e.push(((sq - 2.0 * auto) / c - mean.norm_sqr()).max(0.0));
            displacement.push(mean);
            squares.push(sq);
        }
        Curve {
            e,
            displacement,
            squares,
            folded_power,
            m,
            len: n,
        }
    }

    /// E and D at a shift between whole frames: the autocorrelation by its band-limited
    /// (trigonometric) interpolation, exact at whole shifts, which shifts the noise without
    /// averaging it away; the sums of squares and D, which change by one end point a frame,
    /// linearly.
    pub(super) fn at(&self, tau: f64) -> (f64, Complex64) {
        let k = (tau.floor() as usize).min(self.e.len() - 2);
        let s = tau - k as f64;
        let lerp = |a: f64, b: f64| a + (b - a) * s;
        let sq = lerp(self.squares[k], self.squares[k + 1]);
        let mean = self.displacement[k] + (self.displacement[k + 1] - self.displacement[k]) * s;
        let theta = std::f64::consts::TAU * tau / self.m as f64;
        let mut auto = self.folded_power[0];
        let mut phase = Complex64::new(1.0, 0.0);
        let step = Complex64::from_polar(1.0, theta);
        for (j, p) in self.folded_power.iter().enumerate().skip(1) {
            // Re-anchored every 1024 steps so that round-off in the recurrence cannot grow.
            phase = if j % 1024 == 0 {
                Complex64::from_polar(1.0, theta * j as f64)
            } else {
                phase * step
            };
            auto += p * phase.re;
        }
        let auto = auto / self.m as f64;
        let pairs = self.len as f64 - tau;
        (((sq - 2.0 * auto) / pairs - mean.norm_sqr()).max(0.0), mean)
    }
}

/// The cumulative-mean-normalised mismatch d′(τ) = e(τ)·τ / Σ_{1≤s≤τ} e(s) (d′(0) = 1).
pub(super) fn normalised(e: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(e.len());
    let mut sum = 0.0;
    for (tau, &v) in e.iter().enumerate() {
        if tau == 0 {
            out.push(1.0);
            continue;
        }
        sum += v;
        out.push(if sum > 0.0 { v * tau as f64 / sum } else { 1.0 });
    }
    out
}

/// The lowest d′ anywhere from shift 2 to the end of the range (the chance statistic).
pub(super) fn lowest_dip(dn: &[f64]) -> f64 {
    dn.iter().skip(2).copied().fold(f64::INFINITY, f64::min)
}
