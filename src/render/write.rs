//! Image files: linear OpenEXR and Radiance HDR, tone-mapped PNG, and reading
//! the HDR formats back.

use super::{to_srgb8, HdrImage, ToneMap};
use crate::input::open_regular;
use crate::math::Rgb;
use crate::output::{write_file, Outputs, WriteSeek};
use crate::{Error, Result};
use image::{DynamicImage, ImageError, ImageFormat, Rgb32FImage, RgbImage};
use std::io::BufReader;
use std::path::Path;

/// Writes `img` as an OpenEXR file of 32-bit float linear RGB, whole or not
/// at all (see [`crate::output`]).
pub fn write_exr(img: &HdrImage, path: &Path) -> Result<()> {
    let mut outputs = Outputs::new();
    stage_exr(&mut outputs, img, path)?;
    outputs.commit().map(drop)
}

/// [`write_exr`] into a caller's set of outputs, renamed into place with the
/// rest of the set by [`Outputs::commit`].
pub fn stage_exr(outputs: &mut Outputs, img: &HdrImage, path: &Path) -> Result<()> {
    let buffer = to_f32_buffer(img, path)?;
    outputs.stage(path, |w| {
        encode(
            path,
            w,
            &DynamicImage::ImageRgb32F(buffer),
            ImageFormat::OpenExr,
        )
    })
}

/// [`stage_exr`] and [`stage_png`] of one image at once: the two files are
/// encoded side by side (the EXR's compression and the PNG's tone mapping
/// and compression are each a sizeable serial step at the end of a solve),
/// then staged in that order.
pub fn stage_exr_and_png(
    outputs: &mut Outputs,
    img: &HdrImage,
    exr: &Path,
    png: &Path,
    exposure_stops: f64,
    tone: ToneMap,
) -> Result<()> {
    let (exr_bytes, png_bytes) = rayon::join(
        || {
            let buffer = to_f32_buffer(img, exr)?;
            in_memory(
                exr,
                &DynamicImage::ImageRgb32F(buffer),
                ImageFormat::OpenExr,
            )
        },
        || {
            check_size(img, png)?;
            let rgb = to_srgb8(img, exposure_stops, tone);
            in_memory(png, &DynamicImage::ImageRgb8(rgb), ImageFormat::Png)
        },
    );
    let (exr_bytes, png_bytes) = (exr_bytes?, png_bytes?);
    outputs.stage(exr, |w| {
        w.write_all(&exr_bytes).map_err(|e| Error::io(exr, e))
    })?;
    outputs.stage(png, |w| {
        w.write_all(&png_bytes).map_err(|e| Error::io(png, e))
    })
}

/// `image` encoded as `format`, in memory (`path` names it in errors).
fn in_memory(path: &Path, image: &DynamicImage, format: ImageFormat) -> Result<Vec<u8>> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, format)
        .map_err(|e| image_error(path, e))?;
    Ok(bytes.into_inner())
}

/// Writes `img` as a Radiance RGBE (`.hdr`) file: linear RGB with an 8-bit
/// mantissa per channel and a shared exponent; whole or not at all.
pub fn write_hdr(img: &HdrImage, path: &Path) -> Result<()> {
    let mut outputs = Outputs::new();
    stage_hdr(&mut outputs, img, path)?;
    outputs.commit().map(drop)
}

/// [`write_hdr`] into a caller's set of outputs.
pub fn stage_hdr(outputs: &mut Outputs, img: &HdrImage, path: &Path) -> Result<()> {
    let buffer = to_f32_buffer(img, path)?;
    outputs.stage(path, |w| {
        encode(
            path,
            w,
            &DynamicImage::ImageRgb32F(buffer),
            ImageFormat::Hdr,
        )
    })
}

/// Writes an 8-bit sRGB PNG of `img` through [`to_srgb8`], whole or not at
/// all.
pub fn write_png(img: &HdrImage, path: &Path, exposure_stops: f64, tone: ToneMap) -> Result<()> {
    let mut outputs = Outputs::new();
    stage_png(&mut outputs, img, path, exposure_stops, tone)?;
    outputs.commit().map(drop)
}

/// [`write_png`] into a caller's set of outputs.
pub fn stage_png(
    outputs: &mut Outputs,
    img: &HdrImage,
    path: &Path,
    exposure_stops: f64,
    tone: ToneMap,
) -> Result<()> {
    check_size(img, path)?;
    let rgb = to_srgb8(img, exposure_stops, tone);
    outputs.stage(path, |w| {
        encode(path, w, &DynamicImage::ImageRgb8(rgb), ImageFormat::Png)
    })
}

