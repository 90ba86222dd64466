//! Form factors: one hemi-cube row at three resolutions, and a parallel set of
//! rows, in a room of about 1000 patches.

mod bench_scene;

use bench_scene::{prepared_mesh, row_settings, spread_leaves};
use criterion::{criterion_group, criterion_main, Criterion};
use radiosity::formfactor::hemicube::{DeltaTable, Hemicube};
use radiosity::formfactor::{compute_rows, FormFactorMethod};
use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

/// One hemi-cube row (item buffer and delta form factors, the classic
/// pixel-sum method, no ray casting) from each of 16 receivers spread through
/// the room in turn, at resolutions 64, 128 and 256.
fn hemicube_row(c: &mut Criterion) {
    let (mesh, sources) = prepared_mesh(0);
    let receivers = spread_leaves(&mesh, 16);
    let patches = mesh.patches.len();
    let mut group = c.benchmark_group("hemicube_row");
    for resolution in [64, 128, 256] {
        let mut cube = Hemicube::new(Arc::new(DeltaTable::new(resolution)), patches);
        let mut next = 0;
        group.bench_function(format!("res{resolution}/{patches}_patches"), |b| {
            b.iter(|| {
                let e = &mesh.elements[receivers[next % receivers.len()]];
                next += 1;
                let normal = mesh.surfaces[e.surface as usize].normal;
                black_box(cube.row(
                    &sources,
                    e.centroid + normal * 1e-6,
                    normal,
                    0.3,
                    e.surface,
                    FormFactorMethod::Hemicube,
                    None,
                ))
            });
        });
    }
    group.finish();
}

/// `compute_rows` for 256 elements spread through the room: hybrid rows at
/// resolution 128 with emitter rays (the pipeline's default), on every
/// worker thread.
fn form_factor_rows(c: &mut Criterion) {
    let (mesh, sources) = prepared_mesh(0);
    let keys = spread_leaves(&mesh, 256);
    let settings = row_settings(128);
    let name = format!(
        "hybrid_res128/{}_rows/{}_patches",
        keys.len(),
        mesh.patches.len()
    );
    c.benchmark_group("form_factor_rows")
        .bench_function(name, |b| {
            b.iter(|| black_box(compute_rows(&mesh, &sources, &keys, &settings, &|_| {})));
        });
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    targets = hemicube_row, form_factor_rows
}
criterion_main!(benches);
