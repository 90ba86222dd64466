//! `radiosity reference`: per-object path-traced means with standard errors.

use super::args::ReferenceArgs;
use super::checks::thread_pool;
use super::outputs::{lock_file, refuse_overwriting_inputs, scene_inputs};
use super::solve_cmd::{load, load_options};
use anyhow::Result;
use radiosity::math::Rgb;
use radiosity::output::{check_target, write_bytes};
use radiosity::reference::{Reference, ReferenceSettings};
use radiosity::scene::{Scene, EMISSION_DEPTH};
use serde::Serialize;
use std::time::Instant;

#[derive(Serialize)]
struct ObjectReference {
    name: String,
    /// Whether the object's light is mostly its own emission (more than half
    /// of its radiosity), which `compare` does not count.
    emits: bool,
    /// Its area (m²), so that `compare` can tell another scene.
    area: f64,
    radiosity: Rgb,
    std_error: Rgb,
    paths: u64,
}

#[derive(Serialize)]
struct Report {
    scene: String,
    method: &'static str,
    paths_per_object: u64,
    seed: u64,
    seconds: f64,
    surfaces: Vec<ObjectReference>,
}

/// Per object, its area-mean emitted exitance: each surface's emission
/// averaged over its footprint in its emissive texture where it has one.
fn object_emission(scene: &Scene) -> Vec<Rgb> {
    let mut sums = vec![(0.0, Rgb::ZERO); scene.objects.len()];
    for s in &scene.surfaces {
        let m = scene.material_of(s);
        let e = match (&m.emissive_texture, s.uv.len() == s.vertices.len()) {
            (Some(t), true) => t.mean_over_refined(&s.uv, EMISSION_DEPTH),
            _ => m.emission,
        };
        let slot = &mut sums[s.object as usize];
        slot.0 += s.area;
        slot.1 += e * s.area;
    }
    sums.into_iter()
        .map(|(a, e)| if a > 0.0 { e / a } else { Rgb::ZERO })
        .collect()
}

/// Whether an object's light is mostly its own emission (more than half of
/// its radiosity in its brightest band): `compare` leaves those out, since
/// the solve is given their emission rather than computing it.
fn mostly_emitted(emitted: &Rgb, radiosity: &Rgb) -> bool {
    emitted.max_band() > 0.0 && emitted.max_band() > 0.5 * radiosity.max_band()
}

/// Runs `radiosity reference`.
pub fn run(a: &ReferenceArgs) -> Result<()> {
    let pool = thread_pool(a.threads)?;
    let settings = ReferenceSettings {
        paths: a.paths,
        seed: a.seed,
        ..ReferenceSettings::default()
    };
    settings.validate()?;
    let options = load_options(&a.load)?;
    let _lock = match &a.output {
        Some(path) => {
            check_target(path)?;
            refuse_overwriting_inputs(std::slice::from_ref(path), &scene_inputs(&a.scene)?)?;
            Some(lock_file(path)?)
        }
        None => None,
    };
    let scene = load(&a.scene, &options)?;
    let scene = match a.regions {
        Some(cell) => scene.regions_by_grid(cell)?,
        None => scene,
    };
    let started = Instant::now();
    let means = pool.install(|| -> Result<_> {
        let reference = Reference::new(&scene)?;
        Ok(reference.object_means(&settings)?)
    })?;
    let emitted = object_emission(&scene);
    let report = Report {
        scene: scene.name.clone(),
        method: "path tracing with next-event estimation (MIS), uniform points per object",
        paths_per_object: a.paths,
        seed: a.seed,
        seconds: started.elapsed().as_secs_f64(),
        surfaces: scene
            .objects
            .iter()
            .zip(means)
            .enumerate()
            .map(|(i, (o, m))| ObjectReference {
                name: o.name.clone(),
                emits: mostly_emitted(&emitted[i], &m.radiosity),
                area: scene
                    .surfaces
                    .iter()
                    .filter(|s| s.object as usize == i)
                    .map(|s| s.area)
                    .sum(),
                radiosity: m.radiosity,
                std_error: m.std_error,
                paths: m.paths,
            })
            .collect(),
    };
    let text = serde_json::to_string_pretty(&report)? + "\n";
    match &a.output {
        Some(path) => write_bytes(path, text.as_bytes())?,
        None => super::stdout::write_out(&text)?,
    }
    Ok(())
}
