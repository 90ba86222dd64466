//! Shaped gathers: a receiver close to an unevenly lit patch sees the part
//! of it that is near, not the patch's mean. In a closed room whose floor is
//! one patch, lit at one end, with a low panel standing at the other, the
//! shaped gathers move light between receivers and must lose none.

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::{Settings, Solution};

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A 4 m floor, a 1 m lamp 2 m above its west end facing down, and a panel
/// 0.6 m high standing on it at x = 2.5, facing east. With `closed`, walls
/// and a ceiling close the room.
fn panel_scene(closed: bool) -> Scene {
    let mut b = SceneBuilder::new("panel on a floor");
    let grey = b.material("grey", Rgb::splat(0.8), Rgb::ZERO).unwrap();
    let paint = b
        .material("paint", Rgb::new(0.7, 0.5, 0.3), Rgb::ZERO)
        .unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
    b.object("floor");
    b.quad(
        grey,
        v(0., 0., 0.),
        v(0., 0., 4.),
        v(4., 0., 4.),
        v(4., 0., 0.),
    )
    .unwrap();
    b.object("lamp");
    b.quad(
        lamp,
        v(0.5, 1.999, 1.5),
        v(1.5, 1.999, 1.5),
        v(1.5, 1.999, 2.5),
        v(0.5, 1.999, 2.5),
    )
    .unwrap();
    b.object("panel");
    b.quad(
        paint,
        v(2.5, 0., 1.5),
        v(2.5, 0.6, 1.5),
        v(2.5, 0.6, 2.5),
        v(2.5, 0., 2.5),
    )
    .unwrap();
    if closed {
        b.object("room");
        let h = 2.0;
        let (w, d) = (4.0, 4.0);
        // Ceiling (facing down) and four walls (facing in).
        b.quad(grey, v(0., h, 0.), v(w, h, 0.), v(w, h, d), v(0., h, d))
            .unwrap();
        b.quad(grey, v(0., 0., 0.), v(w, 0., 0.), v(w, h, 0.), v(0., h, 0.))
            .unwrap();
        b.quad(grey, v(0., 0., d), v(0., h, d), v(w, h, d), v(w, 0., d))
            .unwrap();
        b.quad(grey, v(0., 0., 0.), v(0., h, 0.), v(0., h, d), v(0., 0., d))
            .unwrap();
        b.quad(grey, v(w, 0., 0.), v(w, 0., d), v(w, h, d), v(w, h, 0.))
            .unwrap();
    }
    b.build().unwrap()
}

fn solve(scene: &Scene, shaped_gathers: usize) -> Solution {
    let settings = Settings {
        // The floor is one patch.
        patch_size: Some(4.0),
        shaped_gathers,
        ..Settings::default()
    };
    radiosity::solve(scene, &settings, &|_| {}).unwrap()
}

#[test]
fn shaped_gathers_move_light_between_receivers_and_lose_none_in_a_closed_room() {
    let scene = panel_scene(true);
    for shaped_gathers in [0, 2] {
        let sol = solve(&scene, shaped_gathers);
        let energy = sol.stats().energy.relative_difference;
        eprintln!("shaped gathers {shaped_gathers}: energy {energy:e}");
        assert!(sol.stats().energy.closed);
        assert!(energy.abs() < 1e-3, "{shaped_gathers}: {energy}");
        if shaped_gathers > 0 {
            assert!(sol.stats().shaped_sources.iter().all(|n| *n >= 1));
        }
    }
}
