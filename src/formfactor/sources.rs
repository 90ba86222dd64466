//! The polygons a hemi-cube rasterizes: one per patch, or one per element.

use crate::mesh::{ElementKey, Mesh};
use glam::DVec3;

/// A patch polygon as the hemi-cube sees it.
#[derive(Clone, Debug)]
pub struct SourcePolygon {
    /// Vertices (the first `count` are used).
    pub vertices: [DVec3; 4],
    /// 3 or 4.
    pub count: u8,
    /// Unit front normal.
    pub normal: DVec3,
    /// The surface it lies on (a receiver never sees its own planar surface).
    pub surface: u32,
    /// Bounding sphere centre and radius, for culling.
    pub centre: DVec3,
    /// Bounding sphere radius.
    pub radius: f64,
}

/// All patch polygons, indexed by patch id.
#[derive(Clone, Debug, Default)]
pub struct Sources {
    /// One polygon per patch.
    pub polygons: Vec<SourcePolygon>,
    /// Ids of the patches that emit (their visibility is ray cast where the
    /// hemi-cube is unsure).
    pub emitters: Vec<u32>,
}

impl Sources {
    /// The patch polygons of a mesh.
    #[must_use]
    pub fn from_mesh(mesh: &Mesh) -> Self {
        let polygons = mesh
            .patches
            .iter()
            .map(|p| {
                let mut vertices = [DVec3::ZERO; 4];
                for (i, v) in p.polygon.iter().enumerate() {
                    vertices[i] = *v;
                }
                let centre = p.polygon.iter().copied().sum::<DVec3>() / p.polygon.len() as f64;
                let radius = p
                    .polygon
                    .iter()
                    .map(|v| (*v - centre).length())
                    .fold(0.0, f64::max);
                SourcePolygon {
                    vertices,
                    count: p.polygon.len() as u8,
                    normal: mesh.surfaces[p.surface as usize].normal,
                    surface: p.surface,
                    centre,
                    radius,
                }
            })
            .collect();
        let emitters = (0..mesh.patches.len() as u32)
            .filter(|&p| mesh.patch_emission(p).max_band() > 0.0)
            .collect();
        Sources { polygons, emitters }
    }
}

impl SourcePolygon {
    /// The source polygon of a convex world polygon (3 or 4 vertices) with its
    /// surface's unit normal.
    #[must_use]
    pub fn new(polygon: &[DVec3], normal: DVec3, surface: u32) -> Self {
        let mut vertices = [DVec3::ZERO; 4];
        for (slot, v) in vertices.iter_mut().zip(polygon) {
            *slot = *v;
        }
        let centre = polygon.iter().copied().sum::<DVec3>() / polygon.len() as f64;
        let radius = polygon
            .iter()
            .map(|v| (*v - centre).length())
            .fold(0.0, f64::max);
        SourcePolygon {
            vertices,
            count: polygon.len() as u8,
            normal,
            surface,
            centre,
            radius,
        }
    }
}

impl Sources {
    /// The polygons of the given elements, with ids their positions in `keys`
    /// (an item buffer of element ids, as a shooting patch needs).
    #[must_use]
    pub fn from_elements(mesh: &Mesh, keys: &[ElementKey]) -> Self {
        let polygons = keys
            .iter()
            .map(|&k| {
                let e = &mesh.elements[k];
                let lattice = &mesh.surfaces[e.surface as usize];
                SourcePolygon::new(&lattice.polygon(&e.cell), lattice.normal, e.surface)
            })
            .collect();
        Sources {
            polygons,
            emitters: Vec::new(),
        }
    }
}
