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
    pub(crate) surface: u32,
    /// Its root elements: one for a cell of a surface's lattice, one per
    /// surface for a face cluster, in surface order.
    pub(crate) roots: SmallVec<[ElementKey; 1]>,
    /// World polygon of its first root, counter-clockwise around the surface
    /// normal (the whole patch unless it is a cluster).
    pub(crate) polygon: SmallVec<[DVec3; 4]>,
    /// Area in square metres.
    pub(crate) area: f64,
    /// Area centroid.
    pub(crate) centroid: DVec3,
}

impl Patch {
    /// The scene surface it lies on (a face cluster's first surface).
    #[must_use]
    pub fn surface(&self) -> u32 {
        self.surface
    }

    /// World polygon of its first root, counter-clockwise around the surface
    /// normal (the whole patch unless it is a cluster).
    #[must_use]
    pub fn polygon(&self) -> &[DVec3] {
        &self.polygon
    }

    /// Area in square metres.
    #[must_use]
    pub fn area(&self) -> f64 {
        self.area
    }

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
    pub(crate) surface: u32,
    /// The patch it belongs to.
    pub(crate) patch: u32,
    /// Its parent, `None` for a patch root.
    pub(crate) parent: Option<ElementKey>,
    /// Its four children, empty for a leaf.
    pub(crate) children: SmallVec<[ElementKey; 4]>,
    /// Its region in the surface lattice.
    pub(crate) cell: Cell,
    /// Depth below the patch root.
    pub(crate) depth: u8,
    /// Area in square metres.
    pub(crate) area: f64,
    /// Area centroid (where its hemi-cube sits).
    pub(crate) centroid: DVec3,
    /// Diffuse reflectance: its surface's, or for a textured surface the
    /// texture's mean over this element's footprint.
    pub(crate) reflectance: Rgb,
    /// Emitted exitance: its surface's, or for a surface with an emissive
    /// texture the texture's mean over this element's footprint.
    pub(crate) emission: Rgb,
}

impl Element {
    /// The scene surface it lies on.
    #[must_use]
    pub fn surface(&self) -> u32 {
        self.surface
    }

    /// Its parent, `None` for a patch root.
    #[must_use]
    pub fn parent(&self) -> Option<ElementKey> {
        self.parent
    }

    /// Its region in the surface lattice.
    #[must_use]
    pub fn cell(&self) -> Cell {
        self.cell
    }

    /// Depth below the patch root.
    #[must_use]
    pub fn depth(&self) -> u8 {
        self.depth
    }

    /// Area in square metres.
    #[must_use]
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Area centroid (where its hemi-cube sits).
    #[must_use]
    pub fn centroid(&self) -> DVec3 {
        self.centroid
    }

    /// Diffuse reflectance: its surface's, or for a textured surface the
    /// texture's mean over this element's footprint.
    #[must_use]
    pub fn reflectance(&self) -> Rgb {
        self.reflectance
    }

    /// Emitted exitance: its surface's, or for a surface with an emissive
    /// texture the texture's mean over this element's footprint.
    #[must_use]
    pub fn emission(&self) -> Rgb {
        self.emission
    }

    /// True for a leaf.
    #[must_use]
    pub fn is_leaf(&self) -> bool {
        self.children.is_empty()
    }
}
