//! The outputs of one command are one unit (issue 48): whatever stops a run
//! (SIGKILL at any step of its commit, SIGTERM or SIGINT during the solve or
//! the commit), a reader finds the whole previous set or the whole new one;
//! a second run into the same outputs is refused while the first runs.
//!
//! The runs solve the Cornell box in well under a second; the two sets
//! differ in image width and seed, which the PNG's header, the EXR's data
//! window and the JSON each record, so a mix shows.

#![cfg(unix)]

use super::cli_run::{fresh_folder, radiosity, stderr};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

const QUICK: [&str; 12] = [
    "--hemicube-res",
    "16",
    "--max-depth",
    "1",
    "--patch-size",
    "0.3",
    "--initial-depth",
    "0",
    "--threads",
    "1",
    "--height",
    "24",
];

/// The two runs: (width, seed).
const OLD: (u32, u64) = (40, 1);
const NEW: (u32, u64) = (32, 2);

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn solve_args(out: &Path, (width, seed): (u32, u64)) -> Vec<String> {
    let mut args: Vec<String> = ["solve", "cornell_box", "--quiet", "--out", s(out)]
        .iter()
        .map(|a| a.to_string())
        .collect();
    args.extend(QUICK.iter().map(|a| a.to_string()));
    args.extend([
        "--width".into(),
        width.to_string(),
        "--seed".into(),
        seed.to_string(),
    ]);
    args
}

/// Runs one solve to completion.
fn solve(out: &Path, run: (u32, u64)) {
    let args = solve_args(out, run);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let done = radiosity(&args);
    assert!(done.status.success(), "{}", stderr(&done));
}

/// A solve under way, pausing `pause` seconds before each commit step, and
/// its standard error line by line.
fn start(out: &Path, run: (u32, u64), pause: f64) -> (Child, Receiver<String>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(solve_args(out, run))
        .env("RADIOSITY_TEST_COMMIT_PAUSE", pause.to_string())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let lines = BufReader::new(child.stderr.take().unwrap());
    let (send, receive) = channel();
    std::thread::spawn(move || {
        for line in lines.lines().map_while(Result::ok) {
            if send.send(line).is_err() {
                break;
            }
        }
    });
    (child, receive)
}

/// Waits for the `n`-th (from 0) commit step line; `None` when the run
/// ended before it.
fn wait_for_step(lines: &Receiver<String>, n: usize) -> Option<String> {
    let mut seen = 0;
    while let Ok(line) = lines.recv_timeout(Duration::from_secs(60)) {
        if let Some(step) = line.strip_prefix("commit step: ") {
            if seen == n {
                return Some(step.to_string());
            }
            seen += 1;
        }
    }
    None
}

fn send(child: &Child, signal: i32) {
    // SAFETY: kill(2) on the pid of a child this test started and has not
    // yet waited for.
    assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
}

/// The width in a PNG's header.
fn png_width(path: &Path) -> u32 {
    let bytes = std::fs::read(path).unwrap();
    u32::from_be_bytes(bytes[16..20].try_into().unwrap())
}

/// The width of an EXR's data window.
fn exr_width(path: &Path) -> u32 {
    let bytes = std::fs::read(path).unwrap();
    let key = b"dataWindow\0box2i\0";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("an EXR header")
        + key.len()
        + 4;
    let word = |k: usize| i32::from_le_bytes(bytes[at + 4 * k..at + 4 * k + 4].try_into().unwrap());
    (word(2) - word(0) + 1) as u32
}

fn json_seed(path: &Path) -> u64 {
    let text = std::fs::read_to_string(path).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["seed"].as_u64().unwrap()
}

/// Which run the visible set is wholly from; panics on a mix.
fn whole_set(out: &Path, context: &str) -> (u32, u64) {
    let name = |ext: &str| out.join(format!("cornell_box.{ext}"));
    let found = (
        png_width(&name("png")),
        exr_width(&name("exr")),
        json_seed(&name("json")),
    );
    let runs = [OLD, NEW];
    let run = runs
        .iter()
        .find(|(w, seed)| found == (*w, *w, *seed))
        .unwrap_or_else(|| panic!("{context}: a mixed set (png, exr, seed) = {found:?}"));
    *run
}

