//! Back faces that front faces always hide.
//!
//! A hemi-cube draws the back of a single-sided polygon, since it hides what
//! lies behind it. But the back faces of a closed convex object seen from
//! outside it are always behind its front faces: a ray from the eye to a
//! point of a back face enters the solid first, through a front face nearer
//! the eye. Such back faces change no pixel (except where a front and a back
//! face meet at the silhouette, at equal depth, and rounding lets the back
//! one win a pixel the front one should have), so they need not be drawn.
//!
//! An object (the surfaces of one scene object) qualifies when it is convex
//! (every vertex of it on or behind every one of its surfaces' planes) and
//! watertight except for edges in one plane, the plane of its missing faces
//! (a block standing on the floor has no bottom). For an eye on or behind that
//! plane a ray cannot enter through the missing faces, so the argument holds
//! for any eye that is also strictly in front of one of its surfaces, that
//! is, outside the solid. A floor point under the block, inside it, keeps
//! every back face: they hide the whole room from it.

use super::unoccluded::{scene_scale, CONVEX_TOLERANCE};
use crate::mesh::Mesh;
use glam::DVec3;

/// Objects with more surfaces than this are not examined (matching their
/// edges costs the square of their edge count).
pub(super) const MAX_OBJECT_SURFACES: usize = 256;

/// Relative distance (to the scene's scale) within which two vertices are the
/// same point, for matching shared edges.
const SAME_POINT: f64 = 1e-9;

/// One closed (or closed but for one plane) convex object.
#[derive(Clone, Debug)]
struct ClosedObject {
    /// Front plane `(normal, offset)` of each of its surfaces.
    faces: Vec<(DVec3, f64)>,
    /// The plane of its missing faces, outward normal: the eye must lie on or
    /// behind it.
    missing: Option<(DVec3, f64)>,
}

impl ClosedObject {
    /// Whether the object's back faces are hidden from `eye`.
    fn hides_back_faces(&self, eye: DVec3) -> bool {
        let closed_side = self.missing.is_none_or(|(n, d)| n.dot(eye) - d <= 0.0);
        closed_side && self.faces.iter().any(|(n, d)| n.dot(eye) - d > 0.0)
    }
}

/// The closed convex objects of a mesh.
#[derive(Clone, Debug, Default)]
pub(crate) struct ClosedObjects {
    /// Per mesh surface, the index of its object in `objects`, if closed.
    object_of: Vec<Option<u32>>,
    objects: Vec<ClosedObject>,
}

impl ClosedObjects {
    /// Finds the scene objects of `mesh` whose back faces can hide nothing
    /// from outside them.
    #[must_use]
    pub(crate) fn new(mesh: &Mesh) -> Self {
        let scale = scene_scale(mesh);
        let mut by_object: Vec<Vec<u32>> = Vec::new();
        for (s, lattice) in mesh.surfaces.iter().enumerate() {
            let o = lattice.object as usize;
            if by_object.len() <= o {
                by_object.resize(o + 1, Vec::new());
            }
            by_object[o].push(s as u32);
        }
        let mut found = ClosedObjects {
            object_of: vec![None; mesh.surfaces.len()],
            objects: Vec::new(),
        };
        for surfaces in by_object {
            if surfaces.is_empty() || surfaces.len() > MAX_OBJECT_SURFACES {
                continue;
            }
            if let Some(object) = examine(mesh, &surfaces, scale) {
                let index = found.objects.len() as u32;
                for &s in &surfaces {
                    found.object_of[s as usize] = Some(index);
                }
                found.objects.push(object);
            }
        }
        found
    }

    /// True when no object qualifies.
    #[must_use]
    pub(crate) fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// Sets `hidden[s]`, for every mesh surface `s`, to whether its back
    /// face is hidden from `eye` by front faces of its own object.
    pub(crate) fn hidden_from(&self, eye: DVec3, hidden: &mut Vec<bool>) {
        let per_object: Vec<bool> = self
            .objects
            .iter()
            .map(|o| o.hides_back_faces(eye))
            .collect();
        hidden.clear();
        hidden.extend(
            self.object_of
                .iter()
                .map(|o| o.is_some_and(|i| per_object[i as usize])),
        );
    }
}

