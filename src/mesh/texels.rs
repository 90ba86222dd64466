//! The light under a texture: irradiance at display vertices of textured
//! surfaces, so that a display can multiply it by the reflectance of each texel
//! instead of showing the element-sized blotches of element reflectance.
//!
//! A leaf's radiosity is `B_e = E_e + rho_e H_e` with `rho_e` the texture's
//! mean over the leaf's footprint, so its irradiance is
//! `H_e = (B_e - E_e) / rho_e` per band ([`element_irradiance`]). Vertex
//! values are area-weighted means of the leaves around them, T-vertices take
//! the value interpolated along the coarse edge, exactly as for radiosity
//! ([`Mesh::vertex_radiosity`]). What is drawn at a point is then
//! `E(texel) + rho(texel) H`, with `H` interpolated smoothly.
//!
//! A band in which a leaf reflects nothing (`rho_e = 0`) says nothing about
//! the light arriving there (`B_e = E_e`): such a leaf is left out of the mean
//! in that band, so its vertices take the irradiance of their neighbours that
//! do reflect. A vertex whose leaves all reflect nothing in a band gets 0 in
//! that band: the texture is black there (its mean over every leaf around is
//! 0), so the drawn value is the emission alone, as the solve has it.

use super::shading::VertexId;
use super::welds::Welds;
use super::HIDDEN_WEIGHT;
use super::{ElementKey, Mesh, VertexRadiosity};
use crate::math::Rgb;
use crate::scene::Material;
use glam::DVec2;
use smallvec::SmallVec;
use std::collections::HashMap;
use std::sync::Arc;

/// What a textured surface shows: the material whose textures are looked up
/// at each point, and the surface's texture coordinates per vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct TexelSurface {
    /// The material with its base-colour (and emissive) texture.
    pub material: Arc<Material>,
    /// Texture coordinates of the surface's vertices, in vertex order.
    pub uv: SmallVec<[DVec2; 4]>,
}

/// The light under the textures, per vertex of a
/// [`ShadingMesh`](super::ShadingMesh) (parallel to its positions).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadingTexels {
    /// Irradiance `H` per vertex (0 on surfaces without texture): the drawn
    /// radiosity at a point is `E(texel) + rho(texel) H`.
    pub irradiance: Vec<Rgb>,
    /// Texture coordinates per vertex, of the set the surface's textures read,
    /// before any texture transform (0 on surfaces without texture).
    pub uv: Vec<DVec2>,
    /// Per surface of the mesh: what it shows, `None` where it has no texture
    /// (its vertices show their radiosity as they are).
    pub surfaces: Vec<Option<TexelSurface>>,
}

/// The irradiance of a leaf of radiosity `b`, emission `emission` and
/// reflectance `reflectance`, per band, with whether the band is known
/// (reflectance above 0). An unknown band is 0. Never negative: `B - E` that
/// rounding took below 0 counts as 0.
#[must_use]
fn element_irradiance(b: Rgb, emission: Rgb, reflectance: Rgb) -> (Rgb, [bool; 3]) {
    let mut h = Rgb::ZERO;
    let mut known = [false; 3];
    for k in 0..3 {
        if reflectance[k] > 0.0 {
            h[k] = ((b[k] - emission[k]) / reflectance[k]).max(0.0);
            known[k] = true;
        }
    }
    (h, known)
}

impl Mesh {
    /// The irradiance at every lattice vertex of the leaves of the surfaces
    /// `textured` selects, from the leaves' radiosities `leaf` (see the module
    /// docs); vertices of other surfaces are absent.
    #[must_use]
    pub(crate) fn vertex_irradiance(
        &self,
        textured: impl Fn(u32) -> bool,
        leaf: impl Fn(ElementKey) -> (Rgb, f64),
    ) -> VertexRadiosity {
        let leaves: Vec<ElementKey> = self
            .leaves()
            .into_iter()
            .filter(|&k| textured(self.elements[k].surface))
            .collect();
        let mut sums: HashMap<VertexId, ([f64; 3], [f64; 3])> = HashMap::new();
        for &k in &leaves {
            let e = &self.elements[k];
            let (value, share) = leaf(k);
            let (h, known) = element_irradiance(value, e.emission, e.reflectance);
            // A leaf weighs by its visible area (see
            // `Mesh::vertex_radiosity_seen`).
            let weight = e.area * share.max(HIDDEN_WEIGHT);
            for c in e.cell.corners() {
                let s = sums.entry((e.surface, c.0, c.1)).or_default();
                for band in 0..3 {
                    if known[band] {
                        s.0[band] += h[band] * weight;
                        s.1[band] += weight;
                    }
                }
            }
        }
        // Irradiance does not depend on the material: the corners of a
        // smooth mesh's facets pool it whatever their textures.
        Welds::new(self, |_, _| true).pool(&mut sums, |t, s| {
            for band in 0..3 {
                t.0[band] += s.0[band];
                t.1[band] += s.1[band];
            }
        });
        let values = sums
            .into_iter()
            .map(|(id, (sum, weight))| {
                let mean = [0, 1, 2].map(|b| {
                    if weight[b] > 0.0 {
                        sum[b] / weight[b]
                    } else {
                        0.0
                    }
                });
                (id, Rgb(mean))
            })
            .collect();
        self.with_t_vertices(&leaves, values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn irradiance_undoes_the_gather_and_marks_black_bands_unknown() {
        // B = E + rho H with H = (4, 8, ?), E = (2, 0, 1), rho = (0.5, 0.25, 0).
        let (h, known) = element_irradiance(
            Rgb::new(4.0, 2.0, 1.0),
            Rgb::new(2.0, 0.0, 1.0),
            Rgb::new(0.5, 0.25, 0.0),
        );
        assert_eq!(h.0, [4.0, 8.0, 0.0]);
        assert_eq!(known, [true, true, false]);
        let (h, _) = element_irradiance(Rgb::splat(1.0 - 1e-15), Rgb::ONE, Rgb::splat(0.5));
        assert_eq!(h, Rgb::ZERO);
    }
}
