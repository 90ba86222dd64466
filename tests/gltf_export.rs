//! glTF export: round trips through `write_scene` and `load_scene`, the structure
//! of the written file, and the committed built-in scene files.

use glam::DVec3;
use radiosity::gltf_io::{load_scene, write_scene, ImportLimits};
use radiosity::math::Rgb;
use radiosity::scene::{Camera, Scene, SceneBuilder, Surface};
use radiosity::scenes;
use radiosity::Error;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf_export");
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A scene with quads, triangles, several materials per object, awkward numbers
/// and two cameras.
fn sample_scene() -> Scene {
    let mut b = SceneBuilder::new("sample");
    let white = b
        .material("white", Rgb::new(0.725, 0.71, 0.68), Rgb::ZERO)
        .unwrap();
    let odd = b
        .material("odd", Rgb::new(1.0 / 3.0, 0.1, 0.0), Rgb::ZERO)
        .unwrap();
    let lamp = b
        .material(
            "lamp",
            Rgb::splat(0.78),
            Rgb::new(1e6 / 49.0, 2.5, 1.0 / 7.0),
        )
        .unwrap();
    let dim = b
        .material("dim", Rgb::splat(0.5), Rgb::new(0.3, 0.2, 0.1))
        .unwrap();
    b.object("room");
    b.quad(
        white,
        v(0.0, 0.0, 0.0),
        v(3.1, 0.0, 0.0),
        v(3.1, 0.0, -2.7),
        v(0.0, 0.0, -2.7),
    )
    .unwrap();
    b.triangle(odd, v(0.0, 0.0, 0.0), v(0.0, 2.2, 0.0), v(0.1, 0.3, 1.7))
        .unwrap();
    b.quad(
        white,
        v(0.0, 2.4, 0.0),
        v(0.0, 2.4, -2.7),
        v(3.1, 2.4, -2.7),
        v(3.1, 2.4, 0.0),
    )
    .unwrap();
    b.object("lamp");
    b.quad(
        lamp,
        v(1.0, 2.3, -1.0),
        v(1.0, 2.3, -1.5),
        v(1.3, 2.3, -1.5),
        v(1.3, 2.3, -1.0),
    )
    .unwrap();
    b.object("glow");
    b.triangle(dim, v(0.5, 0.5, 0.5), v(0.7, 0.5, 0.5), v(0.5, 0.9, 0.6))
        .unwrap();
    b.axis_box("box", odd, v(0.2, 0.0, -0.9), v(0.8, 0.61, -0.3))
        .unwrap();
    b.camera(Camera::look_at(
        v(1.5, 1.2, 3.0),
        v(1.4, 1.0, -1.0),
        DVec3::Y,
        50.0,
    ));
    let mut tilted = Camera::look_at(v(-1.0, 3.0, 0.5), v(2.0, 0.0, -2.0), v(0.3, 1.0, 0.0), 33.3);
    tilted.name = "tilted".to_string();
    tilted.aspect = Some(16.0 / 9.0);
    b.camera(tilted);
    b.build().unwrap()
}

/// Relative difference of two emissions, band by band.
fn relative_gap(a: Rgb, b: Rgb) -> f64 {
    (0..3)
        .map(|k| (a[k] - b[k]).abs() / a[k].abs().max(1e-300))
        .fold(0.0, f64::max)
}

/// The surfaces in the order a written file holds them: by object, then by the
/// material's first use within the object, then in their original order.
fn file_order(scene: &Scene) -> Vec<&Surface> {
    let mut keyed: Vec<(u32, usize, &Surface)> = scene
        .surfaces
        .iter()
        .map(|s| {
            let first_use = scene
                .surfaces
                .iter()
                .position(|t| t.object == s.object && t.material == s.material)
                .unwrap();
            (s.object, first_use, s)
        })
        .collect();
    keyed.sort_by_key(|&(object, first_use, _)| (object, first_use));
    keyed.into_iter().map(|(_, _, s)| s).collect()
}

