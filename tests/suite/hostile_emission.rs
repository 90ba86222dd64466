//! Emission at the ends of the double range (issue 19, defect 3): results are
//! linear in emission, so a scene lit by 1e-300 or 1e300 solves as fast and as
//! accurately as one lit by 1, and an emission too small to represent is
//! refused at load naming its material.

use super::common::{closed_box, FaceMaterial};
use super::stress_scenes::{downward_quad, lit_room_with_box, quick_settings, room, v};
use glam::DVec3;
use radiosity::gltf_io::{load_scene, write_scene, ImportLimits};
use radiosity::math::Rgb;
use radiosity::pipeline::solve_with_previews;
use radiosity::pipeline::SolverKind;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::{Error, Settings, Solution};
use std::path::Path;

/// A closed box of reflectance 0.999 whose ceiling emits `exitance`: near
/// 1, Gauss-Seidel needs many sweeps, each over values of the emission's
/// size.
fn bright_box(exitance: f64) -> Scene {
    let wall = FaceMaterial::grey(0.999, 0.0);
    let ceiling = FaceMaterial::grey(0.5, exitance);
    closed_box(
        DVec3::new(1.0, 0.8, 1.2),
        [wall, ceiling, wall, wall, wall, wall],
    )
}

fn settings(solver: SolverKind) -> Settings {
    Settings {
        solver_kind: solver,
        ..quick_settings(0.4)
    }
}

/// Solves `scene`, collecting the ceiling's mean radiosity from every preview.
fn solve_with_ceiling_previews(scene: &Scene, settings: &Settings) -> (Solution, Vec<Rgb>) {
    let mut previews = Vec::new();
    let sol = solve_with_previews(scene, settings, &|_| {}, &mut |p| {
        previews.push(p.object_radiosity(scene, true)[1].radiosity);
    })
    .unwrap();
    (sol, previews)
}

/// `2^k` as a double.
fn pow2(k: i32) -> f64 {
    2f64.powi(k)
}

#[test]
fn emission_far_from_one_solves_in_a_normalised_scale() {
    // A power of two apart, the solves must agree to the bit once scaled:
    // the same sweeps, the same refinement, the same shots.
    for solver in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let mut s = settings(solver);
        s.progressive.preview_every = Some(5);
        let (unit, unit_previews) = solve_with_ceiling_previews(&bright_box(1.0), &s);
        for k in [-1000, -300, 300, 1000] {
            let f = pow2(k);
            let scene = bright_box(f);
            let (sol, previews) = solve_with_ceiling_previews(&scene, &s);
            let (a, b) = (unit.stats(), sol.stats());
            assert_eq!(a.total_iterations, b.total_iterations, "{solver:?} 2^{k}");
            assert_eq!(a.elements, b.elements, "{solver:?} 2^{k}");
            let (la, lb) = (unit.leaves(), sol.leaves());
            assert_eq!(la.len(), lb.len());
            for (x, y) in la.iter().zip(&lb) {
                assert_eq!(x.radiosity * f, y.radiosity, "{solver:?} 2^{k}");
            }
            for (x, y) in unit.patch_radiosity().iter().zip(sol.patch_radiosity()) {
                assert_eq!(*x * f, *y, "{solver:?} 2^{k}");
            }
            let (ea, eb) = (&a.energy, &b.energy);
            assert_eq!(ea.emitted_power * f, eb.emitted_power);
            assert_eq!(ea.absorbed_power * f, eb.absorbed_power);
            assert_eq!(ea.relative_difference, eb.relative_difference);
            assert_eq!(a.solver.residual * f, b.solver.residual);
            assert_eq!(unit_previews.len(), previews.len(), "{solver:?} 2^{k}");
            for (x, y) in unit_previews.iter().zip(&previews) {
                assert_eq!(*x * f, *y, "{solver:?} 2^{k}");
            }
            // The patch system and the probes answer at the scene's scale.
            let brightest = sol.patch_system().emission.iter().map(|e| e.max_band());
            assert_eq!(brightest.fold(0.0, f64::max), f, "{solver:?} 2^{k}");
            let point = DVec3::new(0.5, 0.0, 0.6);
            let up = DVec3::Y;
            let (pa, pb) = (
                unit.probe().radiosity_at(point, up).unwrap(),
                sol.probe().radiosity_at(point, up).unwrap(),
            );
            assert_eq!(pa * f, pb, "{solver:?} 2^{k}");
        }
    }
}

