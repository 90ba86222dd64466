//! `radiosity bake`: solve a scene and write the solution as glTF with
//! per-vertex radiosity.

use super::args::SolveSettingsArgs;
use super::budget::solve_settings;
use super::checks::thread_pool;
use super::outputs::{lock_file, refuse_overwriting_inputs, scene_inputs};
use super::progress_bar::Bars;
use super::solve_cmd::{check_gltf_name, load_options, load_within, settings};
use anyhow::{Context, Result};
use clap::Args;
use radiosity::gltf_io::{write_baked, BakeColour};
use radiosity::output::check_target;
use std::path::PathBuf;
use std::time::Instant;

/// `radiosity bake`.
#[derive(Args, Debug, Clone)]
pub struct BakeArgs {
    /// A glTF 2.0 file (.gltf or .glb), or the name of a built-in scene.
    pub scene: String,
    /// The baked file: .glb, or .gltf with the buffer embedded.
    #[arg(short, long)]
    pub output: PathBuf,
    /// What COLOR_0 holds. `radiosity`: the radiosity itself on unlit white
    /// materials (a viewer shows the solution as it is). `light`: the
    /// irradiance, radiosity minus emission over reflectance (0 in bands that
    /// reflect nothing), on the scene's own materials, so that base colour times
    /// vertex colour is the reflected light and emitters keep their emission.
    /// Either way COLOR_0 is scaled into 0..1 by a power of two stored in each
    /// primitive's extras.radiosityScale.
    #[arg(long, default_value = "radiosity")]
    pub colour: BakeColour,
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
            eprintln!("warning: {w}");
        }
        let settings = solve_settings(&settings, &[])?;
        let bars = Bars::new(a.quiet)
            .watching_cost(settings.hemicube_resolution, rayon::current_num_threads());
        let solution = radiosity::solve(&scene, &settings, &|p| bars.update(p))
            .with_context(|| format!("solving '{}'", scene.name))?;
        bars.finish();
        let solved = started.elapsed().as_secs_f64();
        let t = Instant::now();
        let summary = write_baked(&scene, &solution.shading_mesh(), a.colour, &a.output)?;
        if !a.quiet {
            eprintln!(
                "{}: {} elements -> {} vertices, {} triangles, {} bytes ({} colour); \
                 solved in {solved:.3} s, baked in {:.3} s; wrote {}",
                scene.name,
                solution.stats().elements,
                summary.vertices,
                summary.triangles,
                summary.bytes,
                a.colour,
                t.elapsed().as_secs_f64(),
                a.output.display()
            );
        }
        Ok(())
    })
}
