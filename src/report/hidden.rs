//! Points that no light reaches and no outside camera sees: those whose every
//! line of sight ends on the back of a surface (the floor under a box).

use crate::scene::Scene;
use glam::DVec3;

/// Elevations (degrees above the surface) of the probe rays besides the normal.
const ELEVATIONS: [f64; 2] = [20.0, 55.0];
/// Azimuths per elevation.
const AZIMUTHS: usize = 8;

/// Whether every ray of a fixed fan (the normal and 16 directions at 20 and 55
/// degrees above the surface) from `position` on surface `surface` meets the
/// back of some surface first. Such a point lies inside a closed object: it is
/// lit by nothing and seen from nowhere outside, so a mesh element that
/// straddles the object's outline gives it a value no one can see. A ray that
/// meets a front face or leaves the scene makes the point visible.
///
/// Rays start a millionth of the scene's diameter above the surface, so that
/// a face lying in the surface's own plane (a box standing on a floor) does not
/// stop them.
#[must_use]
pub fn sees_only_back_faces(scene: &Scene, surface: u32, position: DVec3, normal: DVec3) -> bool {
    let lift = 1e-6 * scene.diameter();
    let origin = position + normal * lift;
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let mut directions = vec![normal];
    for elevation in ELEVATIONS {
        let (sin_e, cos_e) = elevation.to_radians().sin_cos();
        for k in 0..AZIMUTHS {
            let azimuth = std::f64::consts::TAU * k as f64 / AZIMUTHS as f64;
            let (sin_a, cos_a) = azimuth.sin_cos();
            directions.push((u * cos_a + v * sin_a) * cos_e + normal * sin_e);
        }
    }
    directions
        .iter()
        .all(|d| first_hit_is_back(scene, surface, origin, *d))
}

/// Whether the nearest surface the ray meets (other than `own`) is met from
/// behind. A ray that meets nothing is not.
fn first_hit_is_back(scene: &Scene, own: u32, origin: DVec3, direction: DVec3) -> bool {
    let mut nearest = (f64::INFINITY, false);
    for (i, s) in scene.surfaces.iter().enumerate() {
        if i == own as usize {
            continue;
        }
        let facing = s.normal.dot(direction);
        if facing == 0.0 {
            continue;
        }
        let t = s.normal.dot(s.vertices[0] - origin) / facing;
        if !(t > 0.0 && t < nearest.0) {
            continue;
        }
        let hit = origin + direction * t;
        if inside_convex(&s.vertices, s.normal, hit) {
            nearest = (t, facing > 0.0);
        }
    }
    nearest.1
}

/// Whether `p`, in the plane of the convex polygon `vertices` with normal `n`,
/// lies inside it or on its boundary.
fn inside_convex(vertices: &[DVec3], n: DVec3, p: DVec3) -> bool {
    (0..vertices.len()).all(|i| {
        let a = vertices[i];
        let b = vertices[(i + 1) % vertices.len()];
        n.dot((b - a).cross(p - a)) >= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::cornell_box;

    #[test]
    fn the_floor_under_a_cornell_block_is_hidden_and_beside_it_is_not() {
        let scene = cornell_box();
        let floor = scene
            .surfaces
            .iter()
            .position(|s| scene.objects[s.object as usize].name == "floor")
            .unwrap() as u32;
        let block = scene
            .surfaces
            .iter()
            .find(|s| scene.objects[s.object as usize].name == "short_block" && s.normal.y > 0.9)
            .expect("the short block's top");
        let centre = block.centroid();
        let under = DVec3::new(centre.x, 0.0, centre.z);
        assert!(sees_only_back_faces(&scene, floor, under, DVec3::Y));
        // The floor's centroid of the room is in the open.
        let room = scene.surfaces[floor as usize].centroid();
        let (lo, hi) = scene.bounds();
        let corner = DVec3::new(
            lo.x + 0.01 * (hi.x - lo.x),
            room.y,
            lo.z + 0.01 * (hi.z - lo.z),
        );
        assert!(!sees_only_back_faces(&scene, floor, corner, DVec3::Y));
    }
}
