//! Where a world point lies in a surface's lattice.

use super::{Probe, SurfaceLattice};
use glam::DVec3;

impl SurfaceLattice {
    /// How far `p` (on the surface's plane) lies outside the surface's convex
    /// outline: 0 inside, else the largest distance beyond an edge line.
    #[must_use]
    pub(crate) fn outside_distance(&self, p: DVec3) -> f64 {
        let v = &self.vertices;
        (0..v.len())
            .map(|i| {
                let a = v[i];
                let b = v[(i + 1) % v.len()];
                let inward = self.normal.cross(b - a).normalize_or_zero();
                -inward.dot(p - a)
            })
            .fold(0.0, f64::max)
    }

    /// The lattice probe (at four times lattice resolution) nearest to `p`,
    /// clamped into the surface.
    #[must_use]
    pub(crate) fn probe_at(&self, p: DVec3) -> Probe {
        let (s, t) = self.surface_parameters(p);
        let (ex, ey) = (4 * i64::from(self.extent.0), 4 * i64::from(self.extent.1));
        let a = (s * ex as f64).round() as i64;
        let b = (t * ey as f64).round() as i64;
        if self.vertices.len() == 4 {
            // A quad's patches are half-open towards the far edges: keep the probe
            // a quarter lattice unit inside them (a leaf is at least one unit wide).
            return (a.clamp(0, ex - 1), b.clamp(0, ey - 1));
        }
        let (mut a, mut b) = (a.clamp(0, ex), b.clamp(0, ey));
        if a + b > ex {
            // Rounding pushed a point on the long edge just outside the triangle.
            let excess = a + b - ex;
            if a >= b {
                a -= excess;
            } else {
                b -= excess;
            }
        }
        (a, b)
    }

    /// The parameters `(s, t)` of `p` under the map of
    /// [`SurfaceLattice::position`]: bilinear for a quad (solved by Newton's
    /// method, exact in one step for a parallelogram), affine for a triangle.
    fn surface_parameters(&self, p: DVec3) -> (f64, f64) {
        let v = &self.vertices;
        if v.len() == 3 {
            return solve_2x2(v[1] - v[0], v[2] - v[0], p - v[0]).unwrap_or((0.0, 0.0));
        }
        let (mut s, mut t) = (0.5, 0.5);
        for _ in 0..32 {
            let position = v[0].lerp(v[1], s).lerp(v[3].lerp(v[2], s), t);
            let d_ds = (v[1] - v[0]) * (1.0 - t) + (v[2] - v[3]) * t;
            let d_dt = v[3].lerp(v[2], s) - v[0].lerp(v[1], s);
            let Some((ds, dt)) = solve_2x2(d_ds, d_dt, p - position) else {
                break;
            };
            s += ds;
            t += dt;
            if ds.abs().max(dt.abs()) < 1e-15 {
                break;
            }
        }
        (s, t)
    }
}

/// Least-squares `(x, y)` with `x a + y b = r`, or `None` if `a` and `b` are
/// parallel.
fn solve_2x2(a: DVec3, b: DVec3, r: DVec3) -> Option<(f64, f64)> {
    let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
    let det = aa * bb - ab * ab;
    if det.abs() <= 1e-300 || !det.is_finite() {
        return None;
    }
    let (ar, br) = (a.dot(r), b.dot(r));
    Some(((ar * bb - br * ab) / det, (br * aa - ar * ab) / det))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_by_two_solve_refuses_parallel_directions() {
        assert!(solve_2x2(DVec3::X, DVec3::X * 2.0, DVec3::Y).is_none());
        let (x, y) = solve_2x2(DVec3::X, DVec3::Z, DVec3::new(2.0, 0.0, 3.0)).unwrap();
        assert_eq!((x, y), (2.0, 3.0));
    }
}
