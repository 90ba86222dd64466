//! Intersections with convex polygons by Sutherland-Hodgman clipping: the
//! subject polygon is clipped by one half-space per edge of the convex clip
//! polygon.
//!
//! Two flavours share the code. In a plane, each edge's half-space is bounded by
//! the plane through the edge perpendicular to the polygon. For a cone from an
//! apex, it is bounded by the plane through the apex and the edge; clipping a
//! polygon that lies in another plane by this cone gives exactly its
//! intersection with the central projection of the clip polygon from the apex,
//! without ever forming the projected vertices (which run off to infinity when
//! an edge passes level with the apex).

use super::lambert::check_polygon;
use crate::error::{Error, GeometryFault, Result};
use crate::math::{clip_to_halfspace, is_convex, newell_normal};
use glam::DVec3;
use smallvec::SmallVec;

/// A polygon as clipping produces it: usually a handful of vertices.
pub(crate) type ClippedPolygon = SmallVec<[DVec3; 8]>;

/// The intersection of two coplanar convex polygons (either winding). Empty when
/// they do not overlap (or touch only along an edge or at a vertex, up to
/// rounding).
///
/// Fails if either polygon has fewer than three finite vertices, is not planar,
/// or `clip` is not convex.
pub fn convex_intersection(subject: &[DVec3], clip: &[DVec3]) -> Result<ClippedPolygon> {
    check_polygon("subject polygon", subject)?;
    check_convex("clip polygon", clip)?;
    Ok(intersect_in_plane(subject, clip))
}

/// The part of `subject` inside the cone of rays from `apex` through the convex
/// polygon `clip`. When `subject` lies in a plane beyond `clip` (seen from the
/// apex), this is `subject` intersected with the shadow `clip` casts from a point
/// light at `apex`. Empty when `apex` lies in the plane of `clip` (a flat cone).
///
/// The cone is the set of points `apex + s (q - apex)` with `q` in `clip` and
/// `s >= 0`; it does not include the mirror cone behind the apex, but the
/// half-space test cannot tell the two apart, so `subject` must lie on the
/// clip polygon's side of the plane through `apex` parallel to it.
///
/// Fails on non-finite input, a degenerate or non-convex clip polygon.
pub fn clip_to_cone(subject: &[DVec3], apex: DVec3, clip: &[DVec3]) -> Result<ClippedPolygon> {
    check_polygon("subject polygon", subject)?;
    check_convex("clip polygon", clip)?;
    if !apex.is_finite() {
        return Err(Error::geometry(
            GeometryFault::NonFinite,
            format!("cone apex {apex} is not finite"),
        ));
    }
    Ok(intersect_with_cone(subject, apex, clip))
}

fn check_convex(what: &str, polygon: &[DVec3]) -> Result<()> {
    check_polygon(what, polygon)?;
    let n = newell_normal(polygon);
    if !is_convex(polygon, n) {
        return Err(Error::geometry(
            GeometryFault::NonConvex,
            format!("{what} is not strictly convex (or has repeated vertices)"),
        ));
    }
    Ok(())
}

/// [`convex_intersection`] without the input checks.
pub(crate) fn intersect_in_plane(subject: &[DVec3], clip: &[DVec3]) -> ClippedPolygon {
    let plane_normal = newell_normal(clip);
    if clip.len() < 3 || plane_normal.length_squared() == 0.0 {
        return ClippedPolygon::new();
    }
    clip_by_edge_planes(subject, clip, |a, b| (b - a).cross(plane_normal))
}

/// [`clip_to_cone`] without the input checks.
pub(crate) fn intersect_with_cone(
    subject: &[DVec3],
    apex: DVec3,
    clip: &[DVec3],
) -> ClippedPolygon {
    let plane_normal = newell_normal(clip);
    let area2 = plane_normal.length();
    if clip.len() < 3 || area2 == 0.0 {
        return ClippedPolygon::new();
    }
    let centre = vertex_mean(clip);
    let distance = (apex - centre).dot(plane_normal) / area2;
    let size = clip
        .iter()
        .map(|v| (*v - centre).length())
        .fold((apex - centre).length(), f64::max);
    if distance.abs() <= 1e-12 * size {
        return ClippedPolygon::new();
    }
    clip_by_edge_planes(subject, clip, |a, b| (a - apex).cross(b - apex))
}

