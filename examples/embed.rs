//! Embedding `radiosity` in a program of your own, through its public API
//! only: write a scene to a glTF file, load it back, solve it, read each
//! object's light, and draw one view to a PNG. A file that is not there
//! comes back as a typed error the program can match on.
//!
//! `cargo run --release --example embed` (CI runs it). Writes only to the
//! system's temporary folder; prints each object's mean radiance and the
//! image's path, and fails if any object comes out unlit or not finite.

use radiosity::gltf_io::{self, ImportLimits};
use radiosity::render::{self, ToneMap};
use radiosity::{Error, Settings};
use std::sync::atomic::{AtomicUsize, Ordering};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let folder = std::env::temp_dir().join(format!("radiosity-embed-{}", std::process::id()));
    std::fs::create_dir_all(&folder)?;

    // A glTF file of our own: the built-in Cornell box, written out.
    let file = folder.join("cornell_box.gltf");
    gltf_io::write_scene(&radiosity::scenes::cornell_box(), &file)?;

    // Load it, as any glTF 2.0 file would be, and solve it. The library
    // never prints: progress comes through the callback.
    let scene = gltf_io::load_scene(&file, &ImportLimits::default())?;
    let updates = AtomicUsize::new(0);
    let solution = radiosity::solve(&scene, &Settings::default(), &|_progress| {
        updates.fetch_add(1, Ordering::Relaxed);
    })?;
    let stats = solution.stats();
    println!(
        "{}: {} patches, {} elements, {} progress updates",
        scene.name,
        stats.patches,
        stats.elements,
        updates.load(Ordering::Relaxed)
    );

    // Every object's mean radiance (radiosity / pi), per band.
    let mut unlit = Vec::new();
    for object in solution.object_radiosity(&scene) {
        let radiance = object.radiance().0;
        println!(
            "  {:<12} {:8.4} {:8.4} {:8.4}",
            object.name, radiance[0], radiance[1], radiance[2]
        );
        if !radiance.iter().all(|c| c.is_finite()) || radiance.iter().sum::<f64>() <= 0.0 {
            unlit.push(object.name);
        }
    }

    // One view, from the scene's own camera, tone mapped to a PNG.
    let image = render::render(&solution.radiance_mesh(), &scene.cameras[0], 320, 320)?;
    let tone = ToneMap::default();
    let png = folder.join("cornell_box.png");
    render::write_png(&image, &png, render::auto_exposure(&image, tone), tone)?;
    println!("wrote {}", png.display());

    // Errors are typed: a missing file is an I/O error naming it.
    let missing = folder.join("no_such_scene.glb");
    match gltf_io::load_scene(&missing, &ImportLimits::default()) {
        Err(Error::Io { path, .. }) => {
            println!("refused as expected: {} is missing", path.display())
        }
        Err(other) => return Err(format!("a missing file gave another error: {other}").into()),
        Ok(_) => return Err("a missing file loaded".into()),
    }

    if !unlit.is_empty() {
        return Err(format!("objects with no light: {unlit:?}").into());
    }
    if std::fs::metadata(&png)?.len() == 0 {
        return Err("the PNG is empty".into());
    }
    Ok(())
}
