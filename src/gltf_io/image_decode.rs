//! Decoding one image's bytes to linear RGB (and its alpha, when it has one),
//! at most a given number of pixels: PNG, JPEG and WebP through the `image`
//! crate, KTX2 / Basis Universal through a transcoder (with the `ktx2`
//! feature). An image larger than the pixels it may keep is reduced: a KTX2
//! file to the first mip level that fits, any other by averaging square
//! blocks of texels. Decoder panics are caught, so that a corrupt image cannot
//! abort the import.

use crate::scene::LinearImage;
use std::io::Cursor;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The first bytes of every KTX 2.0 file.
pub(super) const KTX2_MAGIC: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// A decoded image: linear colour, and its alpha (0 to 255, linear as glTF
/// defines alpha) when the file has an alpha channel.
pub(super) struct Decoded {
    pub image: LinearImage,
    pub alpha: Option<Vec<u8>>,
    /// The size the file holds, before any reduction.
    pub full: (u32, u32),
}

/// The width and height the file holds, from its header.
pub(super) fn dimensions(bytes: &[u8]) -> Result<(u32, u32), String> {
    if bytes.starts_with(&KTX2_MAGIC) {
        return ktx2_dimensions(bytes);
    }
    guarded(|| {
        let reader = image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())?;
        if reader.format().is_none() {
            return Err("image format not recognised or not built in".to_string());
        }
        reader.into_dimensions().map_err(|e| e.to_string())
    })
}

/// Decodes `bytes`, keeping at most `max_pixels` texels (reduced as the
/// module docs say). `decode_pixels` bounds what the decoder may allocate
/// for the full-size image.
pub(super) fn decode(bytes: &[u8], max_pixels: u64, decode_pixels: u64) -> Result<Decoded, String> {
    let (rgba, width, height, has_alpha, full) = if bytes.starts_with(&KTX2_MAGIC) {
        ktx2_rgba(bytes, max_pixels)?
    } else {
        let (rgba, w, h, alpha) = raster_rgba(bytes, decode_pixels)?;
        (rgba, w, h, alpha, (w, h))
    };
    Ok(to_linear(&rgba, width, height, max_pixels, has_alpha, full))
}

/// Runs `f`, turning a panic of the decoder into an error.
fn guarded<T>(f: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f))
        .unwrap_or_else(|_| Err("the image decoder failed on this image".to_string()))
}

/// RGBA, 8 bits a channel, of a PNG, JPEG or WebP image, with whether it has
/// an alpha channel.
fn raster_rgba(bytes: &[u8], pixels: u64) -> Result<(Vec<u8>, u32, u32, bool), String> {
    guarded(|| {
        let mut reader = image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())?;
        let mut bounds = image::Limits::default();
        bounds.max_alloc = Some(pixels.saturating_mul(64).max(1 << 20));
        reader.limits(bounds);
        let decoded = reader.decode().map_err(|e| e.to_string())?;
        let has_alpha = decoded.color().has_alpha();
        let (w, h) = (decoded.width(), decoded.height());
        Ok((decoded.into_rgba8().into_raw(), w, h, has_alpha))
    })
}

#[cfg(feature = "ktx2")]
fn ktx2_dimensions(bytes: &[u8]) -> Result<(u32, u32), String> {
    guarded(|| {
        let t = basisu::Transcoder::new(bytes).map_err(|e| format!("KTX2: {e:?}"))?;
        Ok(t.base_dimensions())
    })
}

#[cfg(not(feature = "ktx2"))]
fn ktx2_dimensions(_bytes: &[u8]) -> Result<(u32, u32), String> {
    Err(NO_KTX2.to_string())
}

#[cfg(not(feature = "ktx2"))]
const NO_KTX2: &str =
    "a KTX2 image, which this build cannot decode (the crate's `ktx2` feature is off)";

/// RGBA of the largest mip level of a KTX2 / Basis Universal texture with at
/// most `max_pixels` texels (the smallest level when none has), its size,
/// whether it has alpha, and the base level's size.
#[cfg(feature = "ktx2")]
#[allow(clippy::type_complexity)]
fn ktx2_rgba(
    bytes: &[u8],
    max_pixels: u64,
) -> Result<(Vec<u8>, u32, u32, bool, (u32, u32)), String> {
    guarded(|| {
        let t = basisu::Transcoder::new(bytes).map_err(|e| format!("KTX2: {e:?}"))?;
        let levels = t.level_count();
        if levels == 0 {
            return Err("KTX2: the file has no image level".to_string());
        }
        let mut level = 0;
        while level + 1 < levels {
            let info = t
                .image_level_info(level)
                .map_err(|e| format!("KTX2: {e:?}"))?;
            if u64::from(info.width) * u64::from(info.height) <= max_pixels {
                break;
            }
            level += 1;
        }
        let info = t
            .image_level_info(level)
            .map_err(|e| format!("KTX2: {e:?}"))?;
        let rgba = t
            .transcode(
                level,
                basisu::TargetFormat::Rgba32,
                basisu::DecodeFlags::NONE,
            )
            .map_err(|e| format!("KTX2 level {level}: {e:?}"))?;
        if rgba.len() as u64 != 4 * u64::from(info.width) * u64::from(info.height) {
            return Err(format!(
                "KTX2 level {level}: the transcoder gave {} bytes for {} x {} texels",
                rgba.len(),
                info.width,
                info.height
            ));
        }
        Ok((
            rgba,
            info.width,
            info.height,
            t.has_alpha(),
            t.base_dimensions(),
        ))
    })
}

