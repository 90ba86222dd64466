//! Relative errors of a solution at the reference points.

use super::ReferencePoints;
use crate::error::{Error, Result};
use crate::pipeline::Solution;
use serde::Serialize;

/// The floor of the relative error as a fraction of the mean reference
/// radiosity of the scene's (non-emitting) reference points: a point darker
/// than 1 % of that mean has its error measured against that 1 %.
pub const ERROR_FLOOR_FRACTION: f64 = 0.01;

/// Mean, root-mean-square and largest relative error over the reference points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ErrorSummary {
    /// Mean over points of the point errors.
    pub mean: f64,
    /// Square root of the mean squared point error.
    pub rms: f64,
    /// The largest point error.
    pub max: f64,
    /// How many points.
    pub points: usize,
}

/// Which of the [`ErrorSummary`] figures to compare or plot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorMetric {
    /// [`ErrorSummary::mean`].
    Mean,
    /// [`ErrorSummary::rms`].
    Rms,
    /// [`ErrorSummary::max`].
    Max,
}

impl ErrorMetric {
    /// The figure of `summary`.
    #[must_use]
    pub fn of(self, summary: &ErrorSummary) -> f64 {
        match self {
            ErrorMetric::Mean => summary.mean,
            ErrorMetric::Rms => summary.rms,
            ErrorMetric::Max => summary.max,
        }
    }

    /// Its name in tables and axis labels.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ErrorMetric::Mean => "mean",
            ErrorMetric::Rms => "RMS",
            ErrorMetric::Max => "max",
        }
    }
}

/// The relative error of `solution` at every reference point, in the order of
/// `reference.points`: per band `|B - R| / max(R, f)` with `f` the reference's
/// error floor, averaged over the three bands. `B` is the solution's value as
/// [`Solution::radiosity_at`] reads it (interpolated as the renderer shades).
///
/// Fails, naming the point, if a point lies on no surface of the solution's
/// mesh (a reference made for another scene).
pub fn point_errors(solution: &Solution, reference: &ReferencePoints) -> Result<Vec<f64>> {
    let probe = solution.probe();
    reference
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let b = probe.radiosity_at(p.position, p.normal).ok_or_else(|| {
                Error::Geometry(format!(
                    "reference point {i} at {} (surface {}) lies on no surface of the solution",
                    p.position, p.surface
                ))
            })?;
            let band = |k: usize| {
                let scale = p.radiosity[k]
                    .max(reference.error_floor[k])
                    .max(f64::MIN_POSITIVE);
                (b[k] - p.radiosity[k]).abs() / scale
            };
            Ok((band(0) + band(1) + band(2)) / 3.0)
        })
        .collect()
}

/// Mean, RMS and largest of `errors` (all zero for no errors).
#[must_use]
pub fn error_summary(errors: &[f64]) -> ErrorSummary {
    if errors.is_empty() {
        return ErrorSummary::default();
    }
    let n = errors.len() as f64;
    ErrorSummary {
        mean: errors.iter().sum::<f64>() / n,
        rms: (errors.iter().map(|e| e * e).sum::<f64>() / n).sqrt(),
        max: errors.iter().copied().fold(0.0, f64::max),
        points: errors.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_of_known_values() {
        let s = error_summary(&[0.1, 0.3, 0.0, 0.4]);
        assert!((s.mean - 0.2).abs() < 1e-15);
        assert!((s.rms - (0.26f64 / 4.0).sqrt()).abs() < 1e-15);
        assert_eq!(s.max, 0.4);
        assert_eq!(s.points, 4);
        assert_eq!(error_summary(&[]), ErrorSummary::default());
    }
}