/// Writes an 8-bit RGB image (already in display colours, such as a
/// [`false_colour`](super::false_colour) picture) as a PNG, whole or not at
/// all.
pub fn write_rgb8_png(rgb: &RgbImage, path: &Path) -> Result<()> {
    write_file(path, |w| rgb8_png(rgb, path, w))
}

/// [`write_rgb8_png`] into a caller's set of outputs.
pub fn stage_rgb8_png(outputs: &mut Outputs, rgb: &RgbImage, path: &Path) -> Result<()> {
    outputs.stage(path, |w| rgb8_png(rgb, path, w))
}

fn rgb8_png(rgb: &RgbImage, path: &Path, w: &mut dyn WriteSeek) -> Result<()> {
    rgb.write_to(&mut &mut *w, ImageFormat::Png)
        .map_err(|e| image_error(path, e))
}

/// Reads an OpenEXR or Radiance HDR file (recognised by its content) into a
/// linear image. An alpha channel, if any, is dropped.
pub fn read_hdr_image(path: &Path) -> Result<HdrImage> {
    let file = open_regular(path)?;
    let reader = image::ImageReader::new(BufReader::new(file))
        .with_guessed_format()
        .map_err(|e| Error::io(path, e))?;
    // A PNG or JPEG holds display colours (tone-mapped, 8-bit, sRGB), not
    // radiance: measured as if it were, every figure would be wrong.
    match reader.format() {
        Some(ImageFormat::OpenExr | ImageFormat::Hdr) | None => {}
        Some(other) => {
            return Err(Error::Output {
                path: path.to_path_buf(),
                message: format!(
                    "this is a {} image: display colours, not linear radiance; give the \
                     OpenEXR (.exr) or Radiance HDR (.hdr) file",
                    other
                        .extensions_str()
                        .first()
                        .unwrap_or(&"non-HDR")
                        .to_uppercase()
                ),
            })
        }
    }
    let decoded = reader.decode().map_err(|e| match e {
        ImageError::IoError(io) => Error::io(path, io),
        other => Error::io(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidData, other.to_string()),
        ),
    })?;
    let rgb = decoded.into_rgb32f();
    let (width, height) = rgb.dimensions();
    let pixels = rgb.pixels().map(|p| Rgb(p.0.map(f64::from))).collect();
    Ok(HdrImage {
        width,
        height,
        pixels,
    })
}

fn check_size(img: &HdrImage, path: &Path) -> Result<()> {
    if img.width == 0 || img.height == 0 || !img.is_consistent() {
        return Err(Error::Output {
            path: path.to_path_buf(),
            message: format!(
                "cannot write a {}x{} image holding {} pixels",
                img.width,
                img.height,
                img.pixels.len()
            ),
        });
    }
    Ok(())
}

fn to_f32_buffer(img: &HdrImage, path: &Path) -> Result<Rgb32FImage> {
    check_size(img, path)?;
    check_single_precision(img, path)?;
    let data = img.pixels.iter().flat_map(|p| p.to_f32()).collect();
    Rgb32FImage::from_raw(img.width, img.height, data).ok_or_else(|| Error::Output {
        path: path.to_path_buf(),
        message: "pixel buffer does not match the image size".to_string(),
    })
}

/// Refuses an image with a value a 32-bit float cannot hold (beyond 3.4e38,
/// or not finite), which the file would store as infinity without a word.
fn check_single_precision(img: &HdrImage, path: &Path) -> Result<()> {
    let limit = f64::from(f32::MAX);
    let bad = img
        .pixels
        .iter()
        .position(|p| p.0.iter().any(|v| !(v.is_finite() && v.abs() <= limit)));
    let Some(i) = bad else {
        return Ok(());
    };
    let w = img.width.max(1) as usize;
    Err(Error::Output {
        path: path.to_path_buf(),
        message: format!(
            "pixel ({}, {}) has radiance {:?}, beyond the largest value a 32-bit image file \
             holds ({:e}); results are linear in light, so scale the scene's emission and \
             lights down by one factor",
            i % w,
            i / w,
            img.pixels[i].0,
            f32::MAX
        ),
    })
}

/// Encodes `image` into the writer of a staged output file.
fn encode(
    path: &Path,
    w: &mut dyn WriteSeek,
    image: &DynamicImage,
    format: ImageFormat,
) -> Result<()> {
    image
        .write_to(&mut &mut *w, format)
        .map_err(|e| image_error(path, e))
}

fn image_error(path: &Path, e: ImageError) -> Error {
    match e {
        ImageError::IoError(io) => Error::io(path, io),
        other => Error::Output {
            path: path.to_path_buf(),
            message: other.to_string(),
        },
    }
}
