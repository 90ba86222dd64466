//! Randomised scenes: floating boxes in a closed, lit room with random
//! reflectances. Whatever the layout, the structural invariants of the method
//! must hold (algorithms.md 4.6), and the progressive solver must meet the
//! gathering one.

use super::stress_scenes::{
    assert_finite_non_negative, energy_errors, leaves, quick_settings, room_faces, v,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};
use radiosity::math::Rgb;
use radiosity::pipeline::{ProgressiveSettings, SolverKind};
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::{Settings, Solution};

/// One floating box: its cell of a 2 x 2 grid on the floor (so boxes never
/// overlap), its extent within the cell (fractions) and its reflectance.
#[derive(Clone, Debug)]
struct RandomBox {
    cell: usize,
    x: (f64, f64),
    z: (f64, f64),
    y: (f64, f64),
    reflectance: [f64; 3],
}

#[derive(Clone, Debug)]
struct RandomScene {
    walls: [f64; 6],
    radiance: [f64; 3],
    boxes: Vec<RandomBox>,
}

fn reflectance() -> impl Strategy<Value = f64> {
    0.0..0.95f64
}

fn random_box() -> impl Strategy<Value = RandomBox> {
    (
        0..4usize,
        (0.05..0.45f64, 0.55..0.95f64),
        (0.05..0.45f64, 0.55..0.95f64),
        (0.05..0.5f64, 0.6..1.3f64),
        [reflectance(), reflectance(), reflectance()],
    )
        .prop_map(|(cell, x, z, y, reflectance)| RandomBox {
            cell,
            x,
            z,
            y,
            reflectance,
        })
}

fn random_scene() -> impl Strategy<Value = RandomScene> {
    (
        [
            reflectance(),
            reflectance(),
            reflectance(),
            reflectance(),
            reflectance(),
            reflectance(),
        ],
        [0.2..5.0f64, 0.2..5.0f64, 0.2..5.0f64],
        prop::collection::vec(random_box(), 0..=3),
    )
        .prop_map(|(walls, radiance, boxes)| RandomScene {
            walls,
            radiance,
            boxes,
        })
}

/// Room `2 x 1.6 x 2.4`; each wall its own grey; a glowing slab 20 cm below
/// the ceiling; boxes in distinct cells (a later box in a taken cell is
/// dropped).
fn build(spec: &RandomScene) -> Scene {
    let mut b = SceneBuilder::new("random");
    let walls: Vec<u32> = spec
        .walls
        .iter()
        .enumerate()
        .map(|(i, rho)| {
            b.material(&format!("wall {i}"), Rgb::splat(*rho), Rgb::ZERO)
                .unwrap()
        })
        .collect();
    room_faces(
        &mut b,
        v(0.0, 0.0, 0.0),
        v(2.0, 1.6, 2.4),
        std::array::from_fn(|i| walls[i]),
    );
    let light = b
        .material(
            "light",
            Rgb::splat(0.1),
            Rgb::new(spec.radiance[0], spec.radiance[1], spec.radiance[2]),
        )
        .unwrap();
    // A glowing slab rather than a one-sided quad: a quad's back would hide
    // the ceiling above it from itself, and those ceiling rows would sum to 0.
    b.axis_box("light", light, v(0.8, 1.35, 1.0), v(1.2, 1.4, 1.4))
        .unwrap();
    let mut taken = [false; 4];
    for (k, bx) in spec.boxes.iter().enumerate() {
        if std::mem::replace(&mut taken[bx.cell], true) {
            continue;
        }
        let (cx, cz) = ((bx.cell % 2) as f64, (bx.cell / 2) as f64);
        let m = b
            .material(
                &format!("box {k}"),
                Rgb::new(bx.reflectance[0], bx.reflectance[1], bx.reflectance[2]),
                Rgb::ZERO,
            )
            .unwrap();
        let lo = v(cx + bx.x.0, bx.y.0, 1.2 * (cz + bx.z.0));
        let hi = v(cx + bx.x.1, bx.y.1, 1.2 * (cz + bx.z.1));
        b.axis_box(&format!("box {k}"), m, lo, hi).unwrap();
    }
    b.build().unwrap()
}

