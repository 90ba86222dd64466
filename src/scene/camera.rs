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

    /// The unit right vector.
    #[must_use]
    pub fn right(&self) -> DVec3 {
        self.forward.cross(self.up).normalize()
    }
}
