//! Lambert's contour formula for the form factor from a differential area to a
//! polygon, used by the hybrid method to replace pixel counts where the
//! hemi-cube says a patch is (partly) visible.
//!
//! This is the solver's own implementation; the test oracle in
//! [`crate::analytic`] is written separately so that each checks the other.

use crate::math::clip_to_halfspace;
use glam::DVec3;

/// The unoccluded form factor from a differential area at `p` with unit normal
/// `n` to the polygon `vertices` (any orientation), clipped to the half-space
/// above `p`'s plane.
#[must_use]
pub fn point_to_polygon(p: DVec3, n: DVec3, vertices: &[DVec3]) -> f64 {
    // Wholly above the horizon (most calls), clipping would copy the
    // vertices unchanged.
    let kept;
    let clipped: &[DVec3] = if vertices.iter().all(|v| n.dot(*v - p) >= 0.0) {
        vertices
    } else {
        kept = clip_to_halfspace(vertices, p, n);
        &kept
    };
    let m = clipped.len();
    if m < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..m {
        let a = clipped[i] - p;
        let b = clipped[(i + 1) % m] - p;
        let c = a.cross(b);
        let len = c.length();
        // An edge whose line passes through p subtends no angle.
        if len <= 1e-300 {
            continue;
        }
        let beta = len.atan2(a.dot(b));
        sum += beta * n.dot(c) / len;
    }
    (sum / (2.0 * std::f64::consts::PI)).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_corner_formula() {
        // Point below the corner of a parallel 1 x 1 rectangle at distance 1:
        // 0.138532 (algorithms.md 4.2, corner formula).
        let r = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
        ];
        let f = point_to_polygon(DVec3::ZERO, DVec3::Z, &r);
        assert!((f - 0.138532).abs() < 1e-6, "{f}");
    }
}
