//! `radiosity converge`: run time against error for one or more scenes.

use super::args::ConvergeArgs;
use super::checks::thread_pool;
use super::outputs::{lock_set, output_set, refuse_overwriting_inputs, scene_inputs};
use super::solve_cmd::{load, load_options, settings};
use anyhow::{bail, Context, Result};
use radiosity::output::{prepare_folder, OutputLock, Outputs};
use radiosity::report::{
    self, markdown_report, object_reference, objects_csv, run_sweep, runs_csv, Method,
    MonteCarloPoints, ReferencePoints, SweepEvent, SweepPlan,
};
use radiosity::scenes::penumbra;
use radiosity::Settings;
use std::path::{Path, PathBuf};

/// Runs `radiosity converge`. The options and the output folder are checked
/// before any scene is loaded, each scene's sweep settings before its
/// reference is computed. Each scene's files are one set (SCENE.converge),
/// locked from its load to the end; the sets are all committed at the end
/// (none of them if any scene fails), each in one step.
pub fn run(a: &ConvergeArgs) -> Result<()> {
    let pool = thread_pool(a.settings.threads)?;
    let methods = parse_methods(&a.methods)?;
    let base = settings(&a.settings)?;
    check_counts(a)?;
    prepare_folder(&a.out)?;
    let mut sets = Vec::new();
    pool.install(|| {
        for scene in &a.scenes {
            sets.push(converge_one(a, &methods, &base, scene)?);
        }
        anyhow::Ok(())
    })?;
    let mut listing = String::new();
    for (outputs, _lock) in sets {
        for path in outputs.commit()? {
            listing += &format!("{}\n", path.display());
        }
    }
    super::stdout::write_out(&listing)
}

/// The files of one scene's report, after its name.
const OUTPUT_SUFFIXES: [&str; 7] = [
    ".csv",
    ".md",
    "_objects.csv",
    "_error_time.svg",
    "_error_time.png",
    "_error_depth.svg",
    "_error_depth.png",
];

/// Refuses counts that leave nothing to measure.
fn check_counts(a: &ConvergeArgs) -> Result<()> {
    if a.points == 0 {
        bail!("--points must be at least 1");
    }
    if a.paths < 2 || (a.objects && a.object_paths < 2) {
        bail!("--paths and --object-paths must be at least 2 (one path gives no standard error)");
    }
    if a.repeats == 0 {
        bail!("--repeats must be at least 1");
    }
    Ok(())
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

fn converge_one(
    a: &ConvergeArgs,
    methods: &[Method],
    base: &Settings,
    name: &str,
) -> Result<(Outputs, OutputLock)> {
    let scene = load(name, &load_options(&a.settings.load)?)?;
    let set_name = format!("{}.converge", scene.name);
    let lock = lock_set(&a.out, &set_name)?;
    let files: Vec<PathBuf> = OUTPUT_SUFFIXES
        .iter()
        .map(|suffix| a.out.join(format!("{}{suffix}", scene.name)))
        .collect();
    refuse_overwriting_inputs(&files, &scene_inputs(name)?)?;
    let say = |text: String| {
        if !a.quiet {
            eprintln!("{text}");
        }
    };
    let wants = |m: Method| methods.contains(&m);
    let plan = SweepPlan {
        base: base.clone(),
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
    let mut outputs = output_set(&a.out, &set_name)?;
    let outputs = &mut outputs;
    let csv = runs_csv(&scene.name, &reference, &records);
    outputs.stage_bytes(&file(".csv"), csv.as_bytes())?;
    let md = markdown_report(&scene.name, &reference, &records);
    outputs.stage_bytes(&file(".md"), md.as_bytes())?;
    if objects.is_some() {
        let text = objects_csv(&scene.name, &records);
        outputs.stage_bytes(&file("_objects.csv"), text.as_bytes())?;
    }
    let (svg, png) = (file("_error_time.svg"), file("_error_time.png"));
    report::stage_time_plot(outputs, &scene.name, &records, &svg, &png)?;
    let (svg, png) = (file("_error_depth.svg"), file("_error_depth.png"));
    let base_size = plan.base.patch_size_for(&scene);
    report::stage_depth_plot(outputs, &scene.name, &records, base_size, &svg, &png)?;
    Ok((std::mem::take(outputs), lock))
}