/// Checks every invariant on one scene.
fn check(spec: &RandomScene) -> Result<(), TestCaseError> {
    let scene = build(spec);
    let sol = radiosity::solve(&scene, &quick_settings(0.5), &|_| {})
        .map_err(|e| TestCaseError::fail(format!("solve failed: {e}")))?;
    assert_finite_non_negative(&sol, "random scene");

    // Closed scene, every receiver outside every solid: each row sums to 1
    // within the hemi-cube's error. With hybrid rows, unoccluded patches get
    // exact form factors, so the error comes from patches partly hidden, whose
    // visible fraction is a pixel count: it is about the delta form factor of
    // a one-pixel band along the occluding silhouettes. At 64 pixels a face a
    // pixel is worth up to 3e-4, and a box's silhouette crosses some 60 pixels.
    let mut worst_row: f64 = 0.0;
    for e in leaves(&sol) {
        // A black receiver gets no row: it reflects nothing of what it sees.
        if sol.mesh().surfaces()[e.surface() as usize]
            .reflectance
            .max_band()
            == 0.0
        {
            continue;
        }
        worst_row = worst_row.max((e.row_sum() - 1.0).abs());
    }
    prop_assert!(worst_row < 0.02, "row sum off by {}", worst_row);

    // Emitted power = absorbed power.
    let energy = energy_errors(&sol);
    for (band, err) in energy.iter().enumerate() {
        prop_assert!(err.abs() < 0.01, "band {}: energy balance {}", band, err);
    }

    eprintln!(
        "random scene: {} surfaces, {} elements, worst row-sum error {worst_row:.1e}, energy \
         {:+.1e} {:+.1e} {:+.1e}",
        scene.surfaces.len(),
        sol.stats().elements,
        energy[0],
        energy[1],
        energy[2]
    );

    // Substructuring: each patch is the area mean of its elements, to the
    // solver's tolerance (1e-5 of the brightest patch).
    let brightest = sol
        .patch_radiosity()
        .iter()
        .map(|b| b.max_band())
        .fold(0.0, f64::max);
    for (i, p) in sol.mesh().patches().iter().enumerate() {
        let mut sum = Rgb::ZERO;
        for k in sol.mesh().patch_leaves(i as u32) {
            sum += sol.radiosity().element(k) * sol.mesh()[k].area();
        }
        for band in 0..3 {
            let mean = sum[band] / p.area();
            prop_assert!(
                (mean - sol.patch_radiosity()[i][band]).abs() <= 1e-5 * brightest,
                "patch {}: elements {} patch {}",
                i,
                mean,
                sol.patch_radiosity()[i][band]
            );
        }
    }
    // The shots gather patch means; held to the gathering solver, both
    // gather means (no shaped gathers) and refine by neighbour differences
    // only (no facing splits), which keeps their meshes close.
    let quick = quick_settings(0.5);
    let means = Settings {
        shaped_gathers: Some(0),
        refine: RefineSettings {
            facing_split: false,
            ..quick.refine.clone()
        },
        ..quick
    };
    let sol = radiosity::solve(&scene, &means, &|_| {})
        .map_err(|e| TestCaseError::fail(format!("solve failed: {e}")))?;
    check_progressive(&scene, &sol, &means)
}

/// The progressive solver on the same scene: finite, never raising the unshot
/// power, balancing energy, and meeting the gathering solution per object.
fn check_progressive(
    scene: &Scene,
    gathered: &Solution,
    gathered_with: &Settings,
) -> Result<(), TestCaseError> {
    let settings = Settings {
        solver_kind: SolverKind::Progressive,
        progressive: ProgressiveSettings {
            tolerance: 1e-5,
            ..ProgressiveSettings::default()
        },
        ..gathered_with.clone()
    };
    let shot = radiosity::solve(scene, &settings, &|_| {})
        .map_err(|e| TestCaseError::fail(format!("progressive solve failed: {e}")))?;
    assert_finite_non_negative(&shot, "random scene, progressive");
    let f = shot
        .stats()
        .progressive
        .as_ref()
        .expect("progressive figures");
    prop_assert_eq!(f.unshot_increases, 0);
    prop_assert!(f.rows_gathered_after_shots.is_some());
    for (band, err) in energy_errors(&shot).iter().enumerate() {
        prop_assert!(
            err.abs() < 0.01,
            "progressive band {}: energy balance {}",
            band,
            err
        );
    }
    // Relative differences, with a floor of 1% of the brightest object's
    // radiosity in the band: a nearly black wall's last digits are noise.
    let objects = gathered.object_radiosity(scene);
    let mut floor = [0.0f64; 3];
    for o in &objects {
        for (band, f) in floor.iter_mut().enumerate() {
            *f = f.max(0.01 * o.radiosity[band]);
        }
    }
    let mut worst: f64 = 0.0;
    for (g, p) in objects.iter().zip(shot.object_radiosity(scene)) {
        for (band, least) in floor.iter().enumerate() {
            let (a, b) = (g.radiosity[band], p.radiosity[band]);
            let d = (a - b).abs() / a.abs().max(*least).max(1e-12);
            worst = worst.max(d);
            // Measured at most 0.89% over the ten scenes: the two solvers refine
            // at different moments, so their meshes differ a little.
            prop_assert!(
                d < 0.02,
                "{} band {}: progressive {} gathering {}",
                g.name,
                band,
                b,
                a
            );
        }
    }
    eprintln!(
        "random scene, progressive: worst per-object difference {:.3}%",
        100.0 * worst
    );
    Ok(())
}

#[test]
fn random_boxes_in_a_closed_room_keep_every_invariant() {
    let config = Config {
        cases: 10,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(0x5eed_0008),
        max_shrink_iters: 8,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    if let Err(e) = runner.run(&random_scene(), |spec| check(&spec)) {
        panic!("{e}");
    }
}
