//! The atrium's size series as a Markdown table: for each target, the
//! triangles and surfaces built, objects, the layout and density the size
//! search chose, and the time to generate the scene (search and build, the
//! median of three runs).
//!
//! `cargo run --release --example atrium_sizes [-- TARGET ...]`
//! (default targets: 10 000, 30 000, 100 000, 200 000, 1 000 000).

use radiosity::scenes::atrium::{atrium, triangle_count, AtriumSize};
use std::time::Instant;

fn main() {
    let mut targets: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("targets are whole numbers"))
        .collect();
    if targets.is_empty() {
        targets = vec![10_000, 30_000, 100_000, 200_000, 1_000_000];
    }
    println!("| target | triangles | deviation | surfaces | objects | bays | balusters | density (1/m) | generation (s) |");
    println!("| ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: |");
    for target in targets {
        let mut seconds = Vec::new();
        let mut scene = None;
        for _ in 0..3 {
            let started = Instant::now();
            scene = Some(atrium(target).expect("target in range"));
            seconds.push(started.elapsed().as_secs_f64());
        }
        seconds.sort_by(f64::total_cmp);
        let scene = scene.expect("three runs");
        let size = AtriumSize::for_target(target).expect("target in range");
        let triangles = triangle_count(&scene);
        println!(
            "| {target} | {triangles} | {:+.1}% | {} | {} | {} | {} | {:.2} | {:.3} |",
            100.0 * (triangles as f64 / target as f64 - 1.0),
            scene.surfaces.len(),
            scene.objects.len(),
            size.bays,
            if size.balusters { "yes" } else { "no" },
            size.density,
            seconds[1],
        );
    }
}
