//! Energy conservation in closed scenes through the general hemi-cube path
//! (no convex shortcut): a lamp hung 1 mm under the ceiling of a closed room,
//! boxes on its floor, furnaces; both solvers; the floor against the path
//! tracer; warnings and refusals.

use super::common::{closed_box, rel, FaceMaterial};
use super::stress_scenes::{downward_quad, room, v};
use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::pipeline::Skips;
use radiosity::pipeline::SolverKind;
use radiosity::reference::{Reference, ReferenceSettings};
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::solution::StopReason;
use radiosity::{Settings, Solution};

/// A closed 1 m room whose only light is a 0.2 m square lamp facing down
/// 1 mm below the ceiling (radiance 1, exitance pi), walls and lamp of
/// reflectance `rho`; with `boxes`, two boxes standing on the floor.
pub fn lamp_room(rho: f64, boxes: bool) -> Scene {
    let mut b = SceneBuilder::new("lamp_room");
    let wall = b.material("wall", Rgb::splat(rho), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::splat(rho), Rgb::ONE).unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0), wall, wall, wall);
    b.object("lamp");
    downward_quad(&mut b, lamp, 0.999, (0.4, 0.6), (0.4, 0.6));
    if boxes {
        b.axis_box("box_a", wall, v(0.15, 0.0, 0.2), v(0.45, 0.3, 0.5))
            .unwrap();
        b.axis_box("box_b", wall, v(0.6, 0.0, 0.55), v(0.8, 0.5, 0.75))
            .unwrap();
    }
    b.build().unwrap()
}

fn with_solver(kind: SolverKind) -> Settings {
    Settings {
        solver_kind: kind,
        ..Settings::default()
    }
}

fn solve(scene: &Scene, settings: &Settings) -> Solution {
    radiosity::solve(scene, settings, &|_| {}).unwrap()
}

fn floor(scene: &Scene, sol: &Solution) -> f64 {
    let objects = sol.object_radiosity(scene);
    objects
        .iter()
        .find(|o| o.name == "floor")
        .unwrap()
        .radiosity[0]
}

/// The bound on `energy.relative_difference` at reflectance `rho` (issue
/// 18): 0.1% up to 0.9, 1% at 0.99.
fn energy_bound(rho: f64) -> f64 {
    if rho <= 0.9 {
        1e-3
    } else {
        1e-2
    }
}

/// Checks the energy balance of a closed scene's solution, that it took the
/// general path and that nothing warned, and for the progressive solver that
/// it converged with its unshot power never below zero.
fn assert_conserves(sol: &Solution, rho: f64, what: &str) {
    let e = &sol.stats().energy;
    assert!(e.closed, "{what}: the scene is closed");
    assert_eq!(
        sol.stats().skips.exact_rows,
        0,
        "{what}: no convex shortcut"
    );
    assert!(
        e.relative_difference.abs() <= energy_bound(rho),
        "{what}: absorbed vs emitted {:+.4}% (bound {}%)",
        100.0 * e.relative_difference,
        100.0 * energy_bound(rho)
    );
    assert!(
        sol.stats().warnings.is_empty(),
        "{what}: {:?}",
        sol.stats().warnings
    );
    if let Some(p) = &sol.stats().progressive {
        assert_eq!(p.stop, StopReason::Converged, "{what}");
        assert!(
            p.lowest_signed_unshot_fraction >= -1e-9,
            "{what}: the unshot power fell to {:.3e} of the emitted",
            p.lowest_signed_unshot_fraction
        );
    }
}

#[test]
fn a_closed_room_with_a_lamp_under_the_ceiling_conserves_energy() {
    // Before issue 18 (Gauss-Seidel / progressive): -0.20% / -0.23% at 0.5,
    // -3.3% at 0.9, -30% at 0.99, -81% at 0.999.
    for rho in [0.5, 0.9, 0.99] {
        let scene = lamp_room(rho, false);
        for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
            let sol = solve(&scene, &with_solver(kind));
            let what = format!("lamp room rho {rho} {kind:?}");
            eprintln!(
                "{what}: energy {:+.4}%, floor {:.4}",
                100.0 * sol.stats().energy.relative_difference,
                floor(&scene, &sol)
            );
            assert_conserves(&sol, rho, &what);
        }
    }
    // Reported, not held to a bound.
    let scene = lamp_room(0.999, false);
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let sol = solve(&scene, &with_solver(kind));
        eprintln!(
            "lamp room rho 0.999 {kind:?}: energy {:+.4}%, floor {:.3}",
            100.0 * sol.stats().energy.relative_difference,
            floor(&scene, &sol)
        );
    }
}

