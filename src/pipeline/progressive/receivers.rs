//! The receivers of a shot: the leaf elements in a stable order, as polygons
//! for the shooter's item buffer (id = position in that order).

use crate::formfactor::{back_to_back_twins, receiving_point, Occluders, Sources};
use crate::mesh::{ElementKey, Mesh};
use glam::DVec3;
use rayon::prelude::*;
use slotmap::SecondaryMap;
use std::ops::Range;
use std::sync::Arc;

/// The leaf elements of a mesh as receivers. Rebuilt whenever the mesh is
/// refined.
#[derive(Clone, Debug)]
pub(crate) struct Receivers {
    /// Leaf keys, patch by patch (the order of [`Mesh::leaves`]).
    pub leaves: Vec<ElementKey>,
    /// Leaf polygons; polygon `i` is leaf `i`.
    pub sources: Sources,
    /// Patch polygons; polygon `p` is patch `p`.
    pub patch_sources: Sources,
    /// The leaves of each patch: a range of leaf indices (leaves are stored
    /// patch by patch).
    pub patch_leaves: Vec<Range<u32>>,
    /// Position of each leaf in `leaves`.
    pub index: SecondaryMap<ElementKey, u32>,
    /// Where each leaf receives: its centroid lifted off the surface by a
    /// distance relative to its own size (as its gathering hemi-cube would be).
    pub eyes: Vec<DVec3>,
    /// Unit normal of each leaf.
    pub normals: Vec<DVec3>,
    /// Area of each leaf.
    pub areas: Vec<f64>,
    /// Whether each leaf is exposed: whether its receiving point sees anything
    /// but back faces (see `Occluders::is_shut_in`). A leaf that is not, such
    /// as one under a box standing on it, does not shoot, as its empty row
    /// keeps it out of the exchange when gathering; it receives only on the
    /// part of it the shooters see (none, if it lies wholly under the box).
    /// Once rows are gathered, the rows decide instead.
    pub exposed: Vec<bool>,
    /// The exposure of each leaf: the part of its view that front faces fill,
    /// its weight (times its area) in its patch's radiosity as a source. Its
    /// gathering row's sum once it has one; before, 1 where `exposed` and 0
    /// where not.
    pub exposure: Vec<f64>,
    /// The share of each leaf that other objects do not cover: 1 until its
    /// gathering row says otherwise (see `formfactor/contacts.rs`).
    pub visible: Vec<f64>,
    /// Every patch of `patch_sources` as an occluder, for shadow rays.
    pub occluders: Arc<Occluders>,
    /// Per surface, whether a back-to-back twin hides its back (see
    /// `formfactor::back_to_back_twins`); `None` when no surface has one.
    /// Shooting hemi-cubes leave those backs out, as gathering ones do:
    /// drawn, they tie in depth with their twins' fronts and rounding gives
    /// them a share of the pixels the fronts should take.
    pub twins: Option<Vec<bool>>,
}

impl Receivers {
    /// The current leaves of `mesh`.
    #[must_use]
    pub(crate) fn new(mesh: &Mesh) -> Self {
        let leaves = mesh.leaves();
        let sources = Sources::from_elements(mesh, &leaves);
        let mut index = SecondaryMap::new();
        let mut eyes = Vec::with_capacity(leaves.len());
        let mut normals = Vec::with_capacity(leaves.len());
        let mut areas = Vec::with_capacity(leaves.len());
        let mut patch_leaves = vec![0..0; mesh.patches.len()];
        for (i, &k) in leaves.iter().enumerate() {
            let e = &mesh.elements[k];
            let n = mesh.surfaces[e.surface as usize].normal;
            index.insert(k, i as u32);
            let range = &mut patch_leaves[e.patch as usize];
            if range.start == range.end {
                *range = i as u32..i as u32;
            }
            range.end = i as u32 + 1;
            eyes.push(receiving_point(e.centroid, n, e.area));
            normals.push(n);
            areas.push(e.area);
        }
        let patch_sources = Sources::from_mesh(mesh);
        let occluders = Occluders::new(&patch_sources);
        let exposed: Vec<bool> = leaves
            .par_iter()
            .zip(&eyes)
            .zip(&normals)
            .map(|((k, eye), normal)| {
                let surface = mesh.elements[*k].surface;
                !occluders.is_shut_in(&patch_sources, *eye, *normal, surface)
            })
            .collect();
        let exposure = exposed.iter().map(|&x| if x { 1.0 } else { 0.0 }).collect();
        let visible = vec![1.0; leaves.len()];
        Receivers {
            leaves,
            sources,
            patch_sources,
            patch_leaves,
            index,
            eyes,
            normals,
            areas,
            exposed,
            exposure,
            visible,
            occluders: Arc::new(occluders),
            twins: Some(back_to_back_twins(mesh)).filter(|t| t.iter().any(|&t| t)),
        }
    }

