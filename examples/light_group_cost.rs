//! What light groups cost: a scene solved once as it is, then with its
//! emitting surfaces and punctual lights dealt round-robin into G groups,
//! for each G given: the whole time, the groups' time after the solve, the
//! baked file's size and what each group's attribute adds to it, and how far
//! the groups' sum (what the bake shows) lies from the plain solve, per
//! object (area-weighted mean radiosity, largest band).
//!
//! `cargo run --release --example light_group_cost [-- SCENE [--uniform-depth D]
//! [--out DIR] G ...]` (default: many_boxes 1 4 16, adaptive refinement, the
//! bakes in a folder of the system's temporary directory).

use radiosity::gltf_io::{write_baked, BakeGroup, BakeOptions};
use radiosity::light_groups::{solve_with_light_groups, LightGroup, LightGroups};
use radiosity::scene::Scene;
use radiosity::{scenes, Settings};
use std::time::Instant;

/// The sources of `scene` dealt into `g` groups in turn.
fn dealt(scene: &Scene, g: usize) -> LightGroups {
    let mut groups: Vec<LightGroup> = (0..g)
        .map(|k| LightGroup {
            name: format!("group {}", k + 1),
            surfaces: Vec::new(),
            lights: Vec::new(),
            sky: false,
        })
        .collect();
    let emitters = scene
        .surfaces
        .iter()
        .enumerate()
        .filter(|(_, s)| scene.material_of(s).is_emitter())
        .map(|(i, _)| i as u32);
    for (n, s) in emitters.enumerate() {
        groups[n % g].surfaces.push(s);
    }
    let start = groups.iter().map(|x| x.surfaces.len()).sum::<usize>();
    for l in 0..scene.lights.len() {
        groups[(start + l) % g].lights.push(l as u32);
    }
    groups.retain(|x| !(x.surfaces.is_empty() && x.lights.is_empty()));
    LightGroups { groups }
}

fn main() -> radiosity::Result<()> {
    let mut args = std::env::args().skip(1);
    let name = args.next().unwrap_or_else(|| "many_boxes".to_string());
    let mut settings = Settings::default();
    let mut dir = std::env::temp_dir().join("radiosity-light-group-cost");
    let mut counts: Vec<usize> = Vec::new();
    while let Some(a) = args.next() {
        match a.as_str() {
            "--uniform-depth" => {
                let d = args.next().and_then(|d| d.parse().ok());
                settings.refine.uniform_depth = Some(d.expect("--uniform-depth D"));
            }
            "--out" => dir = args.next().expect("--out DIR").into(),
            g => counts.push(g.parse().expect("G is a whole number")),
        }
    }
    if counts.is_empty() {
        counts = vec![1, 4, 16];
    }
    let scene = scenes::by_name(&name).expect("a built-in scene");
    std::fs::create_dir_all(&dir).map_err(|e| radiosity::Error::io(&dir, e))?;

    let started = Instant::now();
    let plain = radiosity::solve(&scene, &settings, &|_| {})?;
    let plain_seconds = started.elapsed().as_secs_f64();
    let plain_objects = plain.object_radiosity(&scene);
    let path = dir.join("plain.glb");
    let one = write_baked(
        &scene,
        &plain.shading_mesh(),
        &[],
        &BakeOptions::default(),
        &path,
    )?;
    println!(
        "{name}: {} elements, {} display triangles; plain solve {plain_seconds:.1} s, bake {} bytes",
        plain.stats().elements,
        one.triangles,
        one.bytes
    );
    println!("| G | whole (s) | of it groups (s) | whole / plain | file (bytes) | per group (bytes) | objects off the plain solve (mean / max) |");
    println!("| ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for g in counts {
        let groups = dealt(&scene, g);
        let started = Instant::now();
        let mut solution = solve_with_light_groups(&scene, &settings, &groups, &|_| {})?;
        let seconds = started.elapsed().as_secs_f64();
        let shading = solution.shading_mesh();
        let parts = solution.group_shading_meshes();
        let bake: Vec<BakeGroup<'_>> = groups
            .groups
            .iter()
            .zip(&parts)
            .map(|(group, shading)| BakeGroup {
                name: &group.name,
                shading,
            })
            .collect();
        let path = dir.join(format!("groups_{g}.glb"));
        let summary = write_baked(&scene, &shading, &bake, &BakeOptions::default(), &path)?;
        let (mut sum, mut worst, mut n) = (0.0, 0.0f64, 0);
        for (a, b) in solution.object_radiosity(&scene).iter().zip(&plain_objects) {
            let reference = b.radiosity.max_band();
            if reference > 0.0 {
                let off = (a.radiosity - b.radiosity).abs().max_band() / reference;
                sum += off;
                worst = worst.max(off);
                n += 1;
            }
        }
        println!(
            "| {} | {seconds:.1} | {:.1} | {:.2} | {} | {} | {:.3}% / {:.3}% |",
            groups.len(),
            solution.light_group_seconds(),
            seconds / plain_seconds,
            summary.bytes,
            summary.group_bytes / summary.groups,
            100.0 * sum / n.max(1) as f64,
            100.0 * worst
        );
    }
    Ok(())
}
