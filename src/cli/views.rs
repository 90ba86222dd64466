//! Rendering the views of a solution and writing their images: NAME.exr (and
//! NAME.hdr), NAME.png, NAME_false.png, NAME_view2.*, ... Shared by `solve` and
//! `render`, so both write the same files the same way.

use super::setting_flags::with_flags;
use super::view_args::{FalseColourScale, ViewArgs, ViewPlan};
use anyhow::{bail, Result};
use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::output::{check_target, Outputs};
use radiosity::render::{self, DepthBuffer, HdrImage, ShadedMesh};
use radiosity::scene::Camera;
use std::path::{Path, PathBuf};

/// The element mesh drawn over the first view into its own PNG.
pub struct Overlay<'a> {
    /// Where the PNG goes.
    pub png: &'a Path,
    /// The segments to draw (world space).
    pub segments: &'a [[DVec3; 2]],
}

/// The views to render: the `--camera` views, else the first of `own` (the
/// scene's cameras), else `framing()` (the library's default view).
pub fn choose_views(
    plan: &ViewPlan,
    own: &[Camera],
    framing: impl FnOnce() -> Camera,
) -> Vec<Camera> {
    if !plan.cameras.is_empty() {
        plan.cameras.clone()
    } else if let Some(c) = own.first() {
        vec![c.clone()]
    } else {
        vec![framing()]
    }
}

/// Renders `mesh` (radiance per vertex) from every view into `out`, staging
/// the files in `outputs`, and returns their names. View 1 is NAME.*, view k
/// is NAME_viewk.*; one exposure and one false-colour range serve every view,
/// so that they compare.
#[allow(clippy::too_many_arguments)]
pub fn write_views(
    outputs: &mut Outputs,
    mesh: &ShadedMesh,
    views: &[Camera],
    args: &ViewArgs,
    plan: &ViewPlan,
    out: &Path,
    name: &str,
    overlay: Option<Overlay>,
    warnings: &mut Vec<String>,
) -> Result<Vec<String>> {
    let tone = plan.tone;
    let mut names = Vec::new();
    let mut exposure = args.exposure;
    let mut false_range = plan.false_colour.and_then(|(_, r)| r);
    for (i, camera) in views.iter().enumerate() {
        let stem = view_stem(name, i);
        let (image, depth) = render::render_with_depth(mesh, camera, args.width, args.height, 2)?;
        if let Some(w) = black_view(&stem, &image, &depth) {
            eprintln!("warning: {}", with_flags(&w));
            warnings.push(w);
        }
        let stops = *exposure.get_or_insert_with(|| render::auto_exposure(&image, tone));
        let mut write = |suffix: &str| {
            let path = out.join(format!("{stem}{suffix}"));
            names.push(path.display().to_string());
            path
        };
        let exr = write(".exr");
        if args.hdr {
            render::stage_hdr(outputs, &image, &write(".hdr"))?;
        }
        render::stage_exr_and_png(outputs, &image, &exr, &write(".png"), stops, tone)?;
        if let Some((scale, _)) = plan.false_colour {
            let log = scale == FalseColourScale::Log;
            let (lo, hi) = match false_range {
                Some(r) => r,
                None => *false_range.insert(image_range(&image, log)?),
            };
            let picture = render::false_colour(&image, lo, hi, log)?;
            render::stage_rgb8_png(outputs, &picture, &write("_false.png"))?;
        }
        if let (0, Some(o)) = (i, &overlay) {
            let mut over = image.clone();
            // Mesh lines in cyan at display white, whatever the exposure.
            let colour = Rgb::new(0.0, 0.8, 1.0) * 2f64.powf(-stops) * 1.5;
            render::draw_segments_depth_tested(&mut over, &depth, camera, o.segments, colour)?;
            render::stage_png(outputs, &over, o.png, stops, tone)?;
            names.push(o.png.display().to_string());
        }
    }
    Ok(names)
}

/// A warning when the picture of view `stem` is black, saying whether the
/// camera sees no surface or sees only unlit ones, so that a black picture
/// is never taken for a result.
fn black_view(stem: &str, image: &HdrImage, depth: &DepthBuffer) -> Option<String> {
    if image.pixels.iter().any(|p| p.max_band() > 0.0) {
        return None;
    }
    let total = depth.inverse_depth.len();
    let covered = depth.inverse_depth.iter().filter(|d| **d > 0.0).count();
    Some(if covered == 0 {
        format!(
            "{stem}: the picture is black: the camera sees no surface (the scene's camera, \
             --camera or the default framing looks away from it)"
        )
    } else {
        format!(
            "{stem}: the picture is black: every surface in view is unlit ({covered} of \
             {total} pixels show a surface); no light reaches what the camera sees (a light \
             shut inside a closed object, a sun outside a closed room, back faces towards \
             the camera)"
        )
    })
}

/// The file name stem of view `i` (from 0): NAME, then NAME_view2, ...
fn view_stem(name: &str, i: usize) -> String {
    if i == 0 {
        name.to_string()
    } else {
        format!("{name}_view{}", i + 1)
    }
}

/// Checks, before any rendering, that every file [`write_views`] would write
/// for `views` views can be written (no target is a folder, the folder takes
/// new files), and returns their paths.
pub fn check_view_files(
    views: usize,
    args: &ViewArgs,
    plan: &ViewPlan,
    out: &Path,
    name: &str,
) -> Result<Vec<PathBuf>> {
    let mut suffixes = vec![".exr", ".png"];
    if args.hdr {
        suffixes.push(".hdr");
    }
    if plan.false_colour.is_some() {
        suffixes.push("_false.png");
    }
    let mut files = Vec::new();
    for i in 0..views {
        let stem = view_stem(name, i);
        for suffix in &suffixes {
            let file = out.join(format!("{stem}{suffix}"));
            check_target(&file)?;
            files.push(file);
        }
    }
    Ok(files)
}

/// The false-colour range of an image: its smallest and largest luminance
/// (on a log scale, the smallest positive one), widened when they coincide.
fn image_range(image: &HdrImage, log: bool) -> Result<(f64, f64)> {
    let luminance = image
        .pixels
        .iter()
        .map(|p| p.luminance())
        .filter(|l| l.is_finite() && (!log || *l > 0.0));
    let (lo, hi) = luminance.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), l| {
        (lo.min(l), hi.max(l))
    });
    if lo > hi {
        bail!(
            "the image has no {}pixels to scale the false colours by; give --false-colour-range",
            if log { "lit " } else { "finite " }
        );
    }
    Ok(match (log, lo < hi) {
        (_, true) => (lo, hi),
        (true, false) => (lo / 2.0, hi * 2.0),
        (false, false) => (lo - 0.5, hi + 0.5),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_ranges() {
        let mut img = HdrImage::new(3, 1);
        img.set(1, 0, Rgb::splat(0.5));
        img.set(2, 0, Rgb::splat(4.0));
        let (lo, hi) = image_range(&img, true).unwrap();
        assert!((lo - 0.5).abs() < 1e-12 && (hi - 4.0).abs() < 1e-12);
        let (lo, hi) = image_range(&img, false).unwrap();
        assert!(lo.abs() < 1e-12 && (hi - 4.0).abs() < 1e-12);
        let black = HdrImage::new(2, 2);
        assert!(image_range(&black, true).is_err());
        assert_eq!(image_range(&black, false).unwrap(), (-0.5, 0.5));
    }
}
