//! What stands where: a fountain in the middle of the court, in every other
//! bay a round table with stools, a long table with benches or a planter
//! down the court's middle, a bench or a planter in front of each arcade,
//! and a bench against the outer wall of each ambulatory bay. Choices and
//! small shifts come from a fixed hash of the bay, so they never change.

use super::furniture::{bench, fountain, long_table, planter, round_table, FOUNTAIN_RADIUS};
use super::generator::Generator;
use super::plan::{Frame, Side, BAY};
use super::sink::Sink;
use super::{hash_bits, hash_unit};
use crate::error::Result;
use glam::DVec3;

/// Distance of the benches and planters in front of the arcades from the
/// arcade's court face (m).
pub(super) const ARCADE_CLEARANCE: f64 = 1.4;
/// Distance of the ambulatory benches' axis from the outer wall (m).
pub(super) const WALL_BENCH_DEPTH: f64 = 0.5;

/// Adds `fountain`, then per bay the court's middle piece (`table_K` or
/// `planter_K`; long tables come with `bench_K`s), the pieces in front of
/// each arcade, and the ambulatory benches.
pub(super) fn add_furniture<S: Sink>(g: &mut Generator<S>) -> Result<()> {
    let plan = g.plan;
    let (length, middle) = (plan.length(), plan.width() / 2.0);
    g.sink.object("fountain");
    fountain(g, DVec3::new(length / 2.0, 0.0, middle))?;
    for bay in 0..plan.bays {
        let h = hash_bits(&[1, u64::from(bay)]);
        let cx = (f64::from(bay) + 0.5) * BAY;
        // Clear of the fountain by a table's reach and a walkway.
        if (cx - length / 2.0).abs() > FOUNTAIN_RADIUS + 2.0 {
            let at = DVec3::new(cx + 0.6 * (hash_unit(h, 0) - 0.5), 0.0, middle);
            let wood = if h & (1 << 20) == 0 {
                g.palette.wood
            } else {
                g.palette.dark_wood
            };
            match (h >> 32) % 3 {
                0 => {
                    let name = g.names.next("table");
                    g.sink.object(&name);
                    round_table(g, at, wood)?;
                }
                1 => {
                    let name = g.names.next("table");
                    g.sink.object(&name);
                    long_table(g, at, DVec3::Z, wood)?;
                    for side in [-1.0, 1.0] {
                        let name = g.names.next("bench");
                        g.sink.object(&name);
                        bench(g, at + DVec3::X * (side * 0.75), DVec3::Z, 1.6, wood)?;
                    }
                }
                _ => {
                    let name = g.names.next("planter");
                    g.sink.object(&name);
                    planter(g, at)?;
                }
            }
        }
        for side in Side::BOTH {
            let frame = Frame::of(side, &plan);
            let h = hash_bits(&[2, u64::from(bay), side as u64]);
            let d = plan.court_face() + ARCADE_CLEARANCE;
            let at = frame.point(cx + 0.4 * (hash_unit(h, 0) - 0.5), 0.0, d);
            if h.is_multiple_of(2) {
                let name = g.names.next("bench");
                g.sink.object(&name);
                bench(g, at, DVec3::X, 2.0, g.palette.wood)?;
            } else {
                let name = g.names.next("planter");
                g.sink.object(&name);
                planter(g, at)?;
            }
        }
    }
    for side in Side::BOTH {
        let frame = Frame::of(side, &plan);
        for bay in 0..plan.bays {
            let name = g.names.next("bench");
            g.sink.object(&name);
            let at = frame.point((f64::from(bay) + 0.5) * BAY, 0.0, WALL_BENCH_DEPTH);
            bench(g, at, DVec3::X, 1.8, g.palette.dark_wood)?;
        }
    }
    Ok(())
}
