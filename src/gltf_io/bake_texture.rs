//! Base-colour textures kept in a baked file, so that a viewer multiplies the
//! light in `COLOR_0` by the texture's detail rather than showing one colour
//! per element.
//!
//! A kept texture is written as an 8-bit sRGB PNG in the file's buffer, with a
//! sampler of the same wrap modes and magnification filter, read from
//! `TEXCOORD_0`; the texture transform (`KHR_texture_transform`) is applied to
//! the coordinates before they are written, so the file needs no extension.
//! Texels whose reflectance the importer clamped (a band of texel times
//! factor above the largest reflectance) are stored clamped, so that texel
//! times `baseColorFactor` is the reflectance the solve used, up to the 8-bit
//! rounding of the PNG.

use super::export_geometry::GeometryWriter;
use crate::mesh::ShadingMesh;
use crate::render::srgb_encode;
use crate::scene::LinearImage;
use crate::scene::{Scene, Texture, Wrap};
use gltf_json::image::MimeType;
use gltf_json::texture::{Info, MagFilter, MinFilter, Sampler, WrappingMode};
use gltf_json::validation::Checked;
use gltf_json::{Image, Index, Root};
use std::collections::HashMap;
use std::sync::Arc;

/// A vertex colour that clipping to 1 cuts by more than this factor (a
/// stop) shows its texture far darker and flatter than `render` does. Some
/// clipping is common: a texture of mean reflectance 0.5 filling the view
/// is shown brighter than 0.5, clipped by up to a stop (never more, as the
/// tone map stays below 1), and keeps its detail; a texture of darker mean
/// lit as brightly loses more.
pub(super) const FAR_CLIPPED: f64 = 2.0;

/// The largest share of a textured material's vertices that may be clipped
/// by more than [`FAR_CLIPPED`] for its texture to be kept: beyond it the
/// material is baked untextured, each vertex in its display colour (the
/// elements carry their own texture means), which trades the texture's
/// detail within elements for the right light. (A voxel knight under an
/// overcast sky, its palette's reflectances 0.3 to 0.5, clipped 7 533 of
/// its 12 401 vertices, 1 647 of them by more than a stop.)
pub(super) const MAX_CLIPPED_SHARE: f64 = 0.1;

/// Drops from `kept` the texture of every material that `clipped_far`
/// (per material: vertices clipped by more than [`FAR_CLIPPED`], and all
/// its vertices) shows clipped at more than [`MAX_CLIPPED_SHARE`] of its
/// vertices; returns each dropped material's name with its counts, for the
/// warning.
pub(super) fn drop_clipped_textures(
    scene: &Scene,
    clipped_far: &[(usize, usize)],
    kept: &mut [Option<Arc<Texture>>],
) -> Vec<String> {
    let mut dropped = Vec::new();
    for (m, &(clipped, vertices)) in clipped_far.iter().enumerate() {
        if kept[m].is_some() && clipped as f64 > MAX_CLIPPED_SHARE * vertices as f64 {
            kept[m] = None;
            dropped.push(format!(
                "'{}' ({clipped} of {vertices} vertices by more than a stop)",
                scene.materials[m].name
            ));
        }
    }
    dropped
}

/// Per material of `scene`: the base-colour texture a bake keeps, or `None`.
/// A texture is kept when every display triangle on the material lies on a
/// textured surface of `shading` (one with texture coordinates), and the
/// material does not emit: an unlit glTF material draws base colour times
/// vertex colour and cannot add an emission on top, so an emitting textured
/// material is baked as an untextured one is (its radiosity, emission
/// included).
pub(super) fn kept_textures(scene: &Scene, shading: &ShadingMesh) -> Vec<Option<Arc<Texture>>> {
    let Some(texels) = &shading.texels else {
        return vec![None; scene.materials.len()];
    };
    let mut kept: Vec<Option<Arc<Texture>>> = scene
        .materials
        .iter()
        .map(|m| m.base_texture.clone().filter(|_| !m.is_emitter()))
        .collect();
    for &s in &shading.triangle_surface {
        let textured = texels.surfaces.get(s as usize).is_some_and(Option::is_some);
        if !textured {
            kept[scene.surfaces[s as usize].material as usize] = None;
        }
    }
    kept
}

