//! How a material uses a base-colour texture: which texture coordinate set it
//! reads, the `KHR_texture_transform` applied to it, and the sampler's wrap
//! modes and filter, read from the texture reference and its sampler.

use super::document::Document;
use super::precise::{number, numbers};
use crate::math::Rgb;
use crate::scene::LinearImage;
use crate::scene::{uv_transform, Texture, Wrap};
use std::sync::Arc;

/// glTF's `NEAREST` magnification filter.
const NEAREST: f64 = 9728.0;

/// The texture the reference at JSON `pointer` (a `textureInfo`) describes,
/// showing `image`, its texels times `factor`, each band at most `max_value`.
pub(super) fn texture_use(
    doc: &Document,
    pointer: &str,
    info: &gltf_json::texture::Info,
    image: Arc<LinearImage>,
    factor: Rgb,
    max_value: f64,
) -> Texture {
    let ext = format!("{pointer}/extensions/KHR_texture_transform");
    let offset = numbers::<2>(&doc.raw, &format!("{ext}/offset")).unwrap_or([0.0, 0.0]);
    let rotation = number(&doc.raw, &format!("{ext}/rotation")).unwrap_or(0.0);
    let scale = numbers::<2>(&doc.raw, &format!("{ext}/scale")).unwrap_or([1.0, 1.0]);
    // The extension may redirect the texture to another coordinate set.
    let texcoord = number(&doc.raw, &format!("{ext}/texCoord"))
        .filter(|t| t.is_finite() && *t >= 0.0 && *t < 64.0)
        .map_or(info.tex_coord, |t| t as u32);
    let index = info.index.value();
    let sampler = number(&doc.raw, &format!("/textures/{index}/sampler"))
        .filter(|s| s.is_finite() && *s >= 0.0)
        .map(|s| format!("/samplers/{}", s as usize));
    let read = |field: &str| {
        sampler
            .as_ref()
            .and_then(|s| number(&doc.raw, &format!("{s}/{field}")))
    };
    let wrap = |field: &str| Wrap::from_gltf(read(field).map_or(10497, |c| c as u32));
    Texture {
        image,
        wrap: [wrap("wrapS"), wrap("wrapT")],
        nearest: read("magFilter") == Some(NEAREST),
        transform: uv_transform(offset, rotation, scale),
        texcoord,
        factor,
        max_value,
    }
}
