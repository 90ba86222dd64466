//! Furniture standing on a floor: turned round tables and stools, long tables
//! and benches of boxes, terracotta planters with a shrub, and a fountain.
//! Every piece rests on the floor with no bottom face (the floor hides it)
//! and faces out; each is given by the point of the floor under its middle.

use super::generator::Generator;
use super::shapes::{cuboid, lathe, steps_along, steps_around, Faces, Profile};
use super::sink::Sink;
use super::trig::sin_cos;
use crate::error::Result;
use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, PI};

/// Radius of a round table's top (m).
pub(super) const ROUND_TABLE_RADIUS: f64 = 0.45;
/// Distance of the stools from a round table's axis (m).
pub(super) const STOOL_DISTANCE: f64 = 0.78;
/// Outer radius of a planter at its rim (m).
pub(super) const PLANTER_RADIUS: f64 = 0.45;
/// Outer radius of the fountain's basin (m).
pub(super) const FOUNTAIN_RADIUS: f64 = 1.6;

/// A round table with four stools around it.
pub(super) fn round_table<S: Sink>(g: &mut Generator<S>, at: DVec3, wood: u32) -> Result<()> {
    let mut table = Profile::start(0.25, 0.0);
    table
        .to(0.25, 0.03, wood)
        .to(0.05, 0.03, wood)
        .to(0.05, 0.71, wood)
        .to(ROUND_TABLE_RADIUS, 0.71, wood)
        .to(ROUND_TABLE_RADIUS, 0.75, wood)
        .to(0.0, 0.75, wood);
    let density = g.size.density;
    lathe(
        g.sink,
        at,
        &table,
        steps_around(ROUND_TABLE_RADIUS, density, 8),
    )?;
    let mut stool = Profile::start(0.15, 0.0);
    stool
        .to(0.15, 0.02, wood)
        .to(0.03, 0.02, wood)
        .to(0.03, 0.42, wood)
        .to(0.18, 0.42, wood)
        .to(0.18, 0.46, wood)
        .to(0.0, 0.46, wood);
    let around = steps_around(0.18, density, 6);
    for offset in [DVec3::X, DVec3::Z, -DVec3::X, -DVec3::Z] {
        lathe(g.sink, at + offset * STOOL_DISTANCE, &stool, around)?;
    }
    Ok(())
}

/// A long table 1.8 m by 0.8 m on four legs, its length along `along`
/// (x or z).
pub(super) fn long_table<S: Sink>(
    g: &mut Generator<S>,
    at: DVec3,
    along: DVec3,
    wood: u32,
) -> Result<()> {
    let half = footprint(along, 0.9, 0.4);
    let top = DVec3::new(half.x, 0.0, half.z);
    cuboid(
        g.sink,
        super::plan::Frame::WORLD,
        wood,
        at - top + DVec3::Y * 0.72,
        at + top + DVec3::Y * 0.77,
        Faces::ALL,
    )?;
    let leg = 0.03;
    for (sx, sz) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let centre = at + DVec3::new(sx * (half.x - 0.08), 0.0, sz * (half.z - 0.08));
        let lo = centre - DVec3::new(leg, 0.0, leg);
        let hi = centre + DVec3::new(leg, 0.72, leg);
        cuboid(
            g.sink,
            super::plan::Frame::WORLD,
            wood,
            lo,
            hi,
            Faces::SIDES,
        )?;
    }
    Ok(())
}

