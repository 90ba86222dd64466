//! `radiosity solve`: load, solve, render every view, write images and stats.

use super::args::{ExportArgs, LoadArgs, SolveArgs, SolveSettingsArgs};
use super::budget::{image_bytes, solve_settings};
use super::checks::{thread_pool, time_budget};
use super::outputs::{lock_set, output_set, refuse_overwriting_inputs, scene_inputs};
use super::progress_bar::Bars;
use super::setting_flags::with_flags;
use super::solver_flags::refuse_unread;
use super::view_args::ViewPlan;
use super::views::{check_view_files, choose_views, write_views, Overlay};
use anyhow::{bail, Context, Result};
use radiosity::gltf_io::{self, ImportLimits, LoadOptions};
use radiosity::output::{check_target, prepare_folder};
use radiosity::pipeline::{Preview, SolveStats};
use radiosity::pipeline::{ProgressiveSettings, SolverKind, SolverSettings};
use radiosity::refine::RefineSettings;
use radiosity::render::{self, ShadedMesh, ToneMap};
use radiosity::scene::{Camera, Scene};
use radiosity::solution::ObjectRadiosity;
use radiosity::solution::ProgressiveStats;
use radiosity::{scenes, Settings};
use serde::Serialize;
use std::io::Read;
use std::path::Path;
use std::time::Instant;

/// The load options the flags ask for, checked before anything is loaded.
pub fn load_options(a: &LoadArgs) -> Result<LoadOptions> {
    let options = LoadOptions {
        overlaps: a.overlaps.parse().map_err(anyhow::Error::msg)?,
        max_reflectance: a.max_reflectance,
        double_sided: a.double_sided,
        sky: a.sky()?,
        sun: a.sun()?,
    };
    options.validate()?;
    Ok(options)
}

/// Loads a scene from a file, or a built-in scene by name, repaired as
/// `options` say (a built-in scene is made double-sided and checked for
/// overlaps; its reflectances are its own), and checks that something in it
/// gives light: every check that needs the scene but not its solve. Textures
/// are kept within the machine's default memory budget; [`load_within`]
/// takes the budget of `--max-memory`.
pub fn load(scene: &str, options: &LoadOptions) -> Result<Scene> {
    load_within(scene, options, super::peak_memory::default_max_memory())
}

/// [`load`], with the textures kept within `max_memory` bytes
/// ([`ImportLimits::for_memory`]).
pub fn load_within(scene: &str, options: &LoadOptions, max_memory: u64) -> Result<Scene> {
    let path = Path::new(scene);
    let scene = if path.exists() {
        gltf_io::load_scene_with(path, &ImportLimits::for_memory(max_memory), options)?
    } else {
        let Some(mut s) = scenes::by_name(scene) else {
            bail!(
                "'{scene}' is neither a file nor a built-in scene (built-in: {}, {})",
                scenes::NAMES.join(", "),
                scenes::SIZED_NAMES
            );
        };
        if options.double_sided {
            s.make_double_sided();
        }
        s.resolve_overlaps(options.overlaps)?;
        options.add_daylight(&mut s);
        s
    };
    if let Err(e) = scene.check_light() {
        // What the import left out (a light of a type it does not know)
        // may be why nothing gives light: say it before the refusal.
        for w in &scene.warnings {
            eprintln!("warning: {}", with_flags(w));
        }
        return Err(e.into());
    }
    Ok(scene)
}

/// The text of a regular file of at most 1 GiB (a FIFO or device is refused
/// rather than read for ever).
pub fn read_text(path: &Path) -> Result<String> {
    const MAX_BYTES: u64 = 1 << 30;
    let file = radiosity::input::open_regular(path)?;
    let mut text = String::new();
    file.take(MAX_BYTES + 1)
        .read_to_string(&mut text)
        .with_context(|| format!("reading {}", path.display()))?;
    if text.len() as u64 > MAX_BYTES {
        bail!("{}: larger than {MAX_BYTES} bytes", path.display());
    }
    Ok(text)
}

