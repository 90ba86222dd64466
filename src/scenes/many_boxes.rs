//! A scale scene: a room whose floor is covered by a grid of boxes, lit by a
//! grid of area lights below the ceiling. At the default patch size the
//! built-in version ([`many_boxes`], 20 x 20 boxes) has over 2 000 patches; at
//! uniform depth 3 it has over 100 000 elements.

use super::hash::{splitmix64 as hash, unit as hash_unit};
use crate::error::{Error, Result};
use crate::math::Rgb;
use crate::scene::{Camera, Scene, SceneBuilder};
use glam::DVec3;

/// Boxes along each side of the built-in [`many_boxes`] scene.
pub const BOXES_PER_SIDE: u32 = 20;

/// Most boxes along a side that [`many_boxes_with`] accepts (40 000 boxes,
/// 200 000 surfaces).
pub const MAX_BOXES_PER_SIDE: u32 = 200;

/// Distance between neighbouring box centres (m).
pub const PITCH: f64 = 1.0;
/// Floor strip between the outer boxes and the walls (m).
pub const MARGIN: f64 = 1.0;
/// Room height (m).
pub const HEIGHT: f64 = 4.0;
/// Lights hang this far below the ceiling (m), so they do not lie in its plane.
pub(crate) const LIGHT_DROP: f64 = 0.01;
/// Edge of each square light (m).
pub const LIGHT_SIZE: f64 = 1.0;

/// The built-in scale scene: [`many_boxes_with`]`(`[`BOXES_PER_SIDE`]`)`.
#[must_use]
pub fn many_boxes() -> Scene {
    many_boxes_with(BOXES_PER_SIDE).expect("the built-in box count is in range")
}

/// The number of lights along each side for `boxes_per_side` boxes: one per
/// five boxes, at least one.
#[must_use]
pub fn lights_per_side(boxes_per_side: u32) -> u32 {
    (boxes_per_side / 5).max(1)
}

/// A closed room `n * PITCH + 2 * MARGIN` metres square and [`HEIGHT`] tall
/// (walls facing in), with `n x n` boxes standing on the floor on a grid of
/// pitch [`PITCH`], and [`lights_per_side`]`(n)` squared square lights of
/// edge [`LIGHT_SIZE`] just below the ceiling, facing down.
///
/// - Objects: `room` (floor, ceiling, four walls: 6 surfaces), `lights` (one
///   surface per light), then one object `box_i_j` per box (top and four
///   sides, no bottom, since it stands on the floor: 5 surfaces).
/// - Box footprints (0.4 to 0.7 m square) and heights (0.3 to 1.5 m) and
///   one of three materials come from a fixed hash of the box's grid
///   position, so the scene is the same on every run and platform. Boxes
///   never touch each other and never reach the lights.
/// - The room's corner is the origin; the floor is at y = 0, +Y is up.
///
/// Fails with [`Error::Setting`] when `n` is 0 or above [`MAX_BOXES_PER_SIDE`].
pub fn many_boxes_with(n: u32) -> Result<Scene> {
    if n == 0 || n > MAX_BOXES_PER_SIDE {
        return Err(Error::Setting {
            name: "boxes_per_side",
            message: format!("must be 1 to {MAX_BOXES_PER_SIDE}, got {n}"),
        });
    }
    let mut b = SceneBuilder::new("many_boxes");
    let wall = b.material("wall", Rgb::splat(0.7), Rgb::ZERO)?;
    let lamp = b.material("lamp", Rgb::splat(0.8), Rgb::splat(4.0))?;
    let box_materials = [
        b.material("box_grey", Rgb::splat(0.5), Rgb::ZERO)?,
        b.material("box_warm", Rgb::new(0.7, 0.45, 0.3), Rgb::ZERO)?,
        b.material("box_cool", Rgb::new(0.3, 0.45, 0.65), Rgb::ZERO)?,
    ];
    let side = f64::from(n) * PITCH + 2.0 * MARGIN;
    add_room(&mut b, wall, side)?;

    b.object("lights");
    let k = lights_per_side(n);
    let y = HEIGHT - LIGHT_DROP;
    for i in 0..k {
        for j in 0..k {
            // Light centres evenly spread: the middle of k equal strips.
            let cx = side * (f64::from(i) + 0.5) / f64::from(k);
            let cz = side * (f64::from(j) + 0.5) / f64::from(k);
            let (x0, x1) = (cx - LIGHT_SIZE / 2.0, cx + LIGHT_SIZE / 2.0);
            let (z0, z1) = (cz - LIGHT_SIZE / 2.0, cz + LIGHT_SIZE / 2.0);
            // Counter-clockwise seen from below: facing down.
            b.quad(
                lamp,
                DVec3::new(x0, y, z0),
                DVec3::new(x1, y, z0),
                DVec3::new(x1, y, z1),
                DVec3::new(x0, y, z1),
            )?;
        }
    }

    for i in 0..n {
        for j in 0..n {
            let h = hash((u64::from(i) << 32) | u64::from(j));
            let unit = |bits: u32| hash_unit(h, bits);
            let foot = 0.4 + 0.3 * unit(0);
            let height = 0.3 + 1.2 * unit(16);
            let material = box_materials[((h >> 32) % 3) as usize];
            let cx = MARGIN + (f64::from(i) + 0.5) * PITCH;
            let cz = MARGIN + (f64::from(j) + 0.5) * PITCH;
            let lo = DVec3::new(cx - foot / 2.0, 0.0, cz - foot / 2.0);
            let hi = DVec3::new(cx + foot / 2.0, height, cz + foot / 2.0);
            b.object(&format!("box_{i}_{j}"));
            add_open_box(&mut b, material, lo, hi)?;
        }
    }

    let mut camera = Camera::look_at(
        DVec3::new(0.3, HEIGHT - 0.5, 0.3),
        DVec3::new(side * 0.6, 0.0, side * 0.6),
        DVec3::Y,
        60.0,
    );
    camera.name = "corner".to_string();
    b.camera(camera);
    b.build()
}

