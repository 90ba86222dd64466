//! Sampling primitives: discrete choice by weight, and cosine-weighted directions.

use glam::DVec3;

/// The largest f64 below 1, so that remapped uniforms stay in [0, 1).
const BELOW_ONE: f64 = 1.0 - f64::EPSILON / 2.0;

/// A discrete distribution over indices, proportional to non-negative weights.
#[derive(Clone, Debug)]
pub(crate) struct Cdf {
    /// Running sums divided by the total; the last is exactly 1.
    cumulative: Vec<f64>,
    /// Weights divided by the total.
    probabilities: Vec<f64>,
}

impl Cdf {
    /// The distribution of `weights`, or `None` when they do not sum to a positive
    /// finite total (or any is negative or not finite).
    pub(crate) fn new(weights: &[f64]) -> Option<Cdf> {
        if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            return None;
        }
        let total: f64 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let mut running = 0.0;
        let mut cumulative: Vec<f64> = weights
            .iter()
            .map(|w| {
                running += w;
                running / total
            })
            .collect();
        // Entries after the last positive weight are unreachable: pin them at 1.
        let last = weights.iter().rposition(|w| *w > 0.0)?;
        for c in &mut cumulative[last..] {
            *c = 1.0;
        }
        let probabilities = weights.iter().map(|w| w / total).collect();
        Some(Cdf {
            cumulative,
            probabilities,
        })
    }

    /// The index chosen by a uniform `u` in [0, 1), and `u` remapped to [0, 1)
    /// within that index's interval (so it can drive a further choice).
    pub(crate) fn pick(&self, u: f64) -> (usize, f64) {
        let u = u.clamp(0.0, BELOW_ONE);
        let index = self
            .cumulative
            .partition_point(|c| *c <= u)
            .min(self.cumulative.len() - 1);
        let low = if index == 0 {
            0.0
        } else {
            self.cumulative[index - 1]
        };
        let width = self.cumulative[index] - low;
        let remapped = if width > 0.0 { (u - low) / width } else { 0.0 };
        (index, remapped.clamp(0.0, BELOW_ONE))
    }

    /// The probability of index `i`.
    pub(crate) fn probability(&self, i: usize) -> f64 {
        self.probabilities[i]
    }
}

/// Two unit vectors that complete the unit normal `n` to a right-handed
/// orthonormal basis (the branch-free construction of Duff et al. 2017).
pub(crate) fn tangent_frame(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1.0f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let s = DVec3::new(b, sign + n.y * n.y * a, -n.y);
    (t, s)
}

/// A direction about the unit normal `n` with density cos(theta) / pi per unit
/// solid angle (a uniform point on the unit disc lifted to the hemisphere).
pub(crate) fn cosine_direction(n: DVec3, u1: f64, u2: f64) -> DVec3 {
    let radius = u1.sqrt();
    let phi = std::f64::consts::TAU * u2;
    let (t, s) = tangent_frame(n);
    let up = (1.0 - u1).max(0.0).sqrt();
    (t * (radius * phi.cos()) + s * (radius * phi.sin()) + n * up).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::rng::{Domain, Rng};

    #[test]
    fn cdf_picks_in_proportion_and_skips_zero_weights() {
        let cdf = Cdf::new(&[0.0, 1.0, 0.0, 3.0, 0.0]).unwrap();
        assert_eq!(cdf.pick(0.0).0, 1);
        assert_eq!(cdf.pick(0.2499).0, 1);
        assert_eq!(cdf.pick(0.25).0, 3);
        assert_eq!(cdf.pick(BELOW_ONE).0, 3);
        let (_, r) = cdf.pick(0.625);
        assert!((r - 0.5).abs() < 1e-15);
        assert_eq!(cdf.probability(3), 0.75);
        assert!(Cdf::new(&[0.0, 0.0]).is_none());
        assert!(Cdf::new(&[1.0, f64::NAN]).is_none());
    }

    #[test]
    fn frames_are_orthonormal() {
        for n in [
            DVec3::Z,
            -DVec3::Z,
            DVec3::X,
            DVec3::new(0.3, -0.5, 0.8).normalize(),
            DVec3::new(1e-9, 0.0, -1.0).normalize(),
        ] {
            let (t, s) = tangent_frame(n);
            for (a, b) in [(t, s), (t, n), (s, n)] {
                assert!(a.dot(b).abs() < 1e-12);
            }
            for v in [t, s] {
                assert!((v.length() - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn cosine_directions_have_mean_cosine_two_thirds() {
        // E[cos] = 2/3 and E[cos^2] = 1/2 under the cos/pi density; the standard
        // error of the mean cosine is sqrt(1/2 - 4/9)/sqrt(n) = 7.5e-4 for n = 1e5.
        let n_vec = DVec3::new(0.2, 0.9, -0.4).normalize();
        let mut rng = Rng::for_stream(11, Domain::Probe, 0, 0);
        let count = 100_000;
        let mut sum = 0.0;
        for _ in 0..count {
            let d = cosine_direction(n_vec, rng.uniform(), rng.uniform());
            let c = d.dot(n_vec);
            assert!(c >= 0.0 && (d.length() - 1.0).abs() < 1e-12);
            sum += c;
        }
        let mean = sum / count as f64;
        assert!((mean - 2.0 / 3.0).abs() < 4e-3, "mean cosine {mean}");
    }
}
