//! Outputs under faults (issue 19, defect 2): every file is written to a
//! temporary beside its target and renamed into place, so a write that fails
//! part way leaves the previous file as it was, and a set of files staged
//! together replaces its targets together or not at all. The library's
//! writers cut off part way through a file (RLIMIT_FSIZE) are tested through
//! the binary in `hostile_cli`.

use radiosity::output::{write_file, Outputs};
use radiosity::render::{write_exr, write_png, HdrImage, ToneMap};
use radiosity::Error;
use std::path::{Path, PathBuf};

/// A fresh, empty folder for one test.
fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("hostile_outputs")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The names in `dir`, sorted (temporaries would show up here).
fn names(dir: &Path) -> Vec<String> {
    let mut n: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    n.sort();
    n
}

#[test]
fn a_writer_failing_part_way_leaves_the_old_file_intact() {
    let dir = folder("part_way");
    let path = dir.join("result.json");
    std::fs::write(&path, b"the previous run").unwrap();
    let e = write_file(&path, |w| {
        w.write_all(b"half of the new ").unwrap();
        Err(Error::Output {
            path: path.clone(),
            message: "the encoder gave up".to_string(),
        })
    })
    .unwrap_err();
    assert!(e.to_string().contains("gave up"), "{e}");
    assert_eq!(std::fs::read(&path).unwrap(), b"the previous run");
    assert_eq!(names(&dir), ["result.json"], "a temporary was left behind");
}

#[test]
fn a_staged_set_replaces_nothing_until_it_is_committed() {
    let dir = folder("together");
    let (a, b) = (dir.join("a.txt"), dir.join("b.txt"));
    std::fs::write(&a, b"old a").unwrap();
    let mut outputs = Outputs::new();
    outputs.stage_bytes(&a, b"new a").unwrap();
    outputs.stage_bytes(&b, b"new b").unwrap();
    assert_eq!(std::fs::read(&a).unwrap(), b"old a");
    assert!(!b.exists());
    let written = outputs.commit().unwrap();
    assert_eq!(written, [a.clone(), b.clone()]);
    assert_eq!(std::fs::read(&a).unwrap(), b"new a");
    assert_eq!(std::fs::read(&b).unwrap(), b"new b");
    assert_eq!(names(&dir), ["a.txt", "b.txt"]);
}

#[test]
fn a_failure_in_one_file_of_a_set_leaves_every_target_unchanged() {
    let dir = folder("all_or_none");
    let (image, stats) = (dir.join("view.exr"), dir.join("view.json"));
    std::fs::write(&image, b"old image").unwrap();
    std::fs::write(&stats, b"old stats").unwrap();
    // A folder where the second file should go fails the set at staging.
    let blocked = dir.join("view.png");
    std::fs::create_dir(&blocked).unwrap();
    {
        let mut outputs = Outputs::new();
        outputs.stage_bytes(&image, b"new image").unwrap();
        outputs.stage_bytes(&stats, b"new stats").unwrap();
        let e = outputs.stage_bytes(&blocked, b"new png").unwrap_err();
        assert!(e.to_string().contains("folder"), "{e}");
        // Dropped without a commit.
    }
    assert_eq!(std::fs::read(&image).unwrap(), b"old image");
    assert_eq!(std::fs::read(&stats).unwrap(), b"old stats");
    assert!(blocked.is_dir());
    assert_eq!(names(&dir), ["view.exr", "view.json", "view.png"]);
}

#[test]
fn a_target_that_became_a_folder_fails_the_commit_before_anything_is_replaced() {
    let dir = folder("commit_check");
    let (first, second) = (dir.join("first.txt"), dir.join("second.txt"));
    std::fs::write(&first, b"old first").unwrap();
    let mut outputs = Outputs::new();
    outputs.stage_bytes(&first, b"new first").unwrap();
    outputs.stage_bytes(&second, b"new second").unwrap();
    std::fs::create_dir(&second).unwrap();
    assert!(outputs.commit().is_err());
    assert_eq!(std::fs::read(&first).unwrap(), b"old first");
    assert_eq!(names(&dir), ["first.txt", "second.txt"]);
}

#[test]
fn the_same_target_twice_in_one_set_is_an_error() {
    let dir = folder("twice");
    let path = dir.join("x.png");
    let mut outputs = Outputs::new();
    outputs.stage_bytes(&path, b"one").unwrap();
    let e = outputs.stage_bytes(&path, b"two").unwrap_err();
    assert!(e.to_string().contains("twice"), "{e}");
}

#[test]
fn library_image_writers_keep_the_old_file_when_they_fail() {
    let dir = folder("images");
    let path = dir.join("frame.exr");
    std::fs::write(&path, b"previous frame").unwrap();
    // An image with no pixels cannot be encoded.
    let e = write_exr(&HdrImage::new(0, 4), &path).unwrap_err();
    assert!(matches!(e, Error::Output { .. }), "{e}");
    assert_eq!(std::fs::read(&path).unwrap(), b"previous frame");
    let folder_target = dir.join("frame.png");
    std::fs::create_dir(&folder_target).unwrap();
    let e = write_png(&HdrImage::new(4, 4), &folder_target, 0.0, ToneMap::Clamp).unwrap_err();
    assert!(e.to_string().contains("folder"), "{e}");
    assert!(folder_target.is_dir());
    assert_eq!(names(&dir), ["frame.exr", "frame.png"]);
    // And a good write replaces the file.
    write_exr(&HdrImage::new(4, 4), &path).unwrap();
    assert_ne!(std::fs::read(&path).unwrap(), b"previous frame");
}

#[cfg(unix)]
#[test]
fn a_symbolic_link_keeps_pointing_at_the_rewritten_file() {
    let dir = folder("link");
    let real = dir.join("real.txt");
    let link = dir.join("link.txt");
    std::fs::write(&real, b"old").unwrap();
    std::os::unix::fs::symlink(&real, &link).unwrap();
    radiosity::output::write_bytes(&link, b"new").unwrap();
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(std::fs::read(&real).unwrap(), b"new");
}

#[test]
fn an_io_error_states_the_operating_systems_reason_once() {
    let missing = Path::new(env!("CARGO_TARGET_TMPDIR")).join("no such folder/x.exr");
    let e = radiosity::render::read_hdr_image(&missing).unwrap_err();
    // The whole chain, as the command-line tool prints it.
    let chain = format!("{:#}", anyhow::Error::from(e));
    assert_eq!(chain.matches("os error").count(), 1, "{chain}");
}
