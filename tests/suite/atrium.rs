//! The atrium generator (`scenes::atrium`): size series, determinism and the
//! geometric hygiene the solver needs.

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::scene::{Material, Scene, Surface};
use radiosity::scenes::atrium::{
    self, atrium, atrium_sized, triangle_count, AtriumSize, MAX_TRIANGLES, MIN_TRIANGLES,
    SUN_DIRECTION,
};
use radiosity::{Error, Settings};
use std::collections::HashMap;

// The atrium's plan (metres), written out here now that the generator's
// plan constants are private: the sky quad stands 3 m over the roof (as the
// module documentation says) and reaches twice that beyond the end walls;
// ground columns rise to the arches' springing line at 3.3 m; two galleries
// of one 3.8 m storey each stand above the arcade.
const SKY_HEIGHT: f64 = 3.0;
const SKY_OVERHANG: f64 = 6.0;
const SPRING: f64 = 3.3;
const GALLERIES: usize = 2;
const STOREY: f64 = 3.8;

/// |count / target - 1|.
fn deviation(count: usize, target: usize) -> f64 {
    (count as f64 / target as f64 - 1.0).abs()
}

#[test]
fn built_scenes_have_their_target_triangle_count_within_ten_percent() {
    for target in [10_000, 30_000, 100_000, 1_000_000] {
        let scene = atrium(target).unwrap();
        let count = triangle_count(&scene);
        assert!(
            deviation(count, target) <= 0.1,
            "target {target}: {count} triangles"
        );
        // The size search counts without building: the same number.
        let size = AtriumSize::for_target(target).unwrap();
        assert_eq!(size.triangles().unwrap(), count, "target {target}");
    }
}

#[test]
fn every_target_in_the_range_is_met_within_ten_percent() {
    // Geometric steps of 9% across the range, plus both ends: the count is a
    // step function of the density, so this looks between the sizes above.
    let mut targets = vec![MIN_TRIANGLES, MAX_TRIANGLES];
    let mut t = MIN_TRIANGLES as f64 * 1.05;
    while t < MAX_TRIANGLES as f64 {
        targets.push(t as usize);
        t *= 1.09;
    }
    for target in targets {
        let size = AtriumSize::for_target(target).unwrap();
        let count = size.triangles().unwrap();
        assert!(
            deviation(count, target) <= 0.1,
            "target {target}: {count} triangles with {size:?}"
        );
    }
}

#[test]
fn targets_outside_the_range_are_refused() {
    for target in [0, MIN_TRIANGLES - 1, MAX_TRIANGLES + 1] {
        assert!(
            matches!(atrium(target), Err(Error::Setting { .. })),
            "{target}"
        );
    }
    let bad = AtriumSize {
        bays: 1,
        balusters: false,
        density: 1.0,
    };
    assert!(matches!(atrium_sized(&bad), Err(Error::Setting { .. })));
    let bad = AtriumSize {
        density: f64::NAN,
        bays: 4,
        ..bad
    };
    assert!(matches!(atrium_sized(&bad), Err(Error::Setting { .. })));
    // In range field by field, but far too many triangles: refused before
    // anything is built.
    let huge = AtriumSize {
        bays: atrium::MAX_BAYS,
        balusters: true,
        density: 60.0,
    };
    assert!(huge.triangles().unwrap() > atrium::MAX_BUILT_TRIANGLES);
    assert!(matches!(atrium_sized(&huge), Err(Error::Limit { .. })));
}

#[test]
fn larger_targets_have_more_bays_balusters_and_finer_curves() {
    let small = AtriumSize::for_target(10_000).unwrap();
    let large = AtriumSize::for_target(1_000_000).unwrap();
    assert!(large.bays > small.bays);
    assert!(large.balusters && !small.balusters);
    assert!(large.density > 4.0 * small.density);
}

#[test]
fn the_same_size_gives_the_same_bits() {
    let (a, b) = (atrium(30_000).unwrap(), atrium(30_000).unwrap());
    assert_eq!(a.surfaces.len(), b.surfaces.len());
    for (s, t) in a.surfaces.iter().zip(&b.surfaces) {
        let bits = |s: &Surface| -> Vec<u64> {
            s.vertices
                .iter()
                .flat_map(|v| v.to_array())
                .map(f64::to_bits)
                .collect()
        };
        assert_eq!(bits(s), bits(t));
        assert_eq!((s.material, s.object), (t.material, t.object));
    }
    assert_eq!(a.objects, b.objects);
    assert_eq!(a.materials, b.materials);
    assert_eq!(a.cameras, b.cameras);
}

