//! Nothing silently wrong (issue 48, items 3 and 5 to 8): each case that
//! used to end in exit 0 with a black, white or infinite picture, a dropped
//! row or a default taken for a typo now ends in a clear error or a warning
//! that names the light, field, file or figure.

use super::cli_run::{fresh_folder, radiosity, stderr};
use super::common::lamp_room;
use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::refine::RefineSettings;
use radiosity::render::{read_hdr_image, write_exr, HdrImage};
use radiosity::scene::{Light, Scene};
use radiosity::{Error, Settings};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn quick() -> Settings {
    Settings {
        hemicube_resolution: 16,
        patch_size: Some(0.5),
        refine: RefineSettings {
            max_depth: 1,
            initial_depth: 0,
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

const QUICK: [&str; 10] = [
    "--hemicube-res",
    "16",
    "--max-depth",
    "1",
    "--initial-depth",
    "0",
    "--threads",
    "1",
    "--patch-size",
    "0.5",
];

fn warnings_of(scene: &Scene) -> Vec<String> {
    radiosity::solve(scene, &quick(), &|_| {})
        .unwrap()
        .stats()
        .warnings
        .clone()
}

#[test]
fn a_light_shut_in_a_closed_box_is_named_and_a_free_one_is_not() {
    let mut b = lamp_room("shut_in", Rgb::splat(0.7));
    let grey = b.material("box", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    // Outward faces all round, clear of the floor: nothing inside can
    // reach a front.
    let (lo, hi) = (DVec3::new(0.3, 0.2, 0.3), DVec3::new(0.9, 0.8, 0.9));
    b.axis_box("crate", grey, lo, hi).unwrap();
    b.light(Light::point("trapped", (lo + hi) / 2.0, Rgb::ONE, 50.0))
        .unwrap();
    b.light(Light::point(
        "free",
        DVec3::new(1.5, 1.5, 1.5),
        Rgb::ONE,
        5.0,
    ))
    .unwrap();
    let w = warnings_of(&b.build().unwrap()).join("\n");
    assert!(w.contains("'trapped' reaches no surface's front"), "{w}");
    assert!(!w.contains("'free'"), "{w}");
}

#[test]
fn a_sun_over_a_closed_room_is_named() {
    let mut b = lamp_room("sun_over_roof", Rgb::splat(0.7));
    b.light(Light::directional(
        "noon",
        DVec3::new(0.2, -1.0, 0.1),
        Rgb::ONE,
        1000.0,
    ))
    .unwrap();
    let w = warnings_of(&b.build().unwrap()).join("\n");
    assert!(
        w.contains("'noon' reaches no surface's front") && w.contains("sun"),
        "{w}"
    );
}

/// The lamp room written as glTF, its lamp's emission replaced by a
/// punctual light defined by `light` (a JSON object) at the room's centre.
fn room_with_light(dir: &Path, name: &str, light: Value) -> PathBuf {
    let scene = lamp_room(name, Rgb::splat(0.7)).build().unwrap();
    let path = dir.join(format!("{name}.gltf"));
    radiosity::gltf_io::write_scene(&scene, &path).unwrap();
    let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for m in doc["materials"].as_array_mut().unwrap() {
        m.as_object_mut().unwrap().remove("emissiveFactor");
        m.as_object_mut().unwrap().remove("extensions");
    }
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [light]}});
    let nodes = doc["nodes"].as_array_mut().unwrap();
    nodes.push(json!({
        "name": "holder",
        "translation": [1.0, 1.0, 1.0],
        "extensions": {"KHR_lights_punctual": {"light": 0}}
    }));
    let holder = nodes.len() - 1;
    doc["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!(holder));
    std::fs::write(&path, doc.to_string()).unwrap();
    path
}

#[test]
fn wrongly_typed_or_unrepresentable_light_fields_are_errors_naming_light_and_field() {
    let dir = fresh_folder("silent_faults", "light_fields");
    let cases = [
        (
            json!({"name": "a", "type": "point", "intensity": "1000"}),
            "\"intensity\"",
        ),
        (
            json!({"name": "b", "type": "point", "range": "0.01"}),
            "\"range\"",
        ),
        (
            json!({"name": "c", "type": "point", "color": "red"}),
            "\"color\"",
        ),
        (
            json!({"name": "d", "type": "spot", "spot": {"outerConeAngle": "0.5"}}),
            "\"spot.outerConeAngle\"",
        ),
        (json!({"name": "e", "type": 3}), "\"type\""),
        (
            json!({"name": "f", "type": "point", "intensity": 1e-310}),
            "smallest normal",
        ),
        (
            json!({"name": "g", "type": "point", "intensity": 1e300}),
            "single-precision",
        ),
    ];
    for (k, (light, field)) in cases.into_iter().enumerate() {
        let name = light["name"].as_str().unwrap().to_string();
        let path = room_with_light(&dir, &format!("case{k}"), light);
        let e = radiosity::gltf_io::load_scene(&path, &Default::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("('{name}')")) && e.contains(field),
            "{field}: {e}"
        );
    }
    // The same light well typed loads and lights the room.
    let path = room_with_light(
        &dir,
        "good",
        json!({"name": "ok", "type": "point", "intensity": 1000}),
    );
    let scene = radiosity::gltf_io::load_scene(&path, &Default::default()).unwrap();
    assert_eq!(scene.lights.len(), 1);
    assert_eq!(scene.lights[0].intensity, 1000.0);
}

#[test]
fn a_light_of_an_unknown_type_is_named_when_the_scene_is_refused_for_darkness() {
    let dir = fresh_folder("silent_faults", "unknown_type");
    let path = room_with_light(
        &dir,
        "area",
        json!({"name": "panel", "type": "area", "intensity": 10}),
    );
    let out = radiosity(&["solve", s(&path), "--out", s(&dir.join("out")), "--quiet"]);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(
        text.contains("'panel'") && text.contains("type 'area'"),
        "{text}"
    );
    assert!(text.contains("has no light"), "{text}");
}

#[test]
fn coincident_lights_are_merged_into_one_of_their_summed_power() {
    let dir = fresh_folder("silent_faults", "coincident");
    let one = room_with_light(&dir, "one", json!({"type": "point", "intensity": 500.0}));
    let path = room_with_light(&dir, "many", json!({"type": "point", "intensity": 0.5}));
    let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let nodes = doc["nodes"].as_array_mut().unwrap();
    let holder = nodes.last().unwrap().clone();
    let first = nodes.len();
    nodes.extend(std::iter::repeat_n(holder, 999));
    let added: Vec<usize> = (first..first + 999).collect();
    doc["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .extend(added.iter().map(|i| json!(i)));
    std::fs::write(&path, doc.to_string()).unwrap();
    let many = radiosity::gltf_io::load_scene(&path, &Default::default()).unwrap();
    assert_eq!(many.lights.len(), 1);
    assert!(many
        .warnings
        .iter()
        .any(|w| w.contains("999") && w.contains("merged")));
    let single = radiosity::gltf_io::load_scene(&one, &Default::default()).unwrap();
    // A thousand lights of 0.5 cd are one of 500 cd (to rounding).
    let (a, b) = (many.lights[0].intensity, single.lights[0].intensity);
    assert!((a - b).abs() <= 1e-12 * b, "{a} vs {b}");
    assert_eq!(many.lights[0].position, single.lights[0].position);
}

#[test]
fn pixels_beyond_single_precision_refuse_the_image_naming_it() {
    let dir = fresh_folder("silent_faults", "f32");
    let path = dir.join("bright.exr");
    std::fs::write(&path, b"previous").unwrap();
    let mut img = HdrImage::new(3, 2);
    img.set(2, 1, Rgb::new(1.0, 5e38, 1.0));
    let e = write_exr(&img, &path).unwrap_err();
    assert!(matches!(e, Error::Output { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("bright.exr") && text.contains("pixel (2, 1)"),
        "{text}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), b"previous");
}

/// The mean of an EXR's pixels, and the share of them that are lit.
fn lit(path: &Path) -> (f64, f64) {
    let img = read_hdr_image(path).unwrap();
    let n = img.pixels.len() as f64;
    let mean = img.pixels.iter().map(|p| p.luminance()).sum::<f64>() / n;
    let lit = img.pixels.iter().filter(|p| p.max_band() > 0.0).count() as f64 / n;
    (mean, lit)
}

#[test]
fn a_bake_without_a_camera_renders_from_the_default_framing_not_black() {
    let dir = fresh_folder("silent_faults", "no_camera");
    let scene = lamp_room("room", Rgb::splat(0.7)).build().unwrap();
    assert!(scene.cameras.is_empty());
    let path = dir.join("room.gltf");
    radiosity::gltf_io::write_scene(&scene, &path).unwrap();
    // `bake` writes a default view into the file; a bake from elsewhere (or
    // an older one) may carry none, so the cameras are taken out again.
    let baked = dir.join("baked.gltf");
    let mut bake = vec!["bake", s(&path), "-o", s(&baked), "--quiet"];
    bake.extend(QUICK);
    let out = radiosity(&bake);
    assert!(out.status.success(), "{}", stderr(&out));
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&baked).unwrap()).unwrap();
    let root = json.as_object_mut().unwrap();
    assert!(root.remove("cameras").is_some(), "the bake wrote no camera");
    for node in root["nodes"].as_array_mut().unwrap() {
        node.as_object_mut().unwrap().remove("camera");
    }
    std::fs::write(&baked, serde_json::to_string(&json).unwrap()).unwrap();
    let out_dir = dir.join("out");
    let out = radiosity(&[
        "render",
        s(&baked),
        "--out",
        s(&out_dir),
        "--width",
        "40",
        "--height",
        "30",
    ]);
    let text = stderr(&out);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("has no camera"), "{text}");
    // From inside the closed room every pixel shows a lit wall.
    let (mean, share) = lit(&out_dir.join("baked.exr"));
    assert!(mean > 0.0 && share > 0.99, "mean {mean}, lit {share}");
}

#[test]
fn a_black_view_is_a_warning_saying_why() {
    let dir = fresh_folder("silent_faults", "black_view");
    // From outside the closed room, looking away from it.
    let mut args = vec!["solve", "cornell_box", "--out", s(&dir), "--quiet"];
    args.extend([
        "--camera",
        "0.3,0.3,5,0.3,0.3,10,40",
        "--width",
        "24",
        "--height",
        "16",
    ]);
    args.extend(QUICK);
    let out = radiosity(&args);
    let text = stderr(&out);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("the picture is black: the camera sees no surface"),
        "{text}"
    );
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("cornell_box.json")).unwrap())
            .unwrap();
    let listed = json["warnings"].to_string();
    assert!(listed.contains("the picture is black"), "{listed}");
}

