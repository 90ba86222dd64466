//! The coarse solve and the gather, on the room of about 1000 patches with
//! its rows computed once beforehand.

// Shared with the form-factor benches, which use all of it.
#[allow(dead_code)]
mod bench_scene;

use bench_scene::prepared_mesh;
use criterion::{criterion_group, criterion_main, Criterion};
use radiosity::math::Rgb;
use radiosity::solve::{gather, gauss_seidel, PatchSystem, Radiosity, SolverSettings};
use std::hint::black_box;
use std::time::Duration;

/// One Gauss-Seidel sweep over the patch system (every patch updated once, in
/// place), and a whole `gauss_seidel` solve from the emission down to the
/// default 1e-5 error bound.
fn gauss_seidel_bench(c: &mut Criterion) {
    let (mesh, form_factors, _) = prepared_mesh(0);
    let system = PatchSystem::from_mesh(&mesh, &form_factors);
    let n = system.len();
    let settings = SolverSettings::default();
    let mut probe = system.emission.clone();
    let sweeps = gauss_seidel(&system, &mut probe, &settings)
        .expect("the bench room converges")
        .iterations;
    let mut group = c.benchmark_group("gauss_seidel");
    let mut b_sweep: Vec<Rgb> = system.emission.clone();
    group.bench_function(format!("one_sweep/{n}_patches"), |b| {
        b.iter(|| {
            for i in 0..n {
                b_sweep[i] = system.update(i, &b_sweep);
            }
            black_box(&b_sweep);
        });
    });
    group.bench_function(format!("solve_to_1e-5_{sweeps}_sweeps/{n}_patches"), |b| {
        b.iter_batched_ref(
            || system.emission.clone(),
            |radiosity| black_box(gauss_seidel(&system, radiosity, &settings)),
            criterion::BatchSize::SmallInput,
        );
    });
    group.finish();
}

/// One gather from the solved patches to every leaf (patches split to depth 1,
/// four elements each), on every worker thread.
fn gather_bench(c: &mut Criterion) {
    let (mesh, form_factors, _) = prepared_mesh(1);
    let system = PatchSystem::from_mesh(&mesh, &form_factors);
    let mut radiosity = Radiosity::emitted(&mesh);
    let mut b = system.emission.clone();
    gauss_seidel(&system, &mut b, &SolverSettings::default()).expect("converges");
    let name = format!(
        "{}_elements/{}_patches",
        mesh.leaf_count(),
        mesh.patches().len()
    );
    c.benchmark_group("gather").bench_function(name, |bench| {
        bench.iter(|| black_box(gather(&mesh, &form_factors, &mut radiosity, &b)));
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = gauss_seidel_bench, gather_bench
}
criterion_main!(benches);
