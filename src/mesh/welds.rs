//! Corners that a smooth mesh shares between its facets, for display.
//!
//! Every surface of a real mesh is one small facet with vertices of its own
//! in the lattice, so a vertex's radiosity is its own facet's, and a
//! tessellated curved surface (a lamp's shade, a column) would be drawn as
//! the facets it was cut into, each lit evenly. Where facets of one object
//! meet at a corner with normals within [`SMOOTH_ANGLE_DEGREES`] of each
//! other (the angle under which face clusters treat them as one curved
//! surface), the corner is one vertex of a smooth surface: its value is
//! the mean over the leaves of all of them, so the light varies smoothly
//! across the facets. Sharper edges (a box's, a step's) stay sharp, as do a
//! double-sided surface's two sides, which face opposite ways.

use super::shading::VertexId;
use super::Mesh;
use crate::mesh::clusters::MAX_CLUSTER_ANGLE_DEGREES;
use glam::DVec3;
use smallvec::SmallVec;
use std::collections::HashMap;

/// Facets meeting at a corner at less than this angle between their normals
/// are drawn as one smooth surface there.
pub(crate) const SMOOTH_ANGLE_DEGREES: f64 = MAX_CLUSTER_ANGLE_DEGREES;

/// Groups of surface corners drawn as one vertex.
#[derive(Clone, Debug, Default)]
pub(crate) struct Welds {
    /// Per welded corner, its group.
    group_of: HashMap<VertexId, u32>,
    /// How many groups there are.
    groups: u32,
}

impl Welds {
    /// The welds of `mesh`'s surface corners among surfaces that `joins`
    /// lets meet (called with two surface indices; for instance, the same
    /// reflectance where radiosities are averaged).
    pub(crate) fn new(mesh: &Mesh, joins: impl Fn(u32, u32) -> bool) -> Self {
        let min_cos = SMOOTH_ANGLE_DEGREES.to_radians().cos();
        let mut at: HashMap<[u64; 3], SmallVec<[Corner; 6]>> = HashMap::new();
        for (s, lattice) in mesh.surfaces.iter().enumerate() {
            for (corner, id) in lattice
                .vertices
                .iter()
                .zip(corner_ids(lattice.extent, lattice.vertices.len()))
            {
                at.entry(corner.to_array().map(f64::to_bits))
                    .or_default()
                    .push((s as u32, id));
            }
        }
        let mut welds = Welds::default();
        let mut keys: Vec<&[u64; 3]> = at.keys().collect();
        // In a fixed order, so that group numbers do not depend on hashing.
        keys.sort_unstable();
        for key in keys {
            let members = &at[key];
            if members.len() < 2 {
                continue;
            }
            let mut taken = vec![false; members.len()];
            for i in 0..members.len() {
                if taken[i] {
                    continue;
                }
                let (seed, seed_id) = members[i];
                let seed_lattice = &mesh.surfaces[seed as usize];
                let mut group: SmallVec<[VertexId; 6]> = SmallVec::new();
                group.push((seed, seed_id.0, seed_id.1));
                for j in i + 1..members.len() {
                    let (other, id) = members[j];
                    let lattice = &mesh.surfaces[other as usize];
                    if !taken[j]
                        && other != seed
                        && lattice.object == seed_lattice.object
                        && normal_agrees(seed_lattice.normal, lattice.normal, min_cos)
                        && joins(seed, other)
                    {
                        taken[j] = true;
                        group.push((other, id.0, id.1));
                    }
                }
                if group.len() > 1 {
                    for v in group {
                        welds.group_of.insert(v, welds.groups);
                    }
                    welds.groups += 1;
                }
            }
        }
        welds
    }

    /// Adds up the sums of each group's corners and gives every corner of a
    /// group the group's total, so that their means are the group's mean.
    pub(crate) fn pool<T: Copy + Default>(
        &self,
        sums: &mut HashMap<VertexId, T>,
        add: impl Fn(&mut T, &T),
    ) {
        if self.groups == 0 {
            return;
        }
        let mut totals = vec![T::default(); self.groups as usize];
        for (v, g) in &self.group_of {
            if let Some(s) = sums.get(v) {
                add(&mut totals[*g as usize], s);
            }
        }
        for (v, g) in &self.group_of {
            if let Some(s) = sums.get_mut(v) {
                *s = totals[*g as usize];
            }
        }
    }
}

/// A surface and the lattice coordinates of one of its corners.
type Corner = (u32, (u32, u32));

fn normal_agrees(a: DVec3, b: DVec3, min_cos: f64) -> bool {
    a.dot(b) >= min_cos
}

/// The lattice coordinates of a surface's corners, in vertex order: a quad's
/// lattice runs from vertex 0 along edge 0-1 and edge 0-3; a triangle's
/// barycentric lattice from vertex 0 towards vertices 1 and 2.
pub(super) fn corner_ids(extent: (u32, u32), corners: usize) -> SmallVec<[(u32, u32); 4]> {
    let (a, b) = extent;
    if corners == 4 {
        SmallVec::from_slice(&[(0, 0), (a, 0), (a, b), (0, b)])
    } else {
        SmallVec::from_slice(&[(0, 0), (a, 0), (0, a)])
    }
}

#[cfg(test)]
mod tests {
    use crate::math::Rgb;
    use crate::mesh::Mesh;
    use crate::scene::{Scene, SceneBuilder};
    use glam::DVec3;

    /// Two unit right triangles sharing the edge from the origin along z,
    /// their normals `degrees` apart (0: one flat square's halves); in one
    /// object or two.
    fn hinge(degrees: f64, one_object: bool) -> Scene {
        let mut b = SceneBuilder::new("hinge");
        let m = b.material("m", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let t = degrees.to_radians();
        b.object("a");
        b.triangle(m, DVec3::ZERO, DVec3::Z, DVec3::X).unwrap();
        if !one_object {
            b.object("b");
        }
        // Turned about z: the far corner leaves the -x axis.
        let far = DVec3::new(-t.cos(), t.sin(), 0.0);
        b.triangle(m, DVec3::Z, DVec3::ZERO, far).unwrap();
        b.build().unwrap()
    }

    /// The radiosity drawn at the origin on each of the two surfaces when
    /// the first is lit 1 and the second 3.
    fn at_origin(scene: &Scene) -> (Rgb, Rgb) {
        let mesh = Mesh::new(scene, 10.0, 100).unwrap();
        let vr = mesh.vertex_radiosity(|k| {
            if mesh.elements[k].surface == 0 {
                Rgb::splat(1.0)
            } else {
                Rgb::splat(3.0)
            }
        });
        // The origin is the first corner of the first triangle and the
        // second of the second (lattice (L, 0) for L = 2^12 at patch level).
        (vr.values[&(0, 0, 0)], vr.values[&(1, 1 << 12, 0)])
    }

    #[test]
    fn facets_of_one_object_meeting_at_a_small_angle_share_their_corners() {
        // Equal areas lit 1 and 3: one mean, 2, on both.
        let (a, b) = at_origin(&hinge(20.0, true));
        assert!(
            (a.0[0] - 2.0).abs() < 1e-12 && (b.0[0] - 2.0).abs() < 1e-12,
            "{a:?} {b:?}"
        );
    }

    #[test]
    fn a_sharp_edge_or_another_object_keeps_its_own_corners() {
        let (a, _) = at_origin(&hinge(90.0, true));
        assert_eq!(a.0[0], 1.0);
        let (a, _) = at_origin(&hinge(20.0, false));
        assert_eq!(a.0[0], 1.0);
    }
}
