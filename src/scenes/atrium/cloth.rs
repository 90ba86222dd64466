//! Cloth: banners hanging from rods, as height fields over a flat grid. Each
//! hangs a little in front of a wall or of the gallery columns and falls in
//! vertical folds that deepen towards the hem (the rod holds the top edge
//! straight). A banner is single-sided: its front faces the court, its back
//! the wall behind it.

use super::generator::Generator;
use super::hash_bits;
use super::plan::{Side, GALLERIES};
use super::shapes::steps_along;
use super::sink::Sink;
use super::trig::sin_cos;
use crate::error::Result;
use glam::DVec3;

/// Gap between a banner's rod and the wall behind it (m).
pub(super) const BANNER_GAP: f64 = 0.12;
/// Width of the banners in front of the gallery columns (m).
pub(super) const COLUMN_BANNER_WIDTH: f64 = 1.1;
/// Width of the banners on the end walls (m).
pub(super) const WALL_BANNER_WIDTH: f64 = 2.2;
/// Length of the banners on the end walls (m).
pub(super) const WALL_BANNER_LENGTH: f64 = 6.5;

/// A banner's placement and shape.
#[derive(Clone, Copy, Debug)]
struct Banner {
    /// The middle of the rod.
    top: DVec3,
    /// Unit direction the front faces.
    out: DVec3,
    width: f64,
    length: f64,
    /// Whole folds across the width.
    folds: u32,
    /// Depth of the folds at the hem (m).
    depth: f64,
}

/// Adds `banner_K`: one in front of every other column of the top gallery
/// on each side (hung from the roof's edge), then two on each end wall.
pub(super) fn add_banners<S: Sink>(g: &mut Generator<S>) -> Result<()> {
    let plan = g.plan;
    let mut banners = Vec::new();
    let top_gallery = GALLERIES - 1;
    let rod = plan.roof() - 0.15;
    let hem = plan.gallery_floor(top_gallery) + 1.3;
    for side in Side::BOTH {
        let (face, out) = match side {
            Side::South => (plan.court_face(), DVec3::Z),
            Side::North => (plan.width() - plan.court_face(), -DVec3::Z),
        };
        for i in (1..plan.bays).filter(|i| i % 2 == 1) {
            let h = hash_bits(&[3, side as u64, u64::from(i)]);
            banners.push(Banner {
                top: DVec3::new(plan.column_x(i), rod, face) + out * BANNER_GAP,
                out,
                width: COLUMN_BANNER_WIDTH,
                length: rod - hem,
                folds: 2 + (h % 2) as u32,
                depth: 0.06 + 0.04 * super::hash_unit(h, 8),
            });
        }
    }
    let middle = plan.width() / 2.0;
    for (x, out) in [(0.0, DVec3::X), (plan.length(), -DVec3::X)] {
        for offset in [-3.0, 3.0] {
            let h = hash_bits(&[4, x as u64, (offset > 0.0) as u64]);
            banners.push(Banner {
                top: DVec3::new(x, plan.roof() - 1.0, middle + offset) + out * BANNER_GAP,
                out,
                width: WALL_BANNER_WIDTH,
                length: WALL_BANNER_LENGTH,
                folds: 3 + (h % 2) as u32,
                depth: 0.08 + 0.05 * super::hash_unit(h, 8),
            });
        }
    }
    for (k, banner) in banners.iter().enumerate() {
        // Colours in turn, so that neighbours differ.
        let cloth = g.palette.cloths[k % g.palette.cloths.len()];
        let name = g.names.next("banner");
        g.sink.object(&name);
        drape(g, banner, cloth)?;
    }
    Ok(())
}

/// The banner's grid: cells about `1 / density` across and down (at least
/// four cells per fold across, two down), two triangles each, in `cloth`.
fn drape<S: Sink>(g: &mut Generator<S>, b: &Banner, cloth: u32) -> Result<()> {
    let density = g.size.density;
    let across = steps_along(b.width, density, 4 * b.folds as usize);
    let down = steps_along(b.length, density, 2);
    // Seen from the front, `right` runs left to right and up is +y.
    let right = DVec3::Y.cross(b.out);
    let point = |i: usize, j: usize| {
        let u = i as f64 / across as f64;
        let v = j as f64 / down as f64;
        let (_, c) = sin_cos(std::f64::consts::TAU * f64::from(b.folds) * u);
        let fold = b.depth * v * 0.5 * (1.0 - c);
        b.top + right * (b.width * (u - 0.5)) - DVec3::Y * (b.length * v) + b.out * fold
    };
    for j in 0..down {
        for i in 0..across {
            let (a, bb, c, d) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            // Counter-clockwise seen from the front: top-left, bottom-left,
            // bottom-right; top-left, bottom-right, top-right.
            g.sink.polygon(cloth, &[a, d, c])?;
            g.sink.polygon(cloth, &[a, c, bb])?;
        }
    }
    Ok(())
}
