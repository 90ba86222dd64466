//! Overlay of 3D line segments (the element mesh) on a rendered image.

use super::clip::ClipVolume;
use super::view::View;
use super::{DepthBuffer, HdrImage};
use crate::math::Rgb;
use crate::scene::Camera;
use crate::{Error, Result};
use glam::{DVec2, DVec3};

/// A line point is drawn unless the surface is nearer by more than this
/// fraction of its depth. The offset pulls lines lying on a surface in front of
/// it, including at grazing angles where depth changes quickly across a pixel.
const LINE_DEPTH_OFFSET: f64 = 1e-2;

/// The near plane for lines, as a fraction of the farthest endpoint's depth.
const NEAR_FRACTION: f64 = 1e-9;

/// Draws `segments` (world space, clipped to the near plane) in `colour` over
/// `image`, projected through `camera` with the image's aspect ratio. Lines are
/// one pixel wide, not anti-aliased, and drawn over everything.
pub fn draw_segments(
    image: &mut HdrImage,
    camera: &Camera,
    segments: &[[DVec3; 2]],
    colour: Rgb,
) -> Result<()> {
    draw(image, None, camera, segments, colour)
}

/// Like [`draw_segments`], but a line point is hidden where `depth` (from
/// [`super::render_with_depth`] with the same camera and size) holds a surface
/// nearer than the line by more than 1% of the line's depth.
pub fn draw_segments_depth_tested(
    image: &mut HdrImage,
    depth: &DepthBuffer,
    camera: &Camera,
    segments: &[[DVec3; 2]],
    colour: Rgb,
) -> Result<()> {
    if depth.width != image.width
        || depth.height != image.height
        || depth.inverse_depth.len() != image.pixels.len()
    {
        return Err(Error::Setting {
            name: "resolution",
            message: format!(
                "depth buffer is {}x{} but the image is {}x{}",
                depth.width, depth.height, image.width, image.height
            ),
        });
    }
    draw(image, Some(depth), camera, segments, colour)
}

fn draw(
    image: &mut HdrImage,
    depth: Option<&DepthBuffer>,
    camera: &Camera,
    segments: &[[DVec3; 2]],
    colour: Rgb,
) -> Result<()> {
    if !image.is_consistent() {
        return Err(Error::Setting {
            name: "resolution",
            message: format!(
                "image is {}x{} but holds {} pixels",
                image.width,
                image.height,
                image.pixels.len()
            ),
        });
    }
    let view = View::new(camera, image.width, image.height)?;
    let ends: Vec<[DVec3; 2]> = segments
        .iter()
        .filter(|s| s[0].is_finite() && s[1].is_finite())
        .map(|s| s.map(|p| view.to_view(p)))
        .collect();
    let farthest = ends
        .iter()
        .flatten()
        .map(|p| p.z)
        .fold(f64::NEG_INFINITY, f64::max);
    if farthest <= 0.0 {
        return Ok(());
    }
    let clip = ClipVolume::new(&view, farthest * NEAR_FRACTION);
    for &[a, b] in &ends {
        if let Some((a, b)) = clip.clip_segment(a, b) {
            let pa = (view.to_pixel(a), 1.0 / a.z);
            let pb = (view.to_pixel(b), 1.0 / b.z);
            draw_projected(image, depth, pa, pb, colour);
        }
    }
    Ok(())
}

/// Steps along the projected segment one pixel at a time along its major axis.
/// `1 / z` is affine along a projected line, so it is interpolated linearly.
fn draw_projected(
    image: &mut HdrImage,
    depth: Option<&DepthBuffer>,
    (pa, za): (DVec2, f64),
    (pb, zb): (DVec2, f64),
    colour: Rgb,
) {
    let Some((t0, t1)) = clip_to_rect(pa, pb, f64::from(image.width), f64::from(image.height))
    else {
        return;
    };
    let at = |t: f64| (pa + (pb - pa) * t, za + (zb - za) * t);
    let ((a, a_depth), (b, b_depth)) = (at(t0), at(t1));
    let d = b - a;
    let steps = d.x.abs().max(d.y.abs()).ceil().max(1.0) as u32;
    for i in 0..=steps {
        let t = f64::from(i) / f64::from(steps);
        let p = a + d * t;
        let x = (p.x.floor().max(0.0) as u32).min(image.width - 1);
        let y = (p.y.floor().max(0.0) as u32).min(image.height - 1);
        let Some(idx) = image.index(x, y) else {
            continue;
        };
        if let Some(depth) = depth {
            let line = a_depth + (b_depth - a_depth) * t;
            if line * (1.0 + LINE_DEPTH_OFFSET) < depth.inverse_depth[idx] {
                continue;
            }
        }
        image.pixels[idx] = colour;
    }
}

/// The parameter interval of `a + t (b - a)`, `t` in `[0, 1]`, inside the
/// rectangle `[0, w] x [0, h]` (Liang-Barsky).
fn clip_to_rect(a: DVec2, b: DVec2, w: f64, h: f64) -> Option<(f64, f64)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    // Each boundary as (p, q): inside when p t <= q.
    for (p, q) in [(-d.x, a.x), (d.x, w - a.x), (-d.y, a.y), (d.y, h - a.y)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rect_clip_keeps_the_inside_part() {
        let (t0, t1) =
            clip_to_rect(DVec2::new(-10.0, 5.0), DVec2::new(30.0, 5.0), 20.0, 10.0).unwrap();
        assert!((t0 - 0.25).abs() < 1e-15 && (t1 - 0.75).abs() < 1e-15);
        assert!(clip_to_rect(DVec2::new(-1.0, -1.0), DVec2::new(-5.0, 3.0), 20.0, 10.0).is_none());
    }
}
