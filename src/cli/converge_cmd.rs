//! `radiosity converge`: run time against error for one or more scenes.

use super::args::ConvergeArgs;
use super::solve_cmd::{load, settings, thread_pool};
use anyhow::{bail, Context, Result};
use radiosity::report::{
    self, markdown_report, object_reference, objects_csv, run_sweep, runs_csv, Method,
    MonteCarloPoints, ReferencePoints, SweepEvent, SweepPlan,
};
use radiosity::scenes::penumbra;
use std::path::{Path, PathBuf};

/// Runs `radiosity converge`.
pub fn run(a: &ConvergeArgs) -> Result<()> {
    let pool = thread_pool(a.settings.threads)?;
    let methods = parse_methods(&a.methods)?;
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("creating the folder {}", a.out.display()))?;
    pool.install(|| {
        for scene in &a.scenes {
            converge_one(a, &methods, scene)?;
        }
        Ok(())
    })
}

fn parse_methods(names: &[String]) -> Result<Vec<Method>> {
    names
        .iter()
        .map(|n| {
            Method::from_name(n.trim()).with_context(|| {
                let known: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                format!("unknown method '{n}' (known: {})", known.join(", "))
            })
        })
        .collect()
}

fn converge_one(a: &ConvergeArgs, methods: &[Method], name: &str) -> Result<()> {
    let scene = load(name)?;
    let say = |text: String| {
        if !a.quiet {
            eprintln!("{text}");
        }
    };
    let oracle = penumbra::by_name(name).filter(|_| !Path::new(name).exists());
    let reference = match (&oracle, a.monte_carlo) {
        (Some(spec), false) => {
            say(format!(
                "{}: exact oracle at {} floor points",
                scene.name, a.points
            ));
            ReferencePoints::exact(spec, a.points)?
        }
        _ => {
            say(format!(
                "{}: Monte Carlo reference, {} points x {} paths",
                scene.name, a.points, a.paths
            ));
            let mc = MonteCarloPoints {
                count: a.points,
                paths: a.paths,
                seed: a.reference_seed,
            };
            ReferencePoints::monte_carlo(&scene, &mc)?
        }
    };
    say(format!(
        "  reference: {} points in {:.1} s, mean relative standard error {:.3e}",
        reference.points.len(),
        reference.seconds,
        reference.mean_relative_std_error()
    ));
    let objects = if a.objects {
        say(format!(
            "  object means: {} paths per object",
            a.object_paths
        ));
        Some(object_reference(&scene, a.object_paths, a.reference_seed)?)
    } else {
        None
    };

    let wants = |m: Method| methods.contains(&m);
    let plan = SweepPlan {
        base: settings(&a.settings)?,
        uniform_depths: if wants(Method::Uniform) {
            a.depths.clone()
        } else {
            Vec::new()
        },
        adaptive_tolerances: if wants(Method::Adaptive) {
            a.tolerances.clone()
        } else {
            Vec::new()
        },
        hemicube_resolutions: if wants(Method::Hemicube) {
            a.resolutions.clone()
        } else {
            Vec::new()
        },
        patch_divisions: if wants(Method::Patches) {
            a.patch_divisions.clone()
        } else {
            Vec::new()
        },
        unshot_fractions: if wants(Method::Progressive) {
            a.unshot_fractions.clone()
        } else {
            Vec::new()
        },
    };
    let runs = plan.runs(&scene)?;
    if runs.is_empty() {
        bail!("no runs: every chosen method has an empty list");
    }
    let progress = |event: SweepEvent<'_>| {
        if let SweepEvent::Finished {
            index,
            total,
            record: r,
        } = event
        {
            say(format!(
                "  [{}/{total}] {} {}: {:.3} s ({} CPU s), {} elements, mean error {:.3e}, \
                 max {:.3e}",
                index + 1,
                r.method,
                r.parameter,
                r.seconds,
                r.cpu_seconds.map_or("?".to_string(), |c| format!("{c:.3}")),
                r.elements,
                r.errors.mean,
                r.errors.max
            ));
        }
    };
    let records = run_sweep(
        &scene,
        &runs,
        &reference,
        objects.as_deref(),
        a.repeats,
        &progress,
    )
    .with_context(|| format!("sweeping '{}'", scene.name))?;

    let file = |suffix: &str| -> PathBuf { a.out.join(format!("{}{suffix}", scene.name)) };
    let write = |path: PathBuf, text: String| -> Result<PathBuf> {
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        Ok(path)
    };
    let mut written = vec![
        write(file(".csv"), runs_csv(&scene.name, &reference, &records))?,
        write(
            file(".md"),
            markdown_report(&scene.name, &reference, &records),
        )?,
    ];
    if objects.is_some() {
        written.push(write(
            file("_objects.csv"),
            objects_csv(&scene.name, &records),
        )?);
    }
    let (svg, png) = (file("_error_time.svg"), file("_error_time.png"));
    report::write_time_plot(&scene.name, &records, &svg, &png)?;
    written.extend([svg, png]);
    let (svg, png) = (file("_error_depth.svg"), file("_error_depth.png"));
    let base_size = plan.base.patch_size_for(&scene);
    if report::write_depth_plot(&scene.name, &records, base_size, &svg, &png)? {
        written.extend([svg, png]);
    }
    for path in written {
        println!("{}", path.display());
    }
    Ok(())
}
