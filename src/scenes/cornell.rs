//! The Cornell box, from the Cornell Program of Computer Graphics' published
//! measurements ("Cornell Box Data").

use crate::math::Rgb;
use crate::scene::{Camera, Scene, SceneBuilder};
use glam::DVec3;

/// A quad as published: four vertices in millimetres.
type QuadMm = [[f64; 3]; 4];

const FLOOR: QuadMm = [
    [552.8, 0.0, 0.0],
    [0.0, 0.0, 0.0],
    [0.0, 0.0, 559.2],
    [549.6, 0.0, 559.2],
];
/// The published light lies in the ceiling's plane (y = 548.8); it is lowered by
/// 0.1 mm here (see [`cornell_box`]).
const LIGHT: QuadMm = [
    [343.0, 548.7, 227.0],
    [343.0, 548.7, 332.0],
    [213.0, 548.7, 332.0],
    [213.0, 548.7, 227.0],
];
const CEILING: QuadMm = [
    [556.0, 548.8, 0.0],
    [556.0, 548.8, 559.2],
    [0.0, 548.8, 559.2],
    [0.0, 548.8, 0.0],
];
const BACK_WALL: QuadMm = [
    [549.6, 0.0, 559.2],
    [0.0, 0.0, 559.2],
    [0.0, 548.8, 559.2],
    [556.0, 548.8, 559.2],
];
/// Green, at x = 0 (on the right as the camera sees it).
const RIGHT_WALL: QuadMm = [
    [0.0, 0.0, 559.2],
    [0.0, 0.0, 0.0],
    [0.0, 548.8, 0.0],
    [0.0, 548.8, 559.2],
];
/// Red, at x of about 550; not planar (by about 0.8 mm), so the builder splits it
/// into two triangles.
const LEFT_WALL: QuadMm = [
    [552.8, 0.0, 0.0],
    [549.6, 0.0, 559.2],
    [556.0, 548.8, 559.2],
    [556.0, 548.8, 0.0],
];
/// Top, then the four sides.
const SHORT_BLOCK: [QuadMm; 5] = [
    [
        [130.0, 165.0, 65.0],
        [82.0, 165.0, 225.0],
        [240.0, 165.0, 272.0],
        [290.0, 165.0, 114.0],
    ],
    [
        [290.0, 0.0, 114.0],
        [290.0, 165.0, 114.0],
        [240.0, 165.0, 272.0],
        [240.0, 0.0, 272.0],
    ],
    [
        [130.0, 0.0, 65.0],
        [130.0, 165.0, 65.0],
        [290.0, 165.0, 114.0],
        [290.0, 0.0, 114.0],
    ],
    [
        [82.0, 0.0, 225.0],
        [82.0, 165.0, 225.0],
        [130.0, 165.0, 65.0],
        [130.0, 0.0, 65.0],
    ],
    [
        [240.0, 0.0, 272.0],
        [240.0, 165.0, 272.0],
        [82.0, 165.0, 225.0],
        [82.0, 0.0, 225.0],
    ],
];
/// Top, then the four sides.
const TALL_BLOCK: [QuadMm; 5] = [
    [
        [423.0, 330.0, 247.0],
        [265.0, 330.0, 296.0],
        [314.0, 330.0, 456.0],
        [472.0, 330.0, 406.0],
    ],
    [
        [423.0, 0.0, 247.0],
        [423.0, 330.0, 247.0],
        [472.0, 330.0, 406.0],
        [472.0, 0.0, 406.0],
    ],
    [
        [472.0, 0.0, 406.0],
        [472.0, 330.0, 406.0],
        [314.0, 330.0, 456.0],
        [314.0, 0.0, 456.0],
    ],
    [
        [314.0, 0.0, 456.0],
        [314.0, 330.0, 456.0],
        [265.0, 330.0, 296.0],
        [265.0, 0.0, 296.0],
    ],
    [
        [265.0, 0.0, 296.0],
        [265.0, 330.0, 296.0],
        [423.0, 330.0, 247.0],
        [423.0, 0.0, 247.0],
    ],
];

/// Published vertices are in millimetres; scenes are in metres.
fn metres(q: &QuadMm) -> [DVec3; 4] {
    q.map(|[x, y, z]| DVec3::new(x, y, z) / 1000.0)
}

