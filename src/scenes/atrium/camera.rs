//! The default view: standing in the court near its west end, at eye height,
//! looking east along it, so that both arcades, the galleries with their
//! banners, the furniture and the fountain are in sight but the sky is not
//! (a bright sky in the frame would set the automatic exposure).

use super::plan::Plan;
use crate::scene::Camera;
use glam::DVec3;

/// Eye height above the court floor (m).
pub(super) const EYE_HEIGHT: f64 = 1.7;
/// Vertical field of view of the default camera (degrees).
pub(super) const FIELD_OF_VIEW: f64 = 60.0;

/// The default camera of the atrium `plan`.
pub(super) fn default_camera(plan: &Plan) -> Camera {
    let middle = plan.width() / 2.0;
    // Between the benches along the south arcade and the tables down the
    // middle, close to the west wall, aimed at the far north-east corner.
    let eye = DVec3::new(0.6, EYE_HEIGHT, middle - 2.6);
    let target = DVec3::new(plan.length(), 4.0, middle + 2.5);
    let mut camera = Camera::look_at(eye, target, DVec3::Y, FIELD_OF_VIEW);
    camera.name = "court".to_string();
    camera
}