/// The names in `out`.
fn names(out: &Path) -> Vec<String> {
    let mut n: Vec<String> = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    n.sort();
    n
}

/// What a finished set leaves: the three names, the pointer and one
/// version folder; no temporaries, no lock file, no older version.
fn assert_tidy(out: &Path, context: &str) {
    let n = names(out);
    let visible: Vec<&String> = n.iter().filter(|x| !x.starts_with('.')).collect();
    assert_eq!(
        visible,
        ["cornell_box.exr", "cornell_box.json", "cornell_box.png"],
        "{context}"
    );
    let hidden: Vec<&String> = n.iter().filter(|x| x.starts_with('.')).collect();
    assert_eq!(hidden.len(), 2, "{context}: {hidden:?}");
    assert_eq!(hidden[0], ".cornell_box.outputs", "{context}");
    assert!(
        hidden[1].starts_with(".cornell_box.outputs-"),
        "{context}: {hidden:?}"
    );
}

/// Replaces the links of the visible names by copies of their files and
/// removes the set's pointer and versions: the folder as a version of the
/// tool before sets wrote it.
fn as_plain_files(out: &Path) {
    for ext in ["png", "exr", "json"] {
        let path = out.join(format!("cornell_box.{ext}"));
        let bytes = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        std::fs::write(&path, bytes).unwrap();
    }
    for name in names(out)
        .iter()
        .filter(|n| n.starts_with(".cornell_box.outputs"))
    {
        let path = out.join(name);
        if path.is_dir() && !std::fs::symlink_metadata(&path).unwrap().is_symlink() {
            std::fs::remove_dir_all(&path).unwrap();
        } else {
            std::fs::remove_file(&path).unwrap();
        }
    }
}

/// Kills the new run at every step of its commit in turn, from a folder
/// holding the old set (as links, or as plain files the first time a set
/// is written there); after each kill the folder shows one whole run, and
/// the next run tidies up.
fn kill_at_every_step(group: &str, plain: bool) -> usize {
    let out = fresh_folder("output_sets", group);
    let mut steps = 0;
    for k in 0.. {
        solve(&out, OLD);
        if plain {
            as_plain_files(&out);
        }
        let (mut child, lines) = start(&out, NEW, 0.05);
        let Some(step) = wait_for_step(&lines, k) else {
            let status = child.wait().unwrap();
            assert!(status.success(), "the run without a kill failed");
            assert_eq!(whole_set(&out, "after the whole commit"), NEW);
            break;
        };
        child.kill().unwrap();
        child.wait().unwrap();
        whole_set(&out, &format!("killed before step {k} ({step})"));
        steps += 1;
    }
    solve(&out, OLD);
    assert_tidy(&out, "after a run that follows the kills");
    steps
}

#[test]
fn a_kill_at_any_step_of_the_commit_leaves_one_whole_set() {
    let steps = kill_at_every_step("kill_links", false);
    // The manifest, three links to make at most, the swap, the tidying.
    assert!(steps >= 3, "only {steps} steps");
}

#[test]
fn a_kill_while_plain_files_become_a_set_leaves_one_whole_set() {
    let steps = kill_at_every_step("kill_plain", true);
    // Each plain file is kept, then the pointer, links, swap and tidying.
    assert!(steps >= 8, "only {steps} steps");
}