/// Checks that `back` is `original` within single precision for positions and
/// exactly (or to the last bit of pi) for materials and cameras.
fn assert_same_scene(original: &Scene, back: &Scene, position_tolerance: f64) {
    assert_eq!(back.surfaces.len(), original.surfaces.len());
    for (k, (a, b)) in file_order(original)
        .into_iter()
        .zip(&back.surfaces)
        .enumerate()
    {
        assert_eq!(a.vertices.len(), b.vertices.len(), "surface {k}");
        for (p, q) in a.vertices.iter().zip(&b.vertices) {
            assert!(
                (*p - *q).abs().max_element() <= position_tolerance,
                "surface {k}: {p} vs {q}"
            );
        }
        // Moving every vertex by at most the position tolerance changes the
        // area by at most about the perimeter times it (which matters for thin
        // faces such as the edges of a board).
        let perimeter: f64 = (0..a.vertices.len())
            .map(|i| (a.vertices[(i + 1) % a.vertices.len()] - a.vertices[i]).length())
            .sum();
        assert!(
            (a.area - b.area).abs() <= (1e-6 * a.area).max(perimeter * position_tolerance),
            "surface {k} area {} vs {}",
            a.area,
            b.area
        );
        // Likewise the normal turns by at most about twice the tolerance over
        // the shortest edge.
        let shortest = (0..a.vertices.len())
            .map(|i| (a.vertices[(i + 1) % a.vertices.len()] - a.vertices[i]).length())
            .fold(f64::INFINITY, f64::min);
        assert!(
            (a.normal - b.normal).length() < 1e-6f64.max(2.0 * position_tolerance / shortest),
            "surface {k} normal"
        );
        assert_eq!(a.material, b.material, "surface {k}");
        assert_eq!(a.object, b.object, "surface {k}");
    }
    let names = |s: &Scene| s.objects.iter().map(|o| o.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(back), names(original));
    assert_eq!(back.materials.len(), original.materials.len());
    for (a, b) in original.materials.iter().zip(&back.materials) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.reflectance, b.reflectance, "{}", a.name);
        // The file stores the radiance E / pi exactly; E = pi L may differ in the last bit.
        assert!(
            relative_gap(a.emission, b.emission) <= 4.0 * f64::EPSILON,
            "{}: {:?} vs {:?}",
            a.name,
            a.emission,
            b.emission
        );
        assert_eq!(
            a.emission / std::f64::consts::PI,
            b.emission / std::f64::consts::PI
        );
    }
    assert_eq!(back.cameras.len(), original.cameras.len());
    for (a, b) in original.cameras.iter().zip(&back.cameras) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.position, b.position);
        assert!(
            (a.forward - b.forward).length() < 1e-14,
            "{}: {} vs {}",
            a.name,
            a.forward,
            b.forward
        );
        assert!(
            (a.up - b.up).length() < 1e-14,
            "{}: {} vs {}",
            a.name,
            a.up,
            b.up
        );
        assert_eq!(a.yfov, b.yfov);
        assert_eq!(a.aspect, b.aspect);
    }
}

#[test]
fn gltf_and_glb_round_trips_keep_geometry_materials_objects_and_cameras() {
    let scene = sample_scene();
    for file in ["sample.gltf", "sample.glb"] {
        let path = dir().join(file);
        write_scene(&scene, &path).unwrap();
        let back = load_scene(&path, &ImportLimits::default()).unwrap();
        assert_eq!(back.name, "sample");
        // Coordinates below 4 m in f32: half an ulp is under 2.4e-7.
        assert_same_scene(&scene, &back, 2.4e-7);
        let quads = scene.surfaces.iter().filter(|s| s.is_quad()).count();
        assert_eq!(back.import_stats.merged_quads, quads);
        assert_eq!(back.import_stats.degenerate_triangles, 0);
        assert!(back.warnings.is_empty(), "{:?}", back.warnings);
    }
}

