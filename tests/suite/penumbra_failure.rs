//! What a failing penumbra test leaves behind: top-down rasters of the floor's
//! element values (solved and exact) and of their difference, and every
//! floor element as CSV, under `target/penumbra-failures/NAME/`.

use super::penumbra_metrics::FloorErrors;
use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::mesh::ElementKey;
use radiosity::render::{false_colour, write_exr, write_png, HdrImage, ToneMap};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Pixels across the floor in the rasters.
const RASTER: u32 = 256;

/// The folder for one failure: `<target dir>/penumbra-failures/<name>`.
pub fn failure_dir(name: &str) -> PathBuf {
    // CARGO_TARGET_TMPDIR is `<target dir>/tmp`, wherever the target dir is.
    Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("the tmp dir lies in the target dir")
        .join("penumbra-failures")
        .join(name)
}

/// Writes `actual.{exr,png}`, `expected.{exr,png}`, `difference.png` and
/// `elements.csv` for `m` under `failure_dir(name)` and returns the folder.
///
/// The rasters look straight down on the floor (`x` to the right, `z`
/// downwards) and hold each pixel's element value as a fraction of the
/// light-on value, so 1 is white in the PNGs; the difference is
/// `|solved - exact|` in false colour with its scale beside it.
pub fn write_failure(name: &str, m: &FloorErrors) -> PathBuf {
    let dir = failure_dir(name);
    std::fs::create_dir_all(&dir).expect("creating the failure folder");
    let values: HashMap<ElementKey, (f64, f64)> = m
        .floor
        .iter()
        .map(|e| (e.key, (e.solved, e.exact)))
        .collect();
    let (lo, hi) = floor_bounds(m);
    let prober = m.solution.probe();
    let mut actual = HdrImage::new(RASTER, RASTER);
    let mut expected = HdrImage::new(RASTER, RASTER);
    let mut difference = HdrImage::new(RASTER, RASTER);
    for j in 0..RASTER {
        for i in 0..RASTER {
            let fx = (f64::from(i) + 0.5) / f64::from(RASTER);
            let fz = (f64::from(j) + 0.5) / f64::from(RASTER);
            let p = DVec3::new(lo.x + fx * (hi.x - lo.x), lo.y, lo.z + fz * (hi.z - lo.z));
            let Some(hit) = prober.hit(p, DVec3::Y) else {
                continue;
            };
            let Some(&(solved, exact)) = values.get(&hit.element) else {
                continue;
            };
            actual.set(i, j, Rgb::splat(solved / m.light_on));
            expected.set(i, j, Rgb::splat(exact / m.light_on));
            difference.set(i, j, Rgb::splat((solved - exact).abs() / m.light_on));
        }
    }
    write_exr(&actual, &dir.join("actual.exr")).unwrap();
    write_exr(&expected, &dir.join("expected.exr")).unwrap();
    write_png(&actual, &dir.join("actual.png"), 0.0, ToneMap::Clamp).unwrap();
    write_png(&expected, &dir.join("expected.png"), 0.0, ToneMap::Clamp).unwrap();
    let top = m.max.max(1e-12);
    false_colour(&difference, 0.0, top, false)
        .unwrap()
        .save(dir.join("difference.png"))
        .unwrap();
    let mut csv = String::from("centroid_x,centroid_z,area,solved,exact,exact_at_centroid\n");
    for e in &m.floor {
        let c = radiosity::math::polygon_centroid(&e.polygon);
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{}",
            c.x, c.z, e.area, e.solved, e.exact, e.exact_at_centroid
        );
    }
    std::fs::write(dir.join("elements.csv"), csv).unwrap();
    dir
}

/// The floor's bounding box.
fn floor_bounds(m: &FloorErrors) -> (DVec3, DVec3) {
    m.floor
        .iter()
        .flat_map(|e| e.polygon.iter())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        })
}