#[test]
fn boxes_on_the_floor_of_a_closed_room_conserve_energy() {
    for rho in [0.9, 0.99] {
        let scene = lamp_room(rho, true);
        for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
            let sol = solve(&scene, &with_solver(kind));
            let what = format!("boxes rho {rho} {kind:?}");
            eprintln!(
                "{what}: energy {:+.4}%",
                100.0 * sol.stats().energy.relative_difference
            );
            assert_conserves(&sol, rho, &what);
        }
    }
}

/// The path tracer's mean radiosity of the lamp room's floor (independent of
/// the hemi-cube and the solvers), with its standard error: one uniformly
/// jittered point in each of `n x n` cells of the floor, `paths` paths each.
fn traced_floor(scene: &Scene, n: usize, paths: u64) -> (f64, f64) {
    let reference = Reference::new(scene).unwrap();
    // A fixed low-discrepancy jitter (the additive recurrence of the
    // golden ratio): deterministic, and uniform within each cell.
    let jitter = |k: usize, a: f64| (0.5 + a * k as f64).fract();
    let points: Vec<_> = (0..n * n)
        .map(|k| {
            let (i, j) = ((k % n) as f64, (k / n) as f64);
            let x = (i + jitter(k, 0.618_033_988_749_894_9)) / n as f64;
            let z = (j + jitter(k, 0.754_877_666_246_692_7)) / n as f64;
            reference.locate(v(x, 0.0, z), DVec3::Y).unwrap()
        })
        .collect();
    let settings = ReferenceSettings {
        paths,
        seed: 18,
        ..ReferenceSettings::default()
    };
    let estimates = reference.radiosity_at(&points, &settings).unwrap();
    let count = estimates.len() as f64;
    let mean = estimates.iter().map(|e| e.radiosity[0]).sum::<f64>() / count;
    let variance: f64 = estimates.iter().map(|e| e.std_error[0].powi(2)).sum();
    (mean, variance.sqrt() / count)
}

#[test]
fn the_floor_of_the_closed_room_agrees_with_the_path_tracer() {
    // 1% at 0.9 and 2% at 0.99 (issue 18). The analytic area mean of a closed
    // room of uniform reflectance, E_mean / (1 - rho), is no bound here: the
    // lamp's back is black (single-sided), and the gap over it absorbs 1.4%
    // of the light at 0.99 (traced: 2.051 against 2.081).
    for (rho, bound, n, paths) in [(0.9, 0.01, 16, 800), (0.99, 0.02, 16, 400)] {
        let scene = lamp_room(rho, false);
        let (traced, error) = traced_floor(&scene, n, paths);
        assert!(
            error < 0.25 * bound * traced,
            "rho {rho}: {traced} +- {error}"
        );
        for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
            let solved = floor(&scene, &solve(&scene, &with_solver(kind)));
            eprintln!(
                "rho {rho} {kind:?}: floor {solved:.4}, traced {traced:.4} +- {error:.4} \
                 ({:+.2}%)",
                100.0 * (solved / traced - 1.0)
            );
            assert!(
                rel(solved, traced) < bound,
                "rho {rho} {kind:?}: floor {solved} against traced {traced} +- {error}"
            );
        }
    }
}