#[cfg(not(feature = "ktx2"))]
#[allow(clippy::type_complexity)]
fn ktx2_rgba(_: &[u8], _: u64) -> Result<(Vec<u8>, u32, u32, bool, (u32, u32)), String> {
    Err(NO_KTX2.to_string())
}

/// The smallest whole factor by which both sides of a `width` x `height`
/// image must be divided for it to hold at most `max_pixels` texels.
pub(super) fn reduction(width: u32, height: u32, max_pixels: u64) -> u32 {
    let fits =
        |k: u32| u64::from(width.div_ceil(k)) * u64::from(height.div_ceil(k)) <= max_pixels.max(1);
    let mut k = 1;
    while !fits(k) {
        k += 1;
    }
    k
}

/// Linear RGB (and alpha when `has_alpha`) of sRGB-encoded `rgba`, reduced
/// to at most `max_pixels` texels by averaging `k` x `k` blocks of linear
/// values (the blocks of the last row and column are cut short by the
/// image's edge).
fn to_linear(
    rgba: &[u8],
    width: u32,
    height: u32,
    max_pixels: u64,
    has_alpha: bool,
    full: (u32, u32),
) -> Decoded {
    // A table of the 256 linear values instead of a power per texel.
    let table: Vec<f64> = (0..=255u8)
        .map(|v| srgb_to_linear(f64::from(v) / 255.0))
        .collect();
    let k = reduction(width, height, max_pixels);
    let (w, h) = (width.div_ceil(k), height.div_ceil(k));
    let mut texels = Vec::with_capacity(w as usize * h as usize);
    let mut alpha = Vec::with_capacity(if has_alpha { texels.capacity() } else { 0 });
    for by in 0..h {
        for bx in 0..w {
            let mut sum = [0.0f64; 3];
            let mut alpha_sum = 0u32;
            let mut n = 0u32;
            for y in by * k..((by + 1) * k).min(height) {
                for x in bx * k..((bx + 1) * k).min(width) {
                    let at = 4 * (y as usize * width as usize + x as usize);
                    for (s, c) in sum.iter_mut().zip(&rgba[at..at + 3]) {
                        *s += table[usize::from(*c)];
                    }
                    alpha_sum += u32::from(rgba[at + 3]);
                    n += 1;
                }
            }
            texels.push(sum.map(|s| (s / f64::from(n)) as f32));
            if has_alpha {
                alpha.push(((alpha_sum + n / 2) / n) as u8);
            }
        }
    }
    Decoded {
        image: LinearImage {
            width: w,
            height: h,
            texels,
        },
        alpha: has_alpha.then_some(alpha),
        full,
    }
}

/// The sRGB transfer function, inverted.
pub(super) fn srgb_to_linear(c: f64) -> f64 {
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
        let image = decode(&bytes, 2, 2).unwrap().image;
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
        assert!(decode(b"not an image", 1, 1).is_err());
        assert_eq!(dimensions(&png(&[[1, 2, 3]; 6], 3, 2)).unwrap(), (3, 2));
    }

    #[test]
    fn an_image_over_its_pixels_is_averaged_in_blocks() {
        // 5 x 3 texels into at most 6: blocks of 2 x 2 give 3 x 2 texels.
        assert_eq!(reduction(5, 3, 6), 2);
        assert_eq!(reduction(5, 3, 15), 1);
        assert_eq!(reduction(4096, 4096, 1 << 20), 4);
        let mut texels = vec![[0u8, 0, 0]; 15];
        texels[0] = [200, 100, 0];
        texels[1] = [100, 0, 0];
        texels[4] = [30, 0, 0];
        let d = decode(&png(&texels, 5, 3), 6, 15).unwrap();
        assert_eq!((d.image.width, d.image.height), (3, 2));
        assert_eq!(d.full, (5, 3));
        // The first block averages the linear values of texels (0,0), (1,0),
        // (0,1), (1,1).
        let lin = |c: f64| srgb_to_linear(c / 255.0);
        let red = (lin(200.0) + lin(100.0)) / 4.0;
        assert!((f64::from(d.image.texel(0, 0)[0]) - red).abs() < 1e-6);
        assert!((f64::from(d.image.texel(0, 0)[1]) - lin(100.0) / 4.0).abs() < 1e-6);
        // The last column's blocks are one texel wide: texels (4, 0), (4, 1).
        assert!((f64::from(d.image.texel(2, 0)[0]) - lin(30.0) / 2.0).abs() < 1e-6);
        assert!(d.alpha.is_none());
    }
}
