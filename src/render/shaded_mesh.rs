//! The renderer's input: triangles carrying one radiance per vertex, and on
//! textured surfaces the light a texture lookup per sample multiplies.

use crate::math::Rgb;
use crate::mesh::ShadingMesh;
use crate::scene::Material;
use crate::{Error, GeometryFault, Result};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;
use std::sync::Arc;

/// A triangle mesh with one linear RGB value per vertex, ready to render.
///
/// Triangles are counter-clockwise seen from their front. A triangle seen from
/// behind renders black but still hides what lies behind it: surfaces are
/// single-sided, and their back neither emits nor reflects. With
/// `cull_back_faces` it is left out instead, as glTF viewers draw the
/// single-sided materials of a bake.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadedMesh {
    /// Vertex positions in world space.
    pub positions: Vec<DVec3>,
    /// Radiance per vertex (radiosity B / pi), linear RGB; on the triangles
    /// of a textured material (see `texels`), the light: irradiance H / pi.
    pub values: Vec<Rgb>,
    /// Vertex indices, three per triangle.
    pub triangles: Vec<[u32; 3]>,
    /// Texture detail, `None` when no triangle shows a texture.
    pub texels: Option<Texels>,
    /// Leave out triangles seen from behind rather than draw them black
    /// (glTF's single-sided materials: [`load_baked`](crate::gltf_io::load_baked)
    /// sets it, so that `render` of a bake shows what viewers show, and the
    /// back copies of double-sided surfaces never show through the front).
    pub cull_back_faces: bool,
}

/// Where a [`ShadedMesh`] shows textures. On a triangle with a material, the
/// radiance drawn at a sample is `E(uv) / pi + rho(uv) * value`, with `value`
/// (the light) and `uv` interpolated from the vertices, `rho` and `E` the
/// material's [`reflectance_at`](Material::reflectance_at) and
/// [`emission_at`](Material::emission_at) there.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Texels {
    /// Texture coordinates per vertex (parallel to the positions).
    pub uv: Vec<DVec2>,
    /// Per triangle: the material looked up at every sample, or `None` for a
    /// triangle that shows its interpolated values as they are.
    pub materials: Vec<Option<Arc<Material>>>,
}

impl ShadedMesh {
    /// The radiance of a display mesh's vertex radiosities: radiosity / pi,
    /// what a camera sees on a diffuse surface. Vertices of textured surfaces
    /// (see [`ShadingMesh::texels`]) carry the irradiance / pi instead, and
    /// their triangles the surface's material.
    #[must_use]
    pub fn radiance_of(shading: ShadingMesh) -> ShadedMesh {
        let Some(light) = shading.texels else {
            return ShadedMesh {
                positions: shading.positions,
                values: shading.radiosity.iter().map(|b| *b / PI).collect(),
                triangles: shading.triangles,
                texels: None,
                cull_back_faces: false,
            };
        };
        let mut values: Vec<Rgb> = shading.radiosity.iter().map(|b| *b / PI).collect();
        let mut materials = Vec::with_capacity(shading.triangles.len());
        for (tri, &s) in shading.triangles.iter().zip(&shading.triangle_surface) {
            let surface = light.surfaces.get(s as usize).and_then(Option::as_ref);
            if surface.is_some() {
                for &v in tri {
                    values[v as usize] = light.irradiance[v as usize] / PI;
                }
            }
            materials.push(surface.map(|t| Arc::clone(&t.material)));
        }
        ShadedMesh {
            positions: shading.positions,
            values,
            triangles: shading.triangles,
            texels: Some(Texels {
                uv: light.uv,
                materials,
            }),
            cull_back_faces: false,
        }
    }

    /// Checks that there is one value per position, that every index is in
    /// range, and that positions and values are finite. The error names the
    /// first offending vertex or triangle.
    pub fn validate(&self) -> Result<()> {
        if self.values.len() != self.positions.len() {
            return Err(Error::geometry(
                GeometryFault::Mismatch,
                format!(
                    "shaded mesh has {} positions but {} values",
                    self.positions.len(),
                    self.values.len()
                ),
            ));
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::geometry(
                GeometryFault::NonFinite,
                format!(
                    "shaded mesh vertex {i} has a non-finite position {}",
                    self.positions[i]
                ),
            ));
        }
        if let Some(i) = self.values.iter().position(|v| !v.is_finite()) {
            return Err(Error::geometry(
                GeometryFault::NonFinite,
                format!(
                    "shaded mesh vertex {i} has a non-finite value {:?}",
                    self.values[i].0
                ),
            ));
        }
        let n = self.positions.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&bad) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(Error::geometry(
                    GeometryFault::Mismatch,
                    format!(
                        "shaded mesh triangle {t} refers to vertex {bad}, but there are only {n}"
                    ),
                ));
            }
        }
        if let Some(t) = &self.texels {
            if t.uv.len() != n || t.materials.len() != self.triangles.len() {
                return Err(Error::geometry(
                    GeometryFault::Mismatch,
                    format!(
                        "shaded mesh has {n} positions and {} triangles but {} texture \
                     coordinates and {} triangle materials",
                        self.triangles.len(),
                        t.uv.len(),
                        t.materials.len()
                    ),
                ));
            }
            if let Some(i) = t.uv.iter().position(|p| !p.is_finite()) {
                return Err(Error::geometry(
                    GeometryFault::NonFinite,
                    format!(
                        "shaded mesh vertex {i} has non-finite texture coordinates {}",
                        t.uv[i]
                    ),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_triangle() -> ShadedMesh {
        ShadedMesh {
            positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
            values: vec![Rgb::ONE; 3],
            triangles: vec![[0, 1, 2]],
            texels: None,
            cull_back_faces: false,
        }
    }

    #[test]
    fn accepts_a_sound_mesh() {
        assert!(one_triangle().validate().is_ok());
    }

    #[test]
    fn rejects_out_of_range_index() {
        let mut m = one_triangle();
        m.triangles.push([0, 1, 3]);
        let e = m.validate().unwrap_err().to_string();
        assert!(e.contains("triangle 1") && e.contains("vertex 3"), "{e}");
    }

    #[test]
    fn rejects_non_finite_values_and_positions() {
        let mut m = one_triangle();
        m.values[2] = Rgb::new(0.0, f64::NAN, 0.0);
        assert!(m.validate().unwrap_err().to_string().contains("vertex 2"));
        let mut m = one_triangle();
        m.positions[1].x = f64::INFINITY;
        assert!(m.validate().unwrap_err().to_string().contains("vertex 1"));
    }

    #[test]
    fn rejects_mismatched_lengths() {
        let mut m = one_triangle();
        m.values.pop();
        assert!(m.validate().is_err());
        let mut m = one_triangle();
        m.texels = Some(Texels {
            uv: vec![DVec2::ZERO; 2],
            materials: vec![None],
        });
        assert!(m.validate().is_err());
        m.texels.as_mut().unwrap().uv.push(DVec2::NAN);
        assert!(m.validate().unwrap_err().to_string().contains("vertex 2"));
    }
}
