//! Pinhole cameras.

use glam::DVec3;

/// A perspective pinhole camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Name, for messages.
    pub name: String,
    /// Eye position.
    pub position: DVec3,
    /// Unit viewing direction.
    pub forward: DVec3,
    /// Unit up vector, orthogonal to `forward`.
    pub up: DVec3,
    /// Vertical field of view in radians.
    pub yfov: f64,
    /// Width over height, if the camera fixes it.
    pub aspect: Option<f64>,
}

impl Camera {
    /// A camera at `position` looking at `target`, with `up` as a hint for the
    /// vertical (re-orthogonalised), and a vertical field of view in degrees.
    #[must_use]
    pub fn look_at(position: DVec3, target: DVec3, up: DVec3, yfov_degrees: f64) -> Self {
        let forward = (target - position).normalize_or(DVec3::NEG_Z);
        let mut right = forward.cross(up);
        if right.length_squared() < 1e-20 {
            right = forward.any_orthonormal_vector();
        }
        let right = right.normalize();
        let up = right.cross(forward).normalize();
        Camera {
            name: "camera".to_string(),
            position,
            forward,
            up,
            yfov: yfov_degrees.to_radians(),
            aspect: None,
        }
    }

    /// A default view that frames the bounds `lo..hi`: from the +Z side (glTF's
    /// front), a little above and to the right, far enough back that the bounding
    /// sphere fits a 45 degree field of view.
    #[must_use]
    pub fn framing(lo: DVec3, hi: DVec3) -> Self {
        let centre = (lo + hi) * 0.5;
        let radius = ((hi - lo) * 0.5).length().max(1e-9);
        let yfov = 45f64.to_radians();
        let dist = radius / (yfov * 0.5).sin();
        let dir = DVec3::new(0.35, 0.25, 1.0).normalize();
        let mut c = Camera::look_at(centre + dir * dist, centre, DVec3::Y, 45.0);
        c.name = "framing".to_string();
        c
    }

    /// The unit right vector.
    #[must_use]
    pub fn right(&self) -> DVec3 {
        self.forward.cross(self.up).normalize()
    }
}
