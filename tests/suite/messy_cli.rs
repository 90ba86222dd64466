//! Messy real files through the command-line tool (issue 17): overlaps
//! resolved or refused, a scene without light refused at load, load options
//! checked before loading, progress as plain lines when standard error is not
//! a terminal. Fixtures are built in code and written as glTF.

use super::cli_run::{fresh_folder, radiosity, stderr};
use super::stress_scenes::{downward_quad, room, v};
use radiosity::math::Rgb;
use radiosity::scene::{Scene, SceneBuilder};
use std::path::{Path, PathBuf};

/// Settings that make a small room solve take well under a second.
const QUICK: [&str; 8] = [
    "--hemicube-res",
    "16",
    "--max-depth",
    "1",
    "--patch-size",
    "0.5",
    "--initial-depth",
    "0",
];

/// A fresh, empty folder for one test.
fn folder(name: &str) -> PathBuf {
    fresh_folder("messy_cli", name)
}

/// A grey room, with a light flush with its ceiling when `lit` (left as an
/// overlap: the CLI's importer must deal with it).
fn room_scene(lit: bool) -> Scene {
    let mut b = SceneBuilder::new("room");
    b.overlaps(None);
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(2.0, 1.6, 2.4), grey, grey, grey);
    if lit {
        let light = b.material("lamp", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
        b.object("light");
        downward_quad(&mut b, light, 1.6, (0.7, 1.3), (0.9, 1.5));
    }
    b.build().unwrap()
}

fn written(dir: &Path, scene: &Scene, name: &str) -> PathBuf {
    let path = dir.join(name);
    radiosity::gltf_io::write_scene(scene, &path).unwrap();
    path
}

#[test]
fn a_file_without_light_is_refused_at_load_saying_why() {
    let dir = folder("dark");
    let file = written(&dir, &room_scene(false), "dark.gltf");
    let out_dir = dir.join("out");
    let out = radiosity(&[
        "solve",
        file.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(
        text.contains("has no light") && text.contains("emissiveFactor"),
        "{text}"
    );
    // It names the daylight options as the CLI spells them.
    assert!(text.contains("daylight (--sky, --sun)"), "{text}");
    // Refused before the solve: no progress, no outputs.
    assert!(!text.contains("progress:"), "{text}");
    assert_eq!(std::fs::read_dir(&out_dir).map_or(0, |d| d.count()), 0);
}

#[test]
fn a_light_flush_with_the_ceiling_is_resolved_or_refused_by_option() {
    let dir = folder("flush");
    let file = written(&dir, &room_scene(true), "flush.gltf");
    let out_dir = dir.join("out");
    let mut args = vec![
        "solve",
        file.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ];
    args.extend(QUICK);
    let out = radiosity(&[args.as_slice(), &["--overlaps", "error"]].concat());
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(
        text.contains("'light' and 'ceiling'") && text.contains("flush.gltf"),
        "{text}"
    );
    // Resolved by default: the room is lit, the warning says what was done.
    let out = radiosity(&[args.as_slice(), &["--quiet"]].concat());
    let text = stderr(&out);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("warning: 1 pairs") && text.contains("'light' over 'ceiling'"),
        "{text}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out_dir.join("flush.json")).unwrap()).unwrap();
    let floor = json["surfaces"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["name"] == "floor")
        .unwrap();
    assert!(floor["radiosity"][0].as_f64().unwrap() > 0.1, "{floor}");
    assert_eq!(json["import"]["overlapping_pairs"], 1);
}

#[test]
fn load_options_out_of_range_are_refused_before_loading() {
    for (flag, value) in [
        ("--max-reflectance", "1.0"),
        ("--max-reflectance", "nan"),
        ("--overlaps", "ignore"),
    ] {
        let out = radiosity(&["solve", "no_such_scene.gltf", flag, value]);
        let text = stderr(&out);
        assert_ne!(out.status.code(), Some(0), "{text}");
        assert!(
            !text.contains("no_such_scene"),
            "{flag} {value} checked after loading: {text}"
        );
    }
}

#[test]
fn progress_is_plain_lines_when_standard_error_is_not_a_terminal_and_quiet_silences_it() {
    let dir = folder("progress");
    let out_dir = dir.join("out");
    let mut args = vec!["solve", "cornell_box", "--out", out_dir.to_str().unwrap()];
    args.extend(QUICK);
    let out = radiosity(&args);
    let text = stderr(&out);
    assert!(out.status.success(), "{text}");
    let first = text.lines().next().unwrap_or("");
    assert!(first.starts_with("progress: form factors 0/"), "{text}");
    // No terminal control sequences (a bar redraws with carriage returns).
    assert!(!text.contains('\r') && !text.contains('\u{1b}'), "{text:?}");
    let quiet = radiosity(&[args.as_slice(), &["--quiet"]].concat());
    assert!(quiet.status.success());
    assert_eq!(stderr(&quiet), "");
}
