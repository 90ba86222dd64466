//! The mean colour of a texture, used to fold a base colour (or emissive) texture
//! into a single diffuse value per material. Only images the `image` crate was
//! built to read (PNG here) and no larger than
//! [`ImportLimits::max_texture_pixels`] are decoded; for anything else the caller
//! ignores the texture and warns.

use super::accessors::view_bytes;
use super::container::read_limited;
use super::document::Document;
use super::limits::ImportLimits;
use super::uri::{resolve, Resolved};
use crate::math::Rgb;
use std::io::Cursor;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// The mean linear colour of texture `index`: texels are decoded from sRGB (as
/// glTF stores colour textures) and averaged unweighted, ignoring alpha and texture
/// coordinates. The error says why the texture could not be used.
pub(super) fn mean_linear_colour(
    doc: &Document,
    buffers: &[Vec<u8>],
    folder: &Path,
    index: usize,
    limits: &ImportLimits,
) -> Result<Rgb, String> {
    let texture = doc
        .root
        .textures
        .get(index)
        .ok_or_else(|| format!("texture {index} does not exist"))?;
    let image_index = texture.source.value();
    let image = doc
        .root
        .images
        .get(image_index)
        .ok_or_else(|| format!("image {image_index} does not exist"))?;
    let bytes: Vec<u8> = match (&image.buffer_view, &image.uri) {
        (Some(view), _) => view_bytes(doc, buffers, view.value())?.0.to_vec(),
        (None, Some(uri)) => match resolve(uri, folder, limits)? {
            Resolved::Data(b) => b,
            Resolved::File(f) => read_limited(&f, limits).map_err(|e| e.to_string())?,
        },
        (None, None) => {
            return Err(format!(
                "image {image_index} has neither a URI nor a buffer view"
            ))
        }
    };
    decode_mean(&bytes, limits)
}

/// Decodes an image and averages its texels; decoder panics are caught so that a
/// corrupt image cannot abort the import.
fn decode_mean(bytes: &[u8], limits: &ImportLimits) -> Result<Rgb, String> {
    let reader = || {
        image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<Rgb, String> {
        let format = reader()?.format();
        if format.is_none() {
            return Err("image format not recognised or not built in".to_string());
        }
        let (w, h) = reader()?.into_dimensions().map_err(|e| e.to_string())?;
        let pixels = u64::from(w) * u64::from(h);
        if pixels == 0 || pixels > limits.max_texture_pixels {
            return Err(format!(
                "{w} x {h} pixels (the limit is {} pixels)",
                limits.max_texture_pixels
            ));
        }
        let mut r = reader()?;
        let mut bounds = image::Limits::default();
        bounds.max_alloc = Some(pixels.saturating_mul(64).max(1 << 20));
        r.limits(bounds);
        let decoded = r.decode().map_err(|e| e.to_string())?.to_rgb32f();
        let mut sum = [0.0f64; 3];
        for p in decoded.pixels() {
            for (total, c) in sum.iter_mut().zip(p.0) {
                *total += srgb_to_linear(f64::from(c));
            }
        }
        Ok(Rgb(sum) / pixels as f64)
    }));
    outcome.unwrap_or_else(|_| Err("the image decoder failed on this image".to_string()))
}

/// The sRGB transfer function, inverted.
fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(pixels: &[[u8; 3]], w: u32, h: u32) -> Vec<u8> {
        let img = image::RgbImage::from_raw(w, h, pixels.iter().flatten().copied().collect())
            .expect("size matches");
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png)
            .expect("encodes");
        out.into_inner()
    }

    #[test]
    fn mean_of_a_two_texel_png_is_the_mean_of_linear_values() {
        let bytes = png(&[[255, 0, 188], [0, 0, 188]], 2, 1);
        let mean = decode_mean(&bytes, &ImportLimits::default()).unwrap();
        // 188/255 in sRGB is 0.5029... linear: ((188/255 + 0.055)/1.055)^2.4.
        let b = ((188.0 / 255.0 + 0.055) / 1.055f64).powf(2.4);
        assert!((mean.0[0] - 0.5).abs() < 1e-7, "{mean:?}");
        assert_eq!(mean.0[1], 0.0);
        assert!((mean.0[2] - b).abs() < 1e-7, "{mean:?}");
    }

    #[test]
    fn garbage_and_oversized_images_are_refused() {
        assert!(decode_mean(b"not an image", &ImportLimits::default()).is_err());
        let bytes = png(&[[1, 2, 3]; 4], 2, 2);
        let small = ImportLimits {
            max_texture_pixels: 3,
            ..ImportLimits::default()
        };
        assert!(decode_mean(&bytes, &small).unwrap_err().contains("limit"));
    }
}
