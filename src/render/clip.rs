//! Clipping in view space against the near plane and a guard band.
//!
//! The near plane keeps every projected point at positive depth. The guard band
//! (four planes through the eye, far outside the image) bounds projected
//! coordinates so that the rasterizer's fixed-point arithmetic cannot overflow,
//! however close to the camera plane a vertex lies. Both are applied before the
//! perspective division, so a triangle crossing the camera plane is cut in 3D,
//! never wrapped around through infinity.

use super::view::View;
use glam::DVec3;

/// A clipped triangle has at most its three vertices plus one per plane.
pub(crate) const MAX_CLIPPED_VERTICES: usize = 3 + PLANES;
const PLANES: usize = 5;

/// Pixel coordinates of guard-band points stay within this many pixels of the
/// image, so fixed-point coordinates stay below 2^29 (see `raster.rs`).
const GUARD_BAND_PIXELS: f64 = (1u32 << 21) as f64;

/// The half-space `normal . p + offset >= 0` of view space.
#[derive(Clone, Copy, Debug)]
struct HalfSpace {
    normal: DVec3,
    offset: f64,
}

impl HalfSpace {
    #[inline]
    fn eval(&self, p: DVec3) -> f64 {
        self.normal.dot(p) + self.offset
    }
}

/// A convex polygon of view-space points, stored inline (no allocation).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ClipPolygon {
    vertices: [DVec3; MAX_CLIPPED_VERTICES],
    len: usize,
}

impl ClipPolygon {
    const EMPTY: ClipPolygon = ClipPolygon {
        vertices: [DVec3::ZERO; MAX_CLIPPED_VERTICES],
        len: 0,
    };

    /// The polygon's vertices, in order.
    pub(super) fn vertices(&self) -> &[DVec3] {
        &self.vertices[..self.len]
    }

    fn push(&mut self, p: DVec3) {
        // Cannot overflow: each plane adds at most one vertex to a convex polygon.
        if self.len < MAX_CLIPPED_VERTICES {
            self.vertices[self.len] = p;
            self.len += 1;
        }
    }
}

/// The region of view space that is rasterized: in front of the near plane and
/// inside the guard band.
#[derive(Clone, Debug)]
pub(crate) struct ClipVolume {
    planes: [HalfSpace; PLANES],
}

impl ClipVolume {
    /// The clip volume of `view`, with the near plane at depth `near > 0`.
    pub(super) fn new(view: &View, near: f64) -> Self {
        let side = f64::from(view.width.max(view.height));
        // In normalised device units: |x / (z half_width)| <= guard.
        let guard = 2.0 * GUARD_BAND_PIXELS / side - 1.0;
        let gx = guard * view.half_width;
        let gy = guard * view.half_height;
        let plane = |x: f64, y: f64, z: f64, offset: f64| HalfSpace {
            normal: DVec3::new(x, y, z),
            offset,
        };
        ClipVolume {
            planes: [
                plane(0.0, 0.0, 1.0, -near),
                plane(1.0, 0.0, gx, 0.0),
                plane(-1.0, 0.0, gx, 0.0),
                plane(0.0, 1.0, gy, 0.0),
                plane(0.0, -1.0, gy, 0.0),
            ],
        }
    }

    /// True when `p` needs no clipping.
    #[inline]
    pub(super) fn contains(&self, p: DVec3) -> bool {
        self.planes.iter().all(|h| h.eval(p) >= 0.0)
    }

    /// The part of triangle `tri` inside the volume (Sutherland-Hodgman).
    ///
    /// A new vertex is always interpolated from the edge's inside end towards
    /// its outside end, so two triangles sharing an edge get bit-identical cut
    /// points: no crack opens along a clipped shared edge.
    pub(super) fn clip_triangle(&self, tri: [DVec3; 3]) -> ClipPolygon {
        let mut current = ClipPolygon::EMPTY;
        for p in tri {
            current.push(p);
        }
        for plane in &self.planes {
            let verts = current.vertices();
            if verts.iter().all(|&p| plane.eval(p) >= 0.0) {
                continue;
            }
            let mut next = ClipPolygon::EMPTY;
            for (i, &a) in verts.iter().enumerate() {
                let b = verts[(i + 1) % verts.len()];
                let (fa, fb) = (plane.eval(a), plane.eval(b));
                if fa >= 0.0 {
                    next.push(a);
                }
                if (fa >= 0.0) != (fb >= 0.0) {
                    next.push(if fa >= 0.0 {
                        cut(a, fa, b, fb)
                    } else {
                        cut(b, fb, a, fa)
                    });
                }
            }
            current = next;
            if current.len < 3 {
                return ClipPolygon::EMPTY;
            }
        }
        current
    }

