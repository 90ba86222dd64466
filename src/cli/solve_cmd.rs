//! `radiosity solve`: load, solve, render every view, write images and stats.

use super::args::{ExportArgs, SolveArgs, SolveSettingsArgs};
use super::progress_bar::Bars;
use super::views::{choose_views, write_views, Overlay};
use anyhow::{bail, Context, Result};
use radiosity::gltf_io::{self, ImportLimits};
use radiosity::pipeline::{ObjectRadiosity, SolveStats};
use radiosity::refine::RefineSettings;
use radiosity::render::ShadedMesh;
use radiosity::scene::Scene;
use radiosity::solve::SolverSettings;
use radiosity::{scenes, Settings};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Loads a scene from a file, or a built-in scene by name.
pub fn load(scene: &str) -> Result<Scene> {
    let path = Path::new(scene);
    if !path.exists() {
        if let Some(s) = scenes::by_name(scene) {
            return Ok(s);
        }
        bail!(
            "'{scene}' is neither a file nor a built-in scene (built-in: {})",
            scenes::NAMES.join(", ")
        );
    }
    Ok(gltf_io::load_scene(path, &ImportLimits::default())?)
}

/// The library settings the solve flags ask for.
pub fn settings(a: &SolveSettingsArgs) -> Settings {
    Settings {
        hemicube_resolution: a.hemicube_res,
        form_factors: a.form_factors,
        emitter_rays: a.emitter_rays == "on",
        patch_size: a.patch_size,
        seed: a.seed,
        solver: SolverSettings {
            tolerance: a.tolerance,
            max_iterations: a.max_iterations,
            relaxation: a.relaxation,
        },
        refine: RefineSettings {
            uniform_depth: a.uniform_depth,
            initial_depth: a.initial_depth,
            tolerance: a.refine_tolerance,
            max_depth: a.max_depth,
            min_element_area: a.min_element_area,
            max_elements: a.max_elements,
            source_tolerance: (a.source_tolerance > 0.0).then_some(a.source_tolerance),
            source_passes: a.source_passes,
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

#[derive(Serialize)]
struct Counts {
    surfaces: usize,
    objects: usize,
    patches: usize,
    elements: usize,
}

#[derive(Serialize)]
struct Seconds {
    load: f64,
    mesh: f64,
    form_factors: f64,
    solve: f64,
    render: f64,
    total: f64,
}

#[derive(Serialize)]
struct Report<'a> {
    scene: &'a str,
    counts: Counts,
    seconds: Seconds,
    solver: SolverReport,
    energy: &'a radiosity::pipeline::EnergyBalance,
    hemicube: &'a radiosity::pipeline::HemicubeFigures,
    source_passes: &'a [radiosity::pipeline::SourcePassStats],
    passes: &'a [radiosity::pipeline::PassStats],
    final_max_difference: f64,
    patch_size: f64,
    threads: usize,
    seed: u64,
    import: &'a radiosity::scene::ImportStats,
    warnings: &'a [String],
    outputs: Vec<String>,
    surfaces: Vec<ObjectRadiosity>,
}

#[derive(Serialize)]
struct SolverReport {
    iterations: usize,
    final_sweeps: usize,
    residual: f64,
    error_bound: f64,
    contraction: f64,
}

/// Runs `radiosity solve`.
pub fn run(a: &SolveArgs) -> Result<()> {
    let started = Instant::now();
    let pool = thread_pool(a.settings.threads)?;
    let threads = pool.current_num_threads();
    pool.install(|| run_in_pool(a, started, threads))
}

/// A pool of `threads` workers (all cores when `None`).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        pool = pool.num_threads(n);
    }
    pool.build().context("starting the worker threads")
}

fn run_in_pool(a: &SolveArgs, started: Instant, threads: usize) -> Result<()> {
    let plan = a.view.plan()?;

    let t = Instant::now();
    let scene = load(&a.scene)?;
    let load_seconds = t.elapsed().as_secs_f64();
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }

    let bars = Bars::new(a.quiet);
    let solution = radiosity::solve(&scene, &settings(&a.settings), &|p| bars.update(p))
        .with_context(|| format!("solving '{}'", scene.name))?;
    bars.finish();

    let t = Instant::now();
    let (lo, hi) = scene.bounds();
    let views = choose_views(&plan, &scene.cameras, lo, hi);
    let mesh = radiance_mesh(&solution);
    let segments = if a.mesh_out.is_some() {
        solution.mesh.leaf_edges()
    } else {
        Vec::new()
    };
    let overlay = a.mesh_out.as_deref().map(|png| Overlay {
        png,
        segments: &segments,
    });
    let mut outputs = write_views(&mesh, &views, &a.view, &plan, &a.out, &scene.name, overlay)?;
    let render_seconds = t.elapsed().as_secs_f64();

    let s: &SolveStats = &solution.stats;
    let json = a.out.join(format!("{}.json", scene.name));
    outputs.push(json.display().to_string());
    let report = Report {
        scene: &scene.name,
        counts: Counts {
            surfaces: scene.surfaces.len(),
            objects: scene.objects.len(),
            patches: s.patches,
            elements: s.elements,
        },
        seconds: Seconds {
            load: load_seconds,
            mesh: s.seconds.mesh,
            form_factors: s.seconds.form_factors,
            solve: s.seconds.solve,
            render: render_seconds,
            total: started.elapsed().as_secs_f64(),
        },
        solver: SolverReport {
            iterations: s.total_iterations,
            final_sweeps: s.solver.iterations,
            residual: s.solver.residual,
            error_bound: s.solver.error_bound,
            contraction: s.solver.contraction,
        },
        energy: &s.energy,
        hemicube: &s.hemicube,
        source_passes: &s.source_passes,
        passes: &s.passes,
        final_max_difference: s.final_max_difference,
        patch_size: s.patch_size,
        threads,
        seed: a.settings.seed,
        import: &scene.import_stats,
        warnings: &scene.warnings,
        outputs,
        surfaces: solution.object_radiosity(&scene),
    };
    write_json(&json, &report)?;
    if !a.quiet {
        eprintln!(
            "{}: {} patches, {} elements, {} hemi-cubes, {:.3} s; wrote {}",
            scene.name,
            s.patches,
            s.elements,
            s.hemicube.hemicubes,
            report.seconds.total,
            report.outputs.join(", ")
        );
    }
    Ok(())
}

/// The solution's display mesh with radiance (radiosity / pi) per vertex, as
/// the renderer takes it.
pub fn radiance_mesh(solution: &radiosity::Solution) -> ShadedMesh {
    let shading = solution.shading_mesh();
    ShadedMesh {
        positions: shading.positions,
        values: shading
            .radiosity
            .iter()
            .map(|b| *b / std::f64::consts::PI)
            .collect(),
        triangles: shading.triangles,
    }
}

fn write_json<T: Serialize>(path: &PathBuf, value: &T) -> Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    std::fs::write(path, text + "\n").with_context(|| format!("writing {}", path.display()))
}

/// Runs `radiosity export-scene`.
pub fn export_scene(a: &ExportArgs) -> Result<()> {
    let Some(scene) = scenes::by_name(&a.name) else {
        bail!(
            "no built-in scene '{}' (built-in: {})",
            a.name,
            scenes::NAMES.join(", ")
        );
    };
    gltf_io::write_scene(&scene, &a.output)?;
    Ok(())
}