#[test]
fn names_pick_the_size() {
    assert_eq!(atrium::target_of_name("atrium"), Some(10_000));
    assert_eq!(atrium::target_of_name("atrium_200k"), Some(200_000));
    assert_eq!(atrium::target_of_name("atrium_1m"), Some(1_000_000));
    assert_eq!(atrium::target_of_name("atrium_30000"), Some(30_000));
    for bad in [
        "atrium_",
        "atrium_k",
        "atrium_2x",
        "atrium_-5k",
        "atriums",
        "cornell_box",
    ] {
        assert_eq!(atrium::target_of_name(bad), None, "{bad}");
    }
    let scene = radiosity::scenes::by_name("atrium_30k").unwrap();
    assert_eq!(scene.name, "atrium_30k");
    assert_eq!(
        triangle_count(&scene),
        triangle_count(&atrium(30_000).unwrap())
    );
    assert_eq!(atrium::atrium_default().name, "atrium");
}

/// Every surface is finite and as valid as the surface constructor requires
/// (which refuses degenerate slivers), its normal a unit vector; every
/// object has surfaces; the object count stays moderate; reflectances are
/// well below 1 and only the sky emits.
fn assert_valid(scene: &Scene) {
    let mut per_object = vec![0usize; scene.objects.len()];
    for s in &scene.surfaces {
        assert!(s.vertices.iter().all(|v| v.is_finite()));
        assert!(s.area > 0.0 && s.area.is_finite());
        assert!((s.normal.length() - 1.0).abs() < 1e-9);
        let again = Surface::new(&s.vertices, s.material, s.object).unwrap();
        assert_eq!(again.normal, s.normal);
        per_object[s.object as usize] += 1;
    }
    for (o, n) in scene.objects.iter().zip(&per_object) {
        assert!(*n > 0, "object {} is empty", o.name);
    }
    assert!(
        scene.objects.len() < 1000,
        "{} objects",
        scene.objects.len()
    );
    let names: std::collections::HashSet<_> = scene.objects.iter().map(|o| &o.name).collect();
    assert_eq!(names.len(), scene.objects.len(), "object names are unique");
    for m in &scene.materials {
        if m.name == "sky" {
            assert!(m.is_emitter() && m.reflectance == Rgb::ZERO);
        } else {
            assert!(!m.is_emitter(), "{}", m.name);
            assert!(m.reflectance.max_band() <= 0.8, "{}", m.name);
            assert!(m.reflectance.max_band() >= 0.2, "{}", m.name);
        }
    }
}

#[test]
fn every_surface_is_valid_at_every_layout() {
    for target in [10_000, 100_000] {
        assert_valid(&atrium(target).unwrap());
    }
    // The smallest and a coarse large layout, beyond the targets' choices.
    for (bays, balusters, density) in [(3, true, 0.5), (12, true, 3.0), (4, false, 30.0)] {
        let size = AtriumSize {
            bays,
            balusters,
            density,
        };
        assert_valid(&atrium_sized(&size).unwrap());
    }
}

/// Runs the solver's checks on `scene` up to the mesher and no further: a
/// one-patch limit stops the solve there (a `Limit` error) after the
/// coplanar-overlap check, which runs first and refuses with a `Geometry`
/// error naming both objects.
fn solver_accepts(scene: &Scene) -> Result<(), String> {
    let settings = Settings {
        max_patches: 1,
        ..Settings::default()
    };
    match radiosity::solve(scene, &settings, &|_| {}) {
        Err(Error::Limit { .. }) => Ok(()),
        Err(e) => Err(e.to_string()),
        Ok(_) => panic!("a one-patch limit cannot hold the atrium"),
    }
}

/// `scene` with each surface in its own material, so that the coplanar check
/// (which lets identical materials overlap, as they look the same whichever
/// wins) looks at every pair.
fn one_material_per_surface(scene: &Scene) -> Scene {
    let mut strict = scene.clone();
    let n = strict.surfaces.len();
    strict.materials = (0..n)
        .map(|i| {
            let original = &scene.materials[scene.surfaces[i].material as usize];
            let rho = 0.1 + 0.8 * i as f64 / n as f64;
            Material {
                name: format!("surface_{i}"),
                reflectance: Rgb::splat(rho),
                ..original.clone()
            }
        })
        .collect();
    for (i, s) in strict.surfaces.iter_mut().enumerate() {
        s.material = i as u32;
    }
    strict
}