    /// The part of segment `a`-`b` inside the volume (Liang-Barsky), if any.
    pub(super) fn clip_segment(&self, a: DVec3, b: DVec3) -> Option<(DVec3, DVec3)> {
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for plane in &self.planes {
            let (fa, fb) = (plane.eval(a), plane.eval(b));
            if fa < 0.0 && fb < 0.0 {
                return None;
            }
            if fa < 0.0 {
                t0 = t0.max(fa / (fa - fb));
            } else if fb < 0.0 {
                t1 = t1.min(fa / (fa - fb));
            }
        }
        (t0 <= t1).then(|| (a + (b - a) * t0, a + (b - a) * t1))
    }
}

/// The point where the plane crosses the edge from `inside` (value `fi >= 0`)
/// to `outside` (value `fo < 0`).
#[inline]
fn cut(inside: DVec3, fi: f64, outside: DVec3, fo: f64) -> DVec3 {
    inside + (outside - inside) * (fi / (fi - fo))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;

    fn volume() -> ClipVolume {
        let cam = Camera::look_at(DVec3::ZERO, DVec3::NEG_Z, DVec3::Y, 90.0);
        ClipVolume::new(&View::new(&cam, 64, 64).unwrap(), 0.5)
    }

    #[test]
    fn triangle_crossing_near_plane_is_cut_at_it() {
        // View space: one vertex behind the eye, two in front.
        let tri = [
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, 3.0),
            DVec3::new(-1.0, 0.0, 3.0),
        ];
        let poly = volume().clip_triangle(tri);
        let v = poly.vertices();
        assert_eq!(v.len(), 4);
        assert!(v.iter().all(|p| p.z >= 0.5 - 1e-15));
        // The cuts lie on the original edges at z = 0.5: x = +-(1.5 / 4).
        let cuts: Vec<_> = v.iter().filter(|p| (p.z - 0.5).abs() < 1e-15).collect();
        assert_eq!(cuts.len(), 2);
        assert!(cuts.iter().any(|p| (p.x - 0.375).abs() < 1e-15));
        assert!(cuts.iter().any(|p| (p.x + 0.375).abs() < 1e-15));
    }

    #[test]
    fn shared_edge_is_cut_at_the_same_point_from_both_sides() {
        let (a, b) = (DVec3::new(0.3, 0.1, -2.0), DVec3::new(-0.2, 0.7, 5.0));
        let v = volume();
        let p = v.clip_triangle([a, b, DVec3::new(2.0, 0.0, 4.0)]);
        let q = v.clip_triangle([b, a, DVec3::new(-2.0, 0.0, 4.0)]);
        let on_plane = |poly: &ClipPolygon| {
            poly.vertices()
                .iter()
                .copied()
                .filter(|p| p.x.abs() < 0.31 && p.z < 0.6)
                .collect::<Vec<_>>()
        };
        assert_eq!(on_plane(&p), on_plane(&q));
        assert_eq!(on_plane(&p).len(), 1);
    }

    #[test]
    fn segment_behind_is_dropped_and_crossing_one_is_cut() {
        let v = volume();
        assert!(v
            .clip_segment(DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.0, 0.0, -3.0))
            .is_none());
        let (a, b) = v
            .clip_segment(DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.0, 0.0, 3.0))
            .unwrap();
        assert_eq!(a, DVec3::new(0.0, 0.0, 0.5));
        assert_eq!(b, DVec3::new(0.0, 0.0, 3.0));
    }
}
