//! The ground arcade's arches: for each bay, a semicircular intrados
//! (the curved underside) and the two faces of the wall around it, court
//! side and ambulatory side.
//!
//! Each face is the square a bay wide and half a bay tall above the springing
//! line, less the half-disc of the opening. It is cut into quads by rays from
//! the arch's centre through the intrados' vertices, each ray ending on the
//! square's edge; the square's top corners lie on the rays at 45 and 135
//! degrees, so no quad turns a corner. A quad between two rays, a chord of
//! the circle and a piece of the square's edge is always convex.

use super::generator::Generator;
use super::plan::{Frame, Side, ARCH_RADIUS, BAY, PIER_HALF, SPRING};
use super::shapes::steps_along;
use super::sink::Sink;
use super::trig::sin_cos;
use crate::error::Result;
use glam::{DVec2, DVec3};

/// Adds `arch_K` for every bay, south side then north, west to east.
pub(super) fn add_arches<S: Sink>(g: &mut Generator<S>) -> Result<()> {
    let steps = arch_steps(g.size.density);
    let plan = g.plan;
    for side in Side::BOTH {
        let frame = Frame::of(side, &plan);
        for bay in 0..plan.bays {
            let name = g.names.next("arch");
            g.sink.object(&name);
            let centre = DVec2::new((f64::from(bay) + 0.5) * BAY, SPRING);
            arch(g, frame, centre, steps)?;
        }
    }
    Ok(())
}

/// Segments of the half-circle: a multiple of four (so that the rays at 45
/// and 135 degrees are among them), at least eight.
pub(super) fn arch_steps(density: f64) -> usize {
    4 * steps_along(std::f64::consts::PI * ARCH_RADIUS / 4.0, density, 2)
}

/// One arch centred at `centre` (x, springing height) in the side frame.
fn arch<S: Sink>(g: &mut Generator<S>, frame: Frame, centre: DVec2, steps: usize) -> Result<()> {
    let half = BAY / 2.0;
    let (back, court) = (
        g.plan.arcade_axis() - PIER_HALF,
        g.plan.arcade_axis() + PIER_HALF,
    );
    // From the west springing point (angle pi) over the crown to the east.
    // The springing points and the crown exactly on their axes.
    let ray = |k: usize| match k {
        0 => DVec2::new(-1.0, 0.0),
        k if k == steps => DVec2::new(1.0, 0.0),
        k if 2 * k == steps => DVec2::new(0.0, 1.0),
        k => {
            let (s, c) = sin_cos(std::f64::consts::PI * (1.0 - k as f64 / steps as f64));
            DVec2::new(c, s)
        }
    };
    let on_circle = |k: usize| centre + ARCH_RADIUS * ray(k);
    let on_square = |k: usize| {
        let r = ray(k);
        if 4 * k == steps || 4 * k == 3 * steps {
            // The square's top corners.
            DVec2::new(centre.x + half * r.x.signum(), centre.y + half)
        } else if r.x.abs() >= r.y {
            // A side edge: x exactly on the bay's boundary.
            let x = if r.x < 0.0 {
                centre.x - half
            } else {
                centre.x + half
            };
            DVec2::new(x, centre.y + half * r.y / r.x.abs())
        } else {
            DVec2::new(centre.x + half * r.x / r.y, centre.y + half)
        }
    };
    let at = |p: DVec2, d: f64| DVec3::new(p.x, p.y, d);
    let stone = g.palette.stone;
    for k in 0..steps {
        let (p0, p1) = (on_circle(k), on_circle(k + 1));
        let (q0, q1) = (on_square(k), on_square(k + 1));
        // Court face: west to east along the circle, up, back along the square.
        let face = [at(p0, court), at(p1, court), at(q1, court), at(q0, court)];
        g.sink.polygon(stone, &frame.polygon(&face))?;
        let face = [at(p0, back), at(q0, back), at(q1, back), at(p1, back)];
        g.sink.polygon(stone, &frame.polygon(&face))?;
        // The intrados, facing the arch's axis.
        let soffit = [at(p0, back), at(p1, back), at(p1, court), at(p0, court)];
        g.sink.polygon(stone, &frame.polygon(&soffit))?;
    }
    Ok(())
}
