//! Shaped gathers: a receiver close to an unevenly lit patch sees the part
//! of it that is near, not the patch's mean. A low panel stands at the far
//! end of a floor that is one patch, facing away from the lamp: all its light
//! comes from the dark end of the floor, which the floor's mean (bright under
//! the lamp) overstates several times. In a closed room the shaped gathers
//! move light between receivers and must keep the energy balance.

use super::contacts::face;
use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::reference::{Reference, ReferenceSettings};
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
        shaped_gathers: Some(shaped_gathers),
        ..Settings::default()
    };
    radiosity::solve(scene, &settings, &|_| {}).unwrap()
}

#[test]
fn shaped_gathers_keep_a_closed_room_s_energy_balance_within_a_tenth_of_a_percent() {
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

/// The path-traced mean radiosity of each of `scene`'s objects, from
/// `paths` paths per object with `seed`.
pub(super) fn reference_means(scene: &Scene, paths: u64, seed: u64) -> Vec<Rgb> {
    Reference::new(scene)
        .unwrap()
        .object_means(&ReferenceSettings {
            paths,
            seed,
            ..ReferenceSettings::default()
        })
        .unwrap()
        .into_iter()
        .map(|p| p.radiosity)
        .collect()
}

/// Worst relative error over the bands of `object`'s mean radiosity.
pub(super) fn error(scene: &Scene, sol: &Solution, reference: &[Rgb], object: &str) -> f64 {
    let objects = sol.object_radiosity(scene);
    let i = objects.iter().position(|o| o.name == object).unwrap();
    (0..3)
        .map(|band| (objects[i].radiosity[band] / reference[i][band] - 1.0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_panel_at_the_dark_end_of_a_floor_patch_gathers_the_dark_end() {
    let scene = panel_scene(false);
    let reference = reference_means(&scene, 100_000, 5);
    let flat = solve(&scene, 0);
    let shaped = solve(&scene, 2);
    assert!(flat.stats().shaped_sources.is_empty());
    assert_eq!(shaped.stats().shaped_sources.len(), 2);
    let (before, after) = (
        error(&scene, &flat, &reference, "panel"),
        error(&scene, &shaped, &reference, "panel"),
    );
    eprintln!("panel error: patch means {before:.4}, shaped {after:.4}");
    // The floor's mean is about five times what the panel sees of it
    // (measured 4.2 relative error); shaped, 0.09 (0.25 before the patch
    // radiosities were corrected for what the shapes change).
    assert!(before > 2.0, "{before}");
    assert!(after < 0.15, "{before} -> {after}");
    // The floor gathers mostly from the lamp, an even patch; the darker
    // panel it also sees brings it closer to the reference (measured 0.39%
    // -> 0.13%), never farther.
    let floor = (
        error(&scene, &flat, &reference, "floor"),
        error(&scene, &shaped, &reference, "floor"),
    );
    assert!(floor.1 <= floor.0 + 1e-4, "{floor:?}");
}

#[test]
fn more_shaped_gathers_than_the_limit_are_refused_naming_the_setting() {
    let ok = Settings {
        shaped_gathers: Some(radiosity::pipeline::MAX_SHAPED_GATHERS),
        ..Settings::default()
    };
    assert!(ok.validate().is_ok());
    let too_many = Settings {
        shaped_gathers: Some(radiosity::pipeline::MAX_SHAPED_GATHERS + 1),
        ..Settings::default()
    };
    let message = too_many.validate().unwrap_err().to_string();
    assert!(message.contains("shaped_gathers"), "{message}");
}

#[test]
fn shaped_gathers_with_fixed_bounces_are_refused_and_taken_by_the_progressive_solver() {
    // The progressive solver hands its converged shots to the gathering
    // solver, which makes the shaped gathers.
    let progressive = Settings {
        shaped_gathers: Some(2),
        solver_kind: radiosity::pipeline::SolverKind::Progressive,
        ..Settings::default()
    };
    assert!(progressive.validate().is_ok());
    assert_eq!(progressive.shaped_gather_count(), 2);
    let bounces = Settings {
        shaped_gathers: Some(2),
        bounces: Some(2),
        ..Settings::default()
    };
    let message = bounces.validate().unwrap_err().to_string();
    assert!(message.contains("shaped_gathers"), "{message}");
}

#[test]
fn part_views_asked_for_without_a_shaped_gather_are_refused() {
    for with_gather in [
        Settings {
            part_views: Some(true),
            ..Settings::default()
        },
        Settings {
            part_views: Some(true),
            solver_kind: radiosity::pipeline::SolverKind::Progressive,
            ..Settings::default()
        },
    ] {
        assert!(with_gather.validate().is_ok());
    }
    for without in [
        Settings {
            part_views: Some(true),
            shaped_gathers: Some(0),
            ..Settings::default()
        },
        Settings {
            part_views: Some(true),
            bounces: Some(2),
            ..Settings::default()
        },
    ] {
        let message = without.validate().unwrap_err().to_string();
        assert!(message.contains("part_views"), "{message}");
        // Left to the default, they are simply not drawn where no shaped
        // gather is made.
        let default = Settings {
            part_views: None,
            ..without
        };
        assert!(default.validate().is_ok());
        assert!(!default.uses_part_views());
    }
    assert!(Settings::default().uses_part_views());
    let off = Settings {
        part_views: Some(false),
        ..Settings::default()
    };
    assert!(off.validate().is_ok() && !off.uses_part_views());
}

/// A 6 m wall (one patch) with a pier against it, 0.7 m wide and 0.35 m
/// deep, and a floor (one patch); a lamp lights the east side of the pier
/// (z > 3.35), whose shadow darkens the wall and floor west of it. The
/// pier's east face meets the wall in a corner: a receiver there sees the
/// lit wall beside it. A part of the wall's quadtree that also reaches round
/// the pier into its shadow is much darker than what the receiver sees; it
/// must look inside such near parts.
fn pier_scene() -> Scene {
    let mut b = SceneBuilder::new("pier against a wall");
    let grey = b.material("grey", Rgb::splat(0.7), Rgb::ZERO).unwrap();
    let stone = b
        .material("stone", Rgb::new(0.7, 0.6, 0.5), Rgb::ZERO)
        .unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(20.0)).unwrap();
    let (w, h) = (6.0, 4.0);
    b.object("floor");
    face(
        &mut b,
        grey,
        [v(0., 0., 0.), v(w, 0., 0.), v(w, 0., w), v(0., 0., w)],
        DVec3::Y,
    );
    b.object("wall");
    face(
        &mut b,
        grey,
        [v(0., 0., 0.), v(0., h, 0.), v(0., h, w), v(0., 0., w)],
        DVec3::X,
    );
    b.object("lamp");
    face(
        &mut b,
        lamp,
        [
            v(0.5, 3., 4.),
            v(1.5, 3., 4.),
            v(1.5, 3., 5.),
            v(0.5, 3., 5.),
        ],
        DVec3::NEG_Y,
    );
    // The pier: no faces against the wall or the floor.
    let (x1, y1, z0, z1) = (0.35, 2.5, 2.65, 3.35);
    b.object("pier_east");
    face(
        &mut b,
        stone,
        [v(0., 0., z1), v(x1, 0., z1), v(x1, y1, z1), v(0., y1, z1)],
        DVec3::Z,
    );
    b.object("pier_rest");
    face(
        &mut b,
        stone,
        [v(0., 0., z0), v(x1, 0., z0), v(x1, y1, z0), v(0., y1, z0)],
        DVec3::NEG_Z,
    );
    face(
        &mut b,
        stone,
        [v(x1, 0., z0), v(x1, y1, z0), v(x1, y1, z1), v(x1, 0., z1)],
        DVec3::X,
    );
    face(
        &mut b,
        stone,
        [v(0., y1, z0), v(x1, y1, z0), v(x1, y1, z1), v(0., y1, z1)],
        DVec3::Y,
    );
    b.build().unwrap()
}

#[test]
fn a_pier_face_in_a_corner_gathers_the_wall_beside_it() {
    let scene = pier_scene();
    let reference = reference_means(&scene, 100_000, 9);
    let settings = Settings {
        patch_size: Some(6.0),
        ..Settings::default()
    };
    let sol = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
    assert!(!sol.stats().shaped_sources.is_empty());
    for name in ["pier_east", "pier_rest", "wall", "floor"] {
        eprintln!("{name}: {:.4}", error(&scene, &sol, &reference, name));
    }
    // Measured: 7.5% low when receivers weighed only the cut's parts (the
    // part in the corner reaching round the pier into its shadow), 5.9%
    // when they look inside near parts. What is left is the face's own
    // light from the lamp, which it sees at grazing angles.
    let east = error(&scene, &sol, &reference, "pier_east");
    assert!(east < 0.065, "pier_east {east}");
    for name in ["pier_rest", "wall", "floor"] {
        let e = error(&scene, &sol, &reference, name);
        assert!(e < 0.02, "{name} {e}");
    }
}
