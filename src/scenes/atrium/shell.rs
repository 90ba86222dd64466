//! The building's flat shell: floor, end walls, outer walls, ceilings and
//! gallery floors, the court faces of the slabs, the roof, and the sky quad
//! above the opening. All of it faces into the building (or up, for the
//! roof, and down, for the sky).

use super::generator::Generator;
use super::plan::{Frame, Side, GALLERIES, PARAPET_THICKNESS, PIER_HALF};
use super::sink::Sink;
use crate::error::Result;
use glam::DVec3;

/// Height of the sky quad above the roof (m).
pub(super) const SKY_HEIGHT: f64 = 3.0;
/// How far the sky quad reaches beyond each end wall (m). The opening ends
/// at the end walls, so without it a point of the court would see, just over
/// the far end wall's top, the gap under the sky's edge instead of sky; with
/// it no point within `2 * roof` metres of an end wall does. Across the
/// court the roofs already reach well beyond the opening, so the sky stops
/// at the outer walls: sky beyond them would light only the void outside.
pub(super) const SKY_OVERHANG: f64 = 2.0 * SKY_HEIGHT;

/// Adds `floor`, `end_wall_west`, `end_wall_east`, then per side
/// `ambulatory_SIDE`, `gallery_SIDE_K`, `facade_SIDE` and `roof_SIDE`, and
/// finally `sky`.
pub(super) fn add_shell<S: Sink>(g: &mut Generator<S>) -> Result<()> {
    let (x, z, top) = (g.plan.length(), g.plan.width(), g.plan.roof());
    let p = DVec3::new;
    let paving = g.palette.paving;
    let plaster = g.palette.plaster;

    g.sink.object("floor");
    g.sink.polygon(
        paving,
        &[
            p(0.0, 0.0, 0.0),
            p(0.0, 0.0, z),
            p(x, 0.0, z),
            p(x, 0.0, 0.0),
        ],
    )?;
    g.sink.object("end_wall_west");
    g.sink.polygon(
        plaster,
        &[
            p(0.0, 0.0, 0.0),
            p(0.0, top, 0.0),
            p(0.0, top, z),
            p(0.0, 0.0, z),
        ],
    )?;
    g.sink.object("end_wall_east");
    g.sink.polygon(
        plaster,
        &[p(x, 0.0, 0.0), p(x, 0.0, z), p(x, top, z), p(x, top, 0.0)],
    )?;

    for side in Side::BOTH {
        add_side(g, side)?;
    }

    let y = top + SKY_HEIGHT;
    let (x0, x1) = (-SKY_OVERHANG, x + SKY_OVERHANG);
    let (z0, z1) = (0.0, z);
    g.sink.object("sky");
    // Counter-clockwise seen from below: facing down into the court.
    g.sink.polygon(
        g.palette.sky,
        &[p(x0, y, z0), p(x1, y, z0), p(x1, y, z1), p(x0, y, z1)],
    )
}

/// One side's outer walls, ceilings, gallery floors, slab faces and roof.
fn add_side<S: Sink>(g: &mut Generator<S>, side: Side) -> Result<()> {
    let frame = Frame::of(side, &g.plan);
    let plan = g.plan;
    let (x, face) = (plan.length(), plan.court_face());
    let (paving, stone) = (g.palette.paving, g.palette.stone);
    let name = side.name();

    g.sink.object(&format!("ambulatory_{name}"));
    outer_wall(g, frame, 0.0, plan.arcade_top())?;
    ceiling(g, frame, plan.arcade_top(), plan.arcade_axis() - PIER_HALF)?;

    for k in 0..GALLERIES {
        g.sink.object(&format!("gallery_{name}_{k}"));
        outer_wall(g, frame, plan.gallery_floor(k), plan.gallery_ceiling(k))?;
        // The floor stops at the balustrade's inner face.
        let (y, d) = (plan.gallery_floor(k), face - PARAPET_THICKNESS);
        let floor = [
            DVec3::new(0.0, y, 0.0),
            DVec3::new(0.0, y, d),
            DVec3::new(x, y, d),
            DVec3::new(x, y, 0.0),
        ];
        g.sink.polygon(paving, &frame.polygon(&floor))?;
        ceiling(g, frame, plan.gallery_ceiling(k), face)?;
    }

    // The slab edges facing the court: above the arcade and above each gallery.
    g.sink.object(&format!("facade_{name}"));
    let mut bands = vec![(plan.arcade_top(), plan.gallery_floor(0))];
    for k in 0..GALLERIES {
        let next = if k + 1 < GALLERIES {
            plan.gallery_floor(k + 1)
        } else {
            plan.roof()
        };
        bands.push((plan.gallery_ceiling(k), next));
    }
    for (y0, y1) in bands {
        let band = [
            DVec3::new(0.0, y0, face),
            DVec3::new(x, y0, face),
            DVec3::new(x, y1, face),
            DVec3::new(0.0, y1, face),
        ];
        g.sink.polygon(stone, &frame.polygon(&band))?;
    }

    g.sink.object(&format!("roof_{name}"));
    let y = plan.roof();
    let roof = [
        DVec3::new(0.0, y, 0.0),
        DVec3::new(0.0, y, face),
        DVec3::new(x, y, face),
        DVec3::new(x, y, 0.0),
    ];
    g.sink.polygon(stone, &frame.polygon(&roof))
}

/// The outer wall (d = 0, facing the court) from `y0` to `y1`, the length of
/// the building.
fn outer_wall<S: Sink>(g: &mut Generator<S>, frame: Frame, y0: f64, y1: f64) -> Result<()> {
    let x = g.plan.length();
    let wall = [
        DVec3::new(0.0, y0, 0.0),
        DVec3::new(x, y0, 0.0),
        DVec3::new(x, y1, 0.0),
        DVec3::new(0.0, y1, 0.0),
    ];
    g.sink.polygon(g.palette.plaster, &frame.polygon(&wall))
}

/// A ceiling at height `y` from the outer wall to `depth`, facing down.
fn ceiling<S: Sink>(g: &mut Generator<S>, frame: Frame, y: f64, depth: f64) -> Result<()> {
    let x = g.plan.length();
    let quad = [
        DVec3::new(0.0, y, 0.0),
        DVec3::new(x, y, 0.0),
        DVec3::new(x, y, depth),
        DVec3::new(0.0, y, depth),
    ];
    g.sink.polygon(g.palette.plaster, &frame.polygon(&quad))
}
