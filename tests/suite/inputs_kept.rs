//! No command writes over one of its inputs (issue 48, item 4): the scene
//! file, its buffers, a points file, a reference or an image named as an
//! output, by the same name or another, is refused before any work and
//! left as it was.

use super::cli_run::{fresh_folder, radiosity, stderr};
use super::common::lamp_room;
use radiosity::math::Rgb;
use std::path::{Path, PathBuf};
use std::process::Command;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The lamp room as glTF at `path`.
fn room(path: &Path) {
    let scene = lamp_room("room", Rgb::splat(0.7)).build().unwrap();
    radiosity::gltf_io::write_scene(&scene, path).unwrap();
}

/// Runs the binary in `dir`; asserts that it refused, saying the output is
/// an input, and that every file of `kept` is unchanged.
fn assert_refused_keeping(dir: &Path, args: &[&str], kept: &[PathBuf]) {
    let before: Vec<Vec<u8>> = kept.iter().map(|p| std::fs::read(p).unwrap()).collect();
    let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {text}");
    assert!(
        text.contains("is an input of this command"),
        "{args:?}: {text}"
    );
    for (p, bytes) in kept.iter().zip(before) {
        assert!(
            std::fs::read(p).unwrap() == bytes,
            "{args:?} changed {}",
            p.display()
        );
    }
}

#[test]
fn a_scene_saved_as_json_is_not_overwritten_by_its_stats() {
    let dir = fresh_folder("inputs_kept", "json_scene");
    let gltf = dir.join("room.gltf");
    room(&gltf);
    // A glTF saved as .json: solving it into its own folder would write
    // scene.json, its stats, over it.
    let scene = dir.join("scene.json");
    std::fs::rename(&gltf, &scene).unwrap();
    assert_refused_keeping(
        &dir,
        &["solve", "scene.json", "--out", ".", "--quiet"],
        &[scene],
    );
}

#[test]
fn outputs_named_after_an_input_by_any_path_are_refused() {
    let dir = fresh_folder("inputs_kept", "named");
    let scene = dir.join("m.gltf");
    room(&scene);
    let points = dir.join("p.csv");
    std::fs::write(&points, "0.5,0,0.5,0,1,0\n").unwrap();
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    let kept = [scene.clone(), points.clone()];
    let cases: [&[&str]; 5] = [
        &[
            "solve",
            "m.gltf",
            "--mesh-out",
            "m.gltf",
            "--out",
            "out",
            "--quiet",
        ],
        &[
            "solve",
            "m.gltf",
            "--mesh-out",
            "sub/../m.gltf",
            "--out",
            "out",
            "--quiet",
        ],
        &["reference", "m.gltf", "--paths", "10", "-o", "m.gltf"],
        &[
            "probe", "m.gltf", "--points", "p.csv", "-o", "p.csv", "--quiet",
        ],
        &["bake", "m.gltf", "-o", "./m.gltf", "--quiet"],
    ];
    for args in cases {
        assert_refused_keeping(&dir, args, &kept);
    }
}

#[cfg(unix)]
#[test]
fn another_name_of_an_input_and_its_images_are_refused_too() {
    let dir = fresh_folder("inputs_kept", "other_names");
    let scene = dir.join("m.gltf");
    room(&scene);
    // A hard link is the same file under another name.
    std::fs::hard_link(&scene, dir.join("alias.json")).unwrap();
    assert_refused_keeping(
        &dir,
        &["reference", "m.gltf", "--paths", "10", "-o", "alias.json"],
        std::slice::from_ref(&scene),
    );
    // diff's inputs: its output over one of its images.
    let out = radiosity(&[
        "solve",
        "cornell_box",
        "--out",
        s(&dir.join("img")),
        "--quiet",
        "--width",
        "16",
        "--height",
        "12",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let exr = dir.join("img").join("cornell_box.exr");
    assert_refused_keeping(
        &dir,
        &["diff", s(&exr), s(&exr), "-o", s(&exr)],
        std::slice::from_ref(&exr),
    );
}