#[test]
fn compare_refuses_another_scene_and_subnormal_references() {
    let dir = fresh_folder("silent_faults", "compare");
    let table = |scene: &str, area: f64, value: f64| {
        json!({"scene": scene, "surfaces": [
            {"name": "floor", "area": area, "radiosity": [value, 1.0, 1.0]},
            {"name": "wall", "area": 2.0, "radiosity": [1.0, 1.0, 1.0]}
        ]})
        .to_string()
    };
    let write = |name: &str, text: String| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let solution = write("solution.json", table("room", 4.0, 1.0));
    let same = write("same.json", table("room", 4.0, 1.1));
    let out = radiosity(&["compare", s(&solution), s(&same)]);
    assert!(out.status.success(), "{}", stderr(&out));
    for (file, expected) in [
        (write("other.json", table("hall", 4.0, 1.1)), "'hall'"),
        (
            write("resized.json", table("room", 9.0, 1.1)),
            "not of the same scene",
        ),
        (
            write("tiny.json", table("room", 4.0, 1e-310)),
            "smallest normal double",
        ),
    ] {
        let out = radiosity(&["compare", s(&solution), s(&file)]);
        let text = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{text}");
        assert!(text.contains(expected), "{expected}: {text}");
        assert!(!String::from_utf8_lossy(&out.stdout).contains("inf"));
    }
}