/// Clips `subject` by one half-space per edge `(a, b)` of the convex `clip`.
/// Each half-space's boundary plane contains the edge and has the normal
/// `edge_plane_normal(a, b)`, turned to face the clip polygon's interior.
fn clip_by_edge_planes(
    subject: &[DVec3],
    clip: &[DVec3],
    edge_plane_normal: impl Fn(DVec3, DVec3) -> DVec3,
) -> ClippedPolygon {
    let interior = vertex_mean(clip);
    let mut out: ClippedPolygon = subject.iter().copied().collect();
    let m = clip.len();
    for i in 0..m {
        let a = clip[i];
        let b = clip[(i + 1) % m];
        let mut normal = edge_plane_normal(a, b);
        let side = normal.dot(interior - a);
        if side == 0.0 {
            // A zero-length edge, or an edge plane that misses no direction:
            // it bounds nothing.
            continue;
        }
        if side < 0.0 {
            normal = -normal;
        }
        out = clip_to_halfspace(&out, a, normal);
        if out.len() < 3 {
            return ClippedPolygon::new();
        }
    }
    out
}

/// The mean of the vertices: strictly inside a convex polygon.
fn vertex_mean(v: &[DVec3]) -> DVec3 {
    v.iter().copied().sum::<DVec3>() / v.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::polygon_area;

    fn square(x0: f64, z0: f64, side: f64, y: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(x0, y, z0),
            DVec3::new(x0 + side, y, z0),
            DVec3::new(x0 + side, y, z0 + side),
            DVec3::new(x0, y, z0 + side),
        ]
    }

    #[test]
    fn overlapping_squares_in_a_plane() {
        let a = square(0.0, 0.0, 2.0, 1.0);
        let b = square(1.0, 1.5, 2.0, 1.0);
        let i = convex_intersection(&a, &b).unwrap();
        assert!((polygon_area(&i) - 1.0 * 0.5).abs() < 1e-14);
        // The other winding of the clip polygon gives the same region.
        let mut b_rev = b.clone();
        b_rev.reverse();
        let j = convex_intersection(&a, &b_rev).unwrap();
        assert!((polygon_area(&j) - 0.5).abs() < 1e-14);
    }

    #[test]
    fn disjoint_squares_give_nothing() {
        let a = square(0.0, 0.0, 1.0, 0.0);
        let b = square(3.0, 0.0, 1.0, 0.0);
        assert!(convex_intersection(&a, &b).unwrap().is_empty());
    }

    #[test]
    fn cone_projection_doubles_at_twice_the_distance() {
        // A unit square at height 1 seen from the origin covers a 2 x 2 square at
        // height 2; clip a 4 x 4 square there by it.
        let apex = DVec3::ZERO;
        let clip = square(-0.5, -0.5, 1.0, 1.0);
        let subject = square(-2.0, -2.0, 4.0, 2.0);
        let i = clip_to_cone(&subject, apex, &clip).unwrap();
        assert!((polygon_area(&i) - 4.0).abs() < 1e-13);
    }

    #[test]
    fn cone_from_a_point_in_the_clip_plane_is_flat() {
        let clip = square(0.0, 0.0, 1.0, 1.0);
        let subject = square(-2.0, -2.0, 4.0, 2.0);
        let i = clip_to_cone(&subject, DVec3::new(5.0, 1.0, 0.0), &clip).unwrap();
        assert!(i.is_empty());
    }

    #[test]
    fn non_convex_clip_is_refused() {
        let dart = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.5, 0.0, 0.5),
            DVec3::new(0.0, 0.0, 2.0),
        ];
        let subject = square(0.0, 0.0, 1.0, 0.0);
        assert!(convex_intersection(&subject, &dart).is_err());
    }
}
