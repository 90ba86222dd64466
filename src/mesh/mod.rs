//! The mesh: surfaces cut into patches, each patch the root of an element quadtree.
//!
//! Elements live in a slotmap arena ([`Mesh::elements`]); each holds its children in
//! a `SmallVec`. Patches are the sources of the coarse system; leaf elements are the
//! receivers whose hemi-cubes give element-to-patch form factors.

mod cell;
pub mod clusters;
mod element;
mod emission_grid;
mod lattice;
mod light_signature;
mod locate;
mod point_probe;
mod shading;
mod texels;
mod welds;

pub use cell::Cell;
pub(crate) use cell::{Probe, MAX_DEPTH};
pub use element::{Element, ElementKey, Patch};
pub(crate) use lattice::PatchGrid;
pub use lattice::SurfaceLattice;
pub use shading::{ShadingMesh, VertexRadiosity, HIDDEN_WEIGHT};
pub use texels::{ShadingTexels, TexelSurface};

use crate::error::{Error, LimitKind, Result};
use crate::math::{polygon_area, polygon_centroid, Rgb};
use crate::scene::Scene;
use slotmap::SlotMap;

/// Surfaces, patches and element quadtrees of one scene: geometry and
/// topology only (form factors and radiosities are kept by the stages that
/// compute them, keyed by [`ElementKey`]).
#[derive(Clone, Debug)]
pub struct Mesh {
    /// One lattice per scene surface, same order as `Scene::surfaces`.
    pub(crate) surfaces: Vec<SurfaceLattice>,
    /// All patches, surface by surface.
    pub(crate) patches: Vec<Patch>,
    /// The element arena.
    pub(crate) elements: SlotMap<ElementKey, Element>,
    /// The roots of the element quadtrees, one per cell of the initial patch
    /// cut, in surface order. Patches start as these roots; a split patch hands
    /// its role to its children, but the trees keep these roots.
    pub(crate) top_roots: Vec<ElementKey>,
}

impl std::ops::Index<ElementKey> for Mesh {
    type Output = Element;

    /// The element `key` names. Panics for a key of another mesh.
    fn index(&self, key: ElementKey) -> &Element {
        &self.elements[key]
    }
}

impl Mesh {
    /// Cuts every surface of `scene` into patches no larger than `patch_size`
    /// (metres) along any edge, and groups small adjacent surfaces into face
    /// clusters (see [`clusters`]); each patch's roots are single leaf
    /// elements. Fails when the patch count would exceed `max_patches`.
    pub fn new(scene: &Scene, patch_size: f64, max_patches: usize) -> Result<Self> {
        Self::build(scene, patch_size, max_patches, true)
    }