/// The library settings the solve flags ask for, checked (everything that can
/// be checked without the scene).
pub fn settings(a: &SolveSettingsArgs) -> Result<Settings> {
    // The load options too, so that every command refuses them before it loads.
    load_options(&a.load)?;
    let time_budget = time_budget(a.time_budget)?;
    // Values the library would take without a word: a NaN or negative source
    // tolerance turned source splitting off.
    if !(a.source_tolerance.is_finite() && a.source_tolerance >= 0.0) {
        bail!(
            "--source-tolerance must be a fraction >= 0 (0 never splits sources), got {}",
            a.source_tolerance
        );
    }
    let solver_kind: SolverKind = a.solver.parse().map_err(anyhow::Error::msg)?;
    refuse_unread(a, solver_kind)?;
    let refine = RefineSettings::default();
    let progressive = ProgressiveSettings::default();
    let settings = Settings {
        hemicube_resolution: a.hemicube_res,
        emitter_sampling: a.emitter_samples.parse().map_err(anyhow::Error::msg)?,
        patch_size: a.patch_size,
        seed: a.seed,
        solver: SolverSettings {
            tolerance: a.tolerance,
            ..SolverSettings::default()
        },
        solver_kind,
        progressive: ProgressiveSettings {
            tolerance: a.unshot_tolerance.unwrap_or(progressive.tolerance),
            max_shots: a.max_shots,
            time_budget,
            preview_every: a.preview_every,
            ..progressive
        },
        refine: RefineSettings {
            uniform_depth: a.uniform_depth,
            initial_depth: a.initial_depth.unwrap_or(refine.initial_depth),
            tolerance: a.refine_tolerance.unwrap_or(refine.tolerance),
            dim_floor: a.dim_floor.unwrap_or(refine.dim_floor),
            near_floor: a.near_floor.unwrap_or(refine.near_floor),
            max_depth: a.max_depth.unwrap_or(refine.max_depth),
            min_element_area: a.min_element_area,
            max_elements: a.max_elements.unwrap_or(usize::MAX),
            source_tolerance: (a.source_tolerance > 0.0).then_some(a.source_tolerance),
            ..refine
        },
        bounces: if a.direct_only { Some(1) } else { a.bounces },
        shaped_gathers: a.shaped_gathers,
        max_patches: a.max_patches.unwrap_or(usize::MAX),
        max_memory: max_memory(a.max_memory)?,
        ..Settings::default()
    };
    settings.validate()?;
    Ok(settings)
}

