//! The integer lattice of one surface: how lattice coordinates map to world space,
//! how the surface is cut into patches, and which patch holds a lattice point.

use super::cell::{Cell, Probe, MAX_DEPTH};
use crate::math::Rgb;
use crate::scene::{Surface, Texture, EMISSION_DEPTH};
use glam::{DVec2, DVec3};
use smallvec::SmallVec;
use std::collections::HashMap;
use std::sync::Arc;

/// How a surface is cut into patches.
#[derive(Clone, Debug)]
pub enum PatchGrid {
    /// A quad surface cut into `nu x nv` patches.
    Quad {
        /// Patches along the first edge (vertex 0 to 1).
        nu: u32,
        /// Patches along the second edge (vertex 0 to 3).
        nv: u32,
    },
    /// A triangle cut `level` times into four: `4^level` patches.
    Tri {
        /// Subdivision level of the patch triangles.
        level: u32,
        /// Patch index (within the surface) of each patch cell.
        cells: HashMap<Cell, u32>,
    },
}

/// Patches along the two edge directions of a quad (vertex 0 to 1 and 0 to 3)
/// so that none is longer than `patch_size`, each clamped to `1..=2^18`.
fn quad_divisions(v: &[DVec3], patch_size: f64) -> (u32, u32) {
    let along = |a: DVec3, b: DVec3, c: DVec3, d: DVec3| {
        let len = (b - a).length().max((c - d).length());
        ((len / patch_size).ceil() as u32).clamp(1, 1 << 18)
    };
    (along(v[0], v[1], v[2], v[3]), along(v[0], v[3], v[2], v[1]))
}

/// How many times a triangle is cut into four so that no patch edge is longer
/// than `patch_size` (at most 9).
fn triangle_level(v: &[DVec3], patch_size: f64) -> u32 {
    let longest = (v[1] - v[0])
        .length()
        .max((v[2] - v[1]).length())
        .max((v[0] - v[2]).length());
    // A right triangle cut into patches whose legs match the quads' patch size
    // has hypotenuses sqrt(2) times longer; measuring the longest edge against
    // that keeps triangle patches as large as quad patches, not 4 times smaller.
    let mut level = 0u32;
    while longest / f64::from(1u32 << level) > patch_size * std::f64::consts::SQRT_2 && level < 9 {
        level += 1;
    }
    level
}

/// The number of patches [`SurfaceLattice::new`] cuts `surface` into, computed
/// without allocating them (a tiny patch size can ask for 2^36 of them).
pub(crate) fn patch_count(surface: &Surface, patch_size: f64) -> u64 {
    let v = &surface.vertices;
    if v.len() == 4 {
        let (nu, nv) = quad_divisions(v, patch_size);
        u64::from(nu) * u64::from(nv)
    } else {
        1u64 << (2 * triangle_level(v, patch_size))
    }
}

/// One surface's lattice and the material values its elements share.
#[derive(Clone, Debug)]
pub struct SurfaceLattice {
    /// The surface's vertices (3 or 4), counter-clockwise around `normal`.
    pub vertices: SmallVec<[DVec3; 4]>,
    /// Unit front normal.
    pub normal: DVec3,
    /// Reflectance of the surface's material.
    pub reflectance: Rgb,
    /// Emitted exitance of the surface's material.
    pub emission: Rgb,
    /// The scene object this surface belongs to.
    pub object: u32,
    /// Whether its material is double-sided: the importer (or
    /// `Scene::make_double_sided`) put a copy of it back to back with it,
    /// so a front lies over its back wherever the back shows.
    pub double_sided: bool,
    /// The patch cut.
    pub grid: PatchGrid,
    /// Index of this surface's first top-level cell in `Mesh::top_roots` (the
    /// initial patch cut; patches split later do not change it).
    pub first_root: u32,
    /// Lattice extent along each axis (`L` for both axes of a triangle).
    pub extent: (u32, u32),
    /// The surface's texture coordinates per vertex, or empty: its textures
    /// are then seen through their means (the material's values).
    pub uv: SmallVec<[DVec2; 4]>,
    /// The base-colour texture, when the surface has coordinates for it: its
    /// elements' reflectances come from it.
    pub texture: Option<Arc<Texture>>,
    /// The emissive texture, when the surface has coordinates for it: its
    /// elements' emissions come from it.
    pub emissive_texture: Option<Arc<Texture>>,
    /// What the emissive texture's values are multiplied by: 1, or the power
    /// of two the solve scales every emission by (see `pipeline::scale`).
    pub emission_scale: f64,
    /// The largest patch edge this surface was cut at: the solve's patch
    /// size, or a finer one where its emissive texture varies (see
    /// `emission_grid`).
    pub patch_size: f64,
}