/// Per mesh surface, whether another surface lies back to back with it: the
/// same vertices in reverse order (a `doubleSided` material's two copies).
///
/// Wherever such a surface shows its back, its twin shows its front at the
/// same depth over the same pixels. Drawing the back too adds nothing to what
/// it hides and lets rounding give the back a share of the pixels the front
/// should take: light booked on back faces is lost to the solve (on a real
/// double-sided mesh, several per cent of the emitted power). So hemi-cubes
/// leave these back faces out.
#[must_use]
pub(crate) fn back_to_back_twins(mesh: &Mesh) -> Vec<bool> {
    use std::collections::HashMap;
    let key = |v: &[DVec3]| -> Vec<[u64; 3]> {
        let mut k: Vec<[u64; 3]> = v.iter().map(|p| p.to_array().map(f64::to_bits)).collect();
        k.sort_unstable();
        k
    };
    let mut twins = vec![false; mesh.surfaces.len()];
    let mut by_corners: HashMap<Vec<[u64; 3]>, Vec<u32>> = HashMap::new();
    for (s, lattice) in mesh.surfaces.iter().enumerate() {
        by_corners
            .entry(key(&lattice.vertices))
            .or_default()
            .push(s as u32);
    }
    for group in by_corners.values().filter(|g| g.len() > 1) {
        for (i, &a) in group.iter().enumerate() {
            for &b in &group[i + 1..] {
                if reversed(
                    &mesh.surfaces[a as usize].vertices,
                    &mesh.surfaces[b as usize].vertices,
                ) {
                    twins[a as usize] = true;
                    twins[b as usize] = true;
                }
            }
        }
    }
    twins
}

/// True when `b` runs through the vertices of `a` in the opposite order.
pub(super) fn reversed(a: &[DVec3], b: &[DVec3]) -> bool {
    let n = a.len();
    n == b.len() && (0..n).any(|shift| (0..n).all(|i| a[i] == b[(shift + n - i) % n]))
}

/// The object made of `surfaces` if it is convex and watertight but for
/// edges in one plane.
fn examine(mesh: &Mesh, surfaces: &[u32], scale: f64) -> Option<ClosedObject> {
    let tolerance = CONVEX_TOLERANCE * scale;
    let same = SAME_POINT * scale;
    let polygons: Vec<&[DVec3]> = surfaces
        .iter()
        .map(|&s| &mesh.surfaces[s as usize].vertices[..])
        .collect();
    let faces: Vec<(DVec3, f64)> = surfaces
        .iter()
        .map(|&s| {
            let l = &mesh.surfaces[s as usize];
            (l.normal, l.normal.dot(l.vertices[0]))
        })
        .collect();
    let vertices = || polygons.iter().flat_map(|p| p.iter().copied());
    // Convex: every vertex on or behind every plane.
    if !faces
        .iter()
        .all(|(n, d)| vertices().all(|v| n.dot(v) - d <= tolerance))
    {
        return None;
    }
    let edges: Vec<(DVec3, DVec3)> = polygons
        .iter()
        .flat_map(|p| (0..p.len()).map(move |i| (p[i], p[(i + 1) % p.len()])))
        .collect();
    let close = |a: DVec3, b: DVec3| (a - b).length() <= same;
    let mut open: Vec<DVec3> = Vec::new();
    for (i, &(a, b)) in edges.iter().enumerate() {
        let matches = edges
            .iter()
            .enumerate()
            .filter(|&(j, &(c, d))| j != i && close(a, d) && close(b, c))
            .count();
        match matches {
            0 => open.extend([a, b]),
            1 => {}
            _ => return None, // more than two surfaces at one edge
        }
    }
    let missing = if open.is_empty() {
        None
    } else {
        Some(missing_plane(&open, vertices(), tolerance)?)
    };
    Some(ClosedObject { faces, missing })
}

