//! Columns: a square plinth (ground storey) or pedestal (galleries), a
//! turned shaft with base moulding, entasis, necking ring and a convex
//! echinus, and a square abacus under the arch or slab it carries. Also the
//! half-piers (responds) where the arcades meet the end walls.

use super::generator::Generator;
use super::plan::{Frame, Side, GALLERIES, PARAPET_HEIGHT, PIER_HALF, SPRING};
use super::shapes::{cuboid, lathe, steps_along, steps_around, Faces, Profile};
use super::sink::Sink;
use crate::error::Result;
use glam::DVec3;

/// Height of the ground columns' square plinths (m).
pub(super) const PLINTH_HEIGHT: f64 = 0.3;
/// Height of every column's abacus (m).
pub(super) const ABACUS_HEIGHT: f64 = 0.2;
/// Shaft radius at the foot of a ground column (m).
pub(super) const GROUND_SHAFT_RADIUS: f64 = 0.24;
/// Shaft radius at the foot of a gallery column (m).
pub(super) const GALLERY_SHAFT_RADIUS: f64 = 0.2;
/// The shaft's top radius over its foot radius.
const TAPER: f64 = 0.85;
/// Radius of the base moulding's half-round (torus), per metre of shaft radius.
const TORUS: f64 = 0.25;
/// Radius of the necking ring (astragal), per metre of shaft radius.
const ASTRAGAL: f64 = 0.1;
/// Height of the echinus (m).
const ECHINUS_HEIGHT: f64 = 0.18;

/// Adds, per side, the two responds (`respond_K`), the ground columns and
/// then each gallery's columns (`column_K`, numbered side by side, storey by
/// storey, west to east).
pub(super) fn add_columns<S: Sink>(g: &mut Generator<S>) -> Result<()> {
    let plan = g.plan;
    for side in Side::BOTH {
        let frame = Frame::of(side, &plan);
        add_responds(g, frame)?;
        for i in 1..plan.bays {
            let name = g.names.next("column");
            g.sink.object(&name);
            let x = plan.column_x(i);
            let base = block(g, frame, x, 0.0, PLINTH_HEIGHT)?;
            let shaft_top = SPRING - ABACUS_HEIGHT;
            column(g, frame, x, base, shaft_top, GROUND_SHAFT_RADIUS)?;
            block_hanging(g, frame, x, shaft_top, SPRING)?;
        }
        for k in 0..GALLERIES {
            for i in 1..plan.bays {
                let name = g.names.next("column");
                g.sink.object(&name);
                let x = plan.column_x(i);
                let floor = plan.gallery_floor(k);
                let base = block(g, frame, x, floor, floor + PARAPET_HEIGHT)?;
                let shaft_top = plan.gallery_ceiling(k) - ABACUS_HEIGHT;
                column(g, frame, x, base, shaft_top, GALLERY_SHAFT_RADIUS)?;
                block_hanging(g, frame, x, shaft_top, plan.gallery_ceiling(k))?;
            }
        }
    }
    Ok(())
}

/// The half-piers the end arches spring from: boxes against the end walls,
/// as deep as the arcade and as tall as the ground columns.
fn add_responds<S: Sink>(g: &mut Generator<S>, frame: Frame) -> Result<()> {
    let axis = g.plan.arcade_axis();
    let x = g.plan.length();
    let stone = g.palette.stone;
    for (x0, x1, faces) in [
        (
            0.0,
            PIER_HALF,
            Faces {
                neg_x: false,
                ..Faces::SIDES
            },
        ),
        (
            x - PIER_HALF,
            x,
            Faces {
                pos_x: false,
                ..Faces::SIDES
            },
        ),
    ] {
        let name = g.names.next("respond");
        g.sink.object(&name);
        let lo = DVec3::new(x0, 0.0, axis - PIER_HALF);
        let hi = DVec3::new(x1, SPRING, axis + PIER_HALF);
        cuboid(g.sink, frame, stone, lo, hi, faces)?;
    }
    Ok(())
}

/// A square block standing on the floor at column `x` from `y0` to `y1`;
/// returns its top height.
fn block<S: Sink>(g: &mut Generator<S>, frame: Frame, x: f64, y0: f64, y1: f64) -> Result<f64> {
    let axis = g.plan.arcade_axis();
    let lo = DVec3::new(x - PIER_HALF, y0, axis - PIER_HALF);
    let hi = DVec3::new(x + PIER_HALF, y1, axis + PIER_HALF);
    cuboid(g.sink, frame, g.palette.stone, lo, hi, Faces::STANDING)?;
    Ok(y1)
}

/// The abacus: a square block under what the column carries (no top face).
fn block_hanging<S: Sink>(
    g: &mut Generator<S>,
    frame: Frame,
    x: f64,
    y0: f64,
    y1: f64,
) -> Result<()> {
    let axis = g.plan.arcade_axis();
    let lo = DVec3::new(x - PIER_HALF, y0, axis - PIER_HALF);
    let hi = DVec3::new(x + PIER_HALF, y1, axis + PIER_HALF);
    cuboid(g.sink, frame, g.palette.stone, lo, hi, Faces::HANGING)
}

/// The turned part of a column at `x` from `y0` to `y1`, foot radius `radius`.
fn column<S: Sink>(
    g: &mut Generator<S>,
    frame: Frame,
    x: f64,
    y0: f64,
    y1: f64,
    radius: f64,
) -> Result<()> {
    let density = g.size.density;
    let profile = column_profile(y1 - y0, radius, g.palette.stone, density);
    let around = steps_around(radius, density, 8);
    let base = frame.point(x, y0, g.plan.arcade_axis());
    lathe(g.sink, base, &profile, around)
}

/// The profile of a column shaft `height` tall with foot radius `radius`,
/// its segments `density` per metre (never fewer than a smooth outline at
/// the coarsest size needs).
pub(super) fn column_profile(height: f64, radius: f64, material: u32, density: f64) -> Profile {
    use super::trig::sin_cos;
    use std::f64::consts::{FRAC_PI_2, PI};
    let torus = TORUS * radius;
    let ring = ASTRAGAL * radius;
    let top = TAPER * radius;
    let capital = PIER_HALF - 0.04;
    // A half-round standing on the plinth, its centre `torus` in from the rim.
    let foot = radius + 0.5 * torus;
    let mut profile = Profile::start(foot, 0.0);
    profile.curve(steps_along(PI * torus, density, 2), material, |t| {
        let (s, c) = sin_cos(PI * t - FRAC_PI_2);
        (foot + torus * c, torus + torus * s)
    });
    profile.to(radius, 2.0 * torus, material);
    // The shaft tapers faster towards the top (entasis).
    let (shaft_foot, neck) = (2.0 * torus, height - ECHINUS_HEIGHT - 2.0 * ring);
    profile.curve(steps_along(neck - shaft_foot, density, 1), material, |t| {
        (
            radius - (radius - top) * t * t,
            shaft_foot + (neck - shaft_foot) * t,
        )
    });
    profile.curve(steps_along(PI * ring, density, 2), material, |t| {
        let (s, c) = sin_cos(PI * t - FRAC_PI_2);
        (top + ring * c, neck + ring + ring * s)
    });
    // The echinus: a quarter-round swelling out under the abacus.
    let start = neck + 2.0 * ring;
    let length = (capital - top) + (height - start);
    profile.curve(steps_along(length, density, 2), material, |t| {
        let (s, c) = sin_cos(FRAC_PI_2 * t);
        (
            top + (capital - top) * s,
            start + (height - start) * (1.0 - c),
        )
    });
    profile
}
