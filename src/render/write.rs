//! Image files: linear OpenEXR and Radiance HDR, tone-mapped PNG, and reading
//! the HDR formats back.

use super::{to_srgb8, HdrImage, ToneMap};
use crate::math::Rgb;
use crate::{Error, Result};
use image::{DynamicImage, ImageError, ImageFormat, Rgb32FImage};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes `img` as an OpenEXR file of 32-bit float linear RGB.
pub fn write_exr(img: &HdrImage, path: &Path) -> Result<()> {
    let buffer = to_f32_buffer(img, path)?;
    encode(
        path,
        &DynamicImage::ImageRgb32F(buffer),
        ImageFormat::OpenExr,
    )
}

/// Writes `img` as a Radiance RGBE (`.hdr`) file: linear RGB with an 8-bit
/// mantissa per channel and a shared exponent.
pub fn write_hdr(img: &HdrImage, path: &Path) -> Result<()> {
    let buffer = to_f32_buffer(img, path)?;
    encode(path, &DynamicImage::ImageRgb32F(buffer), ImageFormat::Hdr)
}

/// Writes an 8-bit sRGB PNG of `img` through [`to_srgb8`].
pub fn write_png(img: &HdrImage, path: &Path, exposure_stops: f64, tone: ToneMap) -> Result<()> {
    check_size(img, path)?;
    let rgb = to_srgb8(img, exposure_stops, tone);
    encode(path, &DynamicImage::ImageRgb8(rgb), ImageFormat::Png)
}

/// Reads an OpenEXR or Radiance HDR file (recognised by its content) into a
/// linear image. An alpha channel, if any, is dropped.
pub fn read_hdr_image(path: &Path) -> Result<HdrImage> {
    let decoded = image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| Error::io(path, e))?
        .decode()
        .map_err(|e| match e {
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
    let data = img.pixels.iter().flat_map(|p| p.to_f32()).collect();
    Rgb32FImage::from_raw(img.width, img.height, data).ok_or_else(|| Error::Output {
        path: path.to_path_buf(),
        message: "pixel buffer does not match the image size".to_string(),
    })
}

/// Creates the parent folder if needed, then encodes `image` into `path`.
fn encode(path: &Path, image: &DynamicImage, format: ImageFormat) -> Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
    }
    let file = File::create(path).map_err(|e| Error::io(path, e))?;
    let mut writer = BufWriter::new(file);
    image.write_to(&mut writer, format).map_err(|e| match e {
        ImageError::IoError(io) => Error::io(path, io),
        other => Error::Output {
            path: path.to_path_buf(),
            message: other.to_string(),
        },
    })?;
    writer.flush().map_err(|e| Error::io(path, e))
}
