//! The benchmark scene: a closed room with a ceiling light and eight boxes,
//! cut into about 1000 patches, with its rows computed once.

use glam::DVec3;
use radiosity::formfactor::hemicube::DeltaTable;
use radiosity::formfactor::{compute_rows, FormFactorMethod, FormFactors, RowSettings, Sources};
use radiosity::math::Rgb;
use radiosity::mesh::{ElementKey, Mesh};
use radiosity::scene::{Scene, SceneBuilder};
use std::sync::Arc;

/// Patch edge (m) that cuts [`room_with_boxes`] into about 1000 patches.
pub const PATCH_SIZE: f64 = 0.32;

/// A 4 m x 3 m x 4 m room (walls facing in), a 1 m square light just below
/// the ceiling, and eight boxes standing 1 cm above the floor.
pub fn room_with_boxes() -> Scene {
    let mut b = SceneBuilder::new("bench_room");
    let wall = b
        .material("wall", Rgb::splat(0.7), Rgb::ZERO)
        .expect("valid");
    let red = b
        .material("red", Rgb::new(0.6, 0.1, 0.1), Rgb::ZERO)
        .expect("valid");
    let boxes = b
        .material("box", Rgb::splat(0.5), Rgb::ZERO)
        .expect("valid");
    let lamp = b
        .material("lamp", Rgb::ZERO, Rgb::splat(5.0))
        .expect("valid");
    let p = DVec3::new;
    let (x, y, z) = (4.0, 3.0, 4.0);
    b.object("room");
    let faces = [
        // floor (up), ceiling (down), then the four walls facing in.
        (
            wall,
            [p(0., 0., 0.), p(0., 0., z), p(x, 0., z), p(x, 0., 0.)],
        ),
        (wall, [p(0., y, 0.), p(x, y, 0.), p(x, y, z), p(0., y, z)]),
        (
            wall,
            [p(0., 0., 0.), p(x, 0., 0.), p(x, y, 0.), p(0., y, 0.)],
        ),
        (wall, [p(0., 0., z), p(0., y, z), p(x, y, z), p(x, 0., z)]),
        (
            red,
            [p(0., 0., 0.), p(0., y, 0.), p(0., y, z), p(0., 0., z)],
        ),
        (wall, [p(x, 0., 0.), p(x, 0., z), p(x, y, z), p(x, y, 0.)]),
    ];
    for (material, [a, b2, c, d]) in faces {
        b.quad(material, a, b2, c, d).expect("valid quad");
    }
    b.object("light");
    let h = y - 0.01;
    b.quad(
        lamp,
        p(1.5, h, 1.5),
        p(2.5, h, 1.5),
        p(2.5, h, 2.5),
        p(1.5, h, 2.5),
    )
    .expect("valid light");
    for k in 0..8 {
        let (i, j) = (f64::from(k % 4), f64::from(k / 4));
        let lo = p(0.4 + i * 0.9, 0.01, 0.8 + j * 1.8);
        let hi = lo + p(0.5, 0.3 + 0.15 * i, 0.6);
        b.axis_box(&format!("box_{k}"), boxes, lo, hi)
            .expect("valid box");
    }
    b.build().expect("the bench scene builds")
}

/// The room's mesh at [`PATCH_SIZE`], split to `depth`, with every leaf's
/// hybrid row at resolution 128 computed and stored, and its sources.
pub fn prepared_mesh(depth: u8) -> (Mesh, FormFactors, Sources) {
    let scene = room_with_boxes();
    let mut mesh = Mesh::new(&scene, PATCH_SIZE, 100_000).expect("the mesh fits");
    for _ in 0..depth {
        for k in mesh.leaves() {
            mesh.split(k);
        }
    }
    let sources = Sources::from_mesh(&mesh);
    let leaves = mesh.leaves();
    let (rows, _) = compute_rows(&mesh, &sources, &leaves, &row_settings(128), &|_| {});
    let mut form_factors = FormFactors::new();
    for (k, row) in leaves.into_iter().zip(rows) {
        form_factors.set_row(k, row);
    }
    (mesh, form_factors, sources)
}

/// Hybrid rows with emitter rays, as the pipeline computes them by default.
pub fn row_settings(resolution: usize) -> RowSettings {
    RowSettings {
        table: Arc::new(DeltaTable::new(resolution)),
        seed: 1,
        method: FormFactorMethod::Hybrid,
        emitter_sampling: radiosity::formfactor::EmitterSampling::Centre,
        level_of_detail: true,
    }
}

/// `count` leaves spread evenly through the mesh's leaf list.
pub fn spread_leaves(mesh: &Mesh, count: usize) -> Vec<ElementKey> {
    let leaves = mesh.leaves();
    let step = (leaves.len() / count).max(1);
    leaves.into_iter().step_by(step).take(count).collect()
}
