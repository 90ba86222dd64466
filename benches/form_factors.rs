//! Form factors: one hemi-cube row at three resolutions (whole, and stage by
//! stage), and a parallel set of rows on one and two threads, in a room of
//! about 1000 patches; rows in the 10 000-triangle atrium with and without
//! face clusters and level of detail.

mod bench_scene;
mod cpu_clock;

use bench_scene::{prepared_mesh, row_settings, spread_leaves};
use cpu_clock::iter_cpu;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use radiosity::formfactor::hemicube::{DeltaTable, Hemicube};
use radiosity::formfactor::{compute_rows, FormFactorMethod};
use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

/// Pixels of one hemi-cube at `resolution`: the top face and four half faces.
fn hemicube_pixels(resolution: usize) -> u64 {
    (resolution * resolution + 4 * resolution * resolution / 2) as u64
}

/// One hemi-cube row (item buffer and delta form factors, the classic
/// pixel-sum method, no ray casting) from each of 16 receivers spread through
/// the room in turn, at resolutions 64, 128 and 256. Timed by the thread's
/// CPU clock; throughput is in hemi-cube pixels per second of one core.
fn hemicube_row(c: &mut Criterion) {
    let (mesh, _, sources) = prepared_mesh(0);
    let receivers = spread_leaves(&mesh, 16);
    let patches = mesh.patches().len();
    let mut group = c.benchmark_group("hemicube_row");
    for resolution in [64, 128, 256] {
        group.throughput(Throughput::Elements(hemicube_pixels(resolution)));
        let mut cube = Hemicube::new(Arc::new(DeltaTable::new(resolution)), patches);
        let mut next = 0;
        group.bench_function(format!("res{resolution}/{patches}_patches"), |b| {
            iter_cpu(b, || {
                let e = &mesh[receivers[next % receivers.len()]];
                next += 1;
                let normal = mesh.surfaces()[e.surface() as usize].normal;
                black_box(cube.row(
                    &sources,
                    e.centroid() + normal * 1e-6,
                    normal,
                    0.3,
                    e.surface(),
                    FormFactorMethod::Hemicube,
                ));
            });
        });
    }
    group.finish();
}

/// The stages of one classic hemi-cube row, from the same 16 receivers as
/// [`hemicube_row`]: `clear` (no polygons: the buffers reset), `project`
/// (every polygon transformed, culled, clipped and projected onto the faces,
/// no pixel filled), `fill` (the same plus edge walking and the span fill with
/// its depth test: the whole item buffer), and `row` (the item buffer plus the
/// per-patch sums, as [`hemicube_row`]). Differences between them split the
/// row's time. Timed by the thread's CPU clock.
fn hemicube_stages(c: &mut Criterion) {
    let (mesh, _, sources) = prepared_mesh(0);
    let empty = radiosity::formfactor::Sources::default();
    let receivers = spread_leaves(&mesh, 16);
    let patches = mesh.patches().len();
    let mut group = c.benchmark_group("hemicube_stages");
    for resolution in [64, 128, 256] {
        group.throughput(Throughput::Elements(hemicube_pixels(resolution)));
        let mut cube = Hemicube::new(Arc::new(DeltaTable::new(resolution)), patches);
        for stage in ["clear", "project", "fill", "row"] {
            let mut next = 0;
            group.bench_function(format!("res{resolution}/{stage}"), |b| {
                iter_cpu(b, || {
                    let e = &mesh[receivers[next % receivers.len()]];
                    next += 1;
                    let normal = mesh.surfaces()[e.surface() as usize].normal;
                    let eye = e.centroid() + normal * 1e-6;
                    match stage {
                        "clear" => {
                            cube.render_stage::<false>(&empty, eye, normal, 0.3, e.surface())
                        }
                        "project" => {
                            cube.render_stage::<false>(&sources, eye, normal, 0.3, e.surface())
                        }
                        "fill" => {
                            cube.render_stage::<true>(&sources, eye, normal, 0.3, e.surface())
                        }
                        _ => {
                            black_box(cube.row(
                                &sources,
                                eye,
                                normal,
                                0.3,
                                e.surface(),
                                FormFactorMethod::Hemicube,
                            ));
                        }
                    }
                });
            });
        }
    }
    group.finish();
}

/// `compute_rows` for 256 elements spread through the room: hybrid rows at
/// resolution 128 with emitter rays, on a pool of
/// one and of two worker threads. Throughput is in rows.
fn form_factor_rows(c: &mut Criterion) {
    let (mesh, _, sources) = prepared_mesh(0);
    let keys = spread_leaves(&mesh, 256);
    let settings = row_settings(128);
    let mut group = c.benchmark_group("form_factor_rows");
    group.throughput(Throughput::Elements(keys.len() as u64));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a worker pool");
        let name = format!(
            "hybrid_res128/{}_rows/{}_patches/{threads}_threads",
            keys.len(),
            mesh.patches().len()
        );
        group.bench_function(name, |b| {
            b.iter(|| {
                pool.install(|| black_box(compute_rows(&mesh, &sources, &keys, &settings, &|_| {})))
            });
        });
    }
    group.finish();
}

/// `compute_rows` for 128 leaves spread through the 10 000-triangle atrium at
/// its default patch size and hemi-cube resolution (64): with face clusters
/// and level of detail (the defaults), without level of detail, and without
/// either (every surface its own patch). Throughput is in rows; two threads.
fn atrium_rows(c: &mut Criterion) {
    let scene = radiosity::scenes::atrium(10_000).expect("the atrium builds");
    let patch_size = radiosity::Settings::default().patch_size_for(&scene);
    let mut group = c.benchmark_group("atrium_rows");
    for (name, clusters, lod) in [
        ("clusters_lod", true, true),
        ("clusters", true, false),
        ("plain", false, false),
    ] {
        let mesh = radiosity::mesh::Mesh::build(&scene, patch_size, usize::MAX, clusters)
            .expect("the atrium meshes");
        let sources = radiosity::formfactor::Sources::from_mesh(&mesh);
        let keys = spread_leaves(&mesh, 128);
        let settings = radiosity::formfactor::RowSettings {
            level_of_detail: lod,
            ..row_settings(64)
        };
        group.throughput(Throughput::Elements(keys.len() as u64));
        let label = format!("{name}/{}_patches", mesh.patches().len());
        group.bench_function(label, |b| {
            b.iter(|| black_box(compute_rows(&mesh, &sources, &keys, &settings, &|_| {})));
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    targets = hemicube_row, hemicube_stages, form_factor_rows, atrium_rows
}
criterion_main!(benches);