/// The Cornell box as published by the Cornell Program of Computer Graphics, in
/// metres, with the widely used RGB reflectances: white (0.725, 0.71, 0.68),
/// red (0.63, 0.065, 0.05), green (0.14, 0.45, 0.091); the light emits radiance
/// (17, 12, 4) and reflects 0.78.
///
/// - Objects: `floor`, `ceiling`, `back_wall`, `left_wall` (red, x = 0.55 m),
///   `right_wall` (green, x = 0), `light`, `short_block`, `tall_block` (top and four
///   sides each, no bottom). Vertex order is as published; every front face points
///   into the room or out of a block. The front (z = 0) is open.
/// - The red wall is measured non-planar (by about 0.8 mm), so it is two triangles.
/// - The published light lies in the ceiling's plane; here it is lowered 0.1 mm to
///   y = 0.5487 m, single-sided facing down (-Y), so that it neither coincides with
///   the ceiling nor lights it.
/// - The camera is the published one: at (0.278, 0.273, -0.800) looking along +Z
///   with +Y up, a 35 mm lens on 25 mm x 25 mm film, so
///   `yfov = 2 atan(12.5 / 35)` (about 39.3 degrees) and the aspect ratio is 1.
#[must_use]
pub fn cornell_box() -> Scene {
    build().expect("the built-in Cornell box data is valid")
}

fn build() -> crate::Result<Scene> {
    let mut b = SceneBuilder::new("cornell_box");
    let white = b.material("white", Rgb::new(0.725, 0.71, 0.68), Rgb::ZERO)?;
    let red = b.material("red", Rgb::new(0.63, 0.065, 0.05), Rgb::ZERO)?;
    let green = b.material("green", Rgb::new(0.14, 0.45, 0.091), Rgb::ZERO)?;
    let light = b.material("light", Rgb::splat(0.78), Rgb::new(17.0, 12.0, 4.0))?;
    let walls: [(&str, u32, &QuadMm); 6] = [
        ("floor", white, &FLOOR),
        ("ceiling", white, &CEILING),
        ("back_wall", white, &BACK_WALL),
        ("left_wall", red, &LEFT_WALL),
        ("right_wall", green, &RIGHT_WALL),
        ("light", light, &LIGHT),
    ];
    for (name, material, quad) in walls {
        b.object(name);
        b.polygon(material, &metres(quad))?;
    }
    for (name, faces) in [("short_block", &SHORT_BLOCK), ("tall_block", &TALL_BLOCK)] {
        b.object(name);
        for face in faces {
            b.polygon(white, &metres(face))?;
        }
    }
    b.camera(Camera {
        name: "camera".to_string(),
        position: DVec3::new(0.278, 0.273, -0.800),
        forward: DVec3::Z,
        up: DVec3::Y,
        yfov: 2.0 * (12.5f64 / 35.0).atan(),
        aspect: Some(1.0),
    });
    b.build()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn room_faces_point_inwards_and_block_faces_outwards() {
        let scene = cornell_box();
        let room_centre = DVec3::new(0.278, 0.274, 0.280);
        for s in &scene.surfaces {
            let object = scene.objects[s.object as usize].name.as_str();
            let c = s.centroid();
            let outward_ok = match object {
                "short_block" | "tall_block" => {
                    let block: Vec<DVec3> = scene
                        .surfaces
                        .iter()
                        .filter(|t| t.object == s.object)
                        .map(|t| t.centroid())
                        .collect();
                    let mid = block.iter().copied().sum::<DVec3>() / block.len() as f64;
                    s.normal.dot(c - mid) > 0.0
                }
                _ => s.normal.dot(room_centre - c) > 0.0,
            };
            assert!(
                outward_ok,
                "{object} faces the wrong way: normal {}",
                s.normal
            );
        }
    }

    #[test]
    fn light_faces_down_just_below_the_ceiling() {
        let scene = cornell_box();
        let light = scene
            .objects
            .iter()
            .position(|o| o.name == "light")
            .unwrap() as u32;
        let s: Vec<_> = scene
            .surfaces
            .iter()
            .filter(|s| s.object == light)
            .collect();
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].normal, DVec3::NEG_Y);
        assert!(s[0].vertices.iter().all(|v| (v.y - 0.5487).abs() < 1e-15));
        assert!(scene.material_of(s[0]).is_emitter());
        // Exitance is pi times the radiance.
        assert_eq!(
            scene.material_of(s[0]).emission.0[0],
            17.0 * std::f64::consts::PI
        );
    }

    #[test]
    fn the_red_wall_is_two_triangles_and_everything_else_quads() {
        let scene = cornell_box();
        for (o, object) in scene.objects.iter().enumerate() {
            let shapes: Vec<usize> = scene
                .surfaces
                .iter()
                .filter(|s| s.object as usize == o)
                .map(|s| s.vertices.len())
                .collect();
            let expected = match object.name.as_str() {
                "left_wall" => vec![3, 3],
                "short_block" | "tall_block" => vec![4; 5],
                _ => vec![4],
            };
            assert_eq!(shapes, expected, "{}", object.name);
        }
        let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "floor",
                "ceiling",
                "back_wall",
                "left_wall",
                "right_wall",
                "light",
                "short_block",
                "tall_block"
            ]
        );
    }
}