/// The plane through the open edges' `ends`, facing away from the object's
/// `vertices` (all on or behind it), if there is one.
fn missing_plane(
    ends: &[DVec3],
    vertices: impl Iterator<Item = DVec3> + Clone,
    tolerance: f64,
) -> Option<(DVec3, f64)> {
    let p0 = ends[0];
    let p1 = ends
        .iter()
        .copied()
        .max_by(|a, b| (*a - p0).length().total_cmp(&(*b - p0).length()))?;
    let p2 = ends.iter().copied().max_by(|a, b| {
        let area = |p: DVec3| (p1 - p0).cross(p - p0).length();
        area(*a).total_cmp(&area(*b))
    })?;
    let normal = (p1 - p0).cross(p2 - p0).normalize_or_zero();
    if normal == DVec3::ZERO {
        return None; // open edges along one line: no plane
    }
    let offset = normal.dot(p0);
    if ends
        .iter()
        .any(|p| (normal.dot(*p) - offset).abs() > tolerance)
    {
        return None; // open edges in more than one plane
    }
    let above = vertices.clone().any(|v| normal.dot(v) - offset > tolerance);
    let below = vertices
        .clone()
        .any(|v| normal.dot(v) - offset < -tolerance);
    match (above, below) {
        (false, true) => Some((normal, offset)),
        (true, false) => Some((-normal, -offset)),
        // A flat object has no back face hidden from any eye outside it; one
        // with vertices on both sides is not bounded by the plane.
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::{Scene, SceneBuilder};
    use crate::scenes;
    use glam::DVec3;

    fn surfaces_named(scene: &Scene, object: &str) -> Vec<u32> {
        let o = scene
            .objects
            .iter()
            .position(|x| x.name == object)
            .unwrap_or_else(|| panic!("no object {object}"));
        (0..scene.surfaces.len() as u32)
            .filter(|&s| scene.surfaces[s as usize].object as usize == o)
            .collect()
    }

    #[test]
    fn closed_convex_objects_hide_their_back_faces_only_from_outside() {
        let scene = scenes::cornell_box();
        let mesh = Mesh::new(&scene, scene.diameter() / 4.0, 10_000).unwrap();
        let objects = ClosedObjects::new(&mesh);
        let mut hidden = Vec::new();
        let hidden_for = |eye: DVec3, hidden: &mut Vec<bool>, object: &str| {
            objects.hidden_from(eye, hidden);
            surfaces_named(&scene, object)
                .iter()
                .map(|&s| hidden[s as usize])
                .collect::<Vec<bool>>()
        };
        // From the middle of the room both blocks (open only at the floor) hide
        // their back faces; no wall, nor the light, ever does.
        let centre = DVec3::new(0.28, 0.45, 0.28);
        for block in ["short_block", "tall_block"] {
            assert!(
                hidden_for(centre, &mut hidden, block).iter().all(|h| *h),
                "{block}"
            );
        }
        for other in [
            "floor",
            "ceiling",
            "back_wall",
            "left_wall",
            "right_wall",
            "light",
        ] {
            assert!(
                hidden_for(centre, &mut hidden, other).iter().all(|h| !*h),
                "{other}"
            );
        }
        // A floor point under the short block is inside it: every back face
        // counts there (they hide the whole room).
        let short = surfaces_named(&scene, "short_block");
        let top = short
            .iter()
            .map(|&s| &scene.surfaces[s as usize])
            .find(|s| s.normal.y > 0.9)
            .unwrap();
        let under = top.centroid() * DVec3::new(1.0, 0.0, 1.0) + DVec3::new(0.0, 1e-6, 0.0);
        assert!(hidden_for(under, &mut hidden, "short_block")
            .iter()
            .all(|h| !*h));
        // Below the floor a ray could enter through the missing bottom.
        let below = top.centroid() * DVec3::new(1.0, 0.0, 1.0) - DVec3::new(0.2, 0.1, 0.0);
        assert!(hidden_for(below, &mut hidden, "short_block")
            .iter()
            .all(|h| !*h));
    }

    #[test]
    fn an_open_box_shows_its_inside_through_the_opening() {
        let mut b = SceneBuilder::new("open_box");
        let m = b.material("m", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.axis_box("box", m, DVec3::ZERO, DVec3::ONE).unwrap();
        let closed = b.build().unwrap();
        let mut open = closed.clone();
        open.surfaces.retain(|s| s.normal.y < 0.9);
        assert_eq!(open.surfaces.len(), 5);
        let mut hidden = Vec::new();
        let all_hidden = |scene: &Scene, eye: DVec3, hidden: &mut Vec<bool>| {
            ClosedObjects::new(&Mesh::new(scene, 1.0, 100).unwrap()).hidden_from(eye, hidden);
            assert_eq!(hidden.len(), scene.surfaces.len());
            hidden.iter().all(|h| *h)
        };
        let (above, beside, inside) = (
            DVec3::new(0.5, 2.0, 0.5),
            DVec3::new(2.0, 0.5, 0.5),
            DVec3::new(0.5, 0.5, 0.5),
        );
        // Closed: hidden from anywhere outside.
        assert!(all_hidden(&closed, above, &mut hidden));
        assert!(all_hidden(&closed, beside, &mut hidden));
        assert!(!hidden.is_empty() && !all_hidden(&closed, inside, &mut hidden));
        assert!(hidden.iter().all(|h| !*h), "back faces hidden from inside");
        // Open at the top: from above, the inside shows through the opening.
        assert!(all_hidden(&open, beside, &mut hidden));
        all_hidden(&open, above, &mut hidden);
        assert!(
            hidden.iter().all(|h| !*h),
            "back faces hidden through the opening"
        );
        all_hidden(&open, inside, &mut hidden);
        assert!(hidden.iter().all(|h| !*h), "back faces hidden from inside");
    }
}
