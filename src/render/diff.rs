//! Comparing a rendered image with a reference.

use super::HdrImage;
use crate::{Error, Result};
use serde::Serialize;

/// Error metrics of an image against a reference, computed per channel: every
/// R, G and B value of every pixel is one term.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DiffMetrics {
    /// Mean absolute difference.
    pub mae: f64,
    /// Root mean square difference.
    pub rmse: f64,
    /// `rmse` over the root mean square of the reference's values; 0 when both
    /// are 0, infinite when only the reference is 0.
    pub relative_rmse: f64,
    /// Largest absolute difference.
    pub max_abs: f64,
}

/// Compares image `a` with reference `b`. Returns the per-channel absolute
/// difference `|a - b|` as an image, and the metrics of [`DiffMetrics`].
/// Sums run in pixel order, so results do not depend on the thread count.
///
/// Fails when the images differ in size.
pub fn diff(a: &HdrImage, b: &HdrImage) -> Result<(HdrImage, DiffMetrics)> {
    if a.width != b.width || a.height != b.height || !a.is_consistent() || !b.is_consistent() {
        return Err(Error::Setting {
            name: "reference",
            message: format!(
                "cannot compare a {}x{} image ({} pixels) with a {}x{} reference ({} pixels)",
                a.width,
                a.height,
                a.pixels.len(),
                b.width,
                b.height,
                b.pixels.len()
            ),
        });
    }
    let mut out = HdrImage::new(a.width, a.height);
    let (mut abs_sum, mut sq_sum, mut ref_sq_sum, mut max_abs) = (0.0, 0.0, 0.0, 0.0f64);
    for ((pa, pb), d) in a.pixels.iter().zip(&b.pixels).zip(&mut out.pixels) {
        *d = (*pa - *pb).abs();
        for k in 0..3 {
            abs_sum += d[k];
            sq_sum += d[k] * d[k];
            ref_sq_sum += pb[k] * pb[k];
            max_abs = max_abs.max(d[k]);
        }
    }
    let n = (3 * a.pixels.len()).max(1) as f64;
    let rmse = (sq_sum / n).sqrt();
    let ref_rms = (ref_sq_sum / n).sqrt();
    let relative_rmse = if rmse == 0.0 {
        0.0
    } else if ref_rms == 0.0 {
        f64::INFINITY
    } else {
        rmse / ref_rms
    };
    let metrics = DiffMetrics {
        mae: abs_sum / n,
        rmse,
        relative_rmse,
        max_abs,
    };
    Ok((out, metrics))
}
