//! `radiosity solve`: load, solve, render every view, write images and stats.

use super::args::{ExportArgs, SolveArgs};
use super::camera_arg::parse_camera;
use super::progress_bar::Bars;
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

fn settings(a: &SolveArgs) -> Result<Settings> {
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
            ..ProgressiveSettings::default()
        },
        refine: RefineSettings {
            uniform_depth: a.uniform_depth,
            initial_depth: a.initial_depth,
            tolerance: a.refine_tolerance,
            max_depth: a.max_depth,
            min_element_area: a.min_element_area,
            max_elements: a.max_elements,
            ..RefineSettings::default()
        },
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
    passes: &'a [radiosity::pipeline::PassStats],
    #[serde(skip_serializing_if = "Option::is_none")]
    progressive: Option<&'a ProgressiveStats>,
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
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = a.threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        pool = pool.num_threads(n);
    }
    let pool = pool.build().context("starting the worker threads")?;
    let threads = pool.current_num_threads();
    pool.install(|| run_in_pool(a, started, threads))
}

fn run_in_pool(a: &SolveArgs, started: Instant, threads: usize) -> Result<()> {
    let tone: ToneMap = a.tonemap.parse().map_err(anyhow::Error::msg)?;
    let cameras: Vec<Camera> = a
        .camera
        .iter()
        .map(|c| parse_camera(c))
        .collect::<Result<_>>()?;

    let t = Instant::now();
    let scene = load(&a.scene)?;
    let load_seconds = t.elapsed().as_secs_f64();
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }

    let views: Vec<Camera> = if !cameras.is_empty() {
        cameras
    } else if let Some(c) = scene.cameras.first() {
        vec![c.clone()]
    } else {
        let (lo, hi) = scene.bounds();
        vec![Camera::framing(lo, hi)]
    };
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("creating the output folder {}", a.out.display()))?;
    let mut outputs = Vec::new();

    let bars = Bars::new(a.quiet);
    let mut previews = PreviewWriter {
        args: a,
        scene: &scene.name,
        camera: &views[0],
        tone,
        exposure: a.exposure,
        written: Vec::new(),
        error: None,
    };
    let solution = radiosity::pipeline::solve_with_previews(
        &scene,
        &settings(a)?,
        &|p| bars.update(p),
        &mut |p| previews.write(p),
    )
    .with_context(|| format!("solving '{}'", scene.name))?;
    bars.finish();
    if let Some(e) = previews.error {
        return Err(e);
    }
    outputs.append(&mut previews.written);

    let t = Instant::now();
    let shading = solution.shading_mesh();
    let mesh = ShadedMesh {
        positions: shading.positions.clone(),
        values: shading
            .radiosity
            .iter()
            .map(|b| *b / std::f64::consts::PI)
            .collect(),
        triangles: shading.triangles.clone(),
    };
    let mut exposure = a.exposure;
    for (i, camera) in views.iter().enumerate() {
        let stem = if i == 0 {
            scene.name.clone()
        } else {
            format!("{}_view{}", scene.name, i + 1)
        };
        let (image, depth) = render::render_with_depth(&mesh, camera, a.width, a.height, 2)?;
        // One exposure for every view of a solution, so that they compare.
        let stops = *exposure.get_or_insert_with(|| render::auto_exposure(&image, tone));
        let exr = a.out.join(format!("{stem}.exr"));
        let png = a.out.join(format!("{stem}.png"));
        render::write_exr(&image, &exr)?;
        render::write_png(&image, &png, stops, tone)?;
        outputs.push(exr.display().to_string());
        outputs.push(png.display().to_string());
        if i == 0 {
            if let Some(mesh_png) = &a.mesh_out {
                let mut over = image.clone();
                let segments = solution.mesh.leaf_edges();
                // Mesh lines in cyan at display white, whatever the exposure.
                let colour = radiosity::math::Rgb::new(0.0, 0.8, 1.0) * 2f64.powf(-stops) * 1.5;
                render::draw_segments_depth_tested(&mut over, &depth, camera, &segments, colour)?;
                render::write_png(&over, mesh_png, stops, tone)?;
                outputs.push(mesh_png.display().to_string());
            }
        }
    }
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
        passes: &s.passes,
        progressive: s.progressive.as_ref(),
        final_max_difference: s.final_max_difference,
        patch_size: s.patch_size,
        threads,
        seed: a.seed,
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
        let (image, _) =
            render::render_with_depth(&mesh, self.camera, self.args.width, self.args.height, 2)?;
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