#[test]
fn no_two_surfaces_overlap_in_one_plane() {
    for target in [10_000, 30_000, 100_000] {
        let scene = atrium(target).unwrap();
        solver_accepts(&scene).unwrap();
        solver_accepts(&one_material_per_surface(&scene))
            .unwrap_or_else(|e| panic!("target {target}: {e}"));
    }
    // The check is live: a rug of another material flush with the floor,
    // and the same floor twice, are refused.
    let mut scene = atrium(10_000).unwrap();
    let floor = scene
        .surfaces
        .iter()
        .find(|s| scene.objects[s.object as usize].name == "floor")
        .unwrap()
        .clone();
    let mut rug = floor.clone();
    rug.material = scene
        .materials
        .iter()
        .position(|m| m.name == "cloth_red")
        .unwrap() as u32;
    scene.surfaces.push(rug);
    let e = solver_accepts(&scene).unwrap_err();
    assert!(e.contains("one plane") && e.contains("'floor'"), "{e}");
    let mut twice = atrium(10_000).unwrap();
    twice.surfaces.push(floor);
    assert!(solver_accepts(&twice).is_ok());
    assert!(solver_accepts(&one_material_per_surface(&twice)).is_err());
}

/// Surfaces grouped by the kind of their object (`column_3` -> `column`).
fn by_kind(scene: &Scene) -> HashMap<String, Vec<&Surface>> {
    let mut kinds: HashMap<String, Vec<&Surface>> = HashMap::new();
    for s in &scene.surfaces {
        let name = &scene.objects[s.object as usize].name;
        let kind = name.trim_end_matches(|c: char| c.is_ascii_digit() || c == '_');
        kinds.entry(kind.to_string()).or_default().push(s);
    }
    kinds
}

#[test]
fn furniture_stands_on_the_floor_and_nothing_goes_below_it() {
    let scene = atrium(30_000).unwrap();
    let (lo, _) = scene.bounds();
    assert_eq!(lo.y, 0.0, "nothing below the floor");
    let mut pieces = 0;
    for (i, object) in scene.objects.iter().enumerate() {
        let kind = object
            .name
            .trim_end_matches(|c: char| c.is_ascii_digit() || c == '_');
        if !["table", "bench", "planter", "fountain"].contains(&kind) {
            continue;
        }
        pieces += 1;
        let mine: Vec<&Surface> = scene
            .surfaces
            .iter()
            .filter(|s| s.object as usize == i)
            .collect();
        let low = mine
            .iter()
            .flat_map(|s| s.vertices.iter())
            .map(|v| v.y)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(low, 0.0, "{} rests on the floor", object.name);
        for s in mine {
            // No face lies on the floor: a bottom would only be hidden.
            assert!(
                !(s.normal.y < -0.999 && s.vertices.iter().all(|v| v.y == 0.0)),
                "{} has a bottom face",
                object.name
            );
        }
    }
    assert!(pieces > 10, "{pieces} pieces of furniture");
}

#[test]
fn the_sky_faces_down_over_the_whole_opening() {
    let scene = atrium(10_000).unwrap();
    let kinds = by_kind(&scene);
    let sky = &kinds["sky"];
    assert_eq!(sky.len(), 1);
    let s = sky[0];
    assert!(s.normal.y < -0.999_999);
    let roof = scene
        .surfaces
        .iter()
        .flat_map(|s| s.vertices.iter())
        .filter(|v| v.y < s.vertices[0].y)
        .map(|v| v.y)
        .fold(0.0, f64::max);
    assert_eq!(s.vertices[0].y, roof + SKY_HEIGHT);
    // Over the whole building across the court, beyond the end walls along it.
    let (lo, hi) = scene.bounds();
    let floor = &kinds["floor"][0];
    let length = floor.vertices.iter().map(|v| v.x).fold(0.0, f64::max);
    for v in &s.vertices {
        assert!(v.x == lo.x || v.x == hi.x);
        assert!(v.z == lo.z || v.z == hi.z);
    }
    assert_eq!((lo.x, hi.x), (-SKY_OVERHANG, length + SKY_OVERHANG));
    assert_eq!(lo.z, 0.0);
    // Only the sky emits; the sun is not there yet, but its direction is a
    // unit vector along which the middle of the court's floor sees out
    // through the opening.
    let emitting = scene
        .surfaces
        .iter()
        .filter(|s| scene.material_of(s).is_emitter())
        .count();
    assert_eq!(emitting, 1);
    assert!((SUN_DIRECTION.length() - 1.0).abs() < 1e-15);
    let face = |kind: &str| kinds[kind][0].vertices[0].z;
    let (south, north) = (face("facade_south"), face("facade_north"));
    let middle = DVec3::new(length / 2.0, 0.0, (south + north) / 2.0);
    let at_roof = middle + SUN_DIRECTION * (roof / SUN_DIRECTION.y);
    assert!(at_roof.z > south && at_roof.z < north, "{at_roof}");
    assert!(at_roof.x > 0.0 && at_roof.x < length, "{at_roof}");
}

