//! The scene: planar surfaces with diffuse materials, grouped into named objects,
//! and the cameras to view them. Built by the glTF importer or by [`SceneBuilder`].

mod builder;
mod camera;
mod material;
mod overlaps;
mod surface;

pub use builder::SceneBuilder;
pub use camera::Camera;
pub use material::Material;
pub(crate) use overlaps::check_coplanar_overlaps;
pub use overlaps::COPLANAR_GAP;
pub use surface::{Surface, MAX_COORDINATE};

use glam::DVec3;
use serde::Serialize;

/// A named group of surfaces: one glTF node that carries a mesh. Per-object figures
/// (area, mean radiosity) are what the stats report as `surfaces`.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// The node's name, else its mesh's, else its index.
    pub name: String,
}

/// Counts kept by the importer so that nothing it drops goes unreported.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ImportStats {
    /// Triangles read from the file, before merging and skipping.
    pub triangles_read: usize,
    /// Triangles skipped because they have (near) zero area.
    pub degenerate_triangles: usize,
    /// Pairs of coplanar triangles merged into one quad surface.
    pub merged_quads: usize,
    /// Primitives of point or line modes, skipped.
    pub skipped_primitives: usize,
    /// Images read and decoded for textures (each at most once per file).
    pub images_decoded: usize,
    /// Pixels of those images, counted against
    /// [`ImportLimits::max_texture_pixels`](crate::gltf_io::ImportLimits::max_texture_pixels).
    pub texture_pixels: u64,
}

/// A scene ready to mesh: every surface is a planar triangle or convex quad, front
/// face counter-clockwise around its normal.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// A short name, used for output file names.
    pub name: String,
    /// The materials surfaces refer to by index.
    pub materials: Vec<Material>,
    /// The named objects surfaces belong to.
    pub objects: Vec<Object>,
    /// The planar surfaces. A double-sided glTF surface appears twice, back to back.
    pub surfaces: Vec<Surface>,
    /// Cameras found in the file (the first is the default view).
    pub cameras: Vec<Camera>,
    /// Things the importer skipped or changed, in words a user can act on.
    pub warnings: Vec<String>,
    /// What the importer counted.
    pub import_stats: ImportStats,
}

impl Scene {
    /// The axis-aligned bounds of all surfaces (min, max).
    #[must_use]
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for s in &self.surfaces {
            for v in &s.vertices {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
        }
        (lo, hi)
    }

    /// The length of the bounding box diagonal: the scene's size, from which
    /// default patch sizes and tolerances are derived.
    #[must_use]
    pub fn diameter(&self) -> f64 {
        let (lo, hi) = self.bounds();
        if lo.x <= hi.x {
            (hi - lo).length()
        } else {
            0.0
        }
    }

    /// The material of surface `s`.
    #[must_use]
    pub fn material_of(&self, s: &Surface) -> &Material {
        &self.materials[s.material as usize]
    }

    /// Total area of every surface.
    #[must_use]
    pub fn total_area(&self) -> f64 {
        self.surfaces.iter().map(|s| s.area).sum()
    }
}
