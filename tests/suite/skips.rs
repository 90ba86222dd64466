//! Work a solve skips because the scene does not need it: each skip against
//! the same solve with that skip off (the same bits where the arithmetic is
//! the same, within hemi-cube error elsewhere) and, where there is one,
//! against an exact answer.

use super::common::{closed_box, rel, FaceMaterial};
use super::stress_scenes::{lit_room_with_box, quick_settings};
use glam::DVec3;
use radiosity::analytic::cube::unit_cube_radiosity;
use radiosity::formfactor::hemicube::{DeltaTable, Hemicube};
use radiosity::formfactor::{FormFactorMethod, RowState, SourcePolygon, Sources};
use radiosity::math::Rgb;
use radiosity::mesh::Cell;
use radiosity::pipeline::Skips;
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::solve::PatchSystem;
use radiosity::{scenes, Settings, Solution};
use std::collections::HashSet;
use std::sync::Arc;

fn solve(scene: &Scene, settings: &Settings) -> Solution {
    radiosity::solve(scene, settings, &|_| {}).unwrap()
}

/// `settings` with `change` applied to its skips.
fn with_skips(settings: &Settings, change: impl Fn(&mut Skips)) -> Settings {
    let mut s = settings.clone();
    change(&mut s.skips);
    s
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

fn leaf_radiosity_bits(sol: &Solution) -> Vec<u64> {
    sol.mesh()
        .leaves()
        .into_iter()
        .flat_map(|k| sol.radiosity().element(k).0.map(f64::to_bits))
        .collect()
}

fn patch_radiosity_bits(sol: &Solution) -> Vec<u64> {
    sol.patch_radiosity()
        .iter()
        .flat_map(|b| b.0.map(f64::to_bits))
        .collect()
}

fn row_bits(sol: &Solution) -> Vec<Vec<(u32, u32)>> {
    sol.mesh()
        .leaves()
        .into_iter()
        .map(|k| {
            sol.leaf(k)
                .entries()
                .iter()
                .map(|&(j, f)| (j, f.to_bits()))
                .collect()
        })
        .collect()
}

/// The same leaves, radiosities, patch radiosities and sweeps, bit for bit.
fn assert_same_solution(a: &Solution, b: &Solution, what: &str) {
    assert_eq!(
        a.stats().elements,
        b.stats().elements,
        "{what}: meshes differ"
    );
    assert!(
        leaf_radiosity_bits(a) == leaf_radiosity_bits(b),
        "{what}: leaf radiosities differ"
    );
    assert!(
        patch_radiosity_bits(a) == patch_radiosity_bits(b),
        "{what}: patch radiosities differ"
    );
    assert_eq!(
        a.stats().total_iterations,
        b.stats().total_iterations,
        "{what}: sweeps differ"
    );
}

fn surfaces_named(scene: &Scene, object: &str) -> Vec<u32> {
    let o = scene
        .objects
        .iter()
        .position(|x| x.name == object)
        .unwrap_or_else(|| panic!("no object {object}"));
    (0..scene.surfaces.len() as u32)
        .filter(|&s| scene.surfaces[s as usize].object as usize == o)
        .collect()
}

// ---- 1. Receivers that reflect nothing get no rows ----

#[test]
fn black_receivers_get_no_rows_and_change_no_radiosity() {
    // The light and the occluder reflect nothing; the floor reflects 0.5.
    // The occluder, which emits nothing either, gets no rows; the light
    // keeps its own, which say how much of its light reaches front faces.
    let scene = scenes::by_name("penumbra_parallel").unwrap();
    let base = Settings {
        hemicube_resolution: 64,
        ..Settings::default()
    };
    let skipped = solve(&scene, &base);
    let full = solve(&scene, &with_skips(&base, |s| s.zero_reflectance = false));
    assert_same_solution(&skipped, &full, "zero-reflectance skip");

    let black: HashSet<u32> = surfaces_named(&scene, "occluder").into_iter().collect();
    let light: HashSet<u32> = surfaces_named(&scene, "light").into_iter().collect();
    let mut black_leaves = 0u64;
    for k in skipped.mesh().leaves() {
        let (e, f) = (skipped.leaf(k), full.leaf(k));
        if black.contains(&e.surface()) {
            black_leaves += 1;
            assert_eq!(*e.row, RowState::Skipped, "a black leaf has a row");
            assert_eq!(e.radiosity, Rgb::ZERO);
        } else {
            assert!(
                !light.contains(&e.surface()) || !e.entries().is_empty(),
                "the light lost its rows"
            );
            assert_eq!(e.row, f.row, "a leaf's row changed");
        }
    }
    assert!(black_leaves > 0);
    assert_eq!(skipped.stats().skips.zero_reflectance_rows, black_leaves);
    assert_eq!(full.stats().skips.zero_reflectance_rows, 0);
    assert_eq!(
        skipped.stats().hemicube.hemicubes + black_leaves,
        full.stats().hemicube.hemicubes
    );
    // The power the black surfaces absorb now comes from the floor's rows by
    // reciprocity; it agrees with their own rows to within hemi-cube error.
    for band in 0..3 {
        let (a, b) = (
            skipped.stats().energy.absorbed_power[band],
            full.stats().energy.absorbed_power[band],
        );
        assert!(rel(a, b) < 1e-3, "band {band}: absorbed {a} against {b}");
        assert_eq!(
            skipped.stats().energy.emitted_power[band],
            full.stats().energy.emitted_power[band]
        );
    }
}

#[test]
fn a_black_emitter_facing_a_black_wall_keeps_its_rows_and_the_box_balances() {
    // A closed box: the ceiling emits and reflects nothing, the x0 wall
    // reflects nothing, the rest reflect 0.6. The wall absorbs the ceiling's
    // light directly, which only the ceiling's rows can count.
    let mut faces = [FaceMaterial::grey(0.6, 0.0); 6];
    faces[1] = FaceMaterial::grey(0.0, 1.0);
    faces[4] = FaceMaterial::grey(0.0, 0.0);
    let scene = closed_box(DVec3::new(1.0, 0.8, 1.2), faces);
    let base = uniform(0.25, 1);
    let skipped = solve(&scene, &base);
    let full = solve(&scene, &with_skips(&base, |s| s.zero_reflectance = false));
    assert_same_solution(&skipped, &full, "zero-reflectance skip");
    let (ceiling, wall) = (
        surfaces_named(&scene, "ceiling"),
        surfaces_named(&scene, "x0"),
    );
    let mut wall_leaves = 0;
    for k in skipped.mesh().leaves() {
        let e = skipped.leaf(k);
        if ceiling.contains(&e.surface()) {
            assert!(!e.entries().is_empty(), "the black emitter lost its rows");
        }
        if wall.contains(&e.surface()) {
            assert_eq!(*e.row, RowState::Skipped, "the black wall kept its rows");
            wall_leaves += 1;
        }
    }
    assert_eq!(skipped.stats().skips.zero_reflectance_rows, wall_leaves);
    // Closed: everything emitted is absorbed, on both paths, up to the
    // reciprocity error of form factors from element centroids (the wall's
    // own rows, or everyone else's).
    for sol in [&skipped, &full] {
        let d = sol.stats().energy.relative_difference;
        assert!(d.abs() < 0.005, "energy out of balance by {d}");
    }
}

// ---- 2. A grey scene solves one band ----

fn greyed(mut scene: Scene) -> Scene {
    for m in &mut scene.materials {
        m.reflectance = Rgb::splat(m.reflectance.mean());
        m.emission = Rgb::splat(m.emission.mean());
    }
    scene
}

#[test]
fn a_grey_scene_solved_on_one_band_gives_the_same_bits() {
    let scene = greyed(lit_room_with_box(1.0, 2.0, 0.01));
    let base = quick_settings(0.4);
    let one = solve(&scene, &base);
    let three = solve(&scene, &with_skips(&base, |s| s.grey = false));
    assert!(
        !one.stats().passes.is_empty(),
        "the test wants refinement passes"
    );
    assert_same_solution(&one, &three, "grey skip");
    assert_eq!(one.stats().solver, three.stats().solver);
    assert_eq!(
        one.stats().energy.absorbed_power,
        three.stats().energy.absorbed_power
    );
    assert_eq!(one.stats().skips.grey_solves, 1 + one.stats().passes.len());
    assert_eq!(three.stats().skips.grey_solves, 0);
    // A coloured scene is solved on three bands.
    let coloured = solve(&lit_room_with_box(1.0, 2.0, 0.01), &base);
    assert_eq!(coloured.stats().skips.grey_solves, 0);
}

// ---- 3. Convex enclosures: exact rows, no hemi-cube ----

/// Whether the solve of `scene` took every row from the convex-enclosure
/// shortcut (Lambert's formula, no hemi-cube), at coarse settings.
fn took_exact_rows(scene: &Scene) -> bool {
    let settings = Settings {
        hemicube_resolution: 32,
        patch_size: Some(scene.diameter() / 4.0),
        ..uniform(1.0, 0)
    };
    let sol = solve(scene, &settings);
    let exact = sol.stats().skips.exact_rows;
    assert!(exact == 0 || exact == sol.stats().elements as u64);
    exact > 0
}

#[test]
fn convex_enclosures_are_told_from_scenes_with_occlusion() {
    let cube = closed_box(DVec3::new(1.0, 0.7, 1.3), [FaceMaterial::grey(0.5, 1.0); 6]);
    assert!(took_exact_rows(&cube));
    // An open part of an enclosure: a floor and a light facing down at it.
    let mut b = SceneBuilder::new("floor_and_light");
    let m = b.material("m", Rgb::splat(0.5), Rgb::splat(1.0)).unwrap();
    b.object("floor");
    let p = DVec3::new;
    b.polygon(
        m,
        &[p(0., 0., 0.), p(0., 0., 1.), p(1., 0., 1.), p(1., 0., 0.)],
    )
    .unwrap();
    b.object("light");
    b.polygon(
        m,
        &[
            p(0.2, 1., 0.2),
            p(0.8, 1., 0.2),
            p(0.8, 1., 0.8),
            p(0.2, 1., 0.8),
        ],
    )
    .unwrap();
    assert!(took_exact_rows(&b.build().unwrap()));
    // Blocks in a room, an occluder under a light, a box in a room.
    assert!(!took_exact_rows(&scenes::cornell_box()));
    let penumbra = scenes::by_name("penumbra_parallel").unwrap();
    assert!(!took_exact_rows(&penumbra));
    assert!(!took_exact_rows(&lit_room_with_box(1.0, 1.0, 0.01)));
}

#[test]
fn six_patch_cube_rows_are_exact_and_agree_with_the_analytic_cube() {
    for rho in [0.5, 0.8] {
        let mut faces = [FaceMaterial::grey(rho, 0.0); 6];
        faces[1] = FaceMaterial::grey(rho, 1.0);
        let scene = closed_box(DVec3::ONE, faces);
        // One patch a face, 16 x 16 elements on each, gathered by patch
        // means: the analytic cube solves the six-patch system, which a
        // shaped gather leaves for the continuous solution (see
        // `enclosures::one_shaped_gather_brings_a_six_patch_cube_to_the_path_traced_floor`).
        let settings = Settings {
            shaped_gathers: Some(0),
            ..uniform(1.0, 4)
        };
        let exact = solve(&scene, &settings);
        let cubed = solve(&scene, &with_skips(&settings, |s| s.convex = false));
        assert_eq!(exact.stats().patches, 6);
        assert_eq!(
            exact.stats().skips.exact_rows,
            exact.stats().elements as u64
        );
        assert_eq!(exact.stats().hemicube.hemicubes, 0);
        assert_eq!(cubed.stats().skips.exact_rows, 0);
        assert_eq!(
            cubed.stats().hemicube.hemicubes,
            cubed.stats().elements as u64
        );
        // The analytic cube (closed forms of Howell C-11 and C-14).
        let mut e = [0.0; 6];
        e[1] = 1.0;
        let truth = unit_cube_radiosity([rho; 6], e).unwrap();
        // The cube's faces in `closed_box` order: floor, ceiling, z0, z1, x0,
        // x1; the analytic order is floor, ceiling, x0, x1, z0, z1.
        let order = [0, 1, 4, 5, 2, 3];
        for (face, &t) in order.iter().enumerate() {
            let (x, h) = (
                exact.patch_radiosity()[face][0],
                cubed.patch_radiosity()[face][0],
            );
            // 16 x 16 element centroids integrate the exact area-to-area form
            // factors by the midpoint rule: 3e-4 at most at this depth.
            assert!(
                rel(x, truth[t]) < 5e-4,
                "rho {rho} face {face}: exact rows {x} vs {}",
                truth[t]
            );
            assert!(
                rel(h, truth[t]) < 5e-3,
                "rho {rho} face {face}: hemi-cubes {h} vs {}",
                truth[t]
            );
            // The hybrid hemi-cube is exact for unoccluded patches as well
            // (each wins every pixel it covers), so the two agree to rounding.
            assert!(rel(x, h) < 1e-6, "rho {rho} face {face}: {x} vs {h}");
        }
    }
}

#[test]
fn exact_rows_of_a_furnace_sum_to_one() {
    // Every face reflects 0.9 and emits 1: B = 1 / (1 - 0.9) = 10 everywhere
    // when every row sums to 1. The solver's error bound is 1e-5 of the
    // largest radiosity; a row-sum error d adds d / (1 - 0.9).
    let scene = closed_box(DVec3::new(1.0, 0.8, 1.2), [FaceMaterial::grey(0.9, 1.0); 6]);
    let sol = solve(&scene, &uniform(0.3, 1));
    assert_eq!(sol.stats().skips.exact_rows, sol.stats().elements as u64);
    for e in sol.leaves() {
        assert!((e.row_sum() - 1.0).abs() < 1e-6, "row sum {}", e.row_sum());
        assert!(
            rel(e.radiosity[0], 10.0) < 2e-5,
            "radiosity {}",
            e.radiosity[0]
        );
    }
}

// ---- 4. Hemi-cube faces nothing was drawn into ----

fn square_source(centre: DVec3, facing: DVec3, half: f64, surface: u32) -> SourcePolygon {
    let n = facing.normalize();
    let t = n.any_orthonormal_vector();
    let b = n.cross(t);
    let v = [
        centre - t * half - b * half,
        centre + t * half - b * half,
        centre + t * half + b * half,
        centre - t * half + b * half,
    ];
    SourcePolygon::new(&v, n, surface)
}

#[test]
fn hemicube_rows_are_the_same_bits_when_empty_faces_are_skipped() {
    // A small square straight above, one low on the +x side, one far off on
    // the -y side, and one below the horizon.
    let sources = Sources::one_per_patch(vec![
        square_source(DVec3::new(0.0, 0.0, 2.0), -DVec3::Z, 0.2, 1),
        square_source(DVec3::new(3.0, 0.2, 0.5), -DVec3::X, 0.4, 2),
        square_source(DVec3::new(0.3, -4.0, 1.5), DVec3::Y, 1.0, 3),
        square_source(DVec3::new(0.0, 0.0, -1.0), DVec3::Z, 1.0, 4),
    ]);
    let table = Arc::new(DeltaTable::new(64));
    let mut skipping = Hemicube::new(Arc::clone(&table), 4);
    let mut full = Hemicube::new(table, 4);
    full.set_skip_empty_faces(false);
    // Eyes that see different subsets, one after the other in the same
    // buffers, so that a rectangle left uncleared would show.
    let eyes = [
        (DVec3::ZERO, DVec3::Z),
        (
            DVec3::new(0.1, 0.1, 0.0),
            DVec3::new(0.2, 0.0, 1.0).normalize(),
        ),
        (DVec3::new(1.0, 0.0, 0.5), DVec3::X),
        (DVec3::ZERO, DVec3::Z),
        (DVec3::new(0.0, 0.0, 1.0), -DVec3::Y),
    ];
    for method in [FormFactorMethod::Hemicube, FormFactorMethod::Hybrid] {
        for (i, &(eye, normal)) in eyes.iter().enumerate() {
            let angle = 0.3 * i as f64;
            let a = skipping.row(&sources, eye, normal, angle, 0, method);
            let b = full.row(&sources, eye, normal, angle, 0, method);
            let bits = |r: &radiosity::formfactor::Row| {
                r.entries()
                    .iter()
                    .map(|&(j, f)| (j, f.to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&a), bits(&b), "{method:?} eye {i}");
        }
    }
    assert!(skipping.stats.empty_faces > 0 && skipping.stats.pixels_skipped > 0);
    assert_eq!((full.stats.empty_faces, full.stats.pixels_skipped), (0, 0));
    // Looking straight up at the small square only: four side faces empty.
    let only_above = Sources::one_per_patch(vec![sources.polygons[0].clone()]);
    let mut cube = Hemicube::new(Arc::new(DeltaTable::new(64)), 1);
    let row = cube.row(
        &only_above,
        DVec3::ZERO,
        DVec3::Z,
        0.0,
        0,
        FormFactorMethod::Hemicube,
    );
    assert_eq!(row.len(), 1);
    assert_eq!(cube.stats.empty_faces, 4);
}

#[test]
fn an_open_scene_skips_empty_faces_with_the_same_bits() {
    let scene = scenes::by_name("penumbra_parallel").unwrap();
    let base = Settings {
        hemicube_resolution: 64,
        ..Settings::default()
    };
    let skipped = solve(&scene, &base);
    let full = solve(&scene, &with_skips(&base, |s| s.empty_faces = false));
    assert_same_solution(&skipped, &full, "empty-face skip");
    assert!(row_bits(&skipped) == row_bits(&full), "rows differ");
    assert!(skipped.stats().skips.empty_faces > 0);
    assert!(skipped.stats().skips.pixels_skipped > 0);
    assert_eq!(full.stats().skips.pixels_skipped, 0);
}

// ---- 5. Back faces that front faces always hide ----

#[test]
fn skipping_hidden_back_faces_keeps_radiosities_and_shut_in_elements() {
    // A closed box floating in a lit room.
    let scene = lit_room_with_box(1.0, 2.0, 0.01);
    let base = quick_settings(0.4);
    let skipped = solve(&scene, &base);
    let full = solve(&scene, &with_skips(&base, |s| s.hidden_back_faces = false));
    assert!(skipped.stats().skips.back_faces_skipped > 0);
    assert_eq!(full.stats().skips.back_faces_skipped, 0);
    assert!(skipped.stats().hemicube.pixels_tested < full.stats().hemicube.pixels_tested);
    // Only silhouette pixels, where a front and a back face meet at equal
    // depth, can change hands, and the hybrid rows take only the fraction of
    // a patch's pixels it won from them: object means barely move.
    let (a, b) = (
        skipped.object_radiosity(&scene),
        full.object_radiosity(&scene),
    );
    for (x, y) in a.iter().zip(&b) {
        for band in 0..3 {
            assert!(
                rel(x.radiosity[band], y.radiosity[band]) < 1e-5,
                "{}: {} against {}",
                x.name,
                x.radiosity[band],
                y.radiosity[band]
            );
        }
    }
}

#[test]
fn a_floor_under_an_open_block_still_sees_nothing() {
    // Cornell blocks are open at the floor: floor elements under them see
    // only back faces, which must still be drawn.
    let scene = scenes::cornell_box();
    let base = Settings {
        hemicube_resolution: 32,
        ..uniform(0.1, 1)
    };
    let skipped = solve(&scene, &base);
    let full = solve(&scene, &with_skips(&base, |s| s.hidden_back_faces = false));
    let shut_in = |sol: &Solution| -> Vec<bool> {
        sol.mesh()
            .leaves()
            .into_iter()
            .map(|k| matches!(sol.leaf(k).row, RowState::ShutIn(_)))
            .collect()
    };
    let (a, b) = (shut_in(&skipped), shut_in(&full));
    assert!(
        a.iter().filter(|x| **x).count() > 0,
        "no element under a block"
    );
    assert_eq!(a, b, "elements under the blocks changed");
    assert!(skipped.stats().skips.back_faces_skipped > 0);
}

// ---- 6. A refinement pass touches only what changed ----

/// Leaves as (surface, cell): the same element across solves.
fn leaf_cells(sol: &Solution) -> HashSet<(u32, Cell)> {
    sol.mesh()
        .leaves()
        .into_iter()
        .map(|k| {
            let e = &sol.mesh()[k];
            (e.surface(), e.cell())
        })
        .collect()
}

#[test]
fn refinement_passes_compute_hemicubes_for_new_leaves_only() {
    let scene = lit_room_with_box(1.0, 2.0, 0.01);
    let mut base = quick_settings(0.4);
    base.refine.tolerance = 0.02;
    base.refine.max_depth = 3;
    let runs: Vec<Solution> = (0..=2)
        .map(|passes| {
            let mut s = base.clone();
            s.refine.max_passes = passes;
            solve(&scene, &s)
        })
        .collect();
    assert_eq!(runs[2].stats().passes.len(), 2, "the test wants two passes");
    // The first solve renders one hemi-cube per leaf.
    assert_eq!(
        runs[0].stats().hemicube.hemicubes,
        runs[0].stats().elements as u64
    );
    let mut total = runs[0].stats().hemicube.hemicubes;
    for pass in 0..2 {
        let before = leaf_cells(&runs[pass]);
        let after = leaf_cells(&runs[pass + 1]);
        let new = after.difference(&before).count();
        let stats = &runs[2].stats().passes[pass];
        assert_eq!(stats.new_hemicubes, new, "pass {}", pass + 1);
        assert!(new < after.len(), "pass {} recomputed everything", pass + 1);
        total += new as u64;
    }
    assert_eq!(runs[2].stats().hemicube.hemicubes, total);
    // Only patches with new leaves had their rows re-summed, and the patch
    // system is what a rebuild from every row gives, bit for bit.
    let last = &runs[2];
    assert!(last.stats().skips.patch_rows_refreshed > 0);
    assert!(last.stats().skips.patch_rows_refreshed < 2 * last.stats().patches);
    let rebuilt = PatchSystem::from_mesh(last.mesh(), last.form_factors());
    assert!(
        rebuilt.rows == last.patch_system().rows,
        "refreshed rows differ from a rebuild"
    );
}
