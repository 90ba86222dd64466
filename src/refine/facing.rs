//! Facing surfaces closer than their leaves are wide.
//!
//! The contrast criterion compares neighbours' radiosities, each gathered at
//! the leaf's centre, so a shadow narrower than a leaf leaves no mark when no
//! centre falls in it. A bench's seat 0.4 m over a floor leaf 2 m wide is
//! such a shadow: the floor under the seat keeps the value of the open floor
//! beyond it, the seat's underside gathers that bright floor, and nothing
//! ever splits (measured on the 10 000-triangle atrium, the undersides of the
//! benches in the dim ambulatories came out 40% too bright, and no finer
//! contrast floor or deeper limit found the shadow).
//!
//! Where a surface faces another across a gap narrower than the other's
//! leaves, the light on those leaves changes over the gap's width: what
//! faces them hides the light from one side. So a leaf under the foot of a
//! receiver that faces it, sees it and stands closer than the leaf's size
//! (see [`FACING_SPLIT`]) is split, whatever the radiosities say; the
//! contrast criterion then takes over on the finer leaves. The test is
//! geometric and symmetric: the two faces of a gap are refined to about the
//! gap's width where they overlap, and no further by this rule, so it cannot
//! run away in a corner (perpendicular faces do not face each other).

use crate::mesh::{ElementKey, Mesh, MAX_DEPTH};
use rayon::prelude::*;
use smallvec::SmallVec;

/// A receiver faces a surface when their normals are within about 25
/// degrees of opposite: the cosine of the angle between them is below minus
/// this. At 0.7 (45 degrees) the Ferren sculpture's last boards, turned 30
/// degrees from the right wall they face, split the wall and came out
/// brighter still (mean per-object error 1.43% -> 1.53%); at 0.9 its error
/// is as before (1.42%) and the atrium's the same as at 0.7.
pub(crate) const FACING_COS: f64 = 0.9;

/// A leaf under a facing receiver's foot is split while its bounding radius
/// exceeds this many times the receiver's distance from its plane: at the
/// end its centre lies within about half the gap's width of any point under
/// the receiver, where the shadow of a seat 0.36 m deep and 0.4 m high
/// shows.
pub(crate) const FACING_SPLIT: f64 = 0.5;

/// The least form factor from a receiver to a patch of the faced surface for
/// the rule to apply: the receiver must see the surface, not a face of it
/// behind something else.
pub(crate) const FACING_MIN_FF: f64 = 0.05;

/// Lengths below this fraction of a surface's patch size are taken for
/// rounding: a foot that far outside an edge is on it.
const ON_THE_LINE: f64 = 1e-9;

