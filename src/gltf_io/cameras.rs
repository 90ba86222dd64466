//! Cameras: a glTF perspective camera looks down its node's local -Z with local +Y
//! up; its position and orientation come from the node's world transform.

use super::describe;
use super::document::Document;
use super::precise::number;
use crate::scene::Camera;
use glam::{DMat3, DMat4, DQuat, DVec3};

/// The camera that glTF camera `index`, placed by a node with world transform
/// `world`, describes; `Err` with a warning for orthographic or unusable cameras.
pub(super) fn import_camera(
    doc: &Document,
    index: usize,
    node: usize,
    world: &DMat4,
) -> Result<Camera, String> {
    let Some(cam) = doc.root.cameras.get(index) else {
        return Err(format!("camera {index} does not exist; skipped"));
    };
    let node_name = doc.root.nodes.get(node).and_then(|n| n.name.clone());
    let what = describe("camera", index, cam.name.as_deref());
    if cam.perspective.is_none() {
        return Err(format!(
            "{what} (on {}) is orthographic; only perspective cameras are imported",
            describe("node", node, node_name.as_deref())
        ));
    }
    let base = format!("/cameras/{index}/perspective");
    let yfov = number(&doc.raw, &format!("{base}/yfov")).unwrap_or(f64::NAN);
    if !(yfov > 0.0 && yfov < std::f64::consts::PI) {
        return Err(format!(
            "{what}: yfov {yfov} is not between 0 and pi; skipped"
        ));
    }
    let aspect = number(&doc.raw, &format!("{base}/aspectRatio"));
    if aspect.is_some_and(|a| !(a.is_finite() && a > 0.0)) {
        return Err(format!(
            "{what}: aspectRatio {aspect:?} is not positive; skipped"
        ));
    }
    let position = world.transform_point3(DVec3::ZERO);
    let forward = world.transform_vector3(DVec3::NEG_Z).normalize_or_zero();
    let up_hint = world.transform_vector3(DVec3::Y);
    // A non-uniform scale can shear the axes: keep `up` orthogonal to `forward`.
    let up = (up_hint - forward * up_hint.dot(forward)).normalize_or_zero();
    if forward == DVec3::ZERO || up == DVec3::ZERO || !position.is_finite() {
        return Err(format!(
            "{what}: its node's transform is degenerate; skipped"
        ));
    }
    let name = match (cam.name.as_deref(), node_name.as_deref()) {
        (Some(n), _) | (None, Some(n)) if !n.is_empty() => n.to_string(),
        _ => format!("camera {index}"),
    };
    Ok(Camera {
        name,
        position,
        forward,
        up,
        yfov,
        aspect,
    })
}

/// The rotation that turns glTF's camera frame (looking down -Z, +Y up) into the
/// camera's: its columns are right, up and back (= -forward).
pub(super) fn camera_rotation(camera: &Camera) -> DQuat {
    let forward = camera.forward.normalize();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    DQuat::from_mat3(&DMat3::from_cols(right, up, -forward)).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_maps_the_gltf_frame_onto_the_camera() {
        let cam = Camera::look_at(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(4.0, -1.0, 0.5),
            DVec3::Y,
            40.0,
        );
        let q = camera_rotation(&cam);
        assert!((q * DVec3::NEG_Z - cam.forward).length() < 1e-14);
        assert!((q * DVec3::Y - cam.up).length() < 1e-14);
    }
}