#[test]
fn diff_refuses_a_png_as_radiance() {
    let dir = fresh_folder("silent_faults", "diff_png");
    let mut args = vec!["solve", "cornell_box", "--out", s(&dir), "--quiet"];
    args.extend(["--width", "24", "--height", "16"]);
    args.extend(QUICK);
    assert!(radiosity(&args).status.success());
    let (png, exr) = (dir.join("cornell_box.png"), dir.join("cornell_box.exr"));
    let out = radiosity(&["diff", s(&png), s(&exr), "-o", s(&dir.join("d.exr"))]);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(
        text.contains("PNG") && text.contains("not linear radiance"),
        "{text}"
    );
}

#[test]
fn options_that_could_only_give_a_black_or_contradictory_solve_are_refused() {
    let cases: [(&[&str], &str); 2] = [
        (
            &["--solver", "progressive", "--time-budget", "0"],
            "--time-budget",
        ),
        (
            &["--initial-depth", "3", "--max-depth", "1"],
            "--initial-depth",
        ),
    ];
    for (extra, expected) in cases {
        let mut args = vec!["solve", "cornell_box", "--quiet", "--out", "unused"];
        args.extend(extra);
        let out = radiosity(&args);
        let text = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{extra:?}: {text}");
        assert!(text.contains(expected), "{extra:?}: {text}");
    }
}