    /// [`Mesh::new`], with face clusters or without them (every surface a
    /// patch or lattice of patches of its own).
    pub fn build(
        scene: &Scene,
        patch_size: f64,
        max_patches: usize,
        face_clusters: bool,
    ) -> Result<Self> {
        if !(patch_size.is_finite() && patch_size > 0.0) {
            return Err(Error::Setting {
                name: "patch_size",
                message: format!("must be a positive length, got {patch_size}"),
            });
        }
        // Per surface, the patch its single cell joins when it is a member of
        // a cluster (filled in when the cluster's first surface is reached).
        let mut cluster_of: Vec<Option<usize>> = vec![None; scene.surfaces.len()];
        let clusters = if face_clusters {
            clusters::face_clusters(scene, patch_size)
        } else {
            Vec::new()
        };
        for (c, members) in clusters.iter().enumerate() {
            for &s in members {
                cluster_of[s as usize] = Some(c);
            }
        }
        let mut cluster_patch: Vec<Option<u32>> = vec![None; clusters.len()];
        let mut mesh = Mesh {
            surfaces: Vec::with_capacity(scene.surfaces.len()),
            patches: Vec::new(),
            elements: SlotMap::with_key(),
            top_roots: Vec::new(),
        };
        for (si, surface) in scene.surfaces.iter().enumerate() {
            let material = scene.material_of(surface);
            // Counted before the cells are made: a tiny patch size would
            // otherwise allocate billions of them before the check.
            // A surface with an emissive texture is cut finer where its
            // emission varies (cluster members are single small patches).
            let size = match emission_grid::emissive_texture(scene, surface) {
                Some(texture) if cluster_of[si].is_none() => {
                    emission_grid::resolving_patch_size(surface, texture, patch_size)
                }
                _ => patch_size,
            };
            let needed = lattice::patch_count(surface, size);
            if mesh.patches.len() as u64 + needed > max_patches as u64 {
                return Err(Error::limit(
                    LimitKind::Patches,
                    format!(
                        "more than {max_patches} patches at patch size {patch_size} m \
                     (surface {si} alone needs {needed}); raise the patch size or the limit"
                    ),
                ));
            }
            let (lattice, cells) = SurfaceLattice::new(
                surface,
                material.reflectance,
                material.emission,
                size,
                mesh.top_roots.len() as u32,
            );
            let mut lattice = lattice;
            lattice.double_sided = material.double_sided;
            if surface.uv.len() == surface.vertices.len() {
                lattice.uv = surface.uv.clone();
                lattice.texture = material.base_texture.clone();
                lattice.emissive_texture = material.emissive_texture.clone();
            }
            mesh.surfaces.push(lattice);
            for cell in cells {
                let joins = cluster_of[si].and_then(|c| cluster_patch[c]);
                let patch = joins.unwrap_or(mesh.patches.len() as u32);
                let key = mesh.insert_element(si as u32, patch, None, cell, 0);
                mesh.top_roots.push(key);
                let e = &mesh.elements[key];
                let (area, centroid) = (e.area, e.centroid);
                if let Some(p) = joins {
                    let p = &mut mesh.patches[p as usize];
                    p.roots.push(key);
                    let total = p.area + area;
                    p.centroid = (p.centroid * p.area + centroid * area) / total;
                    p.area = total;
                } else {
                    if let Some(c) = cluster_of[si] {
                        cluster_patch[c] = Some(patch);
                    }
                    mesh.patches.push(Patch {
                        surface: si as u32,
                        roots: smallvec::smallvec![key],
                        polygon: mesh.surfaces[si].polygon(&cell),
                        area,
                        centroid,
                    });
                }
            }
        }
        Ok(mesh)
    }

    fn insert_element(
        &mut self,
        surface: u32,
        patch: u32,
        parent: Option<ElementKey>,
        cell: Cell,
        depth: u8,
    ) -> ElementKey {
        let lattice = &self.surfaces[surface as usize];
        let polygon = lattice.polygon(&cell);
        self.elements.insert(Element {
            surface,
            patch,
            parent,
            children: Default::default(),
            cell,
            depth,
            area: polygon_area(&polygon),
            centroid: polygon_centroid(&polygon),
            reflectance: lattice.cell_reflectance(&cell),
            emission: lattice.cell_emission(&cell),
        })
    }

    /// Splits a leaf into four children and returns them. (Its form-factor
    /// row, if any, is now stale: see [`crate::formfactor::FormFactors::forget`].)
    pub fn split(&mut self, key: ElementKey) -> [ElementKey; 4] {
        let (surface, patch, cell, depth) = {
            let e = &self.elements[key];
            debug_assert!(e.is_leaf());
            (e.surface, e.patch, e.cell, e.depth)
        };
        let kids = cell
            .children()
            .map(|c| self.insert_element(surface, patch, Some(key), c, depth + 1));
        let e = &mut self.elements[key];
        e.children.extend_from_slice(&kids);
        kids
    }

    /// Splits patch `p`, a cell of one surface's lattice (not a face
    /// cluster), into the four children of its root element, which become
    /// patches: the first keeps id `p`, the others are appended. Every element
    /// below them is re-labelled. The root is split first if it is a leaf.
    /// Returns the ids of the four patches.
    pub(crate) fn split_patch(&mut self, p: u32) -> [u32; 4] {
        debug_assert!(!self.patches[p as usize].is_cluster());
        let root = self.patches[p as usize].roots[0];
        if self.elements[root].is_leaf() {
            self.split(root);
        }
        let kids: Vec<ElementKey> = self.elements[root].children.to_vec();
        let surface = self.patches[p as usize].surface;
        let mut ids = [p; 4];
        for (i, &k) in kids.iter().enumerate() {
            let id = if i == 0 {
                p
            } else {
                self.patches.push(self.patches[p as usize].clone());
                self.patches.len() as u32 - 1
            };
            ids[i] = id;
            let e = &self.elements[k];
            let (area, centroid) = (e.area, e.centroid);
            let polygon = self.surfaces[surface as usize].polygon(&e.cell);
            self.patches[id as usize] = Patch {
                surface,
                roots: smallvec::smallvec![k],
                polygon,
                area,
                centroid,
            };
            let mut stack = vec![k];
            while let Some(x) = stack.pop() {
                self.elements[x].patch = id;
                stack.extend(self.elements[x].children.iter().copied());
            }
        }
        ids
    }

