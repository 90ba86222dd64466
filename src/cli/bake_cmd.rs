//! `radiosity bake`: solve a scene, its light groups apart, and write the
//! solution as glTF that any viewer shows as `render` does.

use super::args::SolveSettingsArgs;
use super::budget::solve_settings;
use super::checks::{check_exposure, thread_pool};
use super::group_args::GroupArgs;
use super::outputs::{lock_file, refuse_overwriting_inputs, scene_inputs};
use super::progress_bar::Bars;
use super::setting_flags::with_flags;
use super::solve_cmd::{check_gltf_name, load_options, load_within, settings};
use super::view_cmd::MAX_VIEWED_GROUPS;
use super::viewer::write_site;
use anyhow::{Context, Result};
use clap::Args;
use radiosity::gltf_io::{write_baked, BakeGroup, BakeOptions, BakeSummary};
use radiosity::light_groups::solve_with_light_groups;
use radiosity::output::check_target;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `radiosity bake`.
#[derive(Args, Debug, Clone)]
pub struct BakeArgs {
    /// A glTF 2.0 file (.gltf or .glb), or the name of a built-in scene.
    pub scene: String,
    /// The baked file: .glb, or .gltf with the buffer embedded. COLOR_0 holds
    /// what `render` shows (exposed and tone mapped, on unlit materials), so
    /// that any viewer shows the solution; each light group's radiosity is a
    /// vertex attribute of its own (_GROUP_0, ...), named and scaled in
    /// asset.extras.radiosity.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Exposure of COLOR_0 in stops [default: `render`'s automatic exposure
    /// of the file's first camera].
    #[arg(long, allow_hyphen_values = true)]
    pub exposure: Option<f64>,
    /// Also write the bake and a page that walks through it and relights it
    /// (index.html, viewer.js, scene.glb) into this folder, for any web
    /// server (see `radiosity view`).
    #[arg(long, value_name = "DIR")]
    pub html: Option<PathBuf>,
    /// Light groups.
    #[command(flatten)]
    pub groups: GroupArgs,
    /// Solve settings, as for `solve`.
    #[command(flatten)]
    pub settings: SolveSettingsArgs,
    /// Print no progress (bars on a terminal, plain lines every few seconds
    /// otherwise).
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `radiosity bake`. The options and the output file are checked before
/// the scene is loaded; the baked file replaces its target whole or not at
/// all, so `bake x.glb -o x.glb` keeps `x.glb` intact if anything fails.
pub fn run(a: &BakeArgs) -> Result<()> {
    let started = Instant::now();
    let pool = thread_pool(a.settings.threads)?;
    check_gltf_name(&a.output)?;
    check_target(&a.output)?;
    check_exposure(a.exposure)?;
    a.groups.check()?;
    let settings = settings(&a.settings)?;
    refuse_overwriting_inputs(std::slice::from_ref(&a.output), &scene_inputs(&a.scene)?)?;
    let _lock = lock_file(&a.output)?;
    pool.install(|| {
        let scene = load_within(
            &a.scene,
            &load_options(&a.settings.load)?,
            settings.max_memory,
        )?;
        for w in &scene.warnings {
            eprintln!("warning: {}", with_flags(w));
        }
        let settings = solve_settings(&settings, &[])?;
        let scene = a.groups.scaled(scene)?;
        let groups = a.groups.groups(&scene)?;
        let bars = Bars::new(a.quiet)
            .watching_cost(settings.hemicube_resolution, rayon::current_num_threads());
        let progress = |p| bars.update(p);
        let mut solution = match &groups {
            Some(groups) => solve_with_light_groups(&scene, &settings, groups, &progress),
            None => radiosity::solve(&scene, &settings, &progress),
        }
        .with_context(|| format!("solving '{}'", scene.name))?;
        bars.finish();
        let solved = started.elapsed().as_secs_f64();
        let t = Instant::now();
        let shading = solution.shading_mesh();
        let parts = solution.group_shading_meshes();
        let names: Vec<String> = solution
            .light_groups()
            .groups
            .iter()
            .map(|g| g.name.clone())
            .collect();
        let bake_groups: Vec<BakeGroup<'_>> = names
            .iter()
            .zip(&parts)
            .map(|(name, shading)| BakeGroup { name, shading })
            .collect();
        let options = BakeOptions {
            exposure: a.exposure,
            ..BakeOptions::default()
        };
        let summary = write_baked(&scene, &shading, &bake_groups, &options, &a.output)?;
        for w in &summary.warnings {
            eprintln!("warning: {}", with_flags(w));
        }
        if summary.groups > MAX_VIEWED_GROUPS {
            eprintln!(
                "warning: {} light groups: `radiosity view` and the --html page mix at most \
                 {MAX_VIEWED_GROUPS} (--light-group NAME=PATTERN,... merges sources)",
                summary.groups
            );
        }
        if let Some(dir) = &a.html {
            write_site(dir, &a.output)?;
        }
        if !a.quiet {
            report(
                a,
                &scene.name,
                &solution,
                &summary,
                solved,
                t.elapsed().as_secs_f64(),
            );
        }
        Ok(())
    })
}

/// The summary line on standard error.
fn report(
    a: &BakeArgs,
    name: &str,
    solution: &radiosity::Solution,
    summary: &BakeSummary,
    solved: f64,
    baked: f64,
) {
    let groups = match summary.groups {
        1 => "1 light group".to_string(),
        n => format!(
            "{n} light groups ({:.3} s after the solve, {} bytes of attributes)",
            solution.light_group_seconds(),
            summary.group_bytes
        ),
    };
    eprintln!(
        "{name}: {} elements -> {} vertices, {} triangles, {} bytes, {groups}, exposure \
         {:.2}; solved in {solved:.3} s, baked in {baked:.3} s; wrote {}{}",
        solution.stats().elements,
        summary.vertices,
        summary.triangles,
        summary.bytes,
        summary.exposure,
        a.output.display(),
        a.html
            .as_deref()
            .map(|d: &Path| format!(" and the page in {}", d.display()))
            .unwrap_or_default()
    );
}
