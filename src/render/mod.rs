//! Images of a solved scene: a z-buffer rasterizer with perspective-correct
//! Gouraud interpolation, line overlays, tone mapping to sRGB, false colour,
//! image comparison, and HDR/LDR file output.
//!
//! ## Brief overview
//!
//! - [`ShadedMesh`]: triangles with one linear RGB *radiance* per vertex; on
//!   textured surfaces ([`Texels`]) the light per vertex, which the texture's
//!   reflectance at each sample multiplies.
//! - [`render`] / [`render_supersampled`] / [`render_with_depth`]: project a
//!   [`ShadedMesh`] through a [`crate::scene::Camera`] into an [`HdrImage`].
//! - [`draw_segments`] / [`draw_segments_depth_tested`]: overlay 3D line segments
//!   (the element mesh) on an image.
//! - [`default_view`]: the view of a baked mesh that has no camera, framed as
//!   a scene's ([`crate::scene::Camera::framing`]).
//! - [`ToneMap`], [`to_srgb8`], [`auto_exposure`]: from radiance to an 8-bit sRGB
//!   preview.
//! - [`false_colour`]: luminance shown on a colour ramp with a labelled legend.
//! - [`diff`]: error metrics between two images.
//! - [`write_exr`], [`write_hdr`], [`write_png`], [`write_rgb8_png`],
//!   [`read_hdr_image`]: files, each written whole or not at all; the `stage_*`
//!   forms add a file to a caller's [`Outputs`](crate::output::Outputs), so that
//!   all the files of one run replace their targets together.
//!
//! ## Conventions
//!
//! Images are row-major with the top row first; pixel `(x, y)` has its centre at
//! `(x + 0.5, y + 0.5)` in pixel units. The projection is a pinhole with the
//! camera's vertical field of view and the *image's* aspect ratio (the camera's
//! own `aspect`, if any, is not used: the caller chooses the image size).

mod clip;
mod default_view;
mod depth;
mod diff;
mod false_colour;
mod font;
mod frame;
mod image;
mod lines;
mod raster;
mod sample_grid;
mod shaded_mesh;
mod shading;
mod tonemap;
mod view;
mod write;

pub use default_view::default_view;
pub use depth::DepthBuffer;
pub use diff::{diff, DiffMetrics};
pub use false_colour::false_colour;
pub use frame::{render, render_supersampled, render_with_depth};
pub use image::HdrImage;
pub use lines::{draw_segments, draw_segments_depth_tested};
pub use shaded_mesh::{ShadedMesh, Texels};
pub(crate) use tonemap::auto_exposure_above;
pub use tonemap::{auto_exposure, srgb_encode, to_srgb8, ToneMap};
pub use write::{
    read_hdr_image, stage_exr, stage_exr_and_png, stage_hdr, stage_png, stage_rgb8_png, write_exr,
    write_hdr, write_png, write_rgb8_png,
};