/// The leaves that a facing receiver stands too close to (see the module
/// notes), each once, in `leaves` order; only leaves that may split (depth
/// below `max_depth`, children no smaller than `min_area`). `entries(k)` is
/// leaf `k`'s row: (patch, form factor) pairs, empty when unknown.
#[must_use]
pub(crate) fn mark_facing<'a>(
    mesh: &Mesh,
    leaves: &[ElementKey],
    entries: &(dyn Fn(ElementKey) -> &'a [(u32, f32)] + Sync),
    max_depth: u8,
    min_area: f64,
) -> Vec<ElementKey> {
    let surfaces = mesh.surfaces();
    let patches = mesh.patches();
    let found: Vec<SmallVec<[ElementKey; 2]>> = leaves
        .par_iter()
        .map(|&k| {
            let e = &mesh.elements[k];
            let normal = surfaces[e.surface as usize].normal;
            let mut out: SmallVec<[ElementKey; 2]> = SmallVec::new();
            let mut seen: SmallVec<[u32; 4]> = SmallVec::new();
            for &(j, f) in entries(k) {
                if f64::from(f) < FACING_MIN_FF {
                    continue;
                }
                let patch = &patches[j as usize];
                if patch.is_cluster() || seen.contains(&patch.surface) {
                    continue;
                }
                seen.push(patch.surface);
                let lattice = &surfaces[patch.surface as usize];
                if normal.dot(lattice.normal) > -FACING_COS {
                    continue;
                }
                // Rounding must not decide a receiver in the plane or a foot
                // on the edge: what they come to depends on where the scene
                // sits and at what scale (a foot exactly on an edge read
                // 0 at one scale and 1e-19 at another, and the two meshes
                // differed).
                let rounding = ON_THE_LINE * lattice.patch_size;
                let height = lattice.normal.dot(e.centroid - lattice.vertices[0]);
                if height <= rounding {
                    continue;
                }
                let foot = e.centroid - lattice.normal * height;
                if lattice.outside_distance(foot) > rounding {
                    continue;
                }
                let Some(under) = mesh.locate(patch.surface, lattice.probe_at(foot), MAX_DEPTH)
                else {
                    continue;
                };
                let leaf = &mesh.elements[under];
                if !leaf.is_leaf() || leaf.depth >= max_depth || leaf.area * 0.25 < min_area {
                    continue;
                }
                let radius = lattice
                    .polygon(&leaf.cell)
                    .iter()
                    .map(|v| (*v - leaf.centroid).length())
                    .fold(0.0, f64::max);
                if radius > FACING_SPLIT * height && !out.contains(&under) {
                    out.push(under);
                }
            }
            out
        })
        .collect();
    let mut marked = std::collections::HashSet::new();
    let mut split = Vec::new();
    for k in found.into_iter().flatten() {
        if marked.insert(k) {
            split.push(k);
        }
    }
    split
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::SceneBuilder;
    use glam::DVec3;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    /// A 4 m floor (one patch, one leaf) and a 1.8 m by 0.36 m seat at
    /// `height` over its middle, facing `down` or up.
    fn seat_over_floor(height: f64, down: bool) -> Mesh {
        let mut b = SceneBuilder::new("seat over a floor");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("floor");
        b.quad(
            grey,
            v(0., 0., 0.),
            v(0., 0., 4.),
            v(4., 0., 4.),
            v(4., 0., 0.),
        )
        .unwrap();
        b.object("seat");
        let (a, c) = (v(1.1, height, 1.82), v(2.9, height, 2.18));
        if down {
            b.quad(grey, a, v(c.x, height, a.z), c, v(a.x, height, c.z))
                .unwrap();
        } else {
            b.quad(grey, a, v(a.x, height, c.z), c, v(c.x, height, a.z))
                .unwrap();
        }
        Mesh::new(&b.build().unwrap(), 4.0, usize::MAX).unwrap()
    }

    /// The floor's leaf and the seat's leaves, the seat's row being a form
    /// factor `f` to the floor's patch.
    fn marked(mesh: &Mesh, f: f32) -> (ElementKey, Vec<ElementKey>) {
        let leaves = mesh.leaves();
        let floor = *leaves
            .iter()
            .find(|&&k| mesh.elements[k].surface == 0)
            .unwrap();
        let floor_patch = mesh.elements[floor].patch;
        let row = [(floor_patch, f)];
        let entries = |k: ElementKey| -> &[(u32, f32)] {
            if mesh.elements[k].surface == 1 {
                &row
            } else {
                &[]
            }
        };
        let found = mark_facing(mesh, &leaves, &entries, 4, 1e-6);
        (floor, found)
    }

    #[test]
    fn a_seat_close_over_a_floor_leaf_splits_it() {
        // The floor leaf's bounding radius is 2 sqrt 2 = 2.83 m, more than
        // half of 0.4 m: split.
        let mesh = seat_over_floor(0.4, true);
        let (floor, found) = marked(&mesh, 0.6);
        assert_eq!(found, vec![floor]);
    }

    #[test]
    fn no_split_far_away_facing_up_or_unseen() {
        // 6 m up: the radius 2.83 m is under half the distance.
        let (_, found) = marked(&seat_over_floor(6.0, true), 0.6);
        assert!(found.is_empty(), "{found:?}");
        // Facing up, the seat does not face the floor.
        let (_, found) = marked(&seat_over_floor(0.4, false), 0.6);
        assert!(found.is_empty(), "{found:?}");
        // Seeing the floor only under the least form factor: something
        // stands between.
        let (_, found) = marked(&seat_over_floor(0.4, true), 0.01);
        assert!(found.is_empty(), "{found:?}");
    }

    #[test]
    fn leaves_that_may_not_split_are_left() {
        let mesh = seat_over_floor(0.4, true);
        let leaves = mesh.leaves();
        let floor_patch = mesh.elements[leaves[0]].patch;
        let row = [(floor_patch, 0.6f32)];
        let entries = |_: ElementKey| -> &[(u32, f32)] { &row };
        // At the deepest level allowed, or with children under the least area.
        assert!(mark_facing(&mesh, &leaves, &entries, 0, 1e-6).is_empty());
        assert!(mark_facing(&mesh, &leaves, &entries, 4, 5.0).is_empty());
    }
}