/// Writes kept textures into a file being built, each image once.
#[derive(Default)]
pub(super) struct TextureWriter {
    images: HashMap<*const LinearImage, Index<Image>>,
}

impl TextureWriter {
    /// The reference to `texture` (through `TEXCOORD_0`) for a material,
    /// adding its image, sampler and texture to `root` and the image's bytes
    /// to `geometry`'s buffer. Fails only if the PNG cannot be encoded.
    pub(super) fn reference(
        &mut self,
        root: &mut Root,
        geometry: &mut GeometryWriter,
        texture: &Texture,
    ) -> Result<Info, String> {
        let key = Arc::as_ptr(&texture.image);
        let source = match self.images.get(&key) {
            Some(&i) => i,
            None => {
                let png = png_of(texture)?;
                let view = geometry.image_view(root, &png);
                let i = root.push(Image {
                    buffer_view: Some(view),
                    mime_type: Some(MimeType("image/png".to_string())),
                    name: None,
                    uri: None,
                    extensions: None,
                    extras: Default::default(),
                });
                self.images.insert(key, i);
                i
            }
        };
        let wrap = |w: Wrap| {
            Checked::Valid(match w {
                Wrap::Repeat => WrappingMode::Repeat,
                Wrap::MirroredRepeat => WrappingMode::MirroredRepeat,
                Wrap::ClampToEdge => WrappingMode::ClampToEdge,
            })
        };
        let (mag, min) = if texture.nearest {
            (MagFilter::Nearest, MinFilter::Nearest)
        } else {
            (MagFilter::Linear, MinFilter::Linear)
        };
        let sampler = root.push(Sampler {
            mag_filter: Some(Checked::Valid(mag)),
            min_filter: Some(Checked::Valid(min)),
            name: None,
            wrap_s: wrap(texture.wrap[0]),
            wrap_t: wrap(texture.wrap[1]),
            extensions: None,
            extras: Default::default(),
        });
        let index = root.push(gltf_json::Texture {
            name: None,
            sampler: Some(sampler),
            source,
            extensions: None,
            extras: Default::default(),
        });
        Ok(Info {
            index,
            tex_coord: 0,
            extensions: None,
            extras: Default::default(),
        })
    }
}

/// The texture's image as an 8-bit sRGB PNG, each band of a texel lowered
/// where texel times factor exceeds the texture's largest value.
fn png_of(texture: &Texture) -> Result<Vec<u8>, String> {
    let image = &texture.image;
    let mut bytes = Vec::with_capacity(3 * image.texels.len());
    for texel in &image.texels {
        for (k, &c) in texel.iter().enumerate() {
            let factor = texture.factor[k];
            let linear = f64::from(c);
            let kept = if factor > 0.0 {
                (linear * factor).clamp(0.0, texture.max_value) / factor
            } else {
                linear
            };
            bytes.push((srgb_encode(kept) * 255.0).round() as u8);
        }
    }
    let rgb = image::RgbImage::from_raw(image.width, image.height, bytes)
        .ok_or_else(|| "a texture image has fewer texels than its size".to_string())?;
    let mut out = std::io::Cursor::new(Vec::new());
    rgb.write_to(&mut out, image::ImageFormat::Png)
        .map_err(|e| format!("a texture image could not be encoded as PNG: {e}"))?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_round_trips_8_bit_srgb_and_clamps_above_the_largest_value() {
        // Linear values of the sRGB bytes 0, 128 and 255.
        let decode = |b: u8| {
            let c = f64::from(b) / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        let texels = vec![[decode(0) as f32, decode(128) as f32, decode(255) as f32]];
        let texture = Texture {
            max_value: 0.5,
            ..Texture::nearest(1, 1, texels)
        };
        let png = png_of(&texture).unwrap();
        let back = image::load_from_memory(&png).unwrap().to_rgb8();
        let p = back.get_pixel(0, 0).0;
        // 255 (linear 1) is clamped to linear 0.5, sRGB 188.
        assert_eq!(p, [0, 128, 188]);
    }
}
