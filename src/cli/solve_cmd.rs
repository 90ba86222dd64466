//! `radiosity solve`: load, solve, render every view, write images and stats.

use super::args::{ExportArgs, SolveArgs, SolveSettingsArgs};
use super::progress_bar::Bars;
use super::views::{choose_views, write_views, Overlay};
use anyhow::{bail, Context, Result};
use radiosity::gltf_io::{self, ImportLimits};
use radiosity::pipeline::{ObjectRadiosity, Preview, SolveStats};
use radiosity::refine::RefineSettings;
use radiosity::render::{self, ShadedMesh, ToneMap};
use radiosity::scene::{Camera, Scene};
use radiosity::solve::progressive::ProgressiveStats;
use radiosity::solve::{ProgressiveSettings, SolverKind, SolverSettings};
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
pub fn settings(a: &SolveSettingsArgs) -> Result<Settings> {
    let time_budget = match a.time_budget {
        Some(t) if !(t.is_finite() && t >= 0.0) => {
            bail!("--time-budget must be a number of seconds >= 0, got {t}")
        }
        t => t.map(std::time::Duration::from_secs_f64),
    };
    let solver_kind: SolverKind = a.solver.parse().map_err(anyhow::Error::msg)?;
    if a.preview_every.is_some() && solver_kind != SolverKind::Progressive {
        bail!("--preview-every needs --solver progressive (Gauss-Seidel has no previews)");
    }
    Ok(Settings {
        hemicube_resolution: a.hemicube_res,
        form_factors: a.form_factors,
        emitter_rays: a.emitter_rays == "on",
        emitter_sampling: a.emitter_samples,
        patch_size: a.patch_size,
        seed: a.seed,
        solver: SolverSettings {
            tolerance: a.tolerance,
            max_iterations: a.max_iterations,
            relaxation: a.relaxation,
        },
        solver_kind,
        progressive: ProgressiveSettings {
            tolerance: a.unshot_tolerance,
            max_shots: a.max_shots,
            time_budget,
            preview_every: a.preview_every,
            shooter_depth: a.shooter_depth,
            fine_shot_power: a.fine_shot_power,
            gather_rows: a.gather_rows == "on",
            shot_cache_bytes: a.shot_cache_mb.saturating_mul(1 << 20),
            ..ProgressiveSettings::default()
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
        bounces: if a.direct_only { Some(1) } else { a.bounces },
        ..Settings::default()
    })
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
    skips: &'a radiosity::pipeline::SkipStats,
    source_passes: &'a [radiosity::pipeline::SourcePassStats],
    passes: &'a [radiosity::pipeline::PassStats],
    #[serde(skip_serializing_if = "Option::is_none")]
    progressive: Option<&'a ProgressiveStats>,
    memory: Memory<'a>,
    final_max_difference: f64,
    /// `null`: the full solution; N: emitted light and N reflections.
    bounces: Option<u32>,
    patch_size: f64,
    threads: usize,
    seed: u64,
    import: &'a radiosity::scene::ImportStats,
    warnings: &'a [String],
    outputs: Vec<String>,
    surfaces: Vec<ObjectRadiosity>,
}

/// The library's heap estimate of the mesh, and the process's peak resident
/// memory (up to writing the JSON, so rendering included; null where the
/// system does not say).
#[derive(Serialize)]
struct Memory<'a> {
    #[serde(flatten)]
    mesh: &'a radiosity::pipeline::MemoryFigures,
    peak_resident_bytes: Option<u64>,
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

    let (lo, hi) = scene.bounds();
    let views = choose_views(&plan, &scene.cameras, lo, hi);
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("creating the output folder {}", a.out.display()))?;

    let bars = Bars::new(a.quiet);
    let mut previews = PreviewWriter {
        args: a,
        scene: &scene.name,
        camera: &views[0],
        tone: plan.tone,
        exposure: a.view.exposure,
        written: Vec::new(),
        error: None,
    };
    let solution = radiosity::pipeline::solve_with_previews(
        &scene,
        &settings(&a.settings)?,
        &|p| bars.update(p),
        &mut |p| previews.write(p),
    )
    .with_context(|| format!("solving '{}'", scene.name))?;
    bars.finish();
    if let Some(e) = previews.error {
        return Err(e);
    }
    let mut written = std::mem::take(&mut previews.written);

    let t = Instant::now();
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
    outputs.append(&mut written);
    let render_seconds = t.elapsed().as_secs_f64();

    let s: &SolveStats = &solution.stats;
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    let warnings: Vec<String> = scene.warnings.iter().chain(&s.warnings).cloned().collect();
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
        skips: &s.skips,
        source_passes: &s.source_passes,
        passes: &s.passes,
        progressive: s.progressive.as_ref(),
        memory: Memory {
            mesh: &s.memory,
            peak_resident_bytes: super::peak_memory::peak_resident_bytes(),
        },
        final_max_difference: s.final_max_difference,
        bounces: s.bounces,
        patch_size: s.patch_size,
        threads,
        seed: a.settings.seed,
        import: &scene.import_stats,
        warnings: &warnings,
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

/// Writes the previews of a progressive solve: the first view, with the
/// ambient term, at one exposure for all (the first preview's unless
/// `--exposure` is given) so that they show the image filling in.
struct PreviewWriter<'a> {
    args: &'a SolveArgs,
    scene: &'a str,
    camera: &'a Camera,
    tone: ToneMap,
    exposure: Option<f64>,
    written: Vec<String>,
    error: Option<anyhow::Error>,
}

impl PreviewWriter<'_> {
    fn write(&mut self, p: &Preview<'_>) {
        if self.error.is_none() {
            if let Err(e) = self.try_write(p) {
                self.error = Some(e);
            }
        }
    }

    fn try_write(&mut self, p: &Preview<'_>) -> Result<()> {
        let shading = p.shading_mesh(true);
        let mesh = ShadedMesh {
            positions: shading.positions,
            values: shading
                .radiosity
                .iter()
                .map(|b| *b / std::f64::consts::PI)
                .collect(),
            triangles: shading.triangles,
        };
        let (image, _) = render::render_with_depth(
            &mesh,
            self.camera,
            self.args.view.width,
            self.args.view.height,
            2,
        )?;
        let stops = *self
            .exposure
            .get_or_insert_with(|| render::auto_exposure(&image, self.tone));
        let png = self
            .args
            .out
            .join(format!("{}_preview_{:04}.png", self.scene, p.shots));
        render::write_png(&image, &png, stops, self.tone)?;
        self.written.push(png.display().to_string());
        Ok(())
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
