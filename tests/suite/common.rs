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