/// A bench `length` long and 0.36 m deep, seat 0.45 m high, on two slab
/// supports, its length along `along` (x or z).
pub(super) fn bench<S: Sink>(
    g: &mut Generator<S>,
    at: DVec3,
    along: DVec3,
    length: f64,
    wood: u32,
) -> Result<()> {
    let half = footprint(along, length / 2.0, 0.18);
    let seat = DVec3::new(half.x, 0.0, half.z);
    cuboid(
        g.sink,
        super::plan::Frame::WORLD,
        wood,
        at - seat + DVec3::Y * 0.4,
        at + seat + DVec3::Y * 0.45,
        Faces::ALL,
    )?;
    for end in [-1.0, 1.0] {
        let centre = at + along * (end * (length / 2.0 - 0.15));
        let support = footprint(along, 0.03, 0.15);
        let lo = centre - DVec3::new(support.x, 0.0, support.z);
        let hi = centre + DVec3::new(support.x, 0.4, support.z);
        cuboid(
            g.sink,
            super::plan::Frame::WORLD,
            wood,
            lo,
            hi,
            Faces::SIDES,
        )?;
    }
    Ok(())
}

/// Half-extents (x, 0, z) of a footprint `long` by `wide` (halves) whose
/// length runs along `along` (x or z).
fn footprint(along: DVec3, long: f64, wide: f64) -> DVec3 {
    if along.x.abs() > along.z.abs() {
        DVec3::new(long, 0.0, wide)
    } else {
        DVec3::new(wide, 0.0, long)
    }
}

/// A flared terracotta tub filled with soil, and a rounded shrub on it.
pub(super) fn planter<S: Sink>(g: &mut Generator<S>, at: DVec3) -> Result<()> {
    let p = g.palette;
    let (rim, soil_level, inner) = (0.66, 0.62, 0.39);
    let mut tub = Profile::start(0.36, 0.0);
    tub.to(PLANTER_RADIUS, 0.6, p.terracotta)
        .to(PLANTER_RADIUS, rim, p.terracotta)
        .to(inner, rim, p.terracotta)
        .to(inner, soil_level, p.terracotta)
        .to(0.0, soil_level, p.soil);
    let density = g.size.density;
    lathe(g.sink, at, &tub, steps_around(PLANTER_RADIUS, density, 8))?;
    // Part of an ellipsoid, cut where it meets the soil 30 degrees below its
    // equator (radius 0.35 m there, inside the tub's 0.39 m).
    let (a, b, cut) = (0.4, 0.55, PI / 6.0);
    let (sin_cut, cos_cut) = sin_cos(cut);
    let lift = b * sin_cut;
    let mut shrub = Profile::start(a * cos_cut, 0.0);
    shrub.curve(
        steps_along((FRAC_PI_2 + cut) * a, density, 4),
        p.foliage,
        |t| {
            if t == 1.0 {
                return (0.0, lift + b);
            }
            let (s, c) = sin_cos(-cut + (FRAC_PI_2 + cut) * t);
            (a * c, lift + b * s)
        },
    );
    lathe(
        g.sink,
        at + DVec3::Y * soil_level,
        &shrub,
        steps_around(a, density, 8),
    )
}

/// A round basin with a stem and a bowl in its middle, both holding water.
pub(super) fn fountain<S: Sink>(g: &mut Generator<S>, at: DVec3) -> Result<()> {
    let p = g.palette;
    let (stone, water) = (p.stone, p.water);
    let mut basin = Profile::start(FOUNTAIN_RADIUS, 0.0);
    basin
        .to(FOUNTAIN_RADIUS, 0.45, stone)
        .to(FOUNTAIN_RADIUS - 0.2, 0.45, stone)
        .to(FOUNTAIN_RADIUS - 0.2, 0.3, stone)
        .to(0.2, 0.3, water)
        .to(0.2, 0.9, stone);
    let density = g.size.density;
    // The bowl's underside, swelling out and up from the stem.
    basin.curve(steps_along(0.7, density, 3), stone, |t| {
        let (s, c) = sin_cos(FRAC_PI_2 * t);
        (0.2 + 0.5 * s, 0.9 + 0.3 * (1.0 - c))
    });
    basin
        .to(0.7, 1.26, stone)
        .to(0.6, 1.26, stone)
        .to(0.6, 1.2, stone)
        .to(0.0, 1.2, water);
    lathe(
        g.sink,
        at,
        &basin,
        steps_around(FOUNTAIN_RADIUS, density, 16),
    )
}