#[test]
fn the_written_file_is_valid_gltf_with_bounds_and_bounded_emissive_factors() {
    let scene = sample_scene();
    let path = dir().join("structure.gltf");
    write_scene(&scene, &path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    // The gltf crate's own validator accepts it.
    gltf::Gltf::from_slice(&bytes).expect("valid glTF");
    let json: Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(json["asset"]["version"], "2.0");
    assert_eq!(json["buffers"].as_array().unwrap().len(), 1);
    assert!(json["buffers"][0]["uri"]
        .as_str()
        .unwrap()
        .starts_with("data:application/octet-stream;base64,"));
    assert!(json["extensionsUsed"]
        .as_array()
        .unwrap()
        .iter()
        .any(|e| e == "KHR_materials_emissive_strength"));
    for m in json["materials"].as_array().unwrap() {
        assert_eq!(m["doubleSided"], false);
        for f in m["emissiveFactor"].as_array().unwrap() {
            let f = f.as_f64().unwrap();
            assert!((0.0..=1.0).contains(&f), "{m}");
        }
    }
    // One primitive per material used by each object.
    let room = json["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == "room")
        .unwrap();
    assert_eq!(room["primitives"].as_array().unwrap().len(), 2);
    for mesh in json["meshes"].as_array().unwrap() {
        for prim in mesh["primitives"].as_array().unwrap() {
            let acc = &json["accessors"][prim["attributes"]["POSITION"].as_u64().unwrap() as usize];
            assert_eq!(acc["min"].as_array().unwrap().len(), 3);
            assert_eq!(acc["max"].as_array().unwrap().len(), 3);
        }
    }
    // An independent reader (the gltf crate's importer) sees every triangle.
    let (document, buffers, _) = gltf::import(&path).unwrap();
    let mut triangles = 0;
    for mesh in document.meshes() {
        for prim in mesh.primitives() {
            let reader = prim.reader(|b| Some(&buffers[b.index()]));
            triangles += reader.read_indices().unwrap().into_u32().count() / 3;
        }
    }
    let expected: usize = scene.surfaces.iter().map(|s| s.vertices.len() - 2).sum();
    assert_eq!(triangles, expected);
}

#[test]
fn unwritable_scenes_and_names_are_output_errors() {
    let scene = sample_scene();
    let e = write_scene(&scene, &dir().join("scene.obj")).unwrap_err();
    assert!(matches!(e, Error::Output { .. }), "{e}");
    let mut broken = scene.clone();
    broken.surfaces[0].object = 99;
    let e = write_scene(&broken, &dir().join("broken.gltf")).unwrap_err();
    assert!(e.to_string().contains("object 99"), "{e}");
    let mut huge = scene;
    huge.surfaces[0].vertices[0].x = 1e300;
    assert!(matches!(
        write_scene(&huge, &dir().join("huge.glb")),
        Err(Error::Output { .. })
    ));
}

#[test]
fn built_in_scenes_are_listed_by_name() {
    let expected: Vec<&str> = std::iter::once("cornell_box")
        .chain(scenes::penumbra::VARIANTS.iter().map(|(name, _)| *name))
        .chain(std::iter::once("ferren_sculpture"))
        .chain(["many_boxes", "atrium"])
        .collect();
    assert_eq!(scenes::NAMES, expected);
    for name in scenes::NAMES {
        let scene = scenes::by_name(name).expect("listed scenes exist");
        assert_eq!(&scene.name, name);
    }
    assert!(scenes::by_name("no_such_scene").is_none());
}

/// The scene files committed under `scenes/`, one per built-in scene (the
/// Cornell box, every penumbra variant and the Ferren sculpture), are what the
/// builders make, within
/// single precision. With `RADIOSITY_WRITE_SCENES=1` they are rewritten first.
/// The scale scenes `many_boxes` and `atrium` are built in code only (2 000
/// and 6 000 surfaces: too big to ship, and CI bakes every file of `scenes/`).
#[test]
fn scenes_on_disk_match_builders() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let rewrite = std::env::var("RADIOSITY_WRITE_SCENES").is_ok_and(|v| v == "1");
    for name in scenes::NAMES
        .iter()
        .filter(|n| !["many_boxes", "atrium"].contains(n))
    {
        let built = scenes::by_name(name).unwrap();
        let path = folder.join(format!("{name}.gltf"));
        if rewrite {
            std::fs::create_dir_all(&folder).unwrap();
            write_scene(&built, &path).unwrap();
        }
        let on_disk = load_scene(&path, &ImportLimits::default()).unwrap_or_else(|e| {
            panic!("{e} (regenerate with RADIOSITY_WRITE_SCENES=1 cargo test --test gltf_export)")
        });
        assert_eq!(on_disk.name, *name);
        // Positions are stored in f32: half an ulp of x is at most |x| * 2^-24
        // (6e-8 per metre of the largest coordinate, and never less than for 1 m).
        let largest = built
            .surfaces
            .iter()
            .flat_map(|s| s.vertices.iter())
            .map(|v| v.abs().max_element())
            .fold(1.0, f64::max);
        assert_same_scene(&built, &on_disk, largest * 2f64.powi(-24));
    }
}
