//! Scale invariance: radiosity is a ratio of powers and areas, so the same
//! room at a millimetre or ten kilometres across must give the same numbers.

use super::stress_scenes::{assert_finite_non_negative, leaves, lit_room_with_box, quick_settings};
use radiosity::pipeline::{ProgressiveSettings, SolverKind};
use radiosity::Settings;

#[test]
fn the_same_room_at_scales_1e_minus_3_and_1e4_gives_the_same_radiosities() {
    same_at_every_scale(SolverKind::GaussSeidel);
}

#[test]
fn the_progressive_solver_too_gives_the_same_radiosities_at_every_scale() {
    same_at_every_scale(SolverKind::Progressive);
}

fn same_at_every_scale(solver_kind: SolverKind) {
    let solve = |scale: f64| {
        let scene = lit_room_with_box(scale, 1.0, 1e-3);
        // Patch size in proportion; everything else is derived from the scene.
        // Progressive runs stop with some power unshot, at a point that
        // depends on the order of the shots; run them close to convergence so
        // that only the scale can tell the runs apart.
        let settings = Settings {
            solver_kind,
            progressive: ProgressiveSettings {
                tolerance: 1e-8,
                ..ProgressiveSettings::default()
            },
            ..quick_settings(0.4 * scale)
        };
        let sol = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
        assert_finite_non_negative(&sol, "scaled room");
        sol
    };
    let reference = solve(1.0);
    let brightest = leaves(&reference)
        .iter()
        .map(|e| e.radiosity.max_band())
        .fold(0.0, f64::max);
    for scale in [1e-3, 1e4] {
        let sol = solve(scale);
        let (a, b) = (leaves(&sol), leaves(&reference));
        assert_eq!(a.len(), b.len(), "scale {scale}: a different mesh");
        let mut worst: f64 = 0.0;
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(
                x.cell(),
                y.cell(),
                "scale {scale}: elements in another order"
            );
            for band in 0..3 {
                let (p, q) = (x.radiosity[band], y.radiosity[band]);
                // Relative to the element's own value; elements in deep
                // shadow compare against a millionth of the brightest.
                let err = (p - q).abs() / q.abs().max(1e-6 * brightest);
                worst = worst.max(err);
            }
        }
        eprintln!(
            "scale {scale}: worst relative difference {worst:.2e} over {} elements",
            a.len()
        );
        assert!(worst < 1e-4, "scale {scale}: {worst}");
    }
}
