//! The public render entry points: one image from a mesh and a camera, with
//! optional supersampling and depth output.

use super::depth::DepthBuffer;
use super::sample_grid::{render_samples, SampleGrid};
use super::view::View;
use super::{HdrImage, ShadedMesh};
use crate::math::Rgb;
use crate::scene::Camera;
use crate::{Error, Result};
use rayon::prelude::*;

/// The largest supersampling factor accepted (per axis).
const MAX_SAMPLES_PER_AXIS: u32 = 16;

/// Renders `mesh` through `camera` into a `width` x `height` image with one
/// sample at each pixel centre. Background is black.
///
/// Fails on an invalid mesh ([`ShadedMesh::validate`]), a degenerate camera, or
/// a zero or oversized resolution.
pub fn render(mesh: &ShadedMesh, camera: &Camera, width: u32, height: u32) -> Result<HdrImage> {
    render_supersampled(mesh, camera, width, height, 1)
}

/// Like [`render`], averaging a regular `samples_per_axis` x `samples_per_axis`
/// grid of samples in each pixel (anti-aliasing). The grid is the pixel-centre
/// grid of an image `samples_per_axis` times larger, box-filtered down.
pub fn render_supersampled(
    mesh: &ShadedMesh,
    camera: &Camera,
    width: u32,
    height: u32,
    samples_per_axis: u32,
) -> Result<HdrImage> {
    let grid = render_grid(mesh, camera, width, height, samples_per_axis)?;
    Ok(colour_of(grid.colour, width, height, samples_per_axis))
}

/// Like [`render_supersampled`], also returning the depth buffer used to hide
/// overlay lines ([`super::draw_segments_depth_tested`]). With supersampling,
/// each pixel's depth is the farthest of its samples (see [`DepthBuffer`]).
pub fn render_with_depth(
    mesh: &ShadedMesh,
    camera: &Camera,
    width: u32,
    height: u32,
    samples_per_axis: u32,
) -> Result<(HdrImage, DepthBuffer)> {
    let s = samples_per_axis;
    let grid = render_grid(mesh, camera, width, height, s)?;
    let inverse_depth = if s == 1 {
        grid.inverse_depth
    } else {
        box_filter(
            &grid.inverse_depth,
            width,
            height,
            s,
            f64::INFINITY,
            f64::min,
        )
    };
    let depth = DepthBuffer {
        width,
        height,
        inverse_depth,
    };
    Ok((colour_of(grid.colour, width, height, s), depth))
}

/// Checks the settings and renders the sample grid.
fn render_grid(
    mesh: &ShadedMesh,
    camera: &Camera,
    width: u32,
    height: u32,
    s: u32,
) -> Result<SampleGrid> {
    if !(1..=MAX_SAMPLES_PER_AXIS).contains(&s) {
        return Err(Error::Setting {
            name: "supersampling",
            message: format!("{s} samples per axis; must be between 1 and {MAX_SAMPLES_PER_AXIS}"),
        });
    }
    mesh.validate()?;
    let too_big = || Error::Setting {
        name: "resolution",
        message: format!("{width}x{height} pixels at {s}x{s} samples is too large"),
    };
    let grid_w = width.checked_mul(s).ok_or_else(too_big)?;
    let grid_h = height.checked_mul(s).ok_or_else(too_big)?;
    let view = View::new(camera, grid_w, grid_h)?;
    Ok(render_samples(mesh, &view))
}

/// The image whose pixels average each `s` x `s` block of sample colours.
fn colour_of(samples: Vec<Rgb>, width: u32, height: u32, s: u32) -> HdrImage {
    let pixels = if s == 1 {
        samples
    } else {
        let weight = 1.0 / f64::from(s * s);
        box_filter(&samples, width, height, s, Rgb::ZERO, |acc, v| acc + v)
            .into_iter()
            .map(|sum| sum * weight)
            .collect()
    };
    HdrImage {
        width,
        height,
        pixels,
    }
}

/// Folds each `s` x `s` block of a `(width s) x (height s)` grid into one value,
/// visiting samples in a fixed order.
fn box_filter<T: Copy + Send + Sync>(
    grid: &[T],
    width: u32,
    height: u32,
    s: u32,
    init: T,
    fold: impl Fn(T, T) -> T + Sync,
) -> Vec<T> {
    let (w, s) = (width as usize, s as usize);
    let grid_w = w * s;
    let mut out = vec![init; w * height as usize];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, px) in row.iter_mut().enumerate() {
            let mut acc = init;
            for j in 0..s {
                let start = (y * s + j) * grid_w + x * s;
                for &v in &grid[start..start + s] {
                    acc = fold(acc, v);
                }
            }
            *px = acc;
        }
    });
    out
}
