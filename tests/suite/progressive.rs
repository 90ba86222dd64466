//! The progressive (shooting) solver: exact oracles, agreement with
//! Gauss-Seidel on the Cornell box, monotone unshot power, the ambient term,
//! and the stopping rules.

use super::common::{closed_box, rel, FaceMaterial};
use glam::DVec3;
use radiosity::analytic::{furnace_radiosity, unit_cube_ceiling_lit};
use radiosity::formfactor::FormFactorMethod;
use radiosity::math::Rgb;
use radiosity::pipeline::{solve_with_previews, Progress, Stage};
use radiosity::pipeline::{ProgressiveSettings, SolverKind};
use radiosity::refine::RefineSettings;
use radiosity::solution::StopReason;
use radiosity::{scenes, Settings, Solution};
use std::sync::Mutex;
use std::time::Duration;

fn progressive(settings: Settings, p: ProgressiveSettings) -> Settings {
    Settings {
        solver_kind: SolverKind::Progressive,
        progressive: p,
        ..settings
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

/// The Cornell box at a coarse patch size, refined adaptively to depth 3.
fn coarse_cornell() -> Settings {
    Settings {
        patch_size: Some(0.14),
        refine: RefineSettings {
            max_depth: 3,
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

/// The Gauss-Seidel and the progressive solution (with `p`) of `scene` at
/// `settings`.
fn gathered_and_shot(
    scene: &radiosity::scene::Scene,
    settings: &Settings,
    p: ProgressiveSettings,
) -> (Solution, Solution) {
    // The shots take every patch by its mean: with no shaped gathers after
    // them (which the gathering solver makes once it takes the converged
    // shots over), the shots' own solution is what is held to the gathering
    // solve, which then gathers means too.
    let flat = Settings {
        shaped_gathers: Some(0),
        ..settings.clone()
    };
    let gathered = radiosity::solve(scene, &flat, &|_| {}).unwrap();
    let shot = radiosity::solve(scene, &progressive(flat, p), &|_| {}).unwrap();
    (gathered, shot)
}

fn stats(sol: &Solution) -> &radiosity::solution::ProgressiveStats {
    sol.stats()
        .progressive
        .as_ref()
        .expect("a progressive solve reports its figures")
}

#[test]
fn furnace_converges_to_e_over_one_minus_rho() {
    // Uniform emission and reflectance in a closed box: B = E / (1 - rho)
    // everywhere, whatever the form factors, as long as they are right.
    for method in [FormFactorMethod::Hybrid, FormFactorMethod::Hemicube] {
        let rho = 0.5;
        let scene = closed_box(DVec3::new(1.0, 0.8, 1.2), [FaceMaterial::grey(rho, 1.0); 6]);
        let s = progressive(
            Settings {
                form_factors: method,
                ..uniform(0.3, 1)
            },
            ProgressiveSettings::default(),
        );
        let sol = radiosity::solve(&scene, &s, &|_| {}).unwrap();
        assert_eq!(stats(&sol).stop, StopReason::Converged);
        let exact = furnace_radiosity(1.0, rho).unwrap();
        // The classic reciprocal `F_ie A_i / A_e` inherits the aliasing of the
        // element's pixel count (about 1 % RMS here); the hybrid's magnitude is
        // exact. Either way every shot's row sums to one in a closed box, so
        // the mean is right.
        let tolerance = match method {
            FormFactorMethod::Hybrid => 0.005,
            FormFactorMethod::Hemicube => 0.04,
        };
        let (mut sum, mut area) = (0.0, 0.0);
        for e in sol.leaves() {
            sum += e.radiosity[0] * e.area();
            area += e.area();
            for band in 0..3 {
                assert!(
                    rel(e.radiosity[band], exact) < tolerance,
                    "{method:?}: element {} vs exact {exact}",
                    e.radiosity[band]
                );
            }
        }
        assert!(
            rel(sum / area, exact) < 0.002,
            "{method:?}: mean {} vs exact {exact}",
            sum / area
        );
    }
}

#[test]
fn six_patch_cube_converges_to_the_exact_solution() {
    // One patch a face, 16 x 16 elements on each; the exact discrete solution
    // comes from the closed-form face-to-face form factors.
    for rho in [0.5, 0.8] {
        let exact = unit_cube_ceiling_lit(rho).unwrap();
        let mut faces = [FaceMaterial::grey(rho, 0.0); 6];
        faces[1] = FaceMaterial::grey(rho, 1.0);
        let scene = closed_box(DVec3::ONE, faces);
        // The exact solution is that of the patch system, which gathers
        // every patch by its mean: no shaped gathers after the shots.
        let mesh = Settings {
            shaped_gathers: Some(0),
            ..uniform(1.0, 4)
        };
        let s = progressive(mesh, ProgressiveSettings::default());
        let sol = radiosity::solve(&scene, &s, &|_| {}).unwrap();
        assert_eq!(sol.stats().patches, 6);
        for (face, (b, x)) in sol.patch_radiosity().iter().zip(exact).enumerate() {
            assert!(
                rel(b[0], x) < 0.005,
                "rho {rho} face {face}: {} vs exact {x}",
                b[0]
            );
        }
    }
}

/// The Cornell box's settings both solvers are compared at: the defaults,
/// `coarse_cornell`, and the defaults with shooter-side factors throughout
/// (no gathered rows).
fn cornell_cases() -> [(Settings, ProgressiveSettings); 3] {
    let shooting_only = ProgressiveSettings {
        gather_rows: false,
        ..ProgressiveSettings::default()
    };
    [
        (Settings::default(), ProgressiveSettings::default()),
        (coarse_cornell(), ProgressiveSettings::default()),
        (Settings::default(), shooting_only),
    ]
}

#[test]
fn agrees_with_gauss_seidel_per_surface_on_the_cornell_box() {
    // At the default settings (what users run; measured 0.17% at most), and
    // at the coarser settings of `coarse_cornell` (0.34%). The meshes differ
    // a little: the progressive solve refines while it shoots. Shooter-side
    // factors throughout (no gathered rows) meet the check too (0.67%).
    let scene = scenes::cornell_box();
    for (settings, p) in cornell_cases() {
        agrees_per_surface(&scene, &settings, p);
    }
}

#[test]
fn converged_shots_end_within_a_fifth_of_a_percent_of_gauss_seidel_at_default_settings() {
    // At default settings both solvers end in the shaped gathers: the
    // progressive solver hands its converged solution to the gathering
    // solver, which solves the patch system from it and shapes. Only the
    // refined meshes differ (each refines where its light was uneven when
    // it looked). Measured 0.011% at most at the defaults. Shots by
    // shooter-side factors throughout (no gathered rows) leave most leaves
    // without a row: the gathering solver renders them when it takes over.
    let scene = scenes::cornell_box();
    for (settings, p) in cornell_cases() {
        let gathered = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
        let shot = radiosity::solve(&scene, &progressive(settings.clone(), p), &|_| {}).unwrap();
        assert_eq!(stats(&shot).stop, StopReason::Converged);
        assert!(
            shot.stats().shaped_sources.iter().any(|&n| n > 0),
            "the test needs a shaped gather"
        );
        assert!(
            shot.stats().warnings.is_empty(),
            "{:?}",
            shot.stats().warnings
        );
        assert_objects_agree(&scene, &gathered, &shot, 0.002);
    }
}

/// Asserts that every object's radiosity in the progressive solution `shot`
/// is within `bound` of the gathering solution's, relatively, per band.
fn assert_objects_agree(
    scene: &radiosity::scene::Scene,
    gathered: &Solution,
    shot: &Solution,
    bound: f64,
) {
    for (g, p) in gathered
        .object_radiosity(scene)
        .iter()
        .zip(shot.object_radiosity(scene))
    {
        for band in 0..3 {
            let d = rel(p.radiosity[band], g.radiosity[band]);
            assert!(
                d < bound,
                "{} band {band}: progressive {} Gauss-Seidel {} ({:.3}%)",
                g.name,
                p.radiosity[band],
                g.radiosity[band],
                100.0 * d
            );
        }
    }
}

fn agrees_per_surface(
    scene: &radiosity::scene::Scene,
    settings: &Settings,
    p: ProgressiveSettings,
) {
    let (gathered, shot) = gathered_and_shot(scene, settings, p);
    let figures = stats(&shot);
    assert_eq!(figures.stop, StopReason::Converged);
    assert!(!figures.passes.is_empty(), "the test needs refinement");
    assert_eq!(figures.unshot_increases, 0);
    assert_objects_agree(scene, &gathered, &shot, 0.01);
    // The substructuring invariant holds for the shot solution too.
    for (i, patch) in shot.mesh().patches().iter().enumerate() {
        let mut sum = Rgb::ZERO;
        for k in shot.mesh().patch_leaves(i as u32) {
            sum += shot.radiosity().element(k) * shot.mesh()[k].area();
        }
        let mean = sum / patch.area();
        assert!((mean - shot.patch_radiosity()[i]).abs().max_band() <= 1e-9 * mean.max_band());
    }
}

/// The unshot fraction after every shot, split into runs between refinement
/// passes (a pass lets new elements see the shot light better, which may
/// change the unshot power; a shot may not raise it).
fn unshot_runs(reports: &[Progress]) -> Vec<Vec<f64>> {
    let mut runs = vec![Vec::new()];
    for r in reports {
        match r.stage {
            Stage::Shoot {
                unshot_fraction, ..
            } => runs.last_mut().unwrap().push(unshot_fraction),
            Stage::FormFactors { .. } => runs.push(Vec::new()),
            Stage::Solve | Stage::PartViews | Stage::SharedRows { .. } | Stage::LightGroups => {}
        }
    }
    runs
}

#[test]
fn unshot_power_never_increases_from_one_shot_to_the_next() {
    let scene = scenes::cornell_box();
    for method in [FormFactorMethod::Hybrid, FormFactorMethod::Hemicube] {
        let reports = Mutex::new(Vec::new());
        let s = progressive(
            Settings {
                form_factors: method,
                ..coarse_cornell()
            },
            ProgressiveSettings {
                max_shots: Some(250),
                ..ProgressiveSettings::default()
            },
        );
        let sol = radiosity::solve(&scene, &s, &|p| reports.lock().unwrap().push(p)).unwrap();
        let figures = stats(&sol);
        assert_eq!(figures.unshot_increases, 0, "{method:?}");
        assert_eq!(figures.scaled_shots, 0, "{method:?}");
        let runs = unshot_runs(&reports.into_inner().unwrap());
        assert!(
            runs.len() > 1,
            "{method:?}: the test needs refinement passes"
        );
        let mut shots = 0;
        for run in runs {
            shots += run.len();
            for w in run.windows(2) {
                assert!(
                    w[1] <= w[0],
                    "{method:?}: unshot fraction rose from {} to {}",
                    w[0],
                    w[1]
                );
            }
        }
        assert_eq!(shots, 250);
    }
}

#[test]
fn ambient_term_goes_to_zero_and_is_never_stored() {
    let scene = scenes::cornell_box();
    let ceiling = scene
        .objects
        .iter()
        .position(|o| o.name == "ceiling")
        .unwrap();
    // A fixed mesh, so that the unshot power only falls.
    let settings = progressive(
        uniform(0.14, 1),
        ProgressiveSettings {
            preview_every: Some(1),
            ..ProgressiveSettings::default()
        },
    );
    let mut previews: Vec<(usize, Rgb, f64, f64)> = Vec::new();
    let sol = solve_with_previews(&scene, &settings, &|_| {}, &mut |p| {
        let stored = p.object_radiosity(&scene, false)[ceiling].radiosity;
        let shown = p.object_radiosity(&scene, true)[ceiling].radiosity;
        previews.push((p.shots, p.ambient, stored.max_band(), shown.max_band()));
    })
    .unwrap();
    let figures = stats(&sol);
    assert_eq!(previews.len(), figures.shots);

    // After the first shot (the light: it cannot see the ceiling behind it),
    // the ceiling has received nothing, yet the preview shows it lit.
    let (shots, ambient, stored, shown) = previews[0];
    assert_eq!(shots, 1);
    assert_eq!(stored, 0.0);
    assert!(shown > 0.0 && ambient.max_band() > 0.0);

    // Without refinement no unshot radiosity is negative, so the ambient term
    // falls with the unshot power, band by band; but for the one step where
    // the gathered rows take over from the fan of rays: rows that find floor
    // leaves partly under a block let their visible part stand for them as
    // sources, which raises what their patches have left to shoot.
    let adopted = figures.rows_gathered_after_shots;
    let mut rises = 0;
    for w in previews.windows(2) {
        if adopted.is_some_and(|a| w[0].0 <= a && a <= w[1].0)
            && (0..3).any(|band| w[1].1[band] > w[0].1[band])
        {
            rises += 1;
            continue;
        }
        for band in 0..3 {
            assert!(
                w[1].1[band] <= w[0].1[band],
                "ambient rose: {:?} -> {:?}",
                w[0].1,
                w[1].1
            );
        }
    }
    assert!(rises <= 1, "{rises}");
    // At convergence it is at most the unshot power over the absorbing area,
    // a 1e-4 fraction of the emitted power.
    let last = previews.last().unwrap().1;
    assert!(
        last.max_band() < 1e-3 * ambient.max_band(),
        "{last:?} vs {ambient:?}"
    );
    assert_eq!(figures.ambient, last);

    // The stored solution is exactly the last preview's leaves, without the
    // ambient term: a run stopped after the first shot stores a black ceiling.
    let one = radiosity::solve(
        &scene,
        &progressive(
            uniform(0.14, 1),
            ProgressiveSettings {
                max_shots: Some(1),
                ..ProgressiveSettings::default()
            },
        ),
        &|_| {},
    )
    .unwrap();
    assert!(stats(&one).ambient.max_band() > 0.0);
    assert_eq!(one.object_radiosity(&scene)[ceiling].radiosity, Rgb::ZERO);
    assert_eq!(one.patch_radiosity().len(), one.mesh().patches().len());
}

#[test]
fn each_stopping_rule_stops_the_solve() {
    let scene = scenes::cornell_box();
    let run = |p: ProgressiveSettings| {
        let reports = Mutex::new(Vec::new());
        let sol = radiosity::solve(&scene, &progressive(uniform(0.14, 0), p), &|r| {
            reports.lock().unwrap().push(r);
        })
        .unwrap();
        let fractions: Vec<f64> = unshot_runs(&reports.into_inner().unwrap()).concat();
        (sol, fractions)
    };

    // The unshot fraction: stops at the first shot that reaches it.
    let (sol, fractions) = run(ProgressiveSettings {
        tolerance: 0.05,
        ..ProgressiveSettings::default()
    });
    let f = stats(&sol);
    assert_eq!(f.stop, StopReason::Converged);
    assert_eq!(f.shots, fractions.len());
    assert!(f.unshot_fraction <= 0.05 && f.unshot_fraction == fractions[f.shots - 1]);
    assert!(fractions[f.shots - 2] > 0.05);

    // The shot count: stops there, whatever is left unshot.
    let (sol, _) = run(ProgressiveSettings {
        tolerance: 1e-6,
        max_shots: Some(25),
        ..ProgressiveSettings::default()
    });
    let f = stats(&sol);
    assert_eq!((f.stop, f.shots), (StopReason::ShotLimit, 25));
    assert!(f.unshot_fraction > 1e-6);
    // A bounded solve is not handed to the gathering solver for the shaped
    // gathers a converged one ends in, and says so.
    let warnings = &sol.stats().warnings;
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("shot limit") && w.contains("shaped gather")),
        "{warnings:?}"
    );
    assert!(sol.stats().shaped_sources.is_empty());

    // The time budget: an empty budget allows no shot; the solution holds the
    // emission only.
    let (sol, fractions) = run(ProgressiveSettings {
        time_budget: Some(Duration::ZERO),
        ..ProgressiveSettings::default()
    });
    let f = stats(&sol);
    assert_eq!((f.stop, f.shots), (StopReason::TimeBudget, 0));
    assert!(fractions.is_empty());
    assert!((f.unshot_fraction - 1.0).abs() < 1e-12);
    let light = scene
        .objects
        .iter()
        .position(|o| o.name == "light")
        .unwrap();
    for (i, o) in sol.object_radiosity(&scene).iter().enumerate() {
        if i != light {
            assert_eq!(o.radiosity, Rgb::ZERO, "{}", o.name);
        }
    }
    // A generous budget does not stop a solve that converges first.
    let (sol, _) = run(ProgressiveSettings {
        tolerance: 0.05,
        time_budget: Some(Duration::from_secs(3600)),
        ..ProgressiveSettings::default()
    });
    assert_eq!(stats(&sol).stop, StopReason::Converged);
}

#[test]
fn bad_progressive_settings_are_named() {
    let scene = scenes::cornell_box();
    let cases: [(&str, ProgressiveSettings); 6] = [
        (
            "progressive.tolerance",
            ProgressiveSettings {
                tolerance: 0.0,
                ..ProgressiveSettings::default()
            },
        ),
        (
            "progressive.max_shots",
            ProgressiveSettings {
                max_shots: Some(0),
                ..ProgressiveSettings::default()
            },
        ),
        (
            "progressive.preview_every",
            ProgressiveSettings {
                preview_every: Some(0),
                ..ProgressiveSettings::default()
            },
        ),
        (
            "progressive.shooter_depth",
            ProgressiveSettings {
                shooter_depth: 9,
                ..ProgressiveSettings::default()
            },
        ),
        (
            "progressive.fine_shot_power",
            ProgressiveSettings {
                fine_shot_power: -1.0,
                ..ProgressiveSettings::default()
            },
        ),
        (
            "progressive.refine_factor",
            ProgressiveSettings {
                refine_factor: 1.0,
                ..ProgressiveSettings::default()
            },
        ),
    ];
    for (name, p) in cases {
        match radiosity::solve(&scene, &progressive(Settings::default(), p), &|_| {}) {
            Err(radiosity::Error::Setting { name: n, .. }) => assert_eq!(n, name),
            other => panic!(
                "{name}: expected a setting error, got {:?}",
                other.map(|_| ())
            ),
        }
    }
}

#[test]
fn same_seed_gives_the_same_bits_at_any_thread_count() {
    let scene = scenes::cornell_box();
    let s = progressive(
        coarse_cornell(),
        ProgressiveSettings {
            max_shots: Some(150),
            ..ProgressiveSettings::default()
        },
    );
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| radiosity::solve(&scene, &s, &|_| {}).unwrap())
    };
    let (a, b) = (run(1), run(3));
    assert!(
        stats(&a).rows_gathered_after_shots.is_some(),
        "the run reaches the rows"
    );
    assert_eq!(a.patch_radiosity(), b.patch_radiosity());
    let leaves = |s: &Solution| -> Vec<Rgb> {
        s.mesh()
            .leaves()
            .iter()
            .map(|k| s.radiosity().element(*k))
            .collect()
    };
    assert_eq!(leaves(&a), leaves(&b));
}

/// Two unit squares 5 cm apart, facing each other; the lower one emits 1 and
/// neither reflects, so one shot decides everything.
fn close_plates(gap: f64) -> radiosity::scene::Scene {
    let p = DVec3::new;
    lamp_and_black_plate(&[
        p(0., gap, 0.),
        p(1., gap, 0.),
        p(1., gap, 1.),
        p(0., gap, 1.),
    ])
}

/// A unit square lamp in the plane y = 0, facing +y and emitting 1, and a
/// black single-sided plate with the corners `plate`.
fn lamp_and_black_plate(plate: &[DVec3]) -> radiosity::scene::Scene {
    let mut b = radiosity::scene::SceneBuilder::new("lamp_and_plate");
    let lamp = b
        .material("lamp", Rgb::ZERO, Rgb::splat(1.0 / std::f64::consts::PI))
        .unwrap();
    let black = b.material("black", Rgb::ZERO, Rgb::ZERO).unwrap();
    let p = DVec3::new;
    b.object("lamp");
    b.polygon(
        lamp,
        &[p(0., 0., 0.), p(0., 0., 1.), p(1., 0., 1.), p(1., 0., 0.)],
    )
    .unwrap();
    b.object("plate");
    b.polygon(black, plate).unwrap();
    b.build().unwrap()
}

#[test]
fn reciprocals_above_one_split_the_shooter_and_are_counted() {
    // 1 cm apart, a 1/32 m element straight above a shooter's eye subtends
    // about half its hemisphere: the classic reciprocal F_se A_s / A_e of the
    // whole 1 m^2 plate would be hundreds. The classic shooter splits until it
    // is not; the hybrid never forms a reciprocal. Both must deliver the exact
    // plate-to-plate form factor.
    let gap = 0.01;
    let scene = close_plates(gap);
    let exact = radiosity::analytic::parallel_rectangles(1.0, 1.0, gap).unwrap();
    for (method, tolerance) in [
        (FormFactorMethod::Hemicube, 0.02),
        (FormFactorMethod::Hybrid, 0.01),
    ] {
        let s = progressive(
            Settings {
                form_factors: method,
                ..uniform(1.0, 5)
            },
            ProgressiveSettings {
                shooter_depth: 0,
                ..ProgressiveSettings::default()
            },
        );
        let sol = radiosity::solve(&scene, &s, &|_| {}).unwrap();
        let f = stats(&sol);
        assert_eq!(f.shots, 1, "{method:?}: one emitter, nothing reflects");
        // All the power the upper plate absorbs came in the one shot.
        let received = sol.stats().energy.absorbed_power[0] / sol.stats().energy.emitted_power[0];
        assert!(
            rel(received, exact) < tolerance,
            "{method:?}: plate-to-plate form factor {received} vs exact {exact}"
        );
        assert_eq!(f.reciprocity_clips, 0, "{method:?}");
        match method {
            FormFactorMethod::Hemicube => assert!(f.shooter_splits > 0),
            FormFactorMethod::Hybrid => assert_eq!(f.shooter_splits, 0),
        }
    }
}

#[test]
fn kept_form_factors_give_the_bits_of_rendering_every_shot() {
    // On a fixed mesh with every shot fine, a patch's later shots need the
    // factors of its first: keeping them must change nothing but the work.
    let scene = scenes::cornell_box();
    let run = |cache_bytes| {
        let s = progressive(
            uniform(0.14, 1),
            ProgressiveSettings {
                fine_shot_power: 0.0,
                shot_cache_bytes: cache_bytes,
                gather_rows: false,
                ..ProgressiveSettings::default()
            },
        );
        radiosity::solve(&scene, &s, &|_| {}).unwrap()
    };
    let kept = run(ProgressiveSettings::default().shot_cache_bytes);
    let rendered = run(0);
    let (k, r) = (stats(&kept), stats(&rendered));
    assert_eq!(k.shots, r.shots);
    assert_eq!(r.cached_shots, 0);
    // Each patch renders once at most: at its first shot.
    assert!(k.shots - k.cached_shots <= kept.stats().patches);
    assert!(
        k.shots > 2 * kept.stats().patches,
        "patches shoot repeatedly"
    );
    assert!(
        k.shot_hemicubes * 3 < r.shot_hemicubes,
        "{} vs {}",
        k.shot_hemicubes,
        r.shot_hemicubes
    );
    assert!(k.shot_cache_bytes > 0);
    for (a, b) in kept.mesh().leaves().iter().zip(rendered.mesh().leaves()) {
        assert_eq!(
            kept.radiosity().element(*a),
            rendered.radiosity().element(b)
        );
    }
}

#[test]
fn a_shooter_whose_eye_is_behind_a_receiver_still_lights_it_from_the_part_in_front() {
    // A unit square lamp on the floor, cut by a black plate standing on it at
    // x = 0.6 and facing +x. The lamp's centre, where a one-cell shooter's
    // eye is, lies behind the plate, so its item buffer sees only the plate's
    // back; yet the strip x in [0.6, 1] lights the plate's front. Exactly,
    // the plate receives A_strip F(strip -> plate) of the lamp's unit power,
    // with F the perpendicular-rectangles form factor (Howell C-14).
    let p = DVec3::new;
    let scene = lamp_and_black_plate(&[
        p(0.6, 0., 0.),
        p(0.6, 1., 0.),
        p(0.6, 1., 1.),
        p(0.6, 0., 1.),
    ]);
    let exact = 0.4 * radiosity::analytic::perpendicular_rectangles(0.4, 1.0, 1.0).unwrap();
    let s = progressive(
        uniform(1.0, 4),
        ProgressiveSettings {
            shooter_depth: 0,
            ..ProgressiveSettings::default()
        },
    );
    let sol = radiosity::solve(&scene, &s, &|_| {}).unwrap();
    assert_eq!(stats(&sol).shots, 1);
    let received = sol.stats().energy.absorbed_power[0] / sol.stats().energy.emitted_power[0];
    assert!(
        rel(received, exact) < 0.01,
        "plate receives {received}, exactly {exact}"
    );
}

#[test]
fn with_gathered_rows_it_converges_to_the_gauss_seidel_solution_itself() {
    // On a fixed mesh the rows make the shots solve the very system
    // Gauss-Seidel solves, so the two meet leaf by leaf, to the solvers'
    // tolerances (measured 7e-9 of the light's radiosity); the shots before
    // the rows were gathered leave no trace.
    let scene = scenes::cornell_box();
    let mesh = uniform(0.14, 2);
    let (gathered, shot) = gathered_and_shot(
        &scene,
        &mesh,
        ProgressiveSettings {
            tolerance: 1e-7,
            ..ProgressiveSettings::default()
        },
    );
    let f = stats(&shot);
    let after = f.rows_gathered_after_shots.expect("rows were gathered");
    assert!(after > 0, "the first shots use shooter hemi-cubes");
    assert_eq!(f.unshot_increases, 0);
    let brightest = gathered
        .mesh()
        .leaves()
        .iter()
        .map(|k| gathered.radiosity().element(*k).max_band())
        .fold(0.0, f64::max);
    for (g, p) in gathered.mesh().leaves().iter().zip(shot.mesh().leaves()) {
        let (g, p) = (gathered.leaf(*g), shot.leaf(p));
        let d = (g.radiosity - p.radiosity).abs().max_band();
        assert!(
            d < 1e-6 * brightest,
            "{:?}: {:?} vs {:?}",
            g.cell(),
            p.radiosity,
            g.radiosity
        );
    }
}

#[test]
fn rows_that_do_not_fit_the_budget_leave_the_shots_rendering() {
    // 64 KiB holds a few patches' factors but not every row: the switch to
    // rows is refused, said so, and the solve still converges by rendering.
    let scene = scenes::cornell_box();
    let mesh = uniform(0.14, 1);
    let (gathered, shot) = gathered_and_shot(
        &scene,
        &mesh,
        ProgressiveSettings {
            shot_cache_bytes: 64 << 10,
            ..ProgressiveSettings::default()
        },
    );
    let f = stats(&shot);
    assert_eq!(f.stop, StopReason::Converged);
    assert_eq!(f.rows_gathered_after_shots, None);
    assert!(f.shot_cache_bytes <= 64 << 10);
    assert!(f.cached_shots > 0, "what fits is still kept");
    assert_eq!(f.unshot_increases, 0);
    // 1.5%: shots alone judge a floor leaf that a block's edge crosses by
    // its centre (lit or shut in as a whole), gathered rows by its visible
    // share (`formfactor/contacts.rs`); measured 1.07% on the ceiling.
    assert_objects_agree(&scene, &gathered, &shot, 0.015);
}

#[test]
fn settings_the_progressive_solver_cannot_honour_are_refused_by_name() {
    // Source-patch splitting belongs to gathering; the shooting solver says
    // so instead of ignoring it.
    let s = progressive(
        Settings {
            refine: RefineSettings {
                source_tolerance: Some(0.1),
                ..RefineSettings::default()
            },
            ..uniform(0.3, 1)
        },
        ProgressiveSettings::default(),
    );
    let e = radiosity::solve(&scenes::cornell_box(), &s, &|_| {}).unwrap_err();
    assert!(
        matches!(
            e,
            radiosity::Error::Setting {
                name: "refine.source_tolerance",
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn turning_off_the_empty_face_skip_renders_whole_faces_with_the_same_bits() {
    // The progressive solver honours the skip switches its hemi-cubes use:
    // off, every face is cleared and read out whole, and nothing changes.
    let scene = scenes::cornell_box();
    let base = progressive(uniform(0.2, 1), ProgressiveSettings::default());
    let mut full = base.clone();
    full.skips.empty_faces = false;
    let (a, b) = (
        radiosity::solve(&scene, &base, &|_| {}).unwrap(),
        radiosity::solve(&scene, &full, &|_| {}).unwrap(),
    );
    assert!(a.stats().skips.pixels_skipped > 0);
    assert_eq!(b.stats().skips.pixels_skipped, 0);
    assert_eq!(b.stats().skips.empty_faces, 0);
    let bits = |s: &Solution| -> Vec<[u64; 3]> {
        s.leaves()
            .iter()
            .map(|l| l.radiosity.0.map(f64::to_bits))
            .collect()
    };
    assert_eq!(bits(&a), bits(&b));
}
