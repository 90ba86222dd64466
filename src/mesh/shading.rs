//! Radiosity at vertices and the crack-free triangle mesh used for display.
//!
//! A vertex takes the area-weighted mean of the leaves around it, so that
//! surface edges do not darken. A T-vertex (a corner of fine leaves lying inside
//! the edge of a coarser leaf) takes the value interpolated along the coarse
//! edge instead, so that shading is continuous across refined and unrefined
//! neighbours.

use super::cell::Probe;
use super::texels::{ShadingTexels, TexelSurface};
use super::welds::Welds;
use super::{ElementKey, Mesh};
use crate::math::Rgb;
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// The weight per unit area of a leaf that cannot be seen at all, in a
/// vertex's mean (see [`Mesh::vertex_radiosity_seen`]): next to nothing, so
/// that a vertex with nothing visible around it still has a value, its
/// leaves'.
pub const HIDDEN_WEIGHT: f64 = 1e-9;

/// A lattice vertex: surface and lattice coordinates.
pub(super) type VertexId = (u32, u32, u32);

/// Radiosity at every lattice vertex of the leaves.
#[derive(Clone, Debug, Default)]
pub struct VertexRadiosity {
    /// Value per vertex.
    pub values: HashMap<VertexId, Rgb>,
    /// For each leaf that has T-vertices on its edges: those vertices, per edge,
    /// in order along the edge.
    pub t_vertices: HashMap<ElementKey, Vec<Vec<(u32, u32)>>>,
}

/// Triangles with per-vertex radiosity, ready to render or export.
#[derive(Clone, Debug, Default)]
pub struct ShadingMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Radiosity (exitance) per vertex.
    pub radiosity: Vec<Rgb>,
    /// Counter-clockwise triangles (seen from the front).
    pub triangles: Vec<[u32; 3]>,
    /// The scene surface each triangle lies on (parallel to `triangles`), so
    /// that exporters can group triangles by object and material.
    pub triangle_surface: Vec<u32>,
    /// The light under the textures of textured surfaces (`None` when no
    /// surface is textured): see [`ShadingTexels`].
    pub texels: Option<ShadingTexels>,
}

/// One T-vertex constraint: the vertex `mid` lies halfway along the coarse edge
/// `ends`, whose length (in lattice units) orders the constraints.
struct Constraint {
    length: u64,
    surface: u32,
    mid: (u32, u32),
    ends: [(u32, u32); 2],
}

fn midpoint(a: (u32, u32), b: (u32, u32)) -> (u32, u32) {
    ((a.0 + b.0) / 2, (a.1 + b.1) / 2)
}

fn probe_beside(a: (u32, u32), b: (u32, u32), outward: (i64, i64)) -> Probe {
    (
        2 * (i64::from(a.0) + i64::from(b.0)) + outward.0,
        2 * (i64::from(a.1) + i64::from(b.1)) + outward.1,
    )
}

impl Mesh {
    /// Vertex radiosities of the current leaves, whose own values `leaf`
    /// gives (see the module docs).
    #[must_use]
    pub fn vertex_radiosity(&self, leaf: impl Fn(ElementKey) -> Rgb) -> VertexRadiosity {
        self.vertex_radiosity_seen(|k| (leaf(k), 1.0))
    }

    /// Vertex radiosities where `leaf` gives each leaf's value and the share
    /// of its area that can be seen (1 for most; less where another object
    /// stands on it, 0 under it). A vertex takes the mean of the leaves
    /// around it weighted by their seen areas, so that the covered part of
    /// a leaf does not darken the visible part of its neighbours (a leaf
    /// that cannot be seen at all counts next to nothing, so that a vertex
    /// with nothing visible around it keeps its leaves' value).
    #[must_use]
    pub fn vertex_radiosity_seen(
        &self,
        leaf: impl Fn(ElementKey) -> (Rgb, f64),
    ) -> VertexRadiosity {
        let mut sums: HashMap<VertexId, (Rgb, f64)> = HashMap::new();
        let leaves = self.leaves();
        for &k in &leaves {
            let e = &self.elements[k];
            let (value, share) = leaf(k);
            let weight = e.area * share.max(HIDDEN_WEIGHT);
            for c in e.cell.corners() {
                let s = sums.entry((e.surface, c.0, c.1)).or_default();
                s.0 += value * weight;
                s.1 += weight;
            }
        }
        // Corners of a smooth mesh's facets that meet take one mean, over
        // facets that reflect and emit alike (a mean across two materials
        // would blend their colours at the vertex).
        Welds::new(self, |a, b| {
            let (a, b) = (&self.surfaces[a as usize], &self.surfaces[b as usize]);
            a.reflectance == b.reflectance
                && a.emission == b.emission
                && a.texture.is_none()
                && b.texture.is_none()
                && a.emissive_texture.is_none()
                && b.emissive_texture.is_none()
        })
        .pool(&mut sums, |t, s| {
            t.0 += s.0;
            t.1 += s.1;
        });
        let values: HashMap<VertexId, Rgb> = sums
            .into_iter()
            .map(|(k, (sum, w))| (k, if w > 0.0 { sum / w } else { Rgb::ZERO }))
            .collect();
        self.with_t_vertices(&leaves, values)
    }

