//! Decoding the images that textures show, once per image and file.
//!
//! [`Images`] is the cache: the first texture that asks for an image decodes it
//! into a [`LinearImage`] (linear RGB, `f32`), every later texture showing the
//! same image gets the same decoded pixels, and an image that could not be used
//! is not tried again. The pixels decoded from one file are bounded by
//! [`ImportLimits::max_texture_pixels`] in total, not per image, so that a small
//! file cannot have one large image (or many) decoded over and over. Only
//! images the `image` crate was built to read (PNG here) are decoded.

use super::accessors::view_bytes;
use super::container::read_limited;
use super::document::Document;
use super::limits::ImportLimits;
use super::uri::{resolve, Resolved};
use super::{describe, gltf_error};
use crate::error::Error;
use crate::input::is_not_regular;
use crate::math::Rgb;
use std::collections::HashMap;
use std::io::Cursor;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::Arc;

/// An image decoded to linear RGB: texels are converted from sRGB (as glTF
/// stores colour textures), alpha is dropped. Row-major, top row first, as the
/// image file stores it (glTF texture coordinate (0, 0) is the top left).
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// `width * height` linear RGB texels.
    pub texels: Vec<[f32; 3]>,
}

impl LinearImage {
    /// The texel at column `x`, row `y` (both in range).
    #[must_use]
    pub fn texel(&self, x: u32, y: u32) -> [f32; 3] {
        self.texels[y as usize * self.width as usize + x as usize]
    }

    /// The unweighted mean of every texel, summed in double precision.
    #[must_use]
    pub fn mean(&self) -> Rgb {
        let mut sum = [0.0f64; 3];
        for t in &self.texels {
            for (total, c) in sum.iter_mut().zip(t) {
                *total += f64::from(*c);
            }
        }
        Rgb(sum) / self.texels.len().max(1) as f64
    }
}

/// Why a texture cannot be used.
#[derive(Debug)]
pub(super) enum Unusable {
    /// The texture is left out with a warning saying why (a broken, unknown or
    /// over-budget image): the material's factor alone is used.
    Ignored(String),
    /// The file is refused: the image names something that must never be read
    /// (a FIFO or device, which would block or never end).
    Refused(Error),
}

/// The outcome of decoding one image, kept so that it is never decoded twice.
#[derive(Clone, Debug)]
enum Outcome {
    Decoded(Arc<LinearImage>),
    Ignored(String),
}

/// The images of one file, decoded on first use.
pub(super) struct Images<'a> {
    doc: &'a Document,
    buffers: &'a [Vec<u8>],
    /// The scene file, whose folder holds the image files.
    scene: &'a Path,
    limits: &'a ImportLimits,
    by_image: HashMap<usize, Outcome>,
    /// Images decoded (successfully or not) so far; images refused before
    /// decoding (unreadable, over the pixel budget) are not counted.
    pub decodes: usize,
    /// Pixels charged against the file's budget so far.
    pub pixels: u64,
}

impl<'a> Images<'a> {
    /// An empty cache for the images of `doc`, read from the scene file
    /// `scene` (image files are relative to its folder).
    pub(super) fn new(
        doc: &'a Document,
        buffers: &'a [Vec<u8>],
        scene: &'a Path,
        limits: &'a ImportLimits,
    ) -> Self {
        Images {
            doc,
            buffers,
            scene,
            limits,
            by_image: HashMap::new(),
            decodes: 0,
            pixels: 0,
        }
    }

    /// The decoded image that texture `index` shows.
    pub(super) fn for_texture(&mut self, index: usize) -> Result<Arc<LinearImage>, Unusable> {
        let texture = self
            .doc
            .root
            .textures
            .get(index)
            .ok_or_else(|| Unusable::Ignored(format!("texture {index} does not exist")))?;
        let image = texture.source.value();
        let outcome = match self.by_image.get(&image) {
            Some(known) => known.clone(),
            None => {
                let fresh = match self.decode(image) {
                    Ok(decoded) => Outcome::Decoded(Arc::new(decoded)),
                    Err(Unusable::Ignored(why)) => Outcome::Ignored(why),
                    Err(refused) => return Err(refused),
                };
                self.by_image.insert(image, fresh.clone());
                fresh
            }
        };
        match outcome {
            Outcome::Decoded(decoded) => Ok(decoded),
            Outcome::Ignored(why) => Err(Unusable::Ignored(why)),
        }
    }

