//! The default view of a scene without a camera (issue 51): inside the main
//! lit room of an interior, looking across it, whatever way the walls face;
//! never inside a closed object. Checked with the test's own ray casting:
//! where each pixel's ray first meets the scene, and whether the lamp lights
//! that point directly.

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::scene::{Camera, Scene, SceneBuilder};

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// The lamp of room A: a 1 m square 1 cm under the ceiling, facing down.
const LAMP: [f64; 3] = [3.0, 2.99, 2.5];

/// Two rooms 3 m high joined by a door 1 m wide and 2.2 m high: room A
/// (x 0..6, z 0..5) lit by a lamp under its ceiling, room B (x 6..10) dark.
/// Every wall is double-sided (two faces back to back, as exporters write
/// walls); a wardrobe in room A is a closed single-sided box.
fn two_rooms() -> Scene {
    let mut b = SceneBuilder::new("two rooms");
    let wall = b.material("wall", Rgb::splat(0.6), Rgb::ZERO).unwrap();
    let wood = b.material("wood", Rgb::splat(0.4), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
    let h = 3.0;
    b.object("walls");
    // Floors and ceilings of both rooms, walls around both, as one shell.
    b.quad(
        wall,
        v(0., 0., 0.),
        v(0., 0., 5.),
        v(10., 0., 5.),
        v(10., 0., 0.),
    )
    .unwrap();
    b.quad(
        wall,
        v(0., h, 0.),
        v(10., h, 0.),
        v(10., h, 5.),
        v(0., h, 5.),
    )
    .unwrap();
    b.quad(
        wall,
        v(0., 0., 0.),
        v(10., 0., 0.),
        v(10., h, 0.),
        v(0., h, 0.),
    )
    .unwrap();
    b.quad(
        wall,
        v(0., 0., 5.),
        v(0., h, 5.),
        v(10., h, 5.),
        v(10., 0., 5.),
    )
    .unwrap();
    b.quad(
        wall,
        v(0., 0., 0.),
        v(0., h, 0.),
        v(0., h, 5.),
        v(0., 0., 5.),
    )
    .unwrap();
    b.quad(
        wall,
        v(10., 0., 0.),
        v(10., 0., 5.),
        v(10., h, 5.),
        v(10., h, 0.),
    )
    .unwrap();
    // The wall between them at x = 6, the door at z 2..3, y 0..2.2.
    b.quad(
        wall,
        v(6., 0., 0.),
        v(6., 0., 2.),
        v(6., h, 2.),
        v(6., h, 0.),
    )
    .unwrap();
    b.quad(
        wall,
        v(6., 0., 3.),
        v(6., 0., 5.),
        v(6., h, 5.),
        v(6., h, 3.),
    )
    .unwrap();
    b.quad(
        wall,
        v(6., 2.2, 2.),
        v(6., 2.2, 3.),
        v(6., h, 3.),
        v(6., h, 2.),
    )
    .unwrap();
    b.axis_box("wardrobe", wood, v(0.2, 0.0, 0.2), v(1.4, 2.0, 1.0))
        .unwrap();
    b.object("lamp");
    let [x, y, z] = LAMP;
    b.quad(
        lamp,
        v(x - 0.5, y, z - 0.5),
        v(x + 0.5, y, z - 0.5),
        v(x + 0.5, y, z + 0.5),
        v(x - 0.5, y, z + 0.5),
    )
    .unwrap();
    let mut scene = b.build().unwrap();
    // The walls double-sided, as two faces back to back.
    let walls: Vec<_> = scene
        .surfaces
        .iter()
        .filter(|s| s.material == wall)
        .map(|s| s.flipped())
        .collect();
    scene.surfaces.extend(walls);
    scene.materials[wall as usize].double_sided = true;
    scene
}

/// The distance along unit `dir` from `origin` to convex polygon `poly`, if
/// the ray meets it (either side).
fn meet(origin: DVec3, dir: DVec3, poly: &[DVec3]) -> Option<f64> {
    let n = (poly[1] - poly[0]).cross(poly[2] - poly[0]).normalize();
    let denom = n.dot(dir);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = n.dot(poly[0] - origin) / denom;
    if t <= 1e-9 {
        return None;
    }
    let p = origin + dir * t;
    let k = poly.len();
    let inside = (0..k).all(|i| (poly[(i + 1) % k] - poly[i]).cross(p - poly[i]).dot(n) >= -1e-9);
    inside.then_some(t)
}

/// Share of a 32 x 24 grid of the view's pixels whose first surface is lit
/// directly by the lamp (nothing between it and the lamp's centre).
fn lit_share(scene: &Scene, camera: &Camera) -> f64 {
    let (w, h) = (32, 24);
    let tan = (camera.yfov * 0.5).tan();
    let right = camera.right();
    let lamp = DVec3::from_array(LAMP);
    let mut lit = 0;
    for j in 0..h {
        for i in 0..w {
            let sx = ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * tan * 4.0 / 3.0;
            let sy = (1.0 - (j as f64 + 0.5) / h as f64 * 2.0) * tan;
            let dir = (camera.forward + right * sx + camera.up * sy).normalize();
            let hit = scene
                .surfaces
                .iter()
                .filter_map(|s| meet(camera.position, dir, &s.vertices).map(|t| (t, s)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let Some((t, surface)) = hit else { continue };
            if scene.material_of(surface).is_emitter() {
                lit += 1;
                continue;
            }
            // Just in front of the hit, on the eye's side.
            let p = camera.position + dir * (t - 1e-6);
            let to_lamp = lamp - p;
            let d = to_lamp.length();
            let towards = to_lamp / d;
            let blocked = scene.surfaces.iter().any(|s| {
                !scene.material_of(s).is_emitter()
                    && meet(p, towards, &s.vertices).is_some_and(|u| u < d - 1e-6)
            });
            // The lamp and the eye on the same side of the surface.
            let n = surface.normal;
            let same_side = n.dot(camera.position - p).signum() == n.dot(lamp - p).signum();
            lit += usize::from(!blocked && same_side);
        }
    }
    lit as f64 / (w * h) as f64
}

#[test]
fn two_rooms_with_double_sided_walls_are_seen_from_inside_the_lit_one() {
    let scene = two_rooms();
    let camera = Camera::framing(&scene);
    let p = camera.position;
    assert!(
        p.x > 0.0 && p.x < 6.0 && p.y > 0.0 && p.y < 3.0 && p.z > 0.0 && p.z < 5.0,
        "the eye {p} is not in the lit room"
    );
    // Not inside the wardrobe.
    assert!(
        !(p.x < 1.4 && p.z < 1.0 && p.y < 2.0),
        "the eye {p} is in the wardrobe"
    );
    // Looking across the room, level.
    assert!(camera.forward.y.abs() < 1e-9, "{:?}", camera.forward);
    let share = lit_share(&scene, &camera);
    assert!(share > 0.6, "only {share} of the frame is lit");
}

#[test]
fn the_outside_view_of_a_closed_room_shows_little_light() {
    // The checker itself: the three-quarter view of the same shell from
    // outside sees walls the lamp does not reach.
    let scene = two_rooms();
    let camera = Camera::framing_box(v(0., 0., 0.), v(10., 3., 5.));
    let share = lit_share(&scene, &camera);
    assert!(share < 0.1, "{share}");
}
