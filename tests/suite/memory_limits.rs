//! Limits from memory instead of fixed counts: a scene that cannot fit is
//! refused before any form factor, saying what it would need; one that fits
//! refines until the rows it measures would not, and says so.

use crate::stress_scenes::lit_room_with_box;
use radiosity::pipeline::SolverKind;
use radiosity::refine::RefineSettings;
use radiosity::{Error, LimitKind, Settings};

fn settings(max_memory: u64, kind: SolverKind) -> Settings {
    Settings {
        hemicube_resolution: 16,
        patch_size: Some(0.25),
        solver_kind: kind,
        max_memory,
        refine: RefineSettings {
            tolerance: 0.01,
            max_depth: 3,
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

#[test]
fn no_count_limits_by_default_only_memory() {
    let s = Settings::default();
    assert_eq!(s.max_patches, usize::MAX);
    assert_eq!(s.refine.max_elements, usize::MAX);
    assert_eq!(s.max_memory, radiosity::DEFAULT_MAX_MEMORY);
}

#[test]
fn a_scene_that_cannot_fit_is_refused_before_any_form_factor() {
    let scene = lit_room_with_box(1.0, 1.0, 0.01);
    // Too little for the patches themselves, then for the rows' estimate.
    for limit in [100_000, 400_000] {
        let stages = std::sync::Mutex::new(0usize);
        let e = radiosity::solve(&scene, &settings(limit, SolverKind::GaussSeidel), &|_| {
            *stages.lock().unwrap() += 1;
        })
        .unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(
                e,
                Error::Limit {
                    limit: LimitKind::Memory,
                    ..
                }
            ),
            "{text}"
        );
        // The library names the setting, never the CLI's flag.
        assert!(text.contains("`max_memory`"), "{text}");
        assert!(!text.contains("--"), "{text}");
        assert_eq!(*stages.lock().unwrap(), 0, "no stage may start");
        if limit == 400_000 {
            assert!(text.contains("would need at least"), "{text}");
        }
    }
}

#[test]
fn refinement_stops_where_the_rows_would_not_fit_with_a_warning() {
    let scene = lit_room_with_box(1.0, 1.0, 0.01);
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let free = radiosity::solve(&scene, &settings(1 << 30, kind), &|_| {}).unwrap();
        let full = free.stats().memory.mesh_bytes + free.stats().memory.system_bytes;
        assert!(
            free.stats().warnings.is_empty(),
            "{:?}",
            free.stats().warnings
        );
        // Two thirds of what the free solve held: fewer elements, within the
        // limit, and a warning that names the budget.
        let limit = (full as u64) * 2 / 3;
        let held = radiosity::solve(&scene, &settings(limit, kind), &|_| {}).unwrap();
        let stats = held.stats();
        assert!(
            stats.elements < free.stats().elements,
            "{kind:?}: {} elements, {} without the limit",
            stats.elements,
            free.stats().elements
        );
        let used = (stats.memory.mesh_bytes + stats.memory.system_bytes) as u64;
        // The rows are measured as they come; the arena's growth by
        // doubling is not, hence the margin.
        assert!(
            used as f64 <= 1.1 * limit as f64,
            "{kind:?}: {used} bytes held, limit {limit}"
        );
        assert!(
            stats
                .warnings
                .iter()
                .any(|w| w.contains("element budget") && w.contains("`max_memory`")),
            "{kind:?}: {:?}",
            stats.warnings
        );
    }
}

/// Runs the binary with its address space limited to `bytes` (an
/// allocation beyond it fails, and the process aborts), so that a refusal
/// with a message shows the memory was never taken.
#[cfg(unix)]
fn radiosity_with_address_limit(args: &[&str], bytes: u64) -> std::process::Output {
    use std::os::unix::process::CommandExt;
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_radiosity"));
    command.args(args);
    // SAFETY: between fork and exec the closure only calls setrlimit(2).
    unsafe {
        command.pre_exec(move || {
            let limit = libc::rlimit {
                rlim_cur: bytes as libc::rlim_t,
                rlim_max: bytes as libc::rlim_t,
            };
            if libc::setrlimit(libc::RLIMIT_AS, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    command.output().expect("the radiosity binary runs")
}

#[cfg(unix)]
#[test]
fn a_depth_or_image_the_limit_cannot_hold_is_refused_before_it_is_allocated() {
    use super::cli_run::{fresh_folder, stderr};
    let dir = fresh_folder("memory_limits", "up_front");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    // Depth 10 makes 4^10 elements per patch: hundreds of GB. Under a 1 GB
    // address space an attempt would abort; the refusal comes first, with
    // the figure.
    let cases: [(&[&str], &[&str]); 3] = [
        (
            &["--uniform-depth", "10", "--max-memory", "2"],
            // The CLI prints the library's `max_memory` as its flag.
            &["depth 10", "GB", "2.0 GB", "raise --max-memory"],
        ),
        (
            &[
                "--initial-depth",
                "8",
                "--max-depth",
                "8",
                "--max-memory",
                "0.5",
            ],
            &["depth 8", "of the 500 MB --max-memory"],
        ),
        (
            &["--width", "2048", "--height", "2048", "--max-memory", "0.1"],
            &["the images need 671 MB", "100 MB"],
        ),
    ];
    for (extra, expected) in cases {
        let mut args = vec![
            "solve",
            "cornell_box",
            "--quiet",
            "--threads",
            "1",
            "--out",
            out,
        ];
        args.extend(extra);
        let done = radiosity_with_address_limit(&args, 1 << 30);
        let text = stderr(&done);
        assert_eq!(done.status.code(), Some(1), "{extra:?}: {text}");
        for e in expected {
            assert!(text.contains(e), "{extra:?}: expected '{e}' in {text}");
        }
    }
}

/// Hemi-cube buffers count: a resolution whose buffers alone pass the
/// limit is refused, saying so.
#[test]
fn hemicube_buffers_count_against_the_limit() {
    let scene = lit_room_with_box(1.0, 1.0, 0.01);
    let mut s = settings(200_000_000, SolverKind::GaussSeidel);
    s.hemicube_resolution = 4096;
    let e = radiosity::solve(&scene, &s, &|_| panic!("no stage may start")).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("for the hemi-cubes"), "{text}");
}

/// The warning about a hemi-cube resolution out of proportion comes when
/// the form factors begin, before the work: the run is stopped as soon as
/// it shows.
#[cfg(unix)]
#[test]
fn a_hemicube_resolution_out_of_proportion_is_warned_before_the_work() {
    use std::io::{BufRead, BufReader};
    let dir = super::cli_run::fresh_folder("memory_limits", "hemicube_cost");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args([
            "solve",
            "cornell_box",
            "--hemicube-res",
            "4096",
            "--threads",
            "1",
        ])
        .args(["--quiet", "--out", dir.to_str().unwrap()])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut warning = None;
    for line in BufReader::new(child.stderr.take().unwrap()).lines() {
        let line = line.unwrap();
        if line.contains("--hemicube-res 4096 is out of proportion") {
            warning = Some(line);
            break;
        }
    }
    let _ = child.kill();
    let _ = child.wait();
    let warning = warning.expect("the warning");
    // 3 x 4096^2 pixels each.
    assert!(warning.contains("50.3 M pixels"), "{warning}");
}
