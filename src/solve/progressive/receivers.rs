//! The receivers of a shot: the leaf elements in a stable order, as polygons
//! for the shooter's item buffer (id = position in that order).

use crate::formfactor::{Occluders, Sources};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use glam::DVec3;
use rayon::prelude::*;
use slotmap::SecondaryMap;
use std::ops::Range;
use std::sync::Arc;

/// The leaf elements of a mesh as receivers. Rebuilt whenever the mesh is
/// refined.
#[derive(Clone, Debug)]
pub struct Receivers {
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
    /// Reflectance of each leaf.
    pub reflectances: Vec<Rgb>,
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
    /// Every patch of `patch_sources` as an occluder, for shadow rays.
    pub occluders: Arc<Occluders>,
}

impl Receivers {
    /// The current leaves of `mesh`.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        let leaves = mesh.leaves();
        let sources = Sources::from_elements(mesh, &leaves);
        let mut index = SecondaryMap::new();
        let mut eyes = Vec::with_capacity(leaves.len());
        let mut normals = Vec::with_capacity(leaves.len());
        let mut areas = Vec::with_capacity(leaves.len());
        let mut reflectances = Vec::with_capacity(leaves.len());
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
            eyes.push(e.centroid + n * (1e-6 * e.area.sqrt()));
            normals.push(n);
            areas.push(e.area);
            reflectances.push(mesh.surfaces[e.surface as usize].reflectance);
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
        Receivers {
            leaves,
            sources,
            patch_sources,
            patch_leaves,
            index,
            eyes,
            normals,
            areas,
            reflectances,
            exposed,
            exposure,
            occluders: Arc::new(occluders),
        }
    }

    /// Number of leaves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.leaves.len()
    }

    /// True when there are no leaves.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.leaves.is_empty()
    }
}