    /// Finds the T-vertices of `leaves` and sets the value of each to the
    /// value interpolated along the coarse edge it lies on, coarsest edges
    /// first, from the area-weighted means `values`.
    pub(super) fn with_t_vertices(
        &self,
        leaves: &[ElementKey],
        mut values: HashMap<VertexId, Rgb>,
    ) -> VertexRadiosity {
        let mut constraints = Vec::new();
        let mut t_vertices: HashMap<ElementKey, Vec<Vec<(u32, u32)>>> = HashMap::new();
        for &k in leaves {
            let e = &self.elements[k];
            let probes = e.cell.edge_probes();
            let mut per_edge = Vec::with_capacity(probes.len());
            let mut any = false;
            for (probe, p0, p1) in &probes {
                let outward = (
                    probe.0 - 2 * (i64::from(p0.0) + i64::from(p1.0)),
                    probe.1 - 2 * (i64::from(p0.1) + i64::from(p1.1)),
                );
                let mut found = Vec::new();
                self.collect_t_vertices(
                    e.surface,
                    *p0,
                    *p1,
                    outward,
                    e.depth,
                    &mut found,
                    &mut constraints,
                );
                found.sort_by_key(|v| {
                    let d0 = i64::from(v.0) - i64::from(p0.0);
                    let d1 = i64::from(v.1) - i64::from(p0.1);
                    d0.abs() + d1.abs()
                });
                any |= !found.is_empty();
                per_edge.push(found);
            }
            if any {
                t_vertices.insert(k, per_edge);
            }
        }
        constraints.sort_by_key(|c| std::cmp::Reverse(c.length));
        for c in constraints {
            let a = values.get(&(c.surface, c.ends[0].0, c.ends[0].1)).copied();
            let b = values.get(&(c.surface, c.ends[1].0, c.ends[1].1)).copied();
            if let (Some(a), Some(b)) = (a, b) {
                values.insert((c.surface, c.mid.0, c.mid.1), (a + b) * 0.5);
            }
        }
        VertexRadiosity { values, t_vertices }
    }

    /// Finds the T-vertices along the edge `p0 -> p1` of a leaf at `depth`, whose
    /// other side lies in direction `outward`, recursing into finer neighbours.
    #[allow(clippy::too_many_arguments)]
    fn collect_t_vertices(
        &self,
        surface: u32,
        p0: (u32, u32),
        p1: (u32, u32),
        outward: (i64, i64),
        depth: u8,
        found: &mut Vec<(u32, u32)>,
        constraints: &mut Vec<Constraint>,
    ) {
        let probe = probe_beside(p0, p1, outward);
        let Some(n) = self.locate(surface, probe, depth) else {
            return;
        };
        let ne = &self.elements[n];
        if ne.is_leaf() || ne.depth < depth {
            return;
        }
        let m = midpoint(p0, p1);
        let length = u64::from(p0.0.abs_diff(p1.0)) + u64::from(p0.1.abs_diff(p1.1));
        constraints.push(Constraint {
            length,
            surface,
            mid: m,
            ends: [p0, p1],
        });
        found.push(m);
        self.collect_t_vertices(surface, p0, m, outward, depth + 1, found, constraints);
        self.collect_t_vertices(surface, m, p1, outward, depth + 1, found, constraints);
    }

    /// The crack-free display mesh: every leaf becomes a fan around its centre
    /// through its corners and T-vertices; the centre takes the mean of the
    /// corner values, so shading along every edge is linear between the same
    /// vertex values on both sides.
    #[must_use]
    pub fn shading_mesh(&self, vr: &VertexRadiosity) -> ShadingMesh {
        self.display_mesh(vr, None)
    }

