//! Which surfaces of a scene show texture detail in the display mesh.

use crate::mesh::TexelSurface;
use crate::scene::Scene;
use std::collections::HashMap;
use std::sync::Arc;

/// Per surface of `scene`: the material and texture coordinates of a surface
/// whose material has a base-colour or emissive texture and that has texture
/// coordinates, `None` for the others. Empty when no surface is textured, so
/// that untextured scenes pay nothing. Surfaces of one material share it.
pub(crate) fn texel_surfaces(scene: &Scene) -> Vec<Option<TexelSurface>> {
    let textured = |s: &crate::scene::Surface| {
        let m = scene.material_of(s);
        (m.base_texture.is_some() || m.emissive_texture.is_some()) && s.uv.len() == s.vertices.len()
    };
    if !scene.surfaces.iter().any(textured) {
        return Vec::new();
    }
    let mut shared = HashMap::new();
    scene
        .surfaces
        .iter()
        .map(|s| {
            textured(s).then(|| TexelSurface {
                material: Arc::clone(
                    shared
                        .entry(s.material)
                        .or_insert_with(|| Arc::new(scene.material_of(s).clone())),
                ),
                uv: s.uv.clone(),
            })
        })
        .collect()
}
