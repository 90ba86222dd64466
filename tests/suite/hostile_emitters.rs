//! Many small emitters (issue 19, defect 8): a receiver that sees hundreds of
//! emitter polygons smaller than a pixel gives each one shadow ray instead of
//! an exact shaft clipping, so the cost of a row stays in proportion, and the
//! light it receives stays what the exact path gives.

use super::stress_scenes::{quick_settings, room, v};
use radiosity::math::Rgb;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::{Settings, Solution};
use std::f64::consts::TAU;

/// A room lit by an emissive fan of `blades` thin triangles facing down under
/// the ceiling (a regular polygon of radius 0.15 m cut from its centre), with
/// a plate between the fan and the floor that casts a soft shadow.
fn fan_room(blades: usize) -> Scene {
    let mut b = SceneBuilder::new("fan_room");
    let wall = b.material("wall", Rgb::splat(0.6), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::ONE).unwrap();
    let grey = b.material("plate", Rgb::splat(0.4), Rgb::ZERO).unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0), wall, wall, wall);
    b.object("plate");
    b.quad(
        grey,
        v(0.4, 0.5, 0.4),
        v(0.4, 0.5, 0.6),
        v(0.6, 0.5, 0.6),
        v(0.6, 0.5, 0.4),
    )
    .unwrap();
    b.object("fan");
    let centre = v(0.5, 0.95, 0.5);
    let rim = |i: usize| {
        let a = TAU * i as f64 / blades as f64;
        centre + v(a.cos(), 0.0, a.sin()) * 0.15
    };
    for i in 0..blades {
        // Counter-clockwise seen from below: the blade faces down.
        b.triangle(lamp, centre, rim(i), rim(i + 1)).unwrap();
    }
    b.build().unwrap()
}

fn settings() -> Settings {
    Settings {
        hemicube_resolution: 32,
        ..quick_settings(0.25)
    }
}

fn means(sol: &Solution, scene: &Scene) -> Vec<(String, f64)> {
    sol.object_radiosity(scene)
        .into_iter()
        .map(|o| (o.name, o.radiosity.max_band()))
        .collect()
}

#[test]
fn many_subpixel_emitters_take_one_shadow_ray_each_and_keep_their_light() {
    // 48 blades: every one clipped exactly (the reference).
    let few = fan_room(48);
    let exact = radiosity::solve(&few, &settings(), &|_| {}).unwrap();
    let h = &exact.stats().hemicube;
    assert_eq!(h.emitters_one_ray, 0, "{h:?}");
    assert!(h.emitters_exact > 0, "{h:?}");

    // 480 blades of the same fan: rows see hundreds of blades smaller than
    // a pixel, and the exact work per row stays bounded.
    let many = fan_room(480);
    let cheap = radiosity::solve(&many, &settings(), &|_| {}).unwrap();
    let h = &cheap.stats().hemicube;
    assert!(h.emitters_one_ray > 100 * h.hemicubes, "{h:?}");
    assert!(
        h.emitters_exact < 64 * h.hemicubes,
        "exact emitter work per row grew with the blades: {h:?}"
    );

    // The two fans are the same light up to the area the 48-gon misses
    // (0.29%): every object's mean within 1%.
    for ((name, a), (_, b)) in means(&exact, &few).into_iter().zip(means(&cheap, &many)) {
        if name == "fan" {
            continue;
        }
        let off = (b - a).abs() / a;
        assert!(
            off < 0.01,
            "{name}: {a} (exact) vs {b} (one ray a blade), {off:.4}"
        );
    }
}