    /// [`Mesh::shading_mesh`] with the light under the textures: the vertices
    /// also carry the irradiance `light` (from [`Mesh::vertex_irradiance`])
    /// and their texture coordinates on the surfaces `surfaces` marks as
    /// textured (one entry per surface of the mesh), interpolated over the
    /// same fans.
    #[must_use]
    pub(crate) fn textured_shading_mesh(
        &self,
        vr: &VertexRadiosity,
        light: &VertexRadiosity,
        surfaces: &[Option<TexelSurface>],
    ) -> ShadingMesh {
        self.display_mesh(vr, Some((light, surfaces)))
    }

    fn display_mesh(
        &self,
        vr: &VertexRadiosity,
        texels: Option<(&VertexRadiosity, &[Option<TexelSurface>])>,
    ) -> ShadingMesh {
        let mut out = ShadingMesh {
            texels: texels.map(|(_, surfaces)| ShadingTexels {
                surfaces: surfaces.to_vec(),
                ..ShadingTexels::default()
            }),
            ..ShadingMesh::default()
        };
        let mut index: HashMap<VertexId, u32> = HashMap::new();
        let mut vertex = |out: &mut ShadingMesh, id: VertexId| -> u32 {
            *index.entry(id).or_insert_with(|| {
                let surface = &self.surfaces[id.0 as usize];
                out.positions.push(surface.position((id.1, id.2)));
                out.radiosity
                    .push(vr.values.get(&id).copied().unwrap_or(Rgb::ZERO));
                if let (Some(t), Some((light, _))) = (&mut out.texels, texels) {
                    t.irradiance
                        .push(light.values.get(&id).copied().unwrap_or(Rgb::ZERO));
                    let uv = t.surfaces.get(id.0 as usize).and_then(Option::as_ref);
                    t.uv.push(uv.map_or(DVec2::ZERO, |s| surface.map_uv(&s.uv, (id.1, id.2))));
                }
                out.positions.len() as u32 - 1
            })
        };
        for k in self.leaves() {
            let e = &self.elements[k];
            let corners = e.cell.corners();
            let t = vr.t_vertices.get(&k);
            if t.is_none() && corners.len() == 3 {
                let ids: Vec<u32> = corners
                    .iter()
                    .map(|c| vertex(&mut out, (e.surface, c.0, c.1)))
                    .collect();
                out.triangles.push([ids[0], ids[1], ids[2]]);
                out.triangle_surface.push(e.surface);
                continue;
            }
            let mut ring = Vec::new();
            let mut corner_sum = Rgb::ZERO;
            let mut corner_light = Rgb::ZERO;
            let mut corner_uv = DVec2::ZERO;
            for (i, c) in corners.iter().enumerate() {
                let id = vertex(&mut out, (e.surface, c.0, c.1));
                corner_sum += out.radiosity[id as usize];
                if let Some(t) = &out.texels {
                    corner_light += t.irradiance[id as usize];
                    corner_uv += t.uv[id as usize];
                }
                ring.push(id);
                if let Some(t) = t {
                    for m in &t[i] {
                        ring.push(vertex(&mut out, (e.surface, m.0, m.1)));
                    }
                }
            }
            let centre = corners
                .iter()
                .map(|c| self.surfaces[e.surface as usize].position(*c))
                .sum::<DVec3>()
                / corners.len() as f64;
            out.positions.push(centre);
            out.radiosity.push(corner_sum / corners.len() as f64);
            if let Some(t) = &mut out.texels {
                // The cell's centre is the mean of its corners under both the
                // bilinear (quad) and the affine (triangle) lattice map.
                t.irradiance.push(corner_light / corners.len() as f64);
                t.uv.push(corner_uv / corners.len() as f64);
            }
            let ci = out.positions.len() as u32 - 1;
            for i in 0..ring.len() {
                out.triangles
                    .push([ci, ring[i], ring[(i + 1) % ring.len()]]);
                out.triangle_surface.push(e.surface);
            }
        }
        out
    }

    /// The edges of every leaf as world segments (for drawing the mesh).
    #[must_use]
    pub fn leaf_edges(&self) -> Vec<[DVec3; 2]> {
        let mut out = Vec::new();
        for k in self.leaves() {
            let e = &self.elements[k];
            let poly = self.surfaces[e.surface as usize].polygon(&e.cell);
            for i in 0..poly.len() {
                out.push([poly[i], poly[(i + 1) % poly.len()]]);
            }
        }
        out
    }
}
