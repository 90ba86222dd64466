//! The run-time-against-error sweep (`radiosity::report`): a tiny sweep of the
//! parallel penumbra scene end to end, and the Monte Carlo reference path
//! against the exact oracle path at the same points.

use radiosity::report::{
    object_reference, objects_csv, run_sweep, runs_csv, write_depth_plot, write_time_plot, Method,
    MonteCarloPoints, ReferenceKind, ReferencePoints, SweepPlan, RUN_COLUMNS,
};
use radiosity::scenes::penumbra::penumbra_parallel;
use radiosity::Settings;
use std::path::Path;

/// A tiny sweep: 2 m patches (4 on the floor), uniform depths 0, 1 and 3, one
/// adaptive and one hemi-cube run, 64 exact floor points.
#[test]
fn tiny_penumbra_sweep_writes_one_row_per_run_and_finer_uniform_meshes_do_not_lose() {
    let spec = penumbra_parallel();
    let scene = spec.scene().unwrap();
    let plan = SweepPlan {
        base: Settings {
            patch_size: Some(2.0),
            ..Settings::default()
        },
        uniform_depths: vec![0, 1, 3],
        adaptive_tolerances: vec![0.1],
        hemicube_resolutions: vec![32],
        patch_divisions: Vec::new(),
    };
    let runs = plan.runs(&scene).unwrap();
    assert_eq!(runs.len(), 5);
    let reference = ReferencePoints::exact(&spec, 64).unwrap();
    assert_eq!(reference.kind, ReferenceKind::Exact);
    assert_eq!(reference.points.len(), 64);
    let objects = object_reference(&scene, 2_000, 5).unwrap();
    let records = run_sweep(&scene, &runs, &reference, Some(&objects), 1, &|_| {}).unwrap();

    let csv = runs_csv(&scene.name, &reference, &records);
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, RUN_COLUMNS);
    for required in [
        "method",
        "parameter",
        "seconds",
        "elements",
        "hemicubes",
        "form_factors",
        "mean_error",
        "rms_error",
        "max_error",
    ] {
        assert!(header.contains(&required), "no column {required}");
    }
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), runs.len(), "{csv}");
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for (row, run) in rows.iter().zip(&runs) {
        assert_eq!(row.len(), header.len());
        assert_eq!(row[column("method")], run.method.name());
        assert_eq!(
            row[column("parameter")].parse::<f64>().unwrap(),
            run.parameter
        );
        for name in ["seconds", "mean_error", "rms_error", "max_error"] {
            let v: f64 = row[column(name)].parse().unwrap();
            assert!(v.is_finite() && v >= 0.0, "{name} = {v}");
        }
        let (mean, rms, max): (f64, f64, f64) = (
            row[column("mean_error")].parse().unwrap(),
            row[column("rms_error")].parse().unwrap(),
            row[column("max_error")].parse().unwrap(),
        );
        // Mean <= RMS <= max for any set of errors (to the CSV's 7 digits).
        assert!(
            mean <= rms * (1.0 + 1e-6) && rms <= max * (1.0 + 1e-6),
            "{row:?}"
        );
    }

    let uniform: Vec<f64> = rows
        .iter()
        .filter(|r| r[column("method")] == "uniform")
        .map(|r| r[column("mean_error")].parse().unwrap())
        .collect();
    assert_eq!(uniform.len(), 3);
    for (depth, e) in [1, 3].iter().zip(&uniform[1..]) {
        assert!(
            *e <= uniform[0],
            "uniform depth {depth} mean error {e} exceeds depth 0's {}",
            uniform[0]
        );
    }
    // Elements grow fourfold per level under a uniform split.
    let elements: Vec<usize> = records
        .iter()
        .filter(|r| r.method == Method::Uniform)
        .map(|r| r.elements)
        .collect();
    assert_eq!(elements[1], 4 * elements[0]);
    assert_eq!(elements[2], 64 * elements[0]);

    // Per-object errors: every non-emitting object, never the light.
    let names: Vec<&str> = records[0].objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["occluder", "floor"]);
    assert_eq!(
        objects_csv(&scene.name, &records).lines().count(),
        1 + 2 * runs.len()
    );

    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("converge_tiny");
    std::fs::create_dir_all(&dir).unwrap();
    let (svg, png) = (dir.join("time.svg"), dir.join("time.png"));
    write_time_plot(&scene.name, &records, &svg, &png).unwrap();
    let image = image::open(&png).unwrap();
    assert_eq!((image.width(), image.height()), (1400, 600));
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    let (svg, png) = (dir.join("depth.svg"), dir.join("depth.png"));
    let size = plan.base.patch_size_for(&scene);
    assert!(write_depth_plot(&scene.name, &records, size, &svg, &png).unwrap());
}

/// The Monte Carlo reference, forced on a penumbra scene, agrees with the
/// exact oracle at its own sample points within three standard errors: on the
/// floor against `exact_radiosity`, on the black occluder against 0 (the light's
/// points are left out as emitting).
///
/// A normal law puts 0.27 % of estimates beyond three standard errors, so among
/// some 40 independent points one may fall outside by chance (about one seed in
/// ten). The test allows two such points, and none beyond 4.5 standard errors
/// (a chance below 1e-4 for the whole set); a biased reference fails both at
/// once as the paths grow.
#[test]
fn monte_carlo_reference_points_agree_with_the_penumbra_oracle() {
    let spec = penumbra_parallel();
    let scene = spec.scene().unwrap();
    let settings = MonteCarloPoints {
        count: 48,
        paths: 10_000,
        seed: 11,
    };
    let mc = ReferencePoints::monte_carlo(&scene, &settings).unwrap();
    assert_eq!(
        mc.kind,
        ReferenceKind::MonteCarlo {
            paths: 10_000,
            seed: 11
        }
    );
    assert!(
        mc.emitting_left_out > 0,
        "the light takes its share of points"
    );
    assert_eq!(mc.hidden_left_out, 0);
    assert_eq!(mc.points.len() + mc.emitting_left_out, 48);
    let object = |s: u32| {
        scene.objects[scene.surfaces[s as usize].object as usize]
            .name
            .as_str()
    };
    let floor: Vec<_> = mc
        .points
        .iter()
        .filter(|p| object(p.surface) == "floor")
        .collect();
    assert!(floor.len() >= 30, "{} floor points", floor.len());
    let positions: Vec<_> = floor.iter().map(|p| p.position).collect();
    let exact = ReferencePoints::exact_at(&spec, &positions).unwrap();
    assert_eq!(exact.points.len(), floor.len());

    let (mut lit, mut beyond_three) = (0, Vec::new());
    for (m, e) in floor.iter().zip(&exact.points) {
        assert_eq!(m.position, e.position);
        lit += usize::from(e.radiosity[0] > 0.0);
        // The scene is grey: the three bands carry the same estimate.
        let difference = (m.radiosity[0] - e.radiosity[0]).abs();
        let what = format!(
            "at {}: Monte Carlo {} +- {}, exact {}",
            m.position, m.radiosity[0], m.std_error[0], e.radiosity[0]
        );
        assert!(difference <= 4.5 * m.std_error[0] + 1e-12, "{what}");
        if difference > 3.0 * m.std_error[0] + 1e-12 {
            beyond_three.push(what);
        }
    }
    assert!(beyond_three.len() <= 2, "{beyond_three:#?}");
    assert!(lit >= floor.len() / 2, "the test needs lit points");
    for m in mc.points.iter().filter(|p| object(p.surface) == "occluder") {
        assert!(m.radiosity.max_band() <= 3.0 * m.std_error.max_band() + 1e-12);
    }
}
