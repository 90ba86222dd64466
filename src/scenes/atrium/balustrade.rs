//! The galleries' balustrades between the column pedestals: a plinth, a
//! top rail and turned balusters between them, or at the smallest sizes a
//! solid parapet of the same outline (a row of balusters costs more
//! triangles than the smallest scenes have).

use super::generator::Generator;
use super::plan::{Frame, Side, GALLERIES, PARAPET_HEIGHT, PARAPET_THICKNESS};
use super::shapes::{cuboid, lathe, steps_along, steps_around, Faces, Profile};
use super::sink::Sink;
use super::trig::sin_cos;
use crate::error::Result;
use glam::DVec3;

/// Height of the balustrade's plinth (m).
pub(super) const PLINTH: f64 = 0.15;
/// Height of the top rail (m).
pub(super) const RAIL: f64 = 0.14;
/// Distance between baluster axes, at most (m).
pub(super) const BALUSTER_PITCH: f64 = 0.3;
/// Largest radius of a baluster (m).
pub(super) const BALUSTER_RADIUS: f64 = 0.075;

/// Adds `balustrade_K` per side and gallery (south first, lower first).
pub(super) fn add_balustrades<S: Sink>(g: &mut Generator<S>) -> Result<()> {
    let plan = g.plan;
    let stone = g.palette.stone;
    let face = plan.court_face();
    let inner = face - PARAPET_THICKNESS;
    // Only the faces that show: no ends (against pedestals and end walls).
    let long = Faces {
        neg_x: false,
        pos_x: false,
        ..Faces::STANDING
    };
    for side in Side::BOTH {
        let frame = Frame::of(side, &plan);
        for k in 0..GALLERIES {
            let name = g.names.next("balustrade");
            g.sink.object(&name);
            let floor = plan.gallery_floor(k);
            for (x0, x1) in plan.between_pedestals() {
                let box_from =
                    |y0: f64, y1: f64| (DVec3::new(x0, y0, inner), DVec3::new(x1, y1, face));
                if !g.size.balusters {
                    let (lo, hi) = box_from(floor, floor + PARAPET_HEIGHT);
                    cuboid(g.sink, frame, stone, lo, hi, long)?;
                    continue;
                }
                let (lo, hi) = box_from(floor, floor + PLINTH);
                cuboid(g.sink, frame, stone, lo, hi, long)?;
                let top = floor + PARAPET_HEIGHT;
                let (lo, hi) = box_from(top - RAIL, top);
                let rail = Faces {
                    neg_y: true,
                    ..long
                };
                cuboid(g.sink, frame, stone, lo, hi, rail)?;
                let count = ((x1 - x0) / BALUSTER_PITCH).floor().max(1.0);
                let profile =
                    baluster_profile(PARAPET_HEIGHT - PLINTH - RAIL, stone, g.size.density);
                let around = steps_around(BALUSTER_RADIUS, g.size.density, 6);
                for j in 0..count as u32 {
                    let x = x0 + (f64::from(j) + 0.5) * (x1 - x0) / count;
                    let base = frame.point(x, floor + PLINTH, face - PARAPET_THICKNESS / 2.0);
                    lathe(g.sink, base, &profile, around)?;
                }
            }
        }
    }
    Ok(())
}

/// A vase-shaped baluster `height` tall: a square-ish foot, a swelling belly
/// low down, a slender neck and a collar under the rail.
pub(super) fn baluster_profile(height: f64, material: u32, density: f64) -> Profile {
    let foot = 0.055;
    let neck = 0.032;
    let mut profile = Profile::start(foot, 0.0);
    profile.to(foot, 0.05 * height, material);
    let (belly_start, belly_end) = (0.08 * height, 0.8 * height);
    profile.to(0.7 * foot, belly_start, material);
    // The belly: widest a third of the way up, narrowing to the neck.
    profile.curve(
        steps_along(belly_end - belly_start, density, 2),
        material,
        |t| {
            let (s, _) = sin_cos(std::f64::consts::PI * t.sqrt());
            let r0 = 0.7 * foot + (neck - 0.7 * foot) * t;
            (
                r0 + (BALUSTER_RADIUS - 0.5 * (0.7 * foot + neck)) * s,
                belly_start + (belly_end - belly_start) * t,
            )
        },
    );
    profile.to(0.05, 0.88 * height, material);
    profile.to(0.05, height, material);
    profile
}