fn uniform(patch_size: f64, depth: u8) -> Settings {
    Settings {
        patch_size: Some(patch_size),
        refine: RefineSettings {
            uniform_depth: Some(depth),
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

#[test]
fn furnaces_give_e_over_one_minus_rho_through_the_hemi_cubes() {
    // Every surface emits 1 and reflects rho: B = 1 / (1 - rho) everywhere,
    // whatever the geometry, as long as every row sums to 1 and the rows
    // conserve. A closed box with the convex shortcut off, and a room with a
    // box floating in it (not convex: no shortcut to take).
    let general = Settings {
        skips: Skips {
            convex: false,
            ..Skips::default()
        },
        ..uniform(0.3, 1)
    };
    for rho in [0.5, 0.9, 0.99] {
        let boxed = closed_box(DVec3::new(1.0, 0.8, 1.2), [FaceMaterial::grey(rho, 1.0); 6]);
        let mut b = SceneBuilder::new("furnace_room");
        let m = b
            .material(
                "furnace",
                Rgb::splat(rho),
                Rgb::splat(1.0 / std::f64::consts::PI),
            )
            .unwrap();
        room(&mut b, v(0.0, 0.0, 0.0), v(2.0, 1.6, 2.4), m, m, m);
        b.axis_box("box", m, v(0.4, 0.2, 0.5), v(1.0, 0.8, 1.1))
            .unwrap();
        let roomed = b.build().unwrap();
        for (scene, what) in [(boxed, "box"), (roomed, "room with a box")] {
            for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
                let settings = Settings {
                    solver_kind: kind,
                    ..general.clone()
                };
                let sol = solve(&scene, &settings);
                assert_eq!(sol.stats().skips.exact_rows, 0, "{what}: no shortcut");
                assert!(sol.stats().hemicube.hemicubes > 0);
                // Progressive stops at an unshot fraction of 1e-4, which at
                // rho = 0.99 leaves 1e-4 / (1 - rho) = 1% of the light.
                let bound = match kind {
                    SolverKind::GaussSeidel => 2e-3,
                    SolverKind::Progressive => 2e-3 + 1e-4 / (1.0 - rho),
                };
                let exact = 1.0 / (1.0 - rho);
                let worst = sol
                    .leaves()
                    .iter()
                    .map(|l| rel(l.radiosity[0], exact))
                    .fold(0.0, f64::max);
                assert!(
                    worst < bound,
                    "{what}, rho {rho}, {kind:?}: an element off by {:.3}%",
                    100.0 * worst
                );
            }
        }
    }
}

#[test]
fn both_solvers_refuse_a_closed_room_with_a_wall_of_reflectance_one() {
    let mut faces = [FaceMaterial::grey(0.8, 0.0); 6];
    faces[1] = FaceMaterial::grey(0.8, 1.0);
    faces[4] = FaceMaterial::grey(1.0, 0.0);
    let scene = closed_box(DVec3::new(1.0, 0.8, 1.2), faces);
    let coarse = uniform(0.4, 1);
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let settings = Settings {
            solver_kind: kind,
            ..coarse.clone()
        };
        let error = radiosity::solve(&scene, &settings, &|_| {})
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("material 'x0'") && error.contains("lower it"),
            "{kind:?}: {error}"
        );
    }
    // A wall just below the limit is solved by both.
    faces[4] = FaceMaterial::grey(0.999, 0.0);
    let scene = closed_box(DVec3::new(1.0, 0.8, 1.2), faces);
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let settings = Settings {
            solver_kind: kind,
            ..coarse.clone()
        };
        assert!(
            radiosity::solve(&scene, &settings, &|_| {}).is_ok(),
            "{kind:?}"
        );
    }
}

#[test]
fn a_closed_scene_off_balance_is_warned_about_and_an_open_one_is_not() {
    // The progressive solver stopped after a few shots leaves most of the
    // light unshot: a closed scene then absorbs far less than it emits, but
    // that is the truncation, not an error of the form factors.
    let scene = lamp_room(0.9, false);
    let mut settings = with_solver(SolverKind::Progressive);
    settings.progressive.max_shots = Some(20);
    // No shaped gathers due, so no warning that a bounded solve skips them.
    settings.shaped_gathers = Some(0);
    let sol = solve(&scene, &settings);
    assert!(sol.stats().energy.truncated);
    assert!(sol.stats().energy.relative_difference < -0.5);
    assert!(
        sol.stats().warnings.is_empty(),
        "{:?}",
        sol.stats().warnings
    );
    // A converged solve of the same room balances, so nothing is said.
    let sol = solve(&scene, &with_solver(SolverKind::GaussSeidel));
    assert!(
        sol.stats().warnings.is_empty(),
        "{:?}",
        sol.stats().warnings
    );
    // The Cornell box is open: light escapes through its front, and its
    // balance is far from zero without a warning.
    let cornell = radiosity::scenes::cornell_box();
    let sol = solve(&cornell, &Settings::default());
    assert!(!sol.stats().energy.closed);
    assert!(sol.stats().energy.relative_difference < -0.2);
    assert!(sol.stats().energy.escaped_power[0] > 0.2 * sol.stats().energy.emitted_power[0]);
    assert!(
        sol.stats().warnings.is_empty(),
        "{:?}",
        sol.stats().warnings
    );
}
