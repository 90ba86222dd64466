//! Patches and elements.

use super::cell::Cell;
use crate::math::Rgb;
use glam::DVec3;
use smallvec::SmallVec;

slotmap::new_key_type! {
    /// Key of an element in the mesh's arena.
    pub struct ElementKey;
}

/// A patch: a constant-radiosity source of the coarse system, and the root of
/// one element quadtree, or of several for a face cluster (see
/// [`super::clusters`]).
#[derive(Clone, Debug)]
pub struct Patch {
    /// The scene surface it lies on; a face cluster's first surface (its
    /// surfaces share one object and material).
    pub surface: u32,
    /// Its root elements: one for a cell of a surface's lattice, one per
    /// surface for a face cluster, in surface order.
    pub roots: SmallVec<[ElementKey; 1]>,
    /// World polygon of its first root, counter-clockwise around the surface
    /// normal (the whole patch unless it is a cluster).
    pub polygon: SmallVec<[DVec3; 4]>,
    /// Area in square metres.
    pub area: f64,
    /// Area centroid.
    pub centroid: DVec3,
}

impl Patch {
    /// True for a face cluster: a patch of several surfaces.
    #[must_use]
    pub(crate) fn is_cluster(&self) -> bool {
        self.roots.len() > 1
    }
}

/// A quadtree node. Leaves are receivers with a hemi-cube row each.
#[derive(Clone, Debug)]
pub struct Element {
    /// The scene surface it lies on.
    pub surface: u32,
    /// The patch it belongs to.
    pub patch: u32,
    /// Its parent, `None` for a patch root.
    pub parent: Option<ElementKey>,
    /// Its four children, empty for a leaf.
    pub children: SmallVec<[ElementKey; 4]>,
    /// Its region in the surface lattice.
    pub cell: Cell,
    /// Depth below the patch root.
    pub depth: u8,
    /// Area in square metres.
    pub area: f64,
    /// Area centroid (where its hemi-cube sits).
    pub centroid: DVec3,
    /// Diffuse reflectance: its surface's, or for a textured surface the
    /// texture's mean over this element's footprint.
    pub reflectance: Rgb,
    /// Emitted exitance: its surface's, or for a surface with an emissive
    /// texture the texture's mean over this element's footprint.
    pub emission: Rgb,
}

impl Element {
    /// True for a leaf.
    #[must_use]
    pub fn is_leaf(&self) -> bool {
        self.children.is_empty()
    }
}