/// Floor (facing up), ceiling (facing down) and four walls facing in, as
/// the current object `room`.
fn add_room(b: &mut SceneBuilder, material: u32, side: f64) -> Result<()> {
    b.object("room");
    let p = DVec3::new;
    let (x, y, z) = (side, HEIGHT, side);
    let faces = [
        [p(0., 0., 0.), p(0., 0., z), p(x, 0., z), p(x, 0., 0.)],
        [p(0., y, 0.), p(x, y, 0.), p(x, y, z), p(0., y, z)],
        [p(0., 0., 0.), p(x, 0., 0.), p(x, y, 0.), p(0., y, 0.)],
        [p(0., 0., z), p(0., y, z), p(x, y, z), p(x, 0., z)],
        [p(0., 0., 0.), p(0., y, 0.), p(0., y, z), p(0., 0., z)],
        [p(x, 0., 0.), p(x, 0., z), p(x, y, z), p(x, y, 0.)],
    ];
    for [a, b2, c, d] in faces {
        b.quad(material, a, b2, c, d)?;
    }
    Ok(())
}

/// The top and four sides of an axis-aligned box, facing out; no bottom.
fn add_open_box(b: &mut SceneBuilder, material: u32, lo: DVec3, hi: DVec3) -> Result<()> {
    let p = DVec3::new;
    let (a, c) = (lo, hi);
    let faces = [
        // -x, +x, +y (top), -z, +z; each counter-clockwise seen from outside.
        [
            p(a.x, a.y, a.z),
            p(a.x, a.y, c.z),
            p(a.x, c.y, c.z),
            p(a.x, c.y, a.z),
        ],
        [
            p(c.x, a.y, a.z),
            p(c.x, c.y, a.z),
            p(c.x, c.y, c.z),
            p(c.x, a.y, c.z),
        ],
        [
            p(a.x, c.y, a.z),
            p(a.x, c.y, c.z),
            p(c.x, c.y, c.z),
            p(c.x, c.y, a.z),
        ],
        [
            p(a.x, a.y, a.z),
            p(a.x, c.y, a.z),
            p(c.x, c.y, a.z),
            p(c.x, a.y, a.z),
        ],
        [
            p(a.x, a.y, c.z),
            p(c.x, a.y, c.z),
            p(c.x, c.y, c.z),
            p(a.x, c.y, c.z),
        ],
    ];
    for [v0, v1, v2, v3] in faces {
        b.quad(material, v0, v1, v2, v3)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surface_counts_follow_the_grid() {
        for n in [1, 4, 7] {
            let scene = many_boxes_with(n).unwrap();
            let lights = lights_per_side(n).pow(2);
            assert_eq!(
                scene.surfaces.len() as u32,
                6 + lights + 5 * n * n,
                "n = {n}"
            );
            assert_eq!(scene.objects.len() as u32, 2 + n * n, "n = {n}");
        }
    }

    #[test]
    fn box_counts_outside_the_range_are_refused() {
        assert!(matches!(many_boxes_with(0), Err(Error::Setting { .. })));
        assert!(matches!(
            many_boxes_with(MAX_BOXES_PER_SIDE + 1),
            Err(Error::Setting { .. })
        ));
    }

    #[test]
    fn boxes_face_out_and_the_room_faces_in() {
        let scene = many_boxes_with(3).unwrap();
        let side = 3.0 * PITCH + 2.0 * MARGIN;
        let centre = DVec3::new(side / 2.0, HEIGHT / 2.0, side / 2.0);
        for s in &scene.surfaces {
            let object = &scene.objects[s.object as usize].name;
            let c = s.centroid();
            if object.starts_with("box_") {
                // Out of the box: away from the vertical axis through its
                // centre, or up for the top.
                let mine: Vec<DVec3> = scene
                    .surfaces
                    .iter()
                    .filter(|t| t.object == s.object)
                    .flat_map(|t| t.vertices.iter().copied())
                    .collect();
                let mid = mine.iter().copied().sum::<DVec3>() / mine.len() as f64;
                assert!(s.normal.dot(c - mid) > 0.0, "{object}");
            } else if object == "lights" {
                assert!(s.normal.y < -0.999);
            } else {
                assert!(s.normal.dot(centre - c) > 0.0, "{object}");
            }
        }
    }
}
