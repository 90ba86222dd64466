//! Rows with nothing in the way: the convex enclosure.
//!
//! When every vertex of every surface lies on or in front of every surface's
//! plane, all surfaces lie on the boundary of the convex region those front
//! half-spaces bound. A segment between two points of that region stays in
//! it, and meets a surface's plane only at its ends unless it lies in the
//! plane, where it subtends no solid angle. So no surface hides any part of
//! another from any point, and an element's row is Lambert's exact
//! point-to-polygon form factor to every patch off its own surface, with no
//! hemi-cube at all. Furnaces, the 6-patch cube and empty rooms are such
//! scenes; anything standing inside a room is not.

use super::{point_to_polygon, Row, Sources};
use crate::mesh::Mesh;
use glam::DVec3;

/// How far, relative to the scene's [`scene_scale`], a vertex may lie
/// behind a plane and still count as on it: a shared edge's vertices read from
/// single-precision files differ by about `1e-7` of the coordinates. An
/// occluder thinner than this hides nothing measurable.
pub(super) const CONVEX_TOLERANCE: f64 = 1e-6;

/// Most distinct planes a scene may have for [`is_convex_enclosure`] to
/// check it: the check costs planes times vertices, and a scene with more
/// planes than this is treated as not convex (its rows take the general
/// path, which is right for any scene).
const MAX_PLANES: usize = 4096;

/// Whether the surfaces of `mesh` form a convex enclosure (or an open part of
/// one): every vertex of every surface on or in front of every surface's
/// plane, within [`CONVEX_TOLERANCE`] of the scene's scale plus the plane's
/// own departure from planarity. Then no element's view is occluded.
///
/// Each new plane is checked against every vertex as soon as it is met, so
/// that a scene with anything standing inside it is refused at its first
/// such plane rather than after all planes are collected (an interior of a
/// million triangles spent minutes collecting them). Past [`MAX_PLANES`]
/// distinct planes the answer is false.
#[must_use]
pub(crate) fn is_convex_enclosure(mesh: &Mesh) -> bool {
    let scale = scene_scale(mesh);
    let base = CONVEX_TOLERANCE * scale;
    let in_front = |n: DVec3, d: f64, warp: f64| {
        mesh.surfaces
            .iter()
            .flat_map(|s| s.vertices.iter())
            .all(|v| n.dot(*v) - d >= -(base + warp))
    };
    // Distinct planes only: a tessellated wall is one plane however many
    // surfaces it is cut into, so the test costs vertices times planes.
    // A surface that joins a plane already checked widens its tolerance by
    // its own warp, and the plane is checked again if it widened. A plane is
    // refused at the tolerance of the surfaces met so far, so a vertex that
    // only a later member's warp would have let through is refused too:
    // false is safe (the general path), and only warped quads are affected.
    let mut planes: Vec<(DVec3, f64, f64)> = Vec::new();
    for s in &mesh.surfaces {
        let n = s.normal;
        let d = n.dot(s.vertices[0]);
        let warp = s
            .vertices
            .iter()
            .map(|v| (n.dot(*v) - d).abs())
            .fold(0.0, f64::max);
        let same = planes
            .iter_mut()
            .find(|(m, e, _)| m.dot(n) >= 1.0 - 1e-12 && (e - d).abs() <= base);
        match same {
            Some(plane) if plane.2 >= warp => {}
            Some(plane) => {
                plane.2 = warp;
                let (m, e, w) = *plane;
                if !in_front(m, e, w) {
                    return false;
                }
            }
            None => {
                if planes.len() == MAX_PLANES || !in_front(n, d, warp) {
                    return false;
                }
                planes.push((n, d, warp));
            }
        }
    }
    true
}

/// The exact unoccluded row of a differential area at `eye` with unit
/// `normal`: Lambert's form factor to each polygon of `sources` not on
/// `own_surface`, clipped to the horizon; zeros are not stored. Only a scene for which
/// [`is_convex_enclosure`] holds has such rows: elsewhere they ignore
/// occlusion. As with the hybrid method, a row whose sum would exceed 1 (by
/// rounding) is scaled back to 1.
#[must_use]
pub(crate) fn unoccluded_row(
    sources: &Sources,
    eye: DVec3,
    normal: DVec3,
    own_surface: u32,
) -> Row {
    let mut entries: Vec<(u32, f64)> = Vec::new();
    for p in 0..sources.patch_count() as u32 {
        let polygons = sources.patch(p);
        let cluster = polygons.len() > 1;
        let mut f = 0.0;
        for poly in polygons {
            if poly.surface == own_surface
                || (poly.centre - eye).dot(normal) < -poly.radius
                || (cluster && !poly.faces(eye))
            {
                continue;
            }
            f += point_to_polygon(eye, normal, poly.corners());
        }
        if f > 0.0 {
            entries.push((p, f));
        }
    }
    let sum: f64 = entries.iter().map(|e| e.1).sum();
    if sum > 1.0 {
        for e in &mut entries {
            e.1 /= sum;
        }
    }
    // Every surface faces into a convex enclosure, so no back face is in
    // view: what the surfaces leave of the hemisphere is open sky.
    Row::from_sorted(entries.into_iter().map(|(i, f)| (i, f as f32)).collect())
        .with_hidden(0.0, (1.0 - sum).max(0.0))
}

/// The scene's bounding-box diagonal plus its largest coordinate: the scale
/// of the rounding error of any coordinate or plane offset.
#[must_use]
pub(crate) fn scene_scale(mesh: &Mesh) -> f64 {
    let mut lo = DVec3::INFINITY;
    let mut hi = DVec3::NEG_INFINITY;
    for v in mesh.surfaces.iter().flat_map(|s| s.vertices.iter()) {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    if lo.x > hi.x {
        return 0.0;
    }
    (hi - lo).length() + lo.abs().max(hi.abs()).max_element()
}
