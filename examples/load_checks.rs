//! Times loading a glTF file and each check the solve makes before its first
//! form factor (issue 17: all of them well under a second on 100 000
//! triangles). `cargo run --release --example load_checks -- FILE`; without a
//! file, times the built-in atrium of 100 000 triangles as built in code.

use radiosity::gltf_io::{load_scene, ImportLimits};
use radiosity::scene::{Overlaps, Scene};
use std::time::Instant;

fn main() -> radiosity::Result<()> {
    let t = Instant::now();
    let mut scene: Scene = match std::env::args().nth(1) {
        Some(path) => load_scene(path.as_ref(), &ImportLimits::default())?,
        None => radiosity::scenes::atrium(100_000)?,
    };
    let load = t.elapsed().as_secs_f64();
    println!(
        "{}: {} triangles read, {} surfaces; load (with its repairs) {load:.3} s",
        scene.name,
        scene.import_stats.triangles_read,
        scene.surfaces.len()
    );
    let time = |what: &str, f: &mut dyn FnMut() -> radiosity::Result<()>| {
        let t = Instant::now();
        let outcome = f();
        println!(
            "{what}: {:.3} s ({})",
            t.elapsed().as_secs_f64(),
            if outcome.is_ok() { "passed" } else { "failed" }
        );
    };
    time("light", &mut || scene.check_light());
    time("overlaps, refusing", &mut || {
        scene.clone().resolve_overlaps(Overlaps::Error)
    });
    time("overlaps, resolving", &mut || {
        scene.resolve_overlaps(Overlaps::Resolve)
    });
    time("settings", &mut || {
        radiosity::Settings::default().validate()
    });
    Ok(())
}