#[test]
fn probe_takes_a_byte_order_mark_and_refuses_a_first_row_with_a_typo() {
    let dir = fresh_folder("silent_faults", "probe");
    let points = dir.join("points.csv");
    std::fs::write(&points, "\u{feff}0.3,0,0.3,0,1,0\n0.2,0,0.2,0,1,0\n").unwrap();
    let csv = dir.join("probe.csv");
    let mut args = vec![
        "probe",
        "cornell_box",
        "--points",
        s(&points),
        "-o",
        s(&csv),
        "--quiet",
    ];
    args.extend(QUICK);
    let out = radiosity(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let rows = std::fs::read_to_string(&csv).unwrap();
    // The header and both points.
    assert_eq!(rows.lines().count(), 3, "{rows}");
    std::fs::write(&points, "0.3,0,0.3x,0,1,0\n0.2,0,0.2,0,1,0\n").unwrap();
    let out = radiosity(&args);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("line 1"), "{text}");
}

#[cfg(unix)]
#[test]
fn a_buffer_linked_out_of_the_scene_folder_is_refused_for_a_scene_named_without_a_folder() {
    let dir = fresh_folder("silent_faults", "link_out");
    let outside = fresh_folder("silent_faults", "link_target");
    let scene = lamp_room("room", Rgb::splat(0.7)).build().unwrap();
    let staged = outside.join("room.gltf");
    radiosity::gltf_io::write_scene(&scene, &staged).unwrap();
    // The buffer moved out beside the target; the scene names it through a
    // link in its own folder.
    let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(&staged).unwrap()).unwrap();
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let data = uri.split_once(',').unwrap().1;
    let bytes = base64::decode(data).unwrap();
    std::fs::write(outside.join("secret.bin"), bytes).unwrap();
    std::os::unix::fs::symlink(outside.join("secret.bin"), dir.join("room.bin")).unwrap();
    doc["buffers"][0]["uri"] = json!("room.bin");
    std::fs::write(dir.join("room.gltf"), doc.to_string()).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(["solve", "room.gltf", "--out", "out", "--quiet"])
        .current_dir(&dir)
        .output()
        .unwrap();
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("symbolic link"), "{text}");
}
