//! `radiosity render`: more views of a baked solution, without solving again.

use super::outputs::{lock_set, output_set, refuse_overwriting_inputs, scene_inputs};
use super::setting_flags::with_flags;
use super::view_args::ViewArgs;
use super::views::{check_view_files, choose_views, write_views};
use anyhow::Result;
use clap::Args;
use radiosity::gltf_io::{load_baked, ImportLimits};
use radiosity::output::prepare_folder;
use radiosity::render::default_view;
use std::path::PathBuf;
use std::time::Instant;

/// `radiosity render`.
#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// A baked solution (.glb or .gltf written by `radiosity bake`).
    pub baked: PathBuf,
    /// Folder for NAME.png and NAME.exr (NAME is the baked file's stem).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Cameras and images, as for `solve`; the exposure is the bake's own
    /// unless given (automatic for bakes made before light groups).
    #[command(flatten)]
    pub view: ViewArgs,
    /// Print no summary.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `radiosity render`: all views' files replace their targets together.
pub fn run(a: &RenderArgs) -> Result<()> {
    let started = Instant::now();
    let plan = a.view.plan()?;
    prepare_folder(&a.out)?;
    let baked = load_baked(&a.baked, &ImportLimits::default())?;
    for w in &baked.warnings {
        eprintln!("warning: {}", with_flags(w));
    }
    let mut notes = Vec::new();
    let views = choose_views(&plan, &baked.cameras, || {
        notes.push(format!(
            "{} has no camera: the view is the default framing of its mesh, as `solve` \
             frames a scene without one (give --camera for another)",
            a.baked.display()
        ));
        default_view(&baked.mesh)
    });
    for n in &notes {
        eprintln!("warning: {n}");
    }
    let files = check_view_files(views.len(), &a.view, &plan, &a.out, &baked.name)?;
    refuse_overwriting_inputs(&files, &scene_inputs(&a.baked)?)?;
    let _lock = lock_set(&a.out, &baked.name)?;
    let mut staged = output_set(&a.out, &baked.name)?;
    // A bake's colours were made at one exposure: its renders use it too,
    // unless told (so that they show what a viewer of the file shows).
    let mut view = a.view.clone();
    view.exposure = view.exposure.or(baked.exposure);
    let outputs = write_views(
        &mut staged,
        &baked.mesh,
        &views,
        &view,
        &plan,
        &a.out,
        &baked.name,
        None,
        &mut notes,
    )?;
    staged.commit()?;
    if !a.quiet {
        eprintln!(
            "{}: {} triangles, {} view(s) in {:.3} s; wrote {}",
            baked.name,
            baked.mesh.triangles.len(),
            views.len(),
            started.elapsed().as_secs_f64(),
            outputs.join(", ")
        );
    }
    Ok(())
}