    /// Number of leaves.
    #[must_use]
    pub(crate) fn len(&self) -> usize {
        self.leaves.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::SolverKind;
    use crate::refine::RefineSettings;
    use crate::scenes;
    use crate::Settings;

    #[test]
    fn leaves_shut_in_under_the_blocks_are_the_leaves_gathering_leaves_out() {
        // The shooter finds shut-in leaves with a fan of rays; gathering finds
        // them as leaves whose hemi-cube saw no front face (an empty row). On the
        // same uniform mesh the two must pick the same floor leaves, but for
        // those a block's edge crosses, which gather at a visible point. Shut-in
        // leaves shoot nothing, and receive only on the part of them that sticks
        // out from under the block (less than half, as their centre is under it).
        let scene = scenes::cornell_box();
        let settings = Settings {
            patch_size: Some(0.14),
            refine: RefineSettings {
                uniform_depth: Some(2),
                ..RefineSettings::default()
            },
            ..Settings::default()
        };
        let gathered = crate::solve(&scene, &settings, &|_| {}).unwrap();
        let shot = crate::solve(
            &scene,
            &Settings {
                solver_kind: SolverKind::Progressive,
                ..settings
            },
            &|_| {},
        )
        .unwrap();
        let receivers = Receivers::new(shot.mesh());
        let floor = scene
            .surfaces
            .iter()
            .position(|s| scene.objects[s.object as usize].name == "floor")
            .unwrap() as u32;
        let (mut shut, mut checked, mut dark, mut partly) = (0, 0, 0, 0);
        let (mut shut_power, mut shut_area, mut power, mut area) = (0.0, 0.0, 0.0, 0.0);
        for (i, (g, p)) in gathered
            .mesh()
            .leaves()
            .iter()
            .zip(&receivers.leaves)
            .enumerate()
        {
            let (g, p) = (gathered.leaf(*g), shot.leaf(*p));
            assert_eq!(g.cell, p.cell);
            if g.surface != floor {
                continue;
            }
            checked += 1;
            let exposed = receivers.exposed[i];
            if g.row.view().is_some_and(|v| v.covered > 0.0) {
                // A block's edge crosses the leaf: its row is taken at a
                // visible point, whatever the fan at its centre says.
                partly += 1;
                assert!(g.row.is_exposed(), "floor leaf {:?}", g.cell);
            } else {
                assert_eq!(g.row.is_exposed(), exposed, "floor leaf {:?}", g.cell);
            }
            let b = p.radiosity.max_band();
            power += b * p.area;
            area += p.area;
            if !exposed {
                shut += 1;
                shut_power += b * p.area;
                shut_area += p.area;
                dark += usize::from(b == 0.0);
            }
        }
        assert!(shut > 0 && shut < checked, "{shut} of {checked}");
        assert!(partly > 0, "no leaf found partly under a block");
        assert!(dark > 0, "leaves wholly under a block receive nothing");
        assert!(
            shut_power / shut_area < 0.5 * power / area,
            "shut-in leaves {} vs the floor's mean {}",
            shut_power / shut_area,
            power / area
        );
    }
}
