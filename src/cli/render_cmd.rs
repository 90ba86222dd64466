//! `radiosity render`: more views of a baked solution, without solving again.

use super::outputs::{lock_set, output_set, refuse_overwriting_inputs, scene_inputs};
use super::view_args::ViewArgs;
use super::views::{check_view_files, choose_views, write_views};
use anyhow::Result;
use clap::Args;
use glam::DVec3;
use radiosity::gltf_io::{load_baked, ImportLimits};
use radiosity::math::Rgb;
use radiosity::output::prepare_folder;
use radiosity::render::ShadedMesh;
use radiosity::scene::{Camera, SceneBuilder};
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
    /// Cameras and images, as for `solve`.
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
        eprintln!("warning: {w}");
    }
    let mut notes = Vec::new();
    let views = choose_views(&plan, &baked.cameras, || {
        notes.push(format!(
            "{} has no camera: the view is the default framing of its mesh, as `solve` \
             frames a scene without one (give --camera for another)",
            a.baked.display()
        ));
        default_view(&baked.mesh, &baked.name)
    });
    for n in &notes {
        eprintln!("warning: {n}");
    }
    let files = check_view_files(views.len(), &a.view, &plan, &a.out, &baked.name)?;
    refuse_overwriting_inputs(&files, &scene_inputs(&a.baked)?)?;
    let _lock = lock_set(&a.out, &baked.name)?;
    let mut staged = output_set(&a.out, &baked.name)?;
    let outputs = write_views(
        &mut staged,
        &baked.mesh,
        &views,
        &a.view,
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

/// The library's default view of a baked mesh ([`Camera::framing`]: from
/// inside a closed room, from outside an object), taken on the mesh's
/// triangles as the surfaces of a scene; the bounding box's framing when no
/// triangle makes a surface.
fn default_view(mesh: &ShadedMesh, name: &str) -> Camera {
    let corner = |i: u32| mesh.positions.get(i as usize).copied();
    let mut builder = SceneBuilder::new(name);
    if let Ok(grey) = builder.material("baked", Rgb::splat(0.5), Rgb::ZERO) {
        builder.object(name);
        for t in &mesh.triangles {
            if let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) {
                // A degenerate triangle shows nothing and frames nothing.
                let _ = builder.triangle(grey, a, b, c);
            }
        }
    }
    match builder.build() {
        Ok(scene) => Camera::framing(&scene),
        Err(_) => {
            let (lo, hi) = mesh.positions.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            Camera::framing_box(lo, hi)
        }
    }
}