/// `--max-memory` in bytes, or the machine's default.
fn max_memory(gigabytes: Option<f64>) -> Result<u64> {
    match gigabytes {
        None => Ok(super::peak_memory::default_max_memory()),
        Some(g) if g.is_finite() && g > 0.0 && g < 1e9 => Ok((g * 1e9) as u64),
        Some(g) => Err(anyhow::anyhow!(
            "--max-memory must be a positive number of GB, got {g}"
        )),
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
    skips: &'a radiosity::pipeline::SkipStats,
    source_passes: &'a [radiosity::pipeline::SourcePassStats],
    passes: &'a [radiosity::pipeline::PassStats],
    #[serde(skip_serializing_if = "Option::is_none")]
    progressive: Option<&'a ProgressiveStats>,
    /// The punctual lights' direct light: lights, shadow rays, seconds and
    /// the power delivered (absent without punctual lights).
    #[serde(skip_serializing_if = "Option::is_none")]
    direct: Option<&'a radiosity::pipeline::DirectFigures>,
    memory: Memory<'a>,
    /// Per shaped gather, the patches seen by their parts.
    shaped_sources: &'a [usize],
    /// Per shaped gather, the corrections of the patch radiosities.
    shaped_corrections: &'a [usize],
    /// Per shaped gather, the receivers that saw a patch part by part.
    shaped_views: &'a [usize],
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

/// Runs `radiosity solve`: every option and the output folder are checked
/// before the scene is loaded; every file is staged and they all replace
/// their targets together at the end (none of them if anything fails).
pub fn run(a: &SolveArgs) -> Result<()> {
    let started = Instant::now();
    let pool = thread_pool(a.settings.threads)?;
    let plan = a.view.plan()?;
    let settings = settings(&a.settings)?;
    let options = load_options(&a.settings.load)?;
    prepare_folder(&a.out)?;
    if let Some(png) = &a.mesh_out {
        check_target(png)?;
    }
    let threads = pool.current_num_threads();
    pool.install(|| run_in_pool(a, &plan, &settings, &options, started, threads))
}

fn run_in_pool(
    a: &SolveArgs,
    plan: &ViewPlan,
    settings: &Settings,
    options: &LoadOptions,
    started: Instant,
    threads: usize,
) -> Result<()> {
    let t = Instant::now();
    let scene = load_within(&a.scene, options, settings.max_memory)?;
    let load_seconds = t.elapsed().as_secs_f64();
    for w in &scene.warnings {
        eprintln!("warning: {}", with_flags(w));
    }

    let views = choose_views(plan, &scene.cameras, || Camera::framing(&scene));
    // The file names follow the scene's name: checked now, before the solve.
    let mut files = check_view_files(views.len(), &a.view, plan, &a.out, &scene.name)?;
    let json = a.out.join(format!("{}.json", scene.name));
    check_target(&json)?;
    files.push(json.clone());
    files.extend(a.mesh_out.iter().cloned());
    refuse_overwriting_inputs(&files, &scene_inputs(&a.scene)?)?;
    // Held until the outputs are committed: a second run into this folder
    // for the same scene is refused instead of mixing its files with these.
    let _lock = lock_set(&a.out, &scene.name)?;
    let images = image_bytes(a.view.width, a.view.height, a.mesh_out.is_some());
    let limit = settings.max_memory;
    let settings = &solve_settings(settings, &[("the images", images)])?;
    // Checked before the solve too: a bad cell size is known now.
    let regions = a
        .regions
        .map(|cell| scene.regions_by_grid(cell))
        .transpose()?;

    let bars = Bars::new(a.quiet).watching_cost(settings.hemicube_resolution, threads);
    let mut previews = PreviewWriter {
        args: a,
        scene: &scene.name,
        camera: &views[0],
        tone: plan.tone,
        exposure: a.view.exposure,
        written: Vec::new(),
        error: None,
    };
    let solution =
        radiosity::pipeline::solve_with_previews(&scene, settings, &|p| bars.update(p), &mut |p| {
            previews.write(p)
        })
        .map_err(|e| {
            let memory = matches!(e, radiosity::Error::Limit { .. });
            let context = if memory {
                format!(
                    "solving '{}' ({} of the {} --max-memory are the solve's; the rest \
                     holds the program, the scene and the images)",
                    scene.name,
                    super::budget::gb(settings.max_memory),
                    super::budget::gb(limit)
                )
            } else {
                format!("solving '{}'", scene.name)
            };
            anyhow::Error::from(e).context(context)
        })?;
    bars.finish();
    if let Some(e) = previews.error {
        return Err(e);
    }
    let mut staged = output_set(&a.out, &scene.name)?;
    let written: Vec<String> = previews
        .written
        .iter()
        .map(|p| p.display().to_string())
        .collect();

    let t = Instant::now();
    let mut view_warnings = Vec::new();
    let mesh = solution.radiance_mesh();
    let segments = if a.mesh_out.is_some() {
        solution.mesh().leaf_edges()
    } else {
        Vec::new()
    };
    let overlay = a.mesh_out.as_deref().map(|png| Overlay {
        png,
        segments: &segments,
    });
    let mut outputs = write_views(
        &mut staged,
        &mesh,
        &views,
        &a.view,
        plan,
        &a.out,
        &scene.name,
        overlay,
        &mut view_warnings,
    )?;
    outputs.extend(written);
    let render_seconds = t.elapsed().as_secs_f64();

    let s: &SolveStats = solution.stats();
    for w in &s.warnings {
        eprintln!("warning: {}", with_flags(w));
    }
    let warnings: Vec<String> = scene
        .warnings
        .iter()
        .chain(&s.warnings)
        .chain(&view_warnings)
        .chain(&bars.cost_warning())
        .map(with_flags)
        .collect();
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
        direct: s.direct.as_ref(),
        memory: Memory {
            mesh: &s.memory,
            peak_resident_bytes: super::peak_memory::peak_resident_bytes(),
        },
        shaped_sources: &s.shaped_sources,
        shaped_corrections: &s.shaped_corrections,
        shaped_views: &s.shaped_views,
        final_max_difference: s.final_max_difference,
        bounces: s.bounces,
        patch_size: s.patch_size,
        threads,
        seed: a.settings.seed,
        import: &scene.import_stats,
        warnings: &warnings,
        outputs,
        surfaces: match &regions {
            Some(regions) => solution.object_radiosity(regions),
            None => solution.object_radiosity(&scene),
        },
    };
    let text = serde_json::to_string_pretty(&report)? + "\n";
    staged.stage_bytes(&json, text.as_bytes())?;
    staged.commit()?;
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
/// `--exposure` is given) so that they show the image filling in. Each is
/// written (whole, by its own rename) as soon as it is rendered: previews
/// show a solve under way, so they cannot wait for the run's other outputs.
struct PreviewWriter<'a> {
    args: &'a SolveArgs,
    scene: &'a str,
    camera: &'a Camera,
    tone: ToneMap,
    exposure: Option<f64>,
    /// The previews written so far.
    written: Vec<std::path::PathBuf>,
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
        let mesh = ShadedMesh::radiance_of(p.shading_mesh(true));
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
        self.written.push(png);
        Ok(())
    }
}

/// Runs `radiosity export-scene`.
pub fn export_scene(a: &ExportArgs) -> Result<()> {
    check_gltf_name(&a.output)?;
    check_target(&a.output)?;
    let _lock = super::outputs::lock_file(&a.output)?;
    let Some(scene) = scenes::by_name(&a.name) else {
        bail!(
            "no built-in scene '{}' (built-in: {}, {})",
            a.name,
            scenes::NAMES.join(", "),
            scenes::SIZED_NAMES
        );
    };
    gltf_io::write_scene(&scene, &a.output)?;
    Ok(())
}

/// Refuses an output file name that is neither `.glb` nor `.gltf`.
pub fn check_gltf_name(path: &Path) -> Result<()> {
    let extension = path.extension().and_then(|e| e.to_str());
    if !extension.is_some_and(|e| e.eq_ignore_ascii_case("glb") || e.eq_ignore_ascii_case("gltf")) {
        bail!(
            "{}: the file name must end in .glb or .gltf",
            path.display()
        );
    }
    Ok(())
}
