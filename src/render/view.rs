//! The pinhole projection of a camera onto a grid of samples.
//!
//! View space has its origin at the eye, `x` to the right, `y` up and `z` along
//! the viewing direction (depth, positive in front). Pixel space has its origin
//! at the top-left corner of the image, `x` to the right and `y` down, one unit
//! per pixel.

use crate::scene::Camera;
use crate::{Error, Result};
use glam::{DVec2, DVec3};

/// The largest sample grid side accepted. Keeps the fixed-point edge functions
/// of the rasterizer well inside `i64` (see `raster.rs`).
pub(crate) const MAX_GRID_SIDE: u32 = 1 << 15;

/// A camera's projection onto a `width` x `height` grid.
#[derive(Clone, Debug)]
pub(crate) struct View {
    eye: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    /// tan(yfov / 2) times the aspect ratio: view-space x / z at the right edge.
    pub half_width: f64,
    /// tan(yfov / 2): view-space y / z at the top edge.
    pub half_height: f64,
    /// Grid width.
    pub width: u32,
    /// Grid height.
    pub height: u32,
}

impl View {
    /// The projection of `camera` onto a `width` x `height` grid, with the grid's
    /// aspect ratio. Fails on a degenerate camera or grid.
    pub(super) fn new(camera: &Camera, width: u32, height: u32) -> Result<View> {
        if width == 0 || height == 0 || width > MAX_GRID_SIDE || height > MAX_GRID_SIDE {
            return Err(Error::Setting {
                name: "resolution",
                message: format!(
                    "{width}x{height} samples; each side must be between 1 and {MAX_GRID_SIDE}"
                ),
            });
        }
        let bad = |why: &str| Error::Setting {
            name: "camera",
            message: format!("camera '{}': {why}", camera.name),
        };
        if !(camera.position.is_finite() && camera.forward.is_finite() && camera.up.is_finite()) {
            return Err(bad("non-finite position or orientation"));
        }
        if !(camera.yfov > 0.0 && camera.yfov < std::f64::consts::PI) {
            return Err(bad(&format!(
                "vertical field of view {} rad is not strictly between 0 and pi",
                camera.yfov
            )));
        }
        // Re-orthonormalise: a camera read from a file may be slightly off.
        let forward = camera
            .forward
            .try_normalize()
            .ok_or_else(|| bad("zero viewing direction"))?;
        let right = forward
            .cross(camera.up)
            .try_normalize()
            .ok_or_else(|| bad("up vector is zero or parallel to the viewing direction"))?;
        let up = right.cross(forward);
        let half_height = (camera.yfov * 0.5).tan();
        Ok(View {
            eye: camera.position,
            right,
            up,
            forward,
            half_width: half_height * f64::from(width) / f64::from(height),
            half_height,
            width,
            height,
        })
    }

    /// A world point in view space.
    #[inline]
    pub(super) fn to_view(&self, p: DVec3) -> DVec3 {
        let d = p - self.eye;
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.forward))
    }

    /// A view-space point (with `z > 0`) in pixel space.
    #[inline]
    pub(super) fn to_pixel(&self, v: DVec3) -> DVec2 {
        let nx = v.x / (v.z * self.half_width);
        let ny = v.y / (v.z * self.half_height);
        DVec2::new(
            (nx + 1.0) * 0.5 * f64::from(self.width),
            (1.0 - ny) * 0.5 * f64::from(self.height),
        )
    }

    /// The coefficients `(a, b, c)` with `c_vec . D(px, py) = a px + b py + c`,
    /// where `D(px, py)` is the view-space direction through pixel point
    /// `(px, py)` scaled to unit depth. Any linear function of that direction
    /// becomes an affine function of pixel coordinates.
    #[inline]
    pub(super) fn affine_in_pixels(&self, c: DVec3) -> [f64; 3] {
        let sx = 2.0 * self.half_width / f64::from(self.width);
        let sy = 2.0 * self.half_height / f64::from(self.height);
        [
            c.x * sx,
            -c.y * sy,
            c.z - c.x * self.half_width + c.y * self.half_height,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera::look_at(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::Y,
            90.0,
        )
    }

    #[test]
    fn centre_and_corners_project_where_expected() {
        let view = View::new(&camera(), 200, 100).unwrap();
        // The point straight ahead lands at the image centre.
        let c = view.to_pixel(view.to_view(DVec3::new(1.0, 2.0, 0.0)));
        assert!((c - DVec2::new(100.0, 50.0)).length() < 1e-12);
        // 90 degrees vertical: at depth 3 the top edge is 3 up; aspect 2: the
        // right edge is 6 to the right.
        let tr = view.to_pixel(view.to_view(DVec3::new(7.0, 5.0, 0.0)));
        assert!((tr - DVec2::new(200.0, 0.0)).length() < 1e-12, "{tr}");
    }

    #[test]
    fn affine_form_matches_direct_dot_product() {
        let view = View::new(&camera(), 64, 48).unwrap();
        let c = DVec3::new(0.3, -1.7, 2.5);
        let [a, b, k] = view.affine_in_pixels(c);
        let (px, py) = (13.25, 40.5);
        let dir = DVec3::new(
            (2.0 * px / 64.0 - 1.0) * view.half_width,
            (1.0 - 2.0 * py / 48.0) * view.half_height,
            1.0,
        );
        assert!((a * px + b * py + k - c.dot(dir)).abs() < 1e-12);
    }

    #[test]
    fn rejects_degenerate_cameras_and_grids() {
        let mut c = camera();
        c.up = c.forward;
        assert!(View::new(&c, 8, 8).is_err());
        let mut c = camera();
        c.yfov = 0.0;
        assert!(View::new(&c, 8, 8).is_err());
        assert!(View::new(&camera(), 0, 8).is_err());
        assert!(View::new(&camera(), 8, MAX_GRID_SIDE + 1).is_err());
    }
}
