//! Sizes that scale with the scene (issue 19, defect 11): defaults follow the
//! geometry that matters, not one stray triangle far away, and two surfaces
//! are one plane only within a fraction of their own size.

use super::stress_scenes::{downward_quad, quick_settings, room, v};
use radiosity::math::Rgb;
use radiosity::scene::{Overlaps, Scene, SceneBuilder};
use radiosity::Settings;

/// A 1 m room lit from under its ceiling, with a small triangle `far` metres
/// away along x when given.
fn room_with_stray(far: Option<f64>) -> Scene {
    let mut b = SceneBuilder::new("stray");
    let wall = b.material("wall", Rgb::splat(0.7), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::ONE).unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0), wall, wall, wall);
    b.object("lamp");
    downward_quad(&mut b, lamp, 0.99, (0.4, 0.6), (0.4, 0.6));
    if let Some(x) = far {
        b.object("stray");
        b.triangle(wall, v(x, 0.5, 0.5), v(x + 1.0, 0.5, 0.5), v(x, 0.5, 1.5))
            .unwrap();
    }
    b.build().unwrap()
}

#[test]
fn a_stray_triangle_far_away_does_not_set_the_default_sizes() {
    let plain = room_with_stray(None);
    let stray = room_with_stray(Some(1e9));
    assert_eq!(plain.extent(), plain.diameter());
    assert!(plain.warnings.is_empty(), "{:?}", plain.warnings);
    assert_eq!(stray.extent(), plain.extent());
    assert!(stray.diameter() > 1e8);
    let named = stray
        .warnings
        .iter()
        .any(|w| w.contains("'stray'") && w.contains("far outside"));
    assert!(named, "{:?}", stray.warnings);

    // The solve cuts the room as it would without the stray: the same patch
    // size, and the walls' light within a fraction of a per cent.
    let settings = Settings {
        patch_size: None,
        ..quick_settings(1.0)
    };
    let a = radiosity::solve(&plain, &settings, &|_| {}).unwrap();
    let b = radiosity::solve(&stray, &settings, &|_| {}).unwrap();
    assert_eq!(a.stats().patch_size, b.stats().patch_size);
    let (ma, mb) = (a.object_radiosity(&plain), b.object_radiosity(&stray));
    for (x, y) in ma.iter().zip(&mb) {
        let (p, q) = (x.radiosity.max_band(), y.radiosity.max_band());
        assert!((p - q).abs() <= 5e-3 * p, "{}: {p} vs {q}", x.name);
    }
}

#[test]
fn a_lamp_a_millimetre_under_its_ceiling_stays_apart_in_a_wide_scene() {
    // 100 000 small tiles over 100 m x 100 m, and a 10 m room in the middle
    // whose lamp hangs 1 mm under the ceiling: 1e-5 of the scene's 141 m is
    // 1.4 mm, but of the lamp and ceiling's own 14 m only 0.14 mm.
    let mut b = SceneBuilder::new("wide");
    b.overlaps(Some(Overlaps::Error));
    let wall = b.material("wall", Rgb::splat(0.7), Rgb::ZERO).unwrap();
    let tile = b.material("tile", Rgb::splat(0.3), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::ONE).unwrap();
    room(
        &mut b,
        v(45.0, 0.0, 45.0),
        v(55.0, 3.0, 55.0),
        wall,
        wall,
        wall,
    );
    b.object("lamp");
    downward_quad(&mut b, lamp, 2.999, (49.5, 50.5), (49.5, 50.5));
    b.object("tiles");
    let n = 317; // 317^2 > 100 000
    let step = 100.0 / n as f64;
    let mut count = 0;
    for i in 0..n {
        for j in 0..n {
            if count == 100_000 {
                break;
            }
            let (x, z) = (i as f64 * step, j as f64 * step);
            let y = -0.01;
            b.quad(
                tile,
                v(x, y, z),
                v(x, y, z + 0.05),
                v(x + 0.05, y, z + 0.05),
                v(x + 0.05, y, z),
            )
            .unwrap();
            count += 1;
        }
    }
    let scene = b
        .build()
        .expect("the lamp is not one plane with its ceiling");
    assert!(scene.diameter() > 140.0);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}
