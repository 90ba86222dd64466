//! Relative errors of a solution at the reference points.

use super::ReferencePoints;
use crate::error::{Error, GeometryFault, Result};
use crate::math::Rgb;
use crate::solution::Solution;
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
    /// The L1 error: the mean of `|B - R|` over the points over the mean of
    /// `R`, per band, averaged over the bands. Unlike the point errors it
    /// weighs bright and dark points by their absolute error.
    pub l1: f64,
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
    /// [`ErrorSummary::l1`].
    L1,
}

impl ErrorMetric {
    /// The figure of `summary`.
    #[must_use]
    pub fn of(self, summary: &ErrorSummary) -> f64 {
        match self {
            ErrorMetric::Mean => summary.mean,
            ErrorMetric::Rms => summary.rms,
            ErrorMetric::Max => summary.max,
            ErrorMetric::L1 => summary.l1,
        }
    }

    /// Its name in tables and axis labels.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ErrorMetric::Mean => "mean",
            ErrorMetric::Rms => "RMS",
            ErrorMetric::Max => "max",
            ErrorMetric::L1 => "L1",
        }
    }
}

/// The error of a solution at one reference point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointError {
    /// `|B - R| / max(R, f)` per band with `f` the reference's error floor,
    /// averaged over the three bands.
    pub relative: f64,
    /// `B - R` per band.
    pub difference: Rgb,
}

/// The error of `solution` at every reference point, in the order of
/// `reference.points`. `B` is the solution's value as
/// [`Solution::radiosity_at`] reads it (interpolated as the renderer shades).
///
/// Fails, naming the point, if a point lies on no surface of the solution's
/// mesh (a reference made for another scene).
pub fn point_errors(solution: &Solution, reference: &ReferencePoints) -> Result<Vec<PointError>> {
    let probe = solution.probe();
    reference
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let b = probe.radiosity_at(p.position, p.normal).ok_or_else(|| {
                Error::geometry(
                    GeometryFault::Mismatch,
                    format!(
                        "reference point {i} at {} (surface {}) lies on no surface of the solution",
                        p.position, p.surface
                    ),
                )
            })?;
            let difference = b - p.radiosity;
            let band = |k: usize| {
                let scale = p.radiosity[k]
                    .max(reference.error_floor[k])
                    .max(f64::MIN_POSITIVE);
                difference[k].abs() / scale
            };
            Ok(PointError {
                relative: (band(0) + band(1) + band(2)) / 3.0,
                difference,
            })
        })
        .collect()
}

/// Mean, RMS and largest relative error, and the L1 error, of `errors`
/// measured at `reference`'s points (all zero for no errors).
#[must_use]
pub(crate) fn error_summary(reference: &ReferencePoints, errors: &[PointError]) -> ErrorSummary {
    if errors.is_empty() {
        return ErrorSummary::default();
    }
    let n = errors.len() as f64;
    let relative = errors.iter().map(|e| e.relative);
    let absolute = errors.iter().fold(Rgb::ZERO, |a, e| a + e.difference.abs());
    let reference_sum = reference
        .points
        .iter()
        .fold(Rgb::ZERO, |a, p| a + p.radiosity);
    let l1 = (0..3)
        .map(|k| absolute[k] / reference_sum[k].max(f64::MIN_POSITIVE))
        .sum::<f64>()
        / 3.0;
    ErrorSummary {
        mean: relative.clone().sum::<f64>() / n,
        rms: (relative.clone().map(|e| e * e).sum::<f64>() / n).sqrt(),
        max: relative.fold(0.0, f64::max),
        l1,
        points: errors.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::{ReferenceKind, ReferencePoint};
    use glam::DVec3;

    #[test]
    fn summary_of_known_values() {
        let point = |r: f64| ReferencePoint {
            surface: 0,
            position: DVec3::ZERO,
            normal: DVec3::Y,
            radiosity: Rgb::splat(r),
            std_error: Rgb::ZERO,
        };
        let reference = ReferencePoints {
            kind: ReferenceKind::Exact,
            points: vec![point(1.0), point(2.0), point(0.5), point(0.5)],
            emitting_left_out: 0,
            hidden_left_out: 0,
            error_floor: Rgb::splat(0.01),
            seconds: 0.0,
        };
        let errors: Vec<PointError> = [(0.1, 0.1), (0.3, -0.6), (0.0, 0.0), (0.4, 0.2)]
            .iter()
            .map(|&(relative, d)| PointError {
                relative,
                difference: Rgb::splat(d),
            })
            .collect();
        let s = error_summary(&reference, &errors);
        assert!((s.mean - 0.2).abs() < 1e-15);
        assert!((s.rms - (0.26f64 / 4.0).sqrt()).abs() < 1e-15);
        assert_eq!(s.max, 0.4);
        // (0.1 + 0.6 + 0 + 0.2) / (1 + 2 + 0.5 + 0.5)
        assert!((s.l1 - 0.225).abs() < 1e-15);
        assert_eq!(s.points, 4);
        assert_eq!(error_summary(&reference, &[]), ErrorSummary::default());
    }
}
