//! The command-line tool under hostile options and faults (issue 19): options
//! are checked before any scene is loaded (defects 5, 9, 10), a failed write
//! leaves every previous output as it was (defect 2), messages state a reason
//! once, and `compare` refuses a reference that does not fit (defect 13).

use super::cli_run::{fresh_folder, radiosity, stderr};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Settings that make a Cornell box solve take well under a second.
const QUICK: [&str; 8] = [
    "--hemicube-res",
    "16",
    "--max-depth",
    "1",
    "--patch-size",
    "0.3",
    "--initial-depth",
    "0",
];

/// A fresh, empty folder for one test.
fn folder(name: &str) -> PathBuf {
    fresh_folder("hostile_cli", name)
}

/// Asserts a clean refusal: exit code 1 (not a panic's 101), no panic
/// message, and a message that says `expected`.
fn assert_refused(args: &[&str], expected: &str) -> String {
    let out = radiosity(args);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {text}");
    assert!(!text.contains("panicked"), "{args:?}: {text}");
    assert!(
        text.contains(expected),
        "{args:?}: expected '{expected}' in: {text}"
    );
    text
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every case names a scene that does not exist: if the option were checked
/// only after loading, the message would be about the scene instead.
#[test]
fn options_are_checked_before_the_scene_is_loaded() {
    let dir = folder("checks");
    let file = dir.join("a_file");
    std::fs::write(&file, b"not a folder").unwrap();
    let points = dir.join("points.csv");
    std::fs::write(&points, "0.5,0,0.5,0,1,0\n").unwrap();
    let under_file = file.join("x.glb");
    let folder_under_file = file.join("out");
    let out = dir.join("out");
    let missing = "no_such_scene";
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["solve", missing, "--width", "0"], "--width"),
        (vec!["solve", missing, "--height", "100000"], "--height"),
        (
            vec!["solve", missing, "--width", "16384", "--height", "16384"],
            "pixels",
        ),
        (vec!["solve", missing, "--threads", "100000"], "1024"),
        (
            vec!["solve", missing, "--hemicube-res", "7"],
            "--hemicube-res",
        ),
        (
            vec!["solve", missing, "--out", s(&folder_under_file)],
            "is a file",
        ),
        (vec!["bake", missing, "-o", s(&under_file)], "is a file"),
        (vec!["bake", missing, "-o", s(&dir)], ".glb or .gltf"),
        (vec!["render", missing, "--width", "0"], "--width"),
        (vec!["reference", missing, "--paths", "1"], "paths"),
        (vec!["reference", missing, "--threads", "0"], "--threads"),
        (
            vec!["converge", missing, "--repeats", "0", "--out", s(&out)],
            "--repeats",
        ),
        (
            vec!["export-scene", "cornell_box", "-o", s(&under_file)],
            "is a file",
        ),
    ];
    for (args, expected) in &cases {
        let text = assert_refused(args, expected);
        assert!(!text.contains(missing), "{args:?} loaded first: {text}");
    }
    // --time-budget beyond what a Duration holds, or not a number of seconds,
    // in every command that takes it.
    let baked = dir.join("baked.glb");
    for budget in ["1e20", "NaN", "-1", "inf"] {
        let flag = format!("--time-budget={budget}");
        let solve = ["solve", missing, &flag];
        let bake = ["bake", missing, "-o", s(&baked), &flag];
        let probe = ["probe", missing, "--points", s(&points), &flag];
        for args in [&solve[..], &bake[..], &probe[..]] {
            let text = assert_refused(args, "--time-budget");
            assert!(!text.contains(missing), "{args:?} loaded first: {text}");
        }
    }
}

#[test]
fn a_missing_input_states_the_operating_systems_reason_once() {
    let dir = folder("reason_once");
    let a = dir.join("a.exr");
    let text = assert_refused(&["diff", s(&a), s(&a)], "a.exr");
    assert_eq!(text.matches("os error").count(), 1, "{text}");
}

#[test]
fn outputs_whose_target_is_a_folder_are_refused_before_the_solve() {
    let dir = folder("folder_target");
    std::fs::create_dir_all(dir.join("cornell_box.json")).unwrap();
    let mut args = vec!["solve", "cornell_box", "--quiet", "--out", s(&dir)];
    // An impossible element budget would fail the solve itself: the output
    // check must come first.
    args.extend(["--max-elements", "1"]);
    assert_refused(&args, "cornell_box.json");
}

