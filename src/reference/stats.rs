//! Sample mean and standard error per band, accumulated in a fixed order.

use crate::math::Rgb;
use serde::Serialize;

/// A Monte Carlo estimate of radiosity with its standard error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ProbeEstimate {
    /// The sample mean per band (W/m^2, exitance units like the scene's emission).
    pub radiosity: Rgb,
    /// The standard error of that mean per band: the sample standard deviation
    /// over the square root of the number of paths. An unbiased estimator's
    /// result lies within three of these of the true value about 99.7% of the
    /// time (the per-path values are bounded, so the central limit theorem holds).
    pub std_error: Rgb,
    /// The number of independent paths (one per sample point for object means).
    pub paths: u64,
}

/// Welford's running mean and sum of squared deviations, per band.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct RunningStats {
    count: u64,
    mean: [f64; 3],
    squares: [f64; 3],
}

impl RunningStats {
    /// Adds one sample.
    pub(crate) fn push(&mut self, value: Rgb) {
        self.count += 1;
        let n = self.count as f64;
        for band in 0..3 {
            let delta = value[band] - self.mean[band];
            self.mean[band] += delta / n;
            self.squares[band] += delta * (value[band] - self.mean[band]);
        }
    }

    /// Adds another accumulator's samples (Chan, Golub, LeVeque 1979). Merging
    /// chunks in a fixed order keeps the result independent of thread count.
    pub(crate) fn merge(&mut self, other: &RunningStats) {
        if other.count == 0 {
            return;
        }
        if self.count == 0 {
            *self = *other;
            return;
        }
        let (na, nb) = (self.count as f64, other.count as f64);
        let n = na + nb;
        for band in 0..3 {
            let delta = other.mean[band] - self.mean[band];
            self.mean[band] += delta * (nb / n);
            self.squares[band] += other.squares[band] + delta * delta * (na * nb / n);
        }
        self.count += other.count;
    }

    /// The estimate: mean, standard error (zero for fewer than two samples) and
    /// sample count.
    pub(crate) fn estimate(&self) -> ProbeEstimate {
        let n = self.count as f64;
        let mut std_error = Rgb::ZERO;
        if self.count >= 2 {
            for band in 0..3 {
                std_error[band] = (self.squares[band].max(0.0) / (n - 1.0) / n).sqrt();
            }
        }
        ProbeEstimate {
            radiosity: Rgb(self.mean),
            std_error,
            paths: self.count,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merged_chunks_match_the_textbook_formulas() {
        let values: Vec<f64> = (0..37).map(|i| ((i * 13) % 7) as f64 * 0.5 + 1.0).collect();
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let mut whole = RunningStats::default();
        let mut parts = [RunningStats::default(); 3];
        for (i, v) in values.iter().enumerate() {
            whole.push(Rgb::new(*v, 2.0 * v, 0.0));
            parts[i * 3 / values.len()].push(Rgb::new(*v, 2.0 * v, 0.0));
        }
        let mut merged = RunningStats::default();
        for p in &parts {
            merged.merge(p);
        }
        for e in [whole.estimate(), merged.estimate()] {
            assert_eq!(e.paths, 37);
            assert!((e.radiosity[0] - mean).abs() < 1e-14);
            assert!((e.radiosity[1] - 2.0 * mean).abs() < 1e-14);
            assert!((e.std_error[0] - (var / n).sqrt()).abs() < 1e-14);
            assert!((e.std_error[1] - 2.0 * (var / n).sqrt()).abs() < 1e-14);
            assert_eq!(e.std_error[2], 0.0);
        }
    }
}
