//! Walking the occluders' BVH with a test of one's own on each node's box:
//! the queries of the form-factor stage cut the tree by planes (a shaft's
//! sides, a receiver's horizon), which the BVH crate's box and ray
//! traversals cannot express.

use glam::DVec3;
use obvhs::bvh2::Bvh2;

/// Visits the primitives of every leaf of `bvh` reached through nodes whose
/// box (`lo`, `hi`, world coordinates: the BVH's own plus `centre`) passes
/// `keep`, depth first, left child before right: the order the BVH's own
/// traversals use, so results do not depend on anything but the tree.
/// `visit` gets each primitive's index and returns false to stop the walk.
pub(super) fn walk(
    bvh: &Bvh2,
    centre: DVec3,
    mut keep: impl FnMut(DVec3, DVec3) -> bool,
    mut visit: impl FnMut(usize) -> bool,
) {
    if bvh.nodes.is_empty() {
        return;
    }
    let bounds = |i: u32| {
        let node = &bvh.nodes[i as usize];
        let aabb = node.aabb();
        (aabb.min.as_dvec3() + centre, aabb.max.as_dvec3() + centre)
    };
    let leaf = |i: u32, visit: &mut dyn FnMut(usize) -> bool| {
        let node = &bvh.nodes[i as usize];
        let first = node.first_index as usize;
        for slot in first..first + node.prim_count as usize {
            if !visit(bvh.primitive_indices[slot] as usize) {
                return false;
            }
        }
        true
    };
    let root = &bvh.nodes[0];
    let (lo, hi) = bounds(0);
    if !keep(lo, hi) {
        return;
    }
    if root.is_leaf() {
        leaf(0, &mut visit);
        return;
    }
    let mut stack: Vec<u32> = Vec::with_capacity(64);
    stack.push(root.first_index);
    while let Some(left) = stack.pop() {
        for index in [left, left + 1] {
            let (lo, hi) = bounds(index);
            if !keep(lo, hi) {
                continue;
            }
            let node = &bvh.nodes[index as usize];
            if node.is_leaf() {
                if !leaf(index, &mut visit) {
                    return;
                }
            } else {
                stack.push(node.first_index);
            }
        }
    }
}

/// True when the box (`lo`, `hi`) lies wholly on the negative side of the
/// plane through `origin` with normal `n`, by more than `margin`.
#[inline]
pub(super) fn box_below(lo: DVec3, hi: DVec3, origin: DVec3, n: DVec3, margin: f64) -> bool {
    let centre = (lo + hi) * 0.5;
    let half = (hi - lo) * 0.5;
    n.dot(centre - origin) + n.abs().dot(half) < -margin
}