#[test]
fn the_building_faces_in_and_columns_and_banners_face_out() {
    let scene = atrium(30_000).unwrap();
    let kinds = by_kind(&scene);
    let (lo, hi) = scene.bounds();
    // The building without the sky's margin.
    let length = kinds["floor"][0]
        .vertices
        .iter()
        .map(|v| v.x)
        .fold(0.0, f64::max);
    let width = kinds["floor"][0]
        .vertices
        .iter()
        .map(|v| v.z)
        .fold(0.0, f64::max);
    assert!(lo.x < 0.0 && hi.x > length, "the sky reaches beyond");
    let middle = DVec3::new(length / 2.0, 4.0, width / 2.0);
    for kind in [
        "end_wall_east",
        "end_wall_west",
        "ambulatory_south",
        "gallery_north",
    ] {
        for s in &kinds[kind] {
            let c = s.centroid();
            let inward = DVec3::new(middle.x - c.x, middle.y - c.y, middle.z - c.z);
            // Walls face the middle across; floors face up, ceilings down.
            if s.normal.y.abs() < 0.5 {
                assert!(s.normal.dot(inward) > 0.0, "{kind} at {c}");
            }
        }
    }
    // A gallery has a floor facing up and a ceiling facing down.
    let ys: Vec<f64> = kinds["gallery_north"].iter().map(|s| s.normal.y).collect();
    assert!(ys.iter().any(|&y| y > 0.999) && ys.iter().any(|&y| y < -0.999));
    for s in &kinds["roof_south"] {
        assert!(s.normal.y > 0.999);
    }
    // Column surfaces face away from their axis (or straight up or down).
    let columns: std::collections::HashSet<u32> =
        kinds["column"].iter().map(|s| s.object).collect();
    assert_eq!(
        columns.len() as u32,
        3 * 2 * (AtriumSize::for_target(30_000).unwrap().bays - 1)
    );
    for object in columns {
        let mine: Vec<&&Surface> = kinds["column"]
            .iter()
            .filter(|s| s.object == object)
            .collect();
        let n = mine.iter().map(|s| s.vertices.len()).sum::<usize>() as f64;
        let axis = mine
            .iter()
            .flat_map(|s| s.vertices.iter())
            .fold(DVec3::ZERO, |a, v| a + *v)
            / n;
        for s in mine {
            let c = s.centroid();
            let radial = DVec3::new(c.x - axis.x, 0.0, c.z - axis.z);
            let across = DVec3::new(s.normal.x, 0.0, s.normal.z);
            assert!(
                across.length() < 1e-9 || across.dot(radial) > 0.0,
                "column surface at {c} faces its axis"
            );
        }
    }
    // Banners face into the court, towards its long middle line or away from
    // the end wall they hang on.
    for s in &kinds["banner"] {
        let c = s.centroid();
        let inward = if c.x < 0.5 {
            DVec3::X
        } else if c.x > length - 0.5 {
            -DVec3::X
        } else {
            DVec3::new(0.0, 0.0, width / 2.0 - c.z).normalize()
        };
        assert!(s.normal.dot(inward) > 0.3, "banner at {c}");
    }
}

#[test]
fn columns_reach_from_floor_to_arch_and_slab() {
    let scene = atrium(10_000).unwrap();
    let kinds = by_kind(&scene);
    let columns: std::collections::HashSet<u32> =
        kinds["column"].iter().map(|s| s.object).collect();
    let mut heights: Vec<(f64, f64)> = columns
        .iter()
        .map(|&o| {
            let ys = kinds["column"]
                .iter()
                .filter(|s| s.object == o)
                .flat_map(|s| s.vertices.iter())
                .map(|v| v.y);
            ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
                (a.min(y), b.max(y))
            })
        })
        .collect();
    heights.sort_by(|a, b| a.0.total_cmp(&b.0));
    heights.dedup();
    // Ground columns from the floor to the springing line; gallery columns
    // from their floor to their ceiling.
    let floors: Vec<f64> = scene
        .surfaces
        .iter()
        .filter(|s| {
            s.normal.y > 0.999 && scene.objects[s.object as usize].name.starts_with("gallery")
        })
        .map(|s| s.vertices[0].y)
        .collect();
    assert_eq!(heights[0], (0.0, SPRING));
    assert_eq!(heights.len(), 1 + GALLERIES);
    for (k, (bottom, top)) in heights[1..].iter().enumerate() {
        assert!(floors.contains(bottom), "gallery {k} column foot {bottom}");
        assert!((top - bottom - STOREY).abs() < 1e-12);
    }
}