#[test]
fn emission_of_1e_300_converges_in_as_many_sweeps_as_emission_one() {
    // Not a power of two apart: the same sweeps, values equal to rounding.
    let s = settings(SolverKind::GaussSeidel);
    let unit = radiosity::solve(&bright_box(1.0), &s, &|_| {}).unwrap();
    let tiny = radiosity::solve(&bright_box(1e-300), &s, &|_| {}).unwrap();
    assert_eq!(unit.stats().total_iterations, tiny.stats().total_iterations);
    for (x, y) in unit.leaves().iter().zip(&tiny.leaves()) {
        for band in 0..3 {
            let expected = x.radiosity[band] * 1e-300;
            assert!(
                (y.radiosity[band] - expected).abs() <= 1e-12 * expected,
                "{} vs {expected}",
                y.radiosity[band]
            );
        }
    }
    assert!(tiny.stats().solver.error_bound > 0.0);
}

#[test]
fn subnormal_emission_is_refused_naming_the_material() {
    let mut b = SceneBuilder::new("dim");
    let err = b
        .material("lamp", Rgb::ZERO, Rgb::splat(1e-320))
        .unwrap_err();
    match err {
        Error::Material { material, message } => {
            assert_eq!(material, "lamp");
            assert!(message.contains("too small to be represented"), "{message}");
        }
        other => panic!("expected a material error, got {other}"),
    }

    // The same through a glTF file: refused at load, in no time.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hostile_emission");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("room.gltf");
    write_scene(&lit_room_with_box(1.0, 1.0, 0.001), &path).unwrap();
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let lamp = json["materials"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|m| m["name"] == "light")
        .unwrap();
    lamp["emissiveFactor"] = serde_json::json!([1.0, 1.0, 1.0]);
    lamp["extensions"] = serde_json::json!({
        "KHR_materials_emissive_strength": { "emissiveStrength": 1e-320 }
    });
    json["extensionsUsed"] = serde_json::json!(["KHR_materials_emissive_strength"]);
    std::fs::write(&path, serde_json::to_string(&json).unwrap()).unwrap();
    let err = load_scene(&path, &ImportLimits::default()).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("'light'") && text.contains("too small to be represented"),
        "{text}"
    );
}

#[test]
fn an_emitter_too_dim_beside_the_brightest_is_dropped_with_a_warning() {
    let mut b = SceneBuilder::new("two_lamps");
    let wall = b.material("wall", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let sun = b.material("sun", Rgb::ZERO, Rgb::splat(1e200)).unwrap();
    let glow = b.material("glow", Rgb::ZERO, Rgb::splat(1e-200)).unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0), wall, wall, wall);
    b.object("sun");
    downward_quad(&mut b, sun, 0.9, (0.4, 0.6), (0.4, 0.6));
    b.object("glow");
    downward_quad(&mut b, glow, 0.5, (0.2, 0.3), (0.2, 0.3));
    let scene = b.build().unwrap();
    let sol = radiosity::solve(&scene, &settings(SolverKind::GaussSeidel), &|_| {}).unwrap();
    let warnings = &sol.stats().warnings;
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("'glow'") && !w.contains("'sun'")),
        "{warnings:?}"
    );
    let emitted = sol.stats().energy.emitted_power;
    assert!(
        emitted.is_finite() && emitted.max_band() > 1e199,
        "{emitted:?}"
    );
}
