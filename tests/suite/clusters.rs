//! Face clusters: a tessellated column in a lit room. Its facets, far smaller
//! than the patch size, become a few patches instead of hundreds; the light
//! everything receives must not change beyond the approximation of treating a
//! slightly curved cluster as one constant source.

use super::common::rel;
use super::stress_scenes::{downward_quad, energy_errors, room, v};
use radiosity::math::Rgb;
use radiosity::pipeline::{ProgressiveSettings, SolverKind};
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::{Settings, Solution};
use std::f64::consts::TAU;

/// A closed 4 x 3 x 4 m grey room, a 1 m square light under its ceiling and a
/// column of radius 0.3 m and height 2 m of 32 x 12 facets in the middle
/// (each facet about 6 x 17 cm: far below the 0.8 m patch size).
fn room_with_column() -> Scene {
    let mut b = SceneBuilder::new("column_room");
    let grey = b.material("grey", Rgb::splat(0.6), Rgb::ZERO).unwrap();
    let stone = b
        .material("stone", Rgb::new(0.7, 0.6, 0.5), Rgb::ZERO)
        .unwrap();
    let light = b.material("light", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(4.0, 3.0, 4.0), grey, grey, grey);
    b.object("light");
    downward_quad(&mut b, light, 2.99, (1.5, 2.5), (1.5, 2.5));
    b.object("column");
    let (sides, rings) = (32, 12);
    let at = |i: usize, j: usize| {
        let a = TAU * i as f64 / sides as f64;
        v(
            2.0 + 0.3 * a.cos(),
            2.0 * j as f64 / rings as f64,
            2.0 + 0.3 * a.sin(),
        )
    };
    for j in 0..rings {
        for i in 0..sides {
            // Counter-clockwise seen from outside.
            b.polygon(
                stone,
                &[at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)],
            )
            .unwrap();
        }
    }
    b.build().unwrap()
}

fn settings(face_clusters: bool) -> Settings {
    Settings {
        patch_size: Some(0.8),
        face_clusters,
        refine: RefineSettings {
            uniform_depth: Some(0),
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

fn object(sol: &Solution, scene: &Scene, name: &str) -> Rgb {
    sol.object_radiosity(scene)
        .into_iter()
        .find(|o| o.name == name)
        .unwrap()
        .radiosity
}

#[test]
fn face_clusters_cut_the_patches_and_keep_the_light() {
    let scene = room_with_column();
    let facets = 32 * 12;
    let plain = radiosity::solve(&scene, &settings(false), &|_| {}).unwrap();
    let clustered = radiosity::solve(&scene, &settings(true), &|_| {}).unwrap();
    // Every facet its own patch, or a few clusters of them; the receivers
    // are the same facets either way.
    let column_patches = |s: &Solution| s.stats().patches - (plain.stats().patches - facets);
    assert_eq!(column_patches(&plain), facets);
    assert!(
        column_patches(&clustered) * 8 <= facets,
        "{} patches for the column",
        column_patches(&clustered)
    );
    assert_eq!(clustered.stats().elements, plain.stats().elements);
    // The rows hold fewer entries: each sees a few column patches, not
    // every facet on its side.
    assert!(
        clustered.stats().memory.row_entries < plain.stats().memory.row_entries,
        "{} vs {} row entries",
        clustered.stats().memory.row_entries,
        plain.stats().memory.row_entries
    );
    // Per object, the same light within the constant-source approximation
    // (30-degree clusters on a 0.3 m column; measured 0.25% at most).
    for name in ["column", "floor", "ceiling", "wall z0", "wall x1"] {
        let (a, b) = (
            object(&plain, &scene, name),
            object(&clustered, &scene, name),
        );
        for band in 0..3 {
            assert!(
                rel(b[band], a[band]) < 0.01,
                "{name} band {band}: clustered {} plain {}",
                b[band],
                a[band]
            );
        }
    }
    // A closed room keeps its energy either way.
    for sol in [&plain, &clustered] {
        for e in energy_errors(sol) {
            assert!(e.abs() < 0.02, "energy {e}");
        }
    }
}

#[test]
fn the_shooting_solver_takes_face_clusters_too() {
    let scene = room_with_column();
    let gathered = radiosity::solve(&scene, &settings(true), &|_| {}).unwrap();
    let shot = radiosity::solve(
        &scene,
        &Settings {
            solver_kind: SolverKind::Progressive,
            progressive: ProgressiveSettings::default(),
            ..settings(true)
        },
        &|_| {},
    )
    .unwrap();
    for name in ["column", "floor", "wall z1"] {
        let (a, b) = (object(&gathered, &scene, name), object(&shot, &scene, name));
        for band in 0..3 {
            assert!(
                rel(b[band], a[band]) < 0.01,
                "{name} band {band}: shot {} gathered {}",
                b[band],
                a[band]
            );
        }
    }
}
