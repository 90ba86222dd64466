//! The polygons a hemi-cube rasterizes: each patch's (one for a cell of a
//! surface's lattice, one per surface for a face cluster), or one per element.

use super::point_to_polygon;
use crate::mesh::{ElementKey, Mesh};
use glam::DVec3;

/// A polygon as the hemi-cube sees it.
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
    /// The patch (or element) it belongs to: the id the item buffer holds.
    pub patch: u32,
}

/// Every patch's polygons, patch by patch.
#[derive(Clone, Debug, Default)]
pub struct Sources {
    /// The polygons, patch by patch in patch order.
    pub polygons: Vec<SourcePolygon>,
    /// Per patch, the index of its first polygon, and one more entry: the
    /// number of polygons (so patch `p` holds `first[p]..first[p + 1]`).
    pub first: Vec<u32>,
    /// Ids of the patches that emit (their visibility is found exactly where
    /// the hemi-cube is unsure).
    pub emitters: Vec<u32>,
}

impl Sources {
    /// The patch polygons of a mesh.
    #[must_use]
    pub fn from_mesh(mesh: &Mesh) -> Self {
        let mut sources = Sources::default();
        for (id, p) in mesh.patches.iter().enumerate() {
            sources.first.push(sources.polygons.len() as u32);
            if !p.is_cluster() {
                let mut polygon = SourcePolygon::new(
                    &p.polygon,
                    mesh.surfaces[p.surface as usize].normal,
                    p.surface,
                );
                polygon.patch = id as u32;
                sources.polygons.push(polygon);
                continue;
            }
            for &root in &p.roots {
                let e = &mesh.elements[root];
                let lattice = &mesh.surfaces[e.surface as usize];
                let mut polygon =
                    SourcePolygon::new(&lattice.polygon(&e.cell), lattice.normal, e.surface);
                polygon.patch = id as u32;
                sources.polygons.push(polygon);
            }
        }
        sources.first.push(sources.polygons.len() as u32);
        sources.emitters = (0..mesh.patches.len() as u32)
            .filter(|&p| mesh.patch_emission(p).max_band() > 0.0)
            .collect();
        sources
    }

    /// The polygons of the given elements, each its own patch: ids are their
    /// positions in `keys` (an item buffer of element ids, as a shooting
    /// patch needs).
    #[must_use]
    pub fn from_elements(mesh: &Mesh, keys: &[ElementKey]) -> Self {
        let polygons = keys
            .iter()
            .enumerate()
            .map(|(i, &k)| {
                let e = &mesh.elements[k];
                let lattice = &mesh.surfaces[e.surface as usize];
                let mut polygon =
                    SourcePolygon::new(&lattice.polygon(&e.cell), lattice.normal, e.surface);
                polygon.patch = i as u32;
                polygon
            })
            .collect();
        Sources {
            polygons,
            first: (0..=keys.len() as u32).collect(),
            emitters: Vec::new(),
        }
    }

    /// Sources of one polygon per patch, patch `i` being `polygons[i]`
    /// (their `patch` fields are set to match).
    #[must_use]
    pub fn one_per_patch(mut polygons: Vec<SourcePolygon>) -> Self {
        for (i, p) in polygons.iter_mut().enumerate() {
            p.patch = i as u32;
        }
        let first = (0..=polygons.len() as u32).collect();
        Sources {
            polygons,
            first,
            emitters: Vec::new(),
        }
    }

    /// Number of patches.
    #[must_use]
    pub fn patch_count(&self) -> usize {
        self.first.len().saturating_sub(1)
    }

    /// The indices of patch `p`'s polygons.
    #[must_use]
    pub fn range(&self, p: u32) -> std::ops::Range<usize> {
        self.first[p as usize] as usize..self.first[p as usize + 1] as usize
    }

    /// Patch `p`'s polygons.
    #[must_use]
    pub fn patch(&self, p: u32) -> &[SourcePolygon] {
        &self.polygons[self.range(p)]
    }

    /// Lambert's unoccluded form factor from (`eye`, unit `normal`) to patch
    /// `p`, clipped to the horizon: its polygon's, or for a face cluster the
    /// sum over its polygons that face the eye (the others show their backs).
    #[must_use]
    pub fn exact_form_factor(&self, p: u32, eye: DVec3, normal: DVec3) -> f64 {
        match self.patch(p) {
            [one] => point_to_polygon(eye, normal, one.corners()),
            many => many
                .iter()
                .filter(|q| q.faces(eye))
                .map(|q| point_to_polygon(eye, normal, q.corners()))
                .sum(),
        }
    }
}

impl SourcePolygon {
    /// The source polygon of a convex world polygon (3 or 4 vertices) with its
    /// surface's unit normal (its `patch` 0 until set).
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
            patch: 0,
        }
    }

    /// Its vertices.
    #[must_use]
    pub fn corners(&self) -> &[DVec3] {
        &self.vertices[..self.count as usize]
    }

    /// True when `eye` lies in front of its plane.
    #[must_use]
    pub fn faces(&self, eye: DVec3) -> bool {
        self.normal.dot(eye - self.vertices[0]) > 0.0
    }
}
