//! What the polygons under each node of the occluders' BVH add up to, so
//! that a node can be drawn as a single sample.

use crate::formfactor::Sources;
use glam::DVec3;
use obvhs::bvh2::Bvh2;
use smallvec::SmallVec;

/// How many of the patches under a BVH node its summary keeps.
pub(crate) const NODE_PATCHES: usize = 8;

/// [`NodePatch::surface`] of a part on several surfaces.
pub(crate) const MIXED: u32 = u32::MAX;

/// One of the patches under a BVH node: what a sample needs of its part
/// there without reading the polygons (which lie scattered in memory, and
/// reading them was most of a sample's time on the million-triangle atrium).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct NodePatch {
    /// The patch.
    pub(crate) patch: u32,
    /// The surface its polygons there lie on, or [`MIXED`] when they lie on
    /// several (a face cluster's facets). A receiver is never under a
    /// sample (it lies within a pixel of its own eye), so only a large
    /// planar surface, whose polygons are one surface's, can come back to
    /// its own receivers through a sample.
    pub(crate) surface: u32,
    /// The patch's area under the node, as far as the children's lists know.
    pub(crate) area: f32,
    /// The sum of its polygons' areas times their unit normals there: which
    /// way the part faces, and its projected area in any direction it faces.
    pub(crate) vector_area: [f32; 3],
    /// The area-weighted mean of its polygons' vertex means there (their
    /// centroids, but for quads that are not parallelograms), relative to
    /// the occluders' centre.
    pub(crate) centroid: [f32; 3],
}

impl NodePatch {
    /// The part's vector area.
    pub(crate) fn vector_area(&self) -> DVec3 {
        DVec3::from(self.vector_area.map(f64::from))
    }

    /// The part's centroid in the scene, for occluders centred at `centre`.
    pub(crate) fn centroid(&self, centre: DVec3) -> DVec3 {
        DVec3::from(self.centroid.map(f64::from)) + centre
    }

    /// Adds `other`, a part of the same patch.
    fn absorb(&mut self, other: &NodePatch) {
        let (a, b) = (f64::from(self.area), f64::from(other.area));
        let total = a + b;
        if total > 0.0 {
            for axis in 0..3 {
                let (p, q) = (
                    f64::from(self.centroid[axis]),
                    f64::from(other.centroid[axis]),
                );
                self.centroid[axis] = ((p * a + q * b) / total) as f32;
            }
        }
        for axis in 0..3 {
            self.vector_area[axis] += other.vector_area[axis];
        }
        self.area = total as f32;
        if self.surface != other.surface {
            self.surface = MIXED;
        }
    }
}

/// What the polygons under one BVH node add up to, for drawing the node as a
/// single sample (see `hemicube/cull.rs`).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct NodeSummary {
    /// The patches with the most area under the node, largest first (of each
    /// child's list, what the two lists hold); `len` of them are set.
    pub(crate) patches: [NodePatch; NODE_PATCHES],
    /// How many of `patches` are set.
    pub(crate) len: u8,
    /// The area of all the polygons under the node.
    pub(crate) area: f32,
    /// Polygons under the node.
    pub(crate) polygons: u32,
}

impl NodeSummary {
    /// The patches kept, largest first.
    pub(crate) fn patches(&self) -> &[NodePatch] {
        &self.patches[..self.len as usize]
    }

    /// Keeps the [`NODE_PATCHES`] largest of `list`, adding up the parts of
    /// one patch; ties go to the lower patch index, so the choice does not
    /// depend on the order of the list.
    fn keep_largest(&mut self, list: &mut SmallVec<[NodePatch; 16]>) {
        list.sort_unstable_by_key(|e| e.patch);
        list.dedup_by(|b, a| {
            let same = a.patch == b.patch;
            if same {
                a.absorb(b);
            }
            same
        });
        list.sort_by(|a, b| b.area.total_cmp(&a.area).then(a.patch.cmp(&b.patch)));
        let len = list.len().min(NODE_PATCHES);
        self.patches[..len].copy_from_slice(&list[..len]);
        self.len = len as u8;
    }
}

/// The summary of every node of `bvh` over the polygons of `sources`,
/// children before parents, with positions relative to `centre`.
pub(super) fn summarise(bvh: &Bvh2, sources: &Sources, centre: DVec3) -> Vec<NodeSummary> {
    let mut out = vec![NodeSummary::default(); bvh.nodes.len()];
    if bvh.nodes.is_empty() {
        return out;
    }
    let mut list: SmallVec<[NodePatch; 16]> = SmallVec::new();
    // Post order: a node is summed once both children are.
    let mut stack: Vec<(u32, bool)> = vec![(0, false)];
    while let Some((index, children_done)) = stack.pop() {
        let node = &bvh.nodes[index as usize];
        list.clear();
        let mut s = NodeSummary::default();
        if node.is_leaf() {
            let first = node.first_index as usize;
            for &prim in &bvh.primitive_indices[first..first + node.prim_count as usize] {
                let p = &sources.polygons[prim as usize];
                let area = crate::math::polygon_area(p.corners());
                s.polygons += 1;
                s.area += area as f32;
                let relative = p.centre - centre;
                list.push(NodePatch {
                    patch: p.patch,
                    surface: p.surface,
                    area: area as f32,
                    vector_area: (p.normal * area).as_vec3().to_array(),
                    centroid: relative.as_vec3().to_array(),
                });
            }
        } else if children_done {
            for child in [node.first_index, node.first_index + 1] {
                let c = &out[child as usize];
                s.polygons += c.polygons;
                s.area += c.area;
                list.extend_from_slice(c.patches());
            }
        } else {
            stack.push((index, true));
            stack.push((node.first_index, false));
            stack.push((node.first_index + 1, false));
            continue;
        }
        s.keep_largest(&mut list);
        out[index as usize] = s;
    }
    out
}
