//! Determinism: the same scene and seed give the same bits, run after run and
//! at any thread count, in the library and in the files the CLI writes.

use super::stress_scenes::{leaves, lit_room_with_box, quick_settings};
use radiosity::gltf_io::write_scene;
use radiosity::Solution;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn solve_with_threads(threads: usize) -> Solution {
    let scene = lit_room_with_box(1.0, 2.0, 0.01);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| radiosity::solve(&scene, &quick_settings(0.4), &|_| {}).unwrap())
}

/// Every number a solution is made of, as bits.
fn fingerprint(sol: &Solution) -> Vec<u64> {
    let mut bits = Vec::new();
    for e in leaves(sol) {
        bits.extend(e.radiosity.0.iter().map(|x| x.to_bits()));
        bits.extend(
            e.entries()
                .iter()
                .map(|&(j, f)| (u64::from(j) << 32) | u64::from(f.to_bits())),
        );
    }
    for b in sol.patch_radiosity() {
        bits.extend(b.0.iter().map(|x| x.to_bits()));
    }
    bits.push(sol.stats().total_iterations as u64);
    bits.push(sol.stats().elements as u64);
    bits
}

#[test]
fn the_library_gives_the_same_bits_at_one_and_two_threads_and_on_every_run() {
    let one = solve_with_threads(1);
    let two = solve_with_threads(2);
    let again = solve_with_threads(2);
    assert!(
        !one.stats().passes.is_empty(),
        "the test wants an adaptive solve"
    );
    let (a, b, c) = (fingerprint(&one), fingerprint(&two), fingerprint(&again));
    assert_eq!(a.len(), b.len(), "different meshes at 1 and 2 threads");
    let first_difference = a.iter().zip(&b).position(|(x, y)| x != y);
    assert_eq!(first_difference, None, "1 and 2 threads differ");
    assert_eq!(b, c, "two runs at 2 threads differ");
}

fn dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("stress_determinism");
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `radiosity solve` on `scene` with `threads` workers into `out`.
fn run_cli(scene: &Path, threads: usize, out: &Path) {
    let status = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .arg("solve")
        .arg(scene)
        .args(["--threads", &threads.to_string()])
        .args([
            "--hemicube-res",
            "32",
            "--patch-size",
            "0.5",
            "--max-depth",
            "2",
        ])
        .args(["--width", "64", "--height", "48", "--quiet"])
        .arg("--out")
        .arg(out)
        .status()
        .expect("the radiosity binary runs");
    assert!(
        status.success(),
        "radiosity solve --threads {threads} failed"
    );
}

/// The stats JSON without what may differ between runs: timings, the thread
/// count, the output paths (which name the output folder) and the process's
/// peak memory.
fn stable_json(path: &Path) -> Value {
    fn strip(v: &mut Value) {
        match v {
            Value::Object(map) => {
                for key in ["seconds", "threads", "outputs", "peak_resident_bytes"] {
                    map.remove(key);
                }
                map.values_mut().for_each(strip);
            }
            Value::Array(items) => items.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut v: Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    strip(&mut v);
    v
}

#[test]
fn the_cli_writes_the_same_files_at_one_and_two_threads() {
    let scene = dir().join("room.glb");
    write_scene(&lit_room_with_box(1.0, 2.0, 0.01), &scene).unwrap();
    let (one, two) = (dir().join("threads1"), dir().join("threads2"));
    run_cli(&scene, 1, &one);
    run_cli(&scene, 2, &two);
    for file in ["room.exr", "room.png"] {
        let (a, b) = (
            std::fs::read(one.join(file)).unwrap(),
            std::fs::read(two.join(file)).unwrap(),
        );
        assert!(a.len() > 100, "{file} is nearly empty");
        assert!(a == b, "{file} differs between 1 and 2 threads");
    }
    assert_eq!(
        stable_json(&one.join("room.json")),
        stable_json(&two.join("room.json")),
        "the stats differ beyond their timings"
    );
}