/// Runs the binary with writes limited to `bytes` per file: the disk-full
/// and file-size-limit case, part way through a file. SIGXFSZ keeps its
/// default action (death without a word) here: the binary itself ignores
/// it, so that the write fails with EFBIG and the run ends with a message.
#[cfg(unix)]
fn radiosity_with_file_limit(args: &[&str], bytes: u64) -> Output {
    use std::os::unix::process::CommandExt;
    let mut command = Command::new(env!("CARGO_BIN_EXE_radiosity"));
    command.args(args);
    // SAFETY: between fork and exec the closure only calls the async-signal-safe
    // functions signal(2) and setrlimit(2).
    unsafe {
        command.pre_exec(move || {
            libc::signal(libc::SIGXFSZ, libc::SIG_DFL);
            let limit = libc::rlimit {
                rlim_cur: bytes as libc::rlim_t,
                rlim_max: bytes as libc::rlim_t,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    command.output().expect("the radiosity binary runs")
}

/// Every file in `dir` with its bytes, sorted by name, except the pointer
/// and version folders of sets of outputs (`.NAME.outputs*`), which hold
/// what the names show; temporaries and lock files count.
pub fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| {
            let name = e
                .as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .into_owned();
            !(name.starts_with('.') && (name.ends_with(".outputs") || name.contains(".outputs-")))
        })
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    files.sort();
    files
}

#[cfg(unix)]
#[test]
fn a_resolve_that_fails_mid_write_leaves_every_previous_output_unchanged() {
    let dir = folder("resolve");
    let mut first = vec!["solve", "cornell_box", "--quiet", "--out", s(&dir)];
    first.extend(["--width", "32", "--height", "24"]);
    first.extend(QUICK);
    let out = radiosity(&first);
    assert!(out.status.success(), "{}", stderr(&out));
    let before = snapshot(&dir);
    let names: Vec<&str> = before.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["cornell_box.exr", "cornell_box.json", "cornell_box.png"]
    );
    // A larger image: its EXR (over 500 kB) cannot be written whole.
    let mut second = vec!["solve", "cornell_box", "--quiet", "--out", s(&dir)];
    second.extend(["--width", "256", "--height", "192"]);
    second.extend(QUICK);
    let out = radiosity_with_file_limit(&second, 100_000);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("cornell_box.exr"), "{text}");
    assert_eq!(snapshot(&dir), before, "a previous output changed");
}

#[cfg(unix)]
#[test]
fn bake_over_its_own_input_is_refused_and_a_failed_bake_keeps_the_previous_file() {
    let dir = folder("bake_in_place");
    let scene = dir.join("room.glb");
    let out = radiosity(&["export-scene", "cornell_box", "-o", s(&scene)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let exported = std::fs::read(&scene).unwrap();
    // Over its own input: refused before the solve, the input untouched.
    let mut bake = vec!["bake", s(&scene), "-o", s(&scene), "--quiet"];
    bake.extend(QUICK);
    let text = assert_refused(&bake, "is an input of this command");
    assert!(text.contains("room.glb"), "{text}");
    assert_eq!(std::fs::read(&scene).unwrap(), exported);
    // Cut off part way: the bake is larger than this; the previous baked
    // file stays as it was.
    let baked_path = dir.join("baked.glb");
    std::fs::write(&baked_path, b"the previous bake").unwrap();
    let limit = 4096;
    let mut bake = vec!["bake", s(&scene), "-o", s(&baked_path), "--quiet"];
    bake.extend(QUICK);
    let out = radiosity_with_file_limit(&bake, limit);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(std::fs::read(&baked_path).unwrap(), b"the previous bake");
    assert_eq!(snapshot(&dir).len(), 2, "a temporary was left behind");
    // Without a limit the bake replaces the previous baked file.
    let out = radiosity(&bake);
    assert!(out.status.success(), "{}", stderr(&out));
    let baked = std::fs::read(&baked_path).unwrap();
    assert!(baked.len() as u64 > limit, "the limit did not cut the bake");
    let loaded = radiosity::gltf_io::load_baked(&baked_path, &Default::default()).unwrap();
    assert!(!loaded.mesh.triangles.is_empty());
}

/// A table of surfaces in the form `compare` reads.
fn table(rows: &[(&str, serde_json::Value)]) -> String {
    let surfaces: Vec<serde_json::Value> = rows
        .iter()
        .map(|(name, radiosity)| serde_json::json!({"name": name, "radiosity": radiosity}))
        .collect();
    serde_json::json!({ "surfaces": surfaces }).to_string()
}

#[test]
fn compare_reports_zero_reference_bands_absolutely_and_refuses_misfits() {
    let dir = folder("compare");
    let write = |name: &str, text: String| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let solution = write(
        "solution.json",
        table(&[
            ("floor", serde_json::json!([0.5, 0.2, 0.1])),
            ("wall", serde_json::json!([0.3, 0.3, 0.3])),
        ]),
    );
    let zero = write(
        "zero.json",
        table(&[
            ("floor", serde_json::json!([0.5, 0.0, 0.1])),
            ("wall", serde_json::json!([0.3, 0.3, 0.3])),
        ]),
    );
    let out = radiosity(&["compare", s(&solution), s(&zero)]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!text.contains("inf") && !text.contains("NaN"), "{text}");
    assert!(text.contains("floor G: +2.000000e-1"), "{text}");
    assert!(text.contains("(5 surface-bands)"), "{text}");

    let fewer = write(
        "fewer.json",
        table(&[("floor", serde_json::json!([0.5, 0.2, 0.1]))]),
    );
    assert_refused(&["compare", s(&solution), s(&fewer)], "'wall'");
    let other = write(
        "other.json",
        table(&[
            ("floor", serde_json::json!([0.5, 0.2, 0.1])),
            ("ceiling", serde_json::json!([0.3, 0.3, 0.3])),
        ]),
    );
    let text = assert_refused(&["compare", s(&solution), s(&other)], "'ceiling'");
    assert!(text.contains("'wall'"), "{text}");
    let not_finite = write(
        "null.json",
        table(&[
            ("floor", serde_json::json!([0.5, null, 0.1])),
            ("wall", serde_json::json!([0.3, 0.3, 0.3])),
        ]),
    );
    assert_refused(&["compare", s(&solution), s(&not_finite)], "'floor'");
    let wrong = write("wrong.json", r#"{"objects": []}"#.to_string());
    assert_refused(&["compare", s(&solution), s(&wrong)], "no 'surfaces' list");
}
