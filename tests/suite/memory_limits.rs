//! Limits from memory instead of fixed counts: a scene that cannot fit is
//! refused before any form factor, saying what it would need; one that fits
//! refines until the rows it measures would not, and says so.

use crate::stress_scenes::lit_room_with_box;
use radiosity::refine::RefineSettings;
use radiosity::solve::SolverKind;
use radiosity::{Error, Settings};

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
        assert!(matches!(e, Error::Limit(_)), "{text}");
        assert!(text.contains("--max-memory"), "{text}");
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
                .any(|w| w.contains("element budget") && w.contains("--max-memory")),
            "{kind:?}: {:?}",
            stats.warnings
        );
    }
}