impl SurfaceLattice {
    /// Cuts `surface` into patches no larger than `patch_size` along any edge.
    /// Returns the lattice and the patch cells in patch order.
    pub(crate) fn new(
        surface: &Surface,
        reflectance: Rgb,
        emission: Rgb,
        patch_size: f64,
        first_root: u32,
    ) -> (Self, Vec<Cell>) {
        let v = &surface.vertices;
        let root = 1u32 << MAX_DEPTH;
        let (grid, extent, cells) = if v.len() == 4 {
            let (nu, nv) = quad_divisions(v, patch_size);
            let mut cells = Vec::with_capacity(nu as usize * nv as usize);
            for j in 0..nv {
                for i in 0..nu {
                    cells.push(Cell::Quad {
                        u: i * root,
                        v: j * root,
                        size: root,
                    });
                }
            }
            (PatchGrid::Quad { nu, nv }, (nu * root, nv * root), cells)
        } else {
            let level = triangle_level(v, patch_size);
            let extent = root << level;
            let mut cells = vec![Cell::Tri {
                a: 0,
                b: 0,
                size: extent,
                up: true,
            }];
            for _ in 0..level {
                cells = cells.iter().flat_map(|c| c.children()).collect();
            }
            cells.sort();
            let lookup = cells
                .iter()
                .enumerate()
                .map(|(i, c)| (*c, i as u32))
                .collect();
            (
                PatchGrid::Tri {
                    level,
                    cells: lookup,
                },
                (extent, extent),
                cells,
            )
        };
        (
            SurfaceLattice {
                vertices: v.clone(),
                normal: surface.normal,
                reflectance,
                emission,
                object: surface.object,
                double_sided: false,
                grid,
                first_root,
                extent,
                uv: SmallVec::new(),
                texture: None,
                emissive_texture: None,
                emission_scale: 1.0,
                patch_size,
            },
            cells,
        )
    }

    /// World position of a lattice point.
    #[must_use]
    pub fn position(&self, p: (u32, u32)) -> DVec3 {
        let v = &self.vertices;
        let s = f64::from(p.0) / f64::from(self.extent.0);
        let t = f64::from(p.1) / f64::from(self.extent.1);
        if v.len() == 4 {
            // Bilinear map of a planar convex quad: iso-lines are straight, so
            // lattice cells map to planar quads that tile the surface exactly.
            let bottom = v[0].lerp(v[1], s);
            let top = v[3].lerp(v[2], s);
            bottom.lerp(top, t)
        } else {
            v[0] + (v[1] - v[0]) * s + (v[2] - v[0]) * t
        }
    }

    /// Texture coordinates of a lattice point, by the same map as
    /// [`SurfaceLattice::position`] (`None` without a texture).
    #[must_use]
    pub fn uv(&self, p: (u32, u32)) -> Option<DVec2> {
        if self.uv.len() != self.vertices.len() {
            return None;
        }
        Some(self.map_uv(&self.uv, p))
    }

    /// The texture coordinates of a lattice point on a surface whose vertices
    /// have coordinates `uv` (one per vertex), by the same map as
    /// [`SurfaceLattice::position`]; 0 unless there are 3 or 4.
    #[must_use]
    pub(crate) fn map_uv(&self, uv: &[DVec2], p: (u32, u32)) -> DVec2 {
        let s = f64::from(p.0) / f64::from(self.extent.0);
        let t = f64::from(p.1) / f64::from(self.extent.1);
        match uv.len() {
            4 => uv[0].lerp(uv[1], s).lerp(uv[3].lerp(uv[2], s), t),
            3 => uv[0] + (uv[1] - uv[0]) * s + (uv[2] - uv[0]) * t,
            _ => DVec2::ZERO,
        }
    }

    /// The reflectance of an element on `cell`: the material's without a
    /// texture, else the texture's mean over the cell's footprint.
    #[must_use]
    pub(crate) fn cell_reflectance(&self, cell: &Cell) -> Rgb {
        match &self.texture {
            Some(texture) => texture.mean_over(&self.cell_uv(cell)),
            None => self.reflectance,
        }
    }

    /// The emission of an element on `cell`: the material's without an
    /// emissive texture, else the texture's mean over the cell's footprint
    /// (times the solve's emission scale).
    #[must_use]
    pub(crate) fn cell_emission(&self, cell: &Cell) -> Rgb {
        match &self.emissive_texture {
            Some(texture) => {
                texture.mean_over_refined(&self.cell_uv(cell), EMISSION_DEPTH) * self.emission_scale
            }
            None => self.emission,
        }
    }

    /// True when the surface's elements differ in emission.
    #[must_use]
    pub(crate) fn has_emission_texture(&self) -> bool {
        self.emissive_texture.is_some()
    }

    /// Texture coordinates of a cell's corners.
    pub(crate) fn cell_uv(&self, cell: &Cell) -> SmallVec<[DVec2; 4]> {
        cell.corners().iter().filter_map(|c| self.uv(*c)).collect()
    }

    /// World polygon of a cell.
    #[must_use]
    pub fn polygon(&self, cell: &Cell) -> SmallVec<[DVec3; 4]> {
        cell.corners().iter().map(|c| self.position(*c)).collect()
    }

    /// The index (within this surface) of the patch whose cell contains the probe.
    #[must_use]
    pub(crate) fn patch_at(&self, p: Probe) -> Option<u32> {
        let root = 4i64 << MAX_DEPTH;
        match &self.grid {
            PatchGrid::Quad { nu, nv } => {
                if p.0 < 0 || p.1 < 0 {
                    return None;
                }
                let (i, j) = (p.0 / root, p.1 / root);
                (i < i64::from(*nu) && j < i64::from(*nv)).then(|| (j * i64::from(*nu) + i) as u32)
            }
            PatchGrid::Tri { level, cells } => {
                let mut cell = Cell::Tri {
                    a: 0,
                    b: 0,
                    size: self.extent.0,
                    up: true,
                };
                if !cell.contains(p) {
                    return None;
                }
                for _ in 0..*level {
                    cell = *cell.children().iter().find(|c| c.contains(p))?;
                }
                cells.get(&cell).copied()
            }
        }
    }
}
