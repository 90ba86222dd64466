//! Scenes and helpers shared by the stress tests (stability, awkward geometry,
//! scale, random scenes, determinism).

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::refine::RefineSettings;
use radiosity::scene::SceneBuilder;
use radiosity::solution::Leaf;
use radiosity::{Settings, Solution};

/// Shorthand for a point.
pub fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Adds the six faces of the box `lo..hi` facing inwards (a room), as one
/// object per face: floor (y = lo), ceiling, then the four walls.
pub fn room(b: &mut SceneBuilder, lo: DVec3, hi: DVec3, floor: u32, ceiling: u32, walls: u32) {
    room_faces(b, lo, hi, [floor, ceiling, walls, walls, walls, walls]);
}

/// [`room`] with a material per face: floor, ceiling, walls z0, z1, x0, x1.
pub fn room_faces(b: &mut SceneBuilder, lo: DVec3, hi: DVec3, materials: [u32; 6]) {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let (a, c) = (lo, hi);
    let faces = [
        (
            "floor",
            materials[0],
            [
                p(a.x, a.y, a.z),
                p(a.x, a.y, c.z),
                p(c.x, a.y, c.z),
                p(c.x, a.y, a.z),
            ],
        ),
        (
            "ceiling",
            materials[1],
            [
                p(a.x, c.y, a.z),
                p(c.x, c.y, a.z),
                p(c.x, c.y, c.z),
                p(a.x, c.y, c.z),
            ],
        ),
        (
            "wall z0",
            materials[2],
            [
                p(a.x, a.y, a.z),
                p(c.x, a.y, a.z),
                p(c.x, c.y, a.z),
                p(a.x, c.y, a.z),
            ],
        ),
        (
            "wall z1",
            materials[3],
            [
                p(a.x, a.y, c.z),
                p(a.x, c.y, c.z),
                p(c.x, c.y, c.z),
                p(c.x, a.y, c.z),
            ],
        ),
        (
            "wall x0",
            materials[4],
            [
                p(a.x, a.y, a.z),
                p(a.x, c.y, a.z),
                p(a.x, c.y, c.z),
                p(a.x, a.y, c.z),
            ],
        ),
        (
            "wall x1",
            materials[5],
            [
                p(c.x, a.y, a.z),
                p(c.x, a.y, c.z),
                p(c.x, c.y, c.z),
                p(c.x, c.y, a.z),
            ],
        ),
    ];
    for (name, m, q) in faces {
        b.object(name);
        b.polygon(m, &q).expect("room face");
    }
}

/// A horizontal quad facing down (-y) at height `y` over `x0..x1`, `z0..z1`.
pub fn downward_quad(b: &mut SceneBuilder, m: u32, y: f64, x: (f64, f64), z: (f64, f64)) {
    // (+x) x (+z) = -y: counter-clockwise seen from below.
    b.quad(
        m,
        v(x.0, y, z.0),
        v(x.1, y, z.0),
        v(x.1, y, z.1),
        v(x.0, y, z.1),
    )
    .expect("downward quad");
}

/// The test room: `2 x 1.6 x 2.4` times `scale`, grey walls, a light of
/// `radiance` facing down `gap` (times `scale`) below the ceiling, and a red
/// box floating inside (touching nothing).
pub fn lit_room_with_box(scale: f64, radiance: f64, gap: f64) -> radiosity::scene::Scene {
    let s = scale;
    let mut b = SceneBuilder::new("lit_room");
    let grey = b
        .material("grey", Rgb::new(0.6, 0.5, 0.4), Rgb::ZERO)
        .unwrap();
    let white = b.material("white", Rgb::splat(0.75), Rgb::ZERO).unwrap();
    let red = b
        .material("red", Rgb::new(0.7, 0.1, 0.1), Rgb::ZERO)
        .unwrap();
    let light = b
        .material("light", Rgb::splat(0.2), Rgb::splat(radiance))
        .unwrap();
    room(
        &mut b,
        v(0.0, 0.0, 0.0),
        v(2.0, 1.6, 2.4) * s,
        grey,
        white,
        white,
    );
    b.object("light");
    downward_quad(
        &mut b,
        light,
        (1.6 - gap) * s,
        (0.7 * s, 1.3 * s),
        (0.9 * s, 1.5 * s),
    );
    b.axis_box("box", red, v(0.4, 0.2, 0.5) * s, v(1.0, 0.8, 1.1) * s)
        .unwrap();
    b.build().unwrap()
}

/// Settings for small, fast solves: coarse patches, a small hemi-cube.
pub fn quick_settings(patch_size: f64) -> Settings {
    Settings {
        hemicube_resolution: 64,
        patch_size: Some(patch_size),
        refine: RefineSettings {
            max_depth: 2,
            max_passes: 2,
            tolerance: 0.05,
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

/// The leaf elements of a solution, in the mesh's (deterministic) order.
pub fn leaves(sol: &Solution) -> Vec<Leaf<'_>> {
    sol.leaves()
}

/// Every leaf, patch and patch-system radiosity is finite and non-negative.
pub fn assert_finite_non_negative(sol: &Solution, what: &str) {
    for e in leaves(sol) {
        assert!(
            e.radiosity.is_finite() && e.radiosity.min_band() >= 0.0,
            "{what}: element at {} has radiosity {:?}",
            e.centroid(),
            e.radiosity.0
        );
    }
    for (i, b) in sol.patch_radiosity().iter().enumerate() {
        assert!(
            b.is_finite() && b.min_band() >= 0.0,
            "{what}: patch {i} has radiosity {:?}",
            b.0
        );
    }
}

/// The relative energy balance in every band: `(absorbed - emitted) /
/// emitted`, counting what back faces absorb (the back of a single-sided
/// surface blocks light and reflects none).
pub fn energy_errors(sol: &Solution) -> [f64; 3] {
    let e = sol.stats().energy.emitted_power;
    let a = sol.stats().energy.absorbed_power + sol.stats().energy.back_face_power;
    std::array::from_fn(|band| (a[band] - e[band]) / e[band])
}