/// SIGTERM and SIGINT during a long solve: the run stops within seconds
/// with 143 or 130 and a message, the previous set is untouched and no
/// temporary or lock file is left.
#[test]
fn a_signal_during_the_solve_stops_it_and_keeps_the_previous_set() {
    for (signal, code) in [(libc::SIGTERM, 143), (libc::SIGINT, 130)] {
        let out = fresh_folder("output_sets", &format!("signal_{signal}"));
        solve(&out, OLD);
        let before: Vec<(String, Vec<u8>)> = ["png", "exr", "json"]
            .iter()
            .map(|e| {
                let p = out.join(format!("cornell_box.{e}"));
                (e.to_string(), std::fs::read(p).unwrap())
            })
            .collect();
        // Uniform depth 5 makes some 340 000 elements: a minute of work.
        // The adaptive refinement's depths are refused with a uniform mesh.
        let mut args = solve_args(&out, NEW);
        for flag in ["--max-depth", "--initial-depth"] {
            let at = args.iter().position(|a| a == flag).unwrap();
            args.drain(at..at + 2);
        }
        args.extend(["--uniform-depth".into(), "5".into()]);
        let mut child = Command::new(env!("CARGO_BIN_EXE_radiosity"))
            .args(&args)
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(700));
        let sent = Instant::now();
        send(&child, signal);
        let status = child.wait().unwrap();
        let waited = sent.elapsed();
        let mut text = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut text).unwrap();
        assert_eq!(status.code(), Some(code), "{text}");
        assert!(text.contains("stopped by SIG"), "{text}");
        assert!(waited < Duration::from_secs(5), "took {waited:?} to stop");
        for (ext, bytes) in &before {
            let now = std::fs::read(out.join(format!("cornell_box.{ext}"))).unwrap();
            assert!(&now == bytes, "cornell_box.{ext} changed");
        }
        assert_tidy(&out, "after the signal");
    }
}

/// SIGTERM in the middle of the commit: the commit ends first (it is
/// milliseconds of renames), then the run exits with 143; the new set is
/// whole.
#[test]
fn a_signal_during_the_commit_lets_it_finish_first() {
    let out = fresh_folder("output_sets", "term_commit");
    solve(&out, OLD);
    let (mut child, lines) = start(&out, NEW, 0.3);
    wait_for_step(&lines, 1).expect("a second commit step");
    send(&child, libc::SIGTERM);
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(143));
    assert_eq!(whole_set(&out, "after SIGTERM in the commit"), NEW);
    assert_tidy(&out, "after SIGTERM in the commit");
}

/// Two runs into one set: the second is refused, naming the folder and
/// the first run's process, and the first finishes with a whole set.
#[test]
fn a_second_run_into_the_same_outputs_is_refused_while_the_first_runs() {
    let out = fresh_folder("output_sets", "two_runs");
    let (mut first, lines) = start(&out, OLD, 0.5);
    wait_for_step(&lines, 0).expect("the first run's commit");
    let args = solve_args(&out, NEW);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let second = radiosity(&args);
    let text = stderr(&second);
    assert_eq!(second.status.code(), Some(1), "{text}");
    assert!(text.contains("another run"), "{text}");
    assert!(text.contains(&format!("process {}", first.id())), "{text}");
    assert!(text.contains(s(&out)), "{text}");
    assert!(first.wait().unwrap().success());
    assert_eq!(whole_set(&out, "after both"), OLD);
    assert_tidy(&out, "after both");
}

/// A run replaces the whole set: a file the previous run wrote and this
/// one does not (an .hdr, an overlay elsewhere) is removed with it.
#[test]
fn files_the_new_set_lacks_are_removed_even_outside_the_folder() {
    let out = fresh_folder("output_sets", "stale");
    let elsewhere = fresh_folder("output_sets", "stale_overlay");
    let overlay: PathBuf = elsewhere.join("mesh.png");
    let mut args = solve_args(&out, OLD);
    args.extend(["--hdr".into(), "--mesh-out".into(), s(&overlay).into()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let done = radiosity(&args);
    assert!(done.status.success(), "{}", stderr(&done));
    assert!(out.join("cornell_box.hdr").is_file());
    assert_eq!(png_width(&overlay), OLD.0);
    solve(&out, NEW);
    assert!(!out.join("cornell_box.hdr").exists());
    assert!(std::fs::symlink_metadata(out.join("cornell_box.hdr")).is_err());
    assert!(
        std::fs::symlink_metadata(&overlay).is_err(),
        "the overlay's link stayed"
    );
    assert_tidy(&out, "after the smaller set");
}