    /// Reads and decodes image `index`, charging its pixels to the budget.
    fn decode(&mut self, index: usize) -> Result<LinearImage, Unusable> {
        let image = self
            .doc
            .root
            .images
            .get(index)
            .ok_or_else(|| Unusable::Ignored(format!("image {index} does not exist")))?;
        let what = describe("image", index, image.name.as_deref());
        let ignored = |why: String| Unusable::Ignored(format!("{what}: {why}"));
        let bytes: Vec<u8> = match (&image.buffer_view, &image.uri) {
            (Some(view), _) => view_bytes(self.doc, self.buffers, view.value())
                .map_err(ignored)?
                .0
                .to_vec(),
            (None, Some(uri)) => {
                let folder = self.scene.parent().unwrap_or(Path::new("."));
                match resolve(uri, folder, self.limits).map_err(ignored)? {
                    Resolved::Data(b) => b,
                    Resolved::File(f) => read_image_file(self.scene, &f, uri, self.limits, &what)
                        .map_err(|u| match u {
                        Unusable::Ignored(why) => ignored(why),
                        refused => refused,
                    })?,
                }
            }
            (None, None) => return Err(ignored("it has neither a URI nor a buffer view".into())),
        };
        let (w, h) = dimensions(&bytes).map_err(ignored)?;
        let pixels = u64::from(w) * u64::from(h);
        let total = self.pixels.saturating_add(pixels);
        if pixels == 0 || total > self.limits.max_texture_pixels {
            return Err(ignored(format!(
                "{w} x {h} pixels would bring the pixels decoded from this file to {total}, \
                 more than the limit of {}",
                self.limits.max_texture_pixels
            )));
        }
        self.pixels = total;
        self.decodes += 1;
        decode_linear(&bytes, pixels).map_err(ignored)
    }
}

/// The bytes of an image file named by `uri`. A file that cannot be read is
/// ignored like any broken image, but one that is not a regular file refuses
/// the whole scene: a FIFO or a device in a scene's folder is no texture.
fn read_image_file(
    scene: &Path,
    file: &Path,
    uri: &str,
    limits: &ImportLimits,
    what: &str,
) -> Result<Vec<u8>, Unusable> {
    read_limited(file, limits).map_err(|e| {
        if !is_not_regular(&e) {
            return Unusable::Ignored(format!("cannot read '{uri}': {e}"));
        }
        let reason = match &e {
            Error::Io { error, .. } => error.to_string(),
            other => other.to_string(),
        };
        Unusable::Refused(gltf_error(
            scene,
            format!("{what}: its URI '{uri}' is {reason}"),
        ))
    })
}

/// The width and height from the image's header, without decoding it.
fn dimensions(bytes: &[u8]) -> Result<(u32, u32), String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let reader = image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())?;
        if reader.format().is_none() {
            return Err("image format not recognised or not built in".to_string());
        }
        reader.into_dimensions().map_err(|e| e.to_string())
    }));
    outcome.unwrap_or_else(|_| Err("the image decoder failed on this image".to_string()))
}

/// Decodes an image of `pixels` texels into linear RGB; decoder panics are
/// caught so that a corrupt image cannot abort the import.
fn decode_linear(bytes: &[u8], pixels: u64) -> Result<LinearImage, String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<LinearImage, String> {
        let mut reader = image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())?;
        let mut bounds = image::Limits::default();
        bounds.max_alloc = Some(pixels.saturating_mul(64).max(1 << 20));
        reader.limits(bounds);
        let decoded = reader.decode().map_err(|e| e.to_string())?;
        let (width, height) = (decoded.width(), decoded.height());
        let colour = decoded.color();
        let texels = if colour.bytes_per_pixel() == colour.channel_count() {
            // Eight bits a channel: a table of the 256 linear values instead of
            // a power per texel, and no f32 copy of the whole image.
            let table: Vec<f32> = (0..=255u8)
                .map(|v| srgb_to_linear(f64::from(v) / 255.0) as f32)
                .collect();
            let rgb = decoded.into_rgb8();
            rgb.pixels()
                .map(|p| p.0.map(|c| table[usize::from(c)]))
                .collect()
        } else {
            let rgb = decoded.into_rgb32f();
            rgb.pixels()
                .map(|p| p.0.map(|c| srgb_to_linear(f64::from(c)) as f32))
                .collect()
        };
        Ok(LinearImage {
            width,
            height,
            texels,
        })
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
        let image = decode_linear(&bytes, 2).unwrap();
        assert_eq!((image.width, image.height), (2, 1));
        let mean = image.mean();
        // 188/255 in sRGB is 0.5029... linear: ((188/255 + 0.055)/1.055)^2.4.
        let b = ((188.0 / 255.0 + 0.055) / 1.055f64).powf(2.4);
        assert!((mean.0[0] - 0.5).abs() < 1e-7, "{mean:?}");
        assert_eq!(mean.0[1], 0.0);
        assert!((mean.0[2] - b).abs() < 1e-7, "{mean:?}");
        assert_eq!(image.texel(1, 0)[0], 0.0);
        assert_eq!(image.texel(0, 0)[0], 1.0);
    }

    #[test]
    fn garbage_is_refused_and_sizes_come_from_the_header() {
        assert!(dimensions(b"not an image").is_err());
        assert!(decode_linear(b"not an image", 1).is_err());
        assert_eq!(dimensions(&png(&[[1, 2, 3]; 6], 3, 2)).unwrap(), (3, 2));
    }
}