    /// One lattice per scene surface, in the order of `Scene::surfaces`.
    #[must_use]
    pub fn surfaces(&self) -> &[SurfaceLattice] {
        &self.surfaces
    }

    /// Every patch, by patch id.
    #[must_use]
    pub fn patches(&self) -> &[Patch] {
        &self.patches
    }

    /// The element `key` names, if it is one of this mesh's.
    #[must_use]
    pub fn element(&self, key: ElementKey) -> Option<&Element> {
        self.elements.get(key)
    }

    /// Every element node, leaves and interior nodes, with its key.
    pub fn elements(&self) -> impl Iterator<Item = (ElementKey, &Element)> {
        self.elements.iter()
    }

    /// Number of element nodes, leaves and interior nodes.
    #[must_use]
    pub fn element_count(&self) -> usize {
        self.elements.len()
    }

    /// The leaf elements of patch `p`, root by root, depth first in child
    /// order.
    #[must_use]
    pub fn patch_leaves(&self, p: u32) -> Vec<ElementKey> {
        let mut out = Vec::new();
        let mut stack: Vec<ElementKey> = self.patches[p as usize]
            .roots
            .iter()
            .rev()
            .copied()
            .collect();
        while let Some(k) = stack.pop() {
            let e = &self.elements[k];
            if e.is_leaf() {
                out.push(k);
            } else {
                stack.extend(e.children.iter().rev());
            }
        }
        out
    }

    /// Every leaf element, patch by patch, in a stable order (the order used for
    /// all parallel work, so that results do not depend on the thread count).
    #[must_use]
    pub fn leaves(&self) -> Vec<ElementKey> {
        (0..self.patches.len() as u32)
            .flat_map(|p| self.patch_leaves(p))
            .collect()
    }

    /// Number of leaf elements.
    #[must_use]
    pub fn leaf_count(&self) -> usize {
        self.elements.values().filter(|e| e.is_leaf()).count()
    }

    /// Reflectance of a patch: its surface's, or on a textured surface the
    /// area-weighted mean of its roots' (the texture over the patch's
    /// footprint, which refinement below it does not change).
    #[must_use]
    pub(crate) fn patch_reflectance(&self, p: u32) -> Rgb {
        self.patch_value(
            p,
            |s| s.texture.is_some(),
            |s| s.reflectance,
            |e| e.reflectance,
        )
    }

    /// Emission of a patch: its surface's, or on a surface with an emissive
    /// texture the area-weighted mean of its roots'.
    #[must_use]
    pub fn patch_emission(&self, p: u32) -> Rgb {
        self.patch_value(
            p,
            SurfaceLattice::has_emission_texture,
            |s| s.emission,
            |e| e.emission,
        )
    }

    /// A material value of patch `p`: its surface's (`of_surface`) unless a
    /// root lies on a surface where the value varies (`varies`), then the
    /// area-weighted mean of its roots' (`of_element`).
    fn patch_value(
        &self,
        p: u32,
        varies: impl Fn(&SurfaceLattice) -> bool,
        of_surface: impl Fn(&SurfaceLattice) -> Rgb,
        of_element: impl Fn(&Element) -> Rgb,
    ) -> Rgb {
        let patch = &self.patches[p as usize];
        let surface = &self.surfaces[patch.surface as usize];
        let lattice_of = |k: &ElementKey| &self.surfaces[self.elements[*k].surface as usize];
        if !patch.roots.iter().any(|k| varies(lattice_of(k))) {
            return of_surface(surface);
        }
        let mut sum = Rgb::ZERO;
        let mut area = 0.0;
        for &k in &patch.roots {
            let e = &self.elements[k];
            sum += of_element(e) * e.area;
            area += e.area;
        }
        if area > 0.0 {
            sum / area
        } else {
            of_surface(surface)
        }
    }
}
