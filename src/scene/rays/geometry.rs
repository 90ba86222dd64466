//! The ray caster's view of each surface: an exactly planar convex polygon with
//! precomputed edge planes, exact ray intersection in f64, and uniform sampling.
//!
//! Quads are only planar to a relative 1e-6 in the scene, so the vertices are
//! projected onto the plane through their mean with the surface's normal. Rays and
//! sample points then use the same plane, which keeps the ray-origin offset (see
//! [`Tolerances`]) meaningful even for slightly warped input.

use crate::error::{Error, GeometryFault, Result};
use crate::scene::Surface;
use glam::DVec3;

/// Length tolerances derived from the scene's size, so that scenes from
/// millimetres to kilometres (and far from the origin) behave alike.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tolerances {
    /// Distance a ray origin is moved off its surface along the front normal, and
    /// the margin left at the far end of a shadow ray: 1e-7 of the scene diameter
    /// plus a few hundred ulps of the largest coordinate.
    pub(crate) offset: f64,
    /// Slack on edge tests and the window in which two hits count as a tie: far
    /// below any feature size, far above rounding. It closes cracks between
    /// surfaces that share an edge.
    pub(crate) slack: f64,
}

impl Tolerances {
    /// Tolerances for a scene of diagonal `diameter` whose largest absolute
    /// coordinate is `max_coordinate`.
    pub(crate) fn new(diameter: f64, max_coordinate: f64) -> Tolerances {
        let ulp = f64::EPSILON * max_coordinate;
        Tolerances {
            offset: 1e-7 * diameter + 256.0 * ulp,
            slack: 1e-10 * diameter + 32.0 * ulp,
        }
    }
}

/// A planar convex polygon (3 or 4 vertices, counter-clockwise about `normal`).
#[derive(Clone, Debug)]
pub(crate) struct SurfaceGeometry {
    /// Unit front normal.
    pub(crate) normal: DVec3,
    /// The mean of the vertices, on the plane; intersection works relative to it.
    pub(crate) anchor: DVec3,
    /// Vertices projected onto the plane.
    vertices: [DVec3; 4],
    count: usize,
    /// Unit in-plane normals of the edges, pointing inwards.
    edge_normals: [DVec3; 4],
    /// `edge_normals[k] . (vertices[k] - anchor)`.
    edge_offsets: [f64; 4],
    /// Area of the projected polygon.
    pub(crate) area: f64,
    /// Share of the area in triangle (0, 1, 2); 1 for a triangle.
    first_triangle_share: f64,
}

/// Twice the area vector of triangle `a b c`.
fn doubled_area_vector(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    (b - a).cross(c - a)
}

impl SurfaceGeometry {
    /// The geometry of surface number `index`; fails on anything the reference
    /// cannot trace exactly (wrong vertex count, non-finite data, zero area, a
    /// normal that disagrees with the winding, a non-convex quad).
    pub(crate) fn new(index: usize, surface: &Surface) -> Result<SurfaceGeometry> {
        let fail = |fault, what: &str| Error::geometry(fault, format!("surface {index}: {what}"));
        let count = surface.vertices.len();
        if !(3..=4).contains(&count) {
            let fault = if count < 3 {
                GeometryFault::Degenerate
            } else {
                GeometryFault::Unsupported
            };
            return Err(fail(fault, &format!("has {count} vertices (needs 3 or 4)")));
        }
        if surface.vertices.iter().any(|v| !v.is_finite()) || !surface.normal.is_finite() {
            return Err(fail(
                GeometryFault::NonFinite,
                "has a non-finite vertex or normal",
            ));
        }
        let normal = surface.normal.normalize_or_zero();
        if normal == DVec3::ZERO {
            return Err(fail(GeometryFault::Degenerate, "has a zero normal"));
        }
        let mean = surface.vertices.iter().copied().sum::<DVec3>() / count as f64;
        let mut vertices = [DVec3::ZERO; 4];
        for (slot, v) in vertices.iter_mut().zip(&surface.vertices) {
            *slot = *v - normal * normal.dot(*v - mean);
        }
        let v = &vertices;
        let first = doubled_area_vector(v[0], v[1], v[2]).dot(normal) * 0.5;
        let second = if count == 4 {
            doubled_area_vector(v[0], v[2], v[3]).dot(normal) * 0.5
        } else {
            0.0
        };
        let area = first + second;
        if !(first > 0.0 && second >= 0.0 && area.is_finite()) {
            return Err(fail(
                GeometryFault::Degenerate,
                "has zero area, or vertices that run clockwise about its normal",
            ));
        }
        let mut edge_normals = [DVec3::ZERO; 4];
        let mut edge_offsets = [0.0; 4];
        for k in 0..count {
            let edge = v[(k + 1) % count] - v[k];
            let inward = normal.cross(edge).normalize_or_zero();
            if inward == DVec3::ZERO {
                return Err(fail(GeometryFault::Degenerate, "has a zero-length edge"));
            }
            edge_normals[k] = inward;
            edge_offsets[k] = inward.dot(v[k] - mean);
        }
        let geometry = SurfaceGeometry {
            normal,
            anchor: mean,
            vertices,
            count,
            edge_normals,
            edge_offsets,
            area,
            first_triangle_share: first / area,
        };
        // Convexity: every vertex lies inside every edge's half-plane.
        let size = (0..count)
            .map(|k| (v[k] - mean).length())
            .fold(0.0, f64::max);
        for k in 0..count {
            for j in (k + 2)..(k + count) {
                if geometry.edge_margin(k, v[j % count] - mean) < -1e-9 * size {
                    return Err(fail(GeometryFault::NonConvex, "is not convex"));
                }
            }
        }
        Ok(geometry)
    }

