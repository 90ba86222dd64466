//! The whole library solve of the built-in Cornell box at three settings.

use criterion::{criterion_group, criterion_main, Criterion};
use radiosity::refine::RefineSettings;
use radiosity::scenes::cornell_box;
use radiosity::Settings;
use std::hint::black_box;
use std::time::Duration;

/// `radiosity::solve` from the scene to element radiosities: a coarse uniform
/// mesh (no subdivision, hemi-cube 64), the defaults (adaptive, tolerance 0.05,
/// hemi-cube 64), the same with hemi-cubes of 128 (the earlier default), and
/// a fine uniform mesh (depth 2, hemi-cube 128).
fn solve_cornell(c: &mut Criterion) {
    let scene = cornell_box();
    let uniform = |depth: u8, resolution: usize| Settings {
        hemicube_resolution: resolution,
        refine: RefineSettings {
            uniform_depth: Some(depth),
            ..RefineSettings::default()
        },
        ..Settings::default()
    };
    let cases = [
        ("uniform_depth0_res64", uniform(0, 64)),
        ("default_adaptive_tol0.05_res64", Settings::default()),
        (
            "adaptive_tol0.05_res128",
            Settings {
                hemicube_resolution: 128,
                ..Settings::default()
            },
        ),
        ("uniform_depth2_res128", uniform(2, 128)),
    ];
    let mut group = c.benchmark_group("solve_cornell_box");
    for (name, settings) in cases {
        group.bench_function(name, |b| {
            b.iter(|| black_box(radiosity::solve(&scene, &settings, &|_| {}).expect("solves")));
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(8));
    targets = solve_cornell
}
criterion_main!(benches);
