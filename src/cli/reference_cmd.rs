//! `radiosity reference`: per-object path-traced means with standard errors.

use super::args::ReferenceArgs;
use super::checks::thread_pool;
use super::outputs::{lock_file, refuse_overwriting_inputs, scene_inputs};
use super::solve_cmd::{load, load_options};
use anyhow::Result;
use radiosity::math::Rgb;
use radiosity::output::{check_target, write_bytes};
use radiosity::reference::{Reference, ReferenceSettings};
use serde::Serialize;
use std::time::Instant;

#[derive(Serialize)]
struct ObjectReference {
    name: String,
    /// Whether any surface of the object emits (its radiosity is then mostly
    /// its own emission, which `compare` does not count).
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
    let started = Instant::now();
    let means = pool.install(|| -> Result<_> {
        let reference = Reference::new(&scene)?;
        Ok(reference.object_means(&settings)?)
    })?;
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
                emits: scene
                    .surfaces
                    .iter()
                    .any(|s| s.object as usize == i && scene.material_of(s).is_emitter()),
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