    /// Signed in-plane distance of `local` (relative to the anchor) inside edge `k`.
    #[inline]
    fn edge_margin(&self, k: usize, local: DVec3) -> f64 {
        self.edge_normals[k].dot(local) - self.edge_offsets[k]
    }

    /// The smallest edge margin of an in-plane point given relative to the
    /// anchor: positive inside, negative outside (the distance to the nearest
    /// edge line).
    pub(crate) fn inside_margin(&self, local: DVec3) -> f64 {
        (0..self.count)
            .map(|k| self.edge_margin(k, local))
            .fold(f64::INFINITY, f64::min)
    }

    /// The distance along the unit direction `dir` from `origin` to the polygon,
    /// if the ray's line meets it (t may be negative; callers choose the range).
    /// Points within `slack` outside an edge count as inside.
    #[inline]
    pub(crate) fn intersect(&self, origin: DVec3, dir: DVec3, slack: f64) -> Option<f64> {
        let along = self.normal.dot(dir);
        if along == 0.0 {
            return None;
        }
        let to_origin = origin - self.anchor;
        let t = -self.normal.dot(to_origin) / along;
        let local = to_origin + dir * t;
        for k in 0..self.count {
            if self.edge_margin(k, local) < -slack {
                return None;
            }
        }
        Some(t)
    }

    /// A point uniformly distributed by area, from two uniforms in [0, 1).
    pub(crate) fn sample(&self, u1: f64, u2: f64) -> DVec3 {
        let v = &self.vertices;
        let share = self.first_triangle_share;
        if u1 < share || self.count == 3 {
            let u = (u1 / share).min(1.0);
            point_in_triangle(v[0], v[1], v[2], u, u2)
        } else {
            let u = ((u1 - share) / (1.0 - share)).clamp(0.0, 1.0);
            point_in_triangle(v[0], v[2], v[3], u, u2)
        }
    }

    /// The distance of `point` from the polygon's plane, and its projection.
    pub(crate) fn project(&self, point: DVec3) -> (f64, DVec3) {
        let height = self.normal.dot(point - self.anchor);
        (height.abs(), point - self.normal * height)
    }

    /// The vertices projected onto the plane, in the surface's order.
    pub(crate) fn vertices(&self) -> &[DVec3] {
        &self.vertices[..self.count]
    }

    /// Axis-aligned bounds of the (projected) vertices.
    pub(crate) fn bounds(&self) -> (DVec3, DVec3) {
        let v = &self.vertices[..self.count];
        let lo = v.iter().copied().fold(DVec3::INFINITY, DVec3::min);
        let hi = v.iter().copied().fold(DVec3::NEG_INFINITY, DVec3::max);
        (lo, hi)
    }
}

/// A point uniformly distributed over triangle `a b c` (square-root warp of the
/// unit square onto barycentric coordinates).
fn point_in_triangle(a: DVec3, b: DVec3, c: DVec3, u1: f64, u2: f64) -> DVec3 {
    let root = u1.sqrt();
    a * (1.0 - root) + b * (root * (1.0 - u2)) + c * (root * u2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square() -> SurfaceGeometry {
        let v = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        SurfaceGeometry::new(0, &Surface::new(&v, 0, 0).unwrap()).unwrap()
    }

    #[test]
    fn rays_hit_inside_and_miss_outside() {
        let g = unit_square();
        let down = -DVec3::Z;
        let t = g.intersect(DVec3::new(0.3, 0.7, 2.0), down, 0.0).unwrap();
        assert!((t - 2.0).abs() < 1e-15);
        assert!(g.intersect(DVec3::new(1.2, 0.5, 2.0), down, 0.0).is_none());
        assert!(g
            .intersect(DVec3::new(0.5, 0.5, 2.0), DVec3::X, 0.0)
            .is_none());
        assert!((g.area - 1.0).abs() < 1e-15);
    }

    #[test]
    fn clockwise_winding_is_refused() {
        let v = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let mut s = Surface::new(&v, 0, 0).unwrap();
        s.normal = -s.normal;
        assert!(SurfaceGeometry::new(5, &s).is_err());
    }

    #[test]
    fn samples_cover_the_square_evenly() {
        // Quadrant counts of the sampler over a stratified grid of its
        // inputs: each near n/4, within five binomial standard deviations
        // (sqrt(n 3/16) = 43 for n = 10^4), as uniform random inputs give.
        let g = unit_square();
        let n = 10_000;
        let side = 100;
        let mut counts = [0usize; 4];
        for i in 0..n {
            let u = |k: usize| (k as f64 + 0.5) / side as f64;
            let p = g.sample(u(i / side), u(i % side));
            assert!(g.inside_margin(p - g.anchor) >= -1e-15);
            counts[(p.x >= 0.5) as usize + 2 * (p.y >= 0.5) as usize] += 1;
        }
        for c in counts {
            assert!((c as f64 - n as f64 / 4.0).abs() < 5.0 * 43.0, "{counts:?}");
        }
    }
}
