//! Scenes shared by the tests.

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::scene::{Scene, SceneBuilder};

/// Reflectance and emitted exitance of one face of a box.
#[derive(Clone, Copy)]
pub struct FaceMaterial {
    pub reflectance: Rgb,
    pub exitance: Rgb,
}

impl FaceMaterial {
    pub fn grey(rho: f64, exitance: f64) -> Self {
        FaceMaterial {
            reflectance: Rgb::splat(rho),
            exitance: Rgb::splat(exitance),
        }
    }
}

/// A closed box `[0,sx] x [0,sy] x [0,sz]` whose six faces point inwards, each
/// its own object: floor, ceiling, z0, z1, x0, x1 (in that order).
pub fn closed_box(size: DVec3, faces: [FaceMaterial; 6]) -> Scene {
    let mut b = SceneBuilder::new("box");
    let p = |x: f64, y: f64, z: f64| DVec3::new(x * size.x, y * size.y, z * size.z);
    let quads = [
        (
            "floor",
            [p(0., 0., 0.), p(0., 0., 1.), p(1., 0., 1.), p(1., 0., 0.)],
        ),
        (
            "ceiling",
            [p(0., 1., 0.), p(1., 1., 0.), p(1., 1., 1.), p(0., 1., 1.)],
        ),
        (
            "z0",
            [p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)],
        ),
        (
            "z1",
            [p(0., 0., 1.), p(0., 1., 1.), p(1., 1., 1.), p(1., 0., 1.)],
        ),
        (
            "x0",
            [p(0., 0., 0.), p(0., 1., 0.), p(0., 1., 1.), p(0., 0., 1.)],
        ),
        (
            "x1",
            [p(1., 0., 0.), p(1., 0., 1.), p(1., 1., 1.), p(1., 1., 0.)],
        ),
    ];
    for (i, (name, q)) in quads.iter().enumerate() {
        let f = faces[i];
        let m = b
            .material(name, f.reflectance, f.exitance / std::f64::consts::PI)
            .unwrap();
        b.object(name);
        b.polygon(m, q).unwrap();
    }
    b.build().unwrap()
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Starts a closed 2 m room (x, y and z from 0 to 2, y up) of white walls
/// (reflectance 0.7) whose left wall (x = 0) reflects `left`, lit by a
/// 0.4 m lamp (exitance 10) 1 mm under the ceiling's centre: the objects
/// floor, ceiling, wall_left, wall_right, wall_back, wall_front and lamp, in
/// that order. The caller adds what stands in it.
pub fn lamp_room(name: &str, left: Rgb) -> SceneBuilder {
    let (w, h) = (2.0, 2.0);
    let v = DVec3::new;
    let mut b = SceneBuilder::new(name);
    let white = b.material("white", Rgb::splat(0.7), Rgb::ZERO).unwrap();
    let coloured = b.material("left", left, Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(10.0)).unwrap();
    let walls: [(&str, u32, [DVec3; 4]); 6] = [
        (
            "floor",
            white,
            [v(0., 0., 0.), v(0., 0., w), v(w, 0., w), v(w, 0., 0.)],
        ),
        (
            "ceiling",
            white,
            [v(0., h, 0.), v(w, h, 0.), v(w, h, w), v(0., h, w)],
        ),
        (
            "wall_left",
            coloured,
            [v(0., 0., 0.), v(0., h, 0.), v(0., h, w), v(0., 0., w)],
        ),
        (
            "wall_right",
            white,
            [v(w, 0., 0.), v(w, 0., w), v(w, h, w), v(w, h, 0.)],
        ),
        (
            "wall_back",
            white,
            [v(0., 0., 0.), v(w, 0., 0.), v(w, h, 0.), v(0., h, 0.)],
        ),
        (
            "wall_front",
            white,
            [v(0., 0., w), v(0., h, w), v(w, h, w), v(w, 0., w)],
        ),
    ];
    for (name, m, c) in walls {
        b.object(name);
        b.quad(m, c[0], c[1], c[2], c[3]).unwrap();
    }
    let (l0, l1, y) = (0.8, 1.2, h - 0.001);
    b.object("lamp");
    b.quad(lamp, v(l0, y, l0), v(l1, y, l0), v(l1, y, l1), v(l0, y, l1))
        .unwrap();
    b
}
