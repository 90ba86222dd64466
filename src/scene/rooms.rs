//! Finding the main lit room of an interior by casting rays, whatever way
//! its walls face.
//!
//! The winding number ([`super::framing`]) tells inside from outside only
//! where walls are single-sided and face inwards; double-sided walls (two
//! faces back to back) cancel it out. Rays do not care: a point is
//! **enclosed** when nearly every ray from it meets a surface, and **inside
//! a solid** when many meet the back of a single-sided surface first (the
//! inside of a closed object, or the far side of a wall). Points of a grid
//! over the scene's bounds that are enclosed and not inside a solid are
//! gathered into rooms ([`find_rooms`]); a room is
//! **lit** when one of its points sees an emitting surface or a punctual
//! light, or, under a sky, when one of its rays leaves the scene upwards
//! (through a window, a skylight, an open court). The main lit room is the
//! largest lit one, if it is large enough for a person to stand in and
//! holds a few grid points; the largest enclosed one stands in only when
//! nothing in the scene gives light (see [`super::framing`]).

use super::rays::{Accel, SurfaceGeometry, Tolerances};
use super::{Scene, Surface};
use glam::DVec3;

/// Share of rays from a point that must meet a surface for it to be
/// enclosed: a door or window may let some out.
const ENCLOSED: f64 = 0.9;

/// Share of rays that may meet the back of a single-sided surface first
/// before the point counts as inside a solid.
const SOLID: f64 = 0.25;

/// Grid points along the longest side of the bounds.
const GRID: f64 = 14.0;

/// Rays cast from each grid point.
const RAYS: usize = 64;

/// The smallest room a view is taken inside, in metres (glTF's unit): a
/// lamp shade or a cupboard is an object, not a room.
pub(crate) const ROOM_SIZE: f64 = 1.2;

/// The fewest grid points a room a view is taken inside holds: a nook of
/// one or two points between an object's parts (a figure's arm and its
/// body, which may be metres across in a model of odd units) is not a room.
pub(crate) const MIN_ROOM_POINTS: usize = 4;

/// Punctual lights and emitting surfaces looked for from each point, at most
/// (the caller lists the brightest first).
pub(crate) const SOURCES: usize = 64;

/// A room found in the scene.
#[derive(Clone, Debug)]
pub(crate) struct Room {
    /// The free point the room grew from: the one with the most space
    /// around it.
    pub centre: DVec3,
    /// The room's grid points (free points enclosed by the scene).
    pub points: Vec<DVec3>,
    /// For each point, the mean distance its rays travel: how open it is.
    pub openness: Vec<f64>,
    /// Whether some point of it sees a light.
    pub lit: bool,
}

impl Room {
    /// The bounds of the room's points.
    pub(crate) fn bounds(&self) -> (DVec3, DVec3) {
        self.points
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            })
    }
}

/// The scene's surfaces in a ray caster, with their sidedness.
pub(crate) struct Tracer {
    geometry: Vec<SurfaceGeometry>,
    accel: Accel,
    double_sided: Vec<bool>,
}

/// One ray's first hit.
pub(crate) struct Meeting {
    /// Distance along the ray.
    pub t: f64,
    /// True when the ray meets the back of a single-sided surface.
    pub back: bool,
    /// The front normal of the surface met.
    pub normal: DVec3,
}

impl Tracer {
    /// A tracer over `surfaces` of `scene` (those the reference can trace:
    /// planar convex polygons; others are left out).
    pub(crate) fn new(scene: &Scene, surfaces: &[&Surface], lo: DVec3, hi: DVec3) -> Tracer {
        let mut geometry = Vec::with_capacity(surfaces.len());
        let mut double_sided = Vec::with_capacity(surfaces.len());
        for (i, s) in surfaces.iter().enumerate() {
            if let Ok(g) = SurfaceGeometry::new(i, s) {
                geometry.push(g);
                double_sided.push(scene.material_of(s).double_sided);
            }
        }
        let diameter = (hi - lo).length().max(1e-9);
        let largest = lo.abs().max(hi.abs()).max_element();
        let accel = Accel::new(&geometry, lo, hi, Tolerances::new(diameter, largest));
        Tracer {
            geometry,
            accel,
            double_sided,
        }
    }

    /// The first surface met from `origin` along unit `dir`.
    pub(crate) fn first(&self, origin: DVec3, dir: DVec3) -> Option<Meeting> {
        let hit = self.accel.nearest(&self.geometry, origin, dir, u32::MAX)?;
        let k = hit.surface as usize;
        Some(Meeting {
            t: hit.t,
            back: !hit.front && !self.double_sided[k],
            normal: self.geometry[k].normal,
        })
    }

    /// True when nothing lies between `a` and `b`.
    pub(crate) fn sees(&self, a: DVec3, b: DVec3) -> bool {
        self.accel.unblocked(&self.geometry, a, b, u32::MAX)
    }
}

/// `n` directions spread evenly over the sphere (a Fibonacci lattice), the
/// same on every run.
pub(crate) fn sphere_directions(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - (i as f64 + 0.5) / n as f64 * 2.0;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
}

/// Most rooms looked for.
const MAX_ROOMS: usize = 8;

/// The rooms of the scene whose surfaces `tracer` holds, within `lo..hi`,
/// largest first; `lights` are the points a room is lit from (punctual
/// lights, and points just in front of emitting surfaces); with `sky`, a
/// room whose points see the sky (a ray that meets nothing and rises) is
/// lit too.
///
/// Each room grows from the free point with the most space around it (the
/// longest mean distance to the surfaces its rays meet) not yet in a room,
/// and holds every such point that sees it: two rooms joined by a door
/// stay two rooms (the door lets each see only a narrow cone of the other).
pub(crate) fn find_rooms(
    tracer: &Tracer,
    lo: DVec3,
    hi: DVec3,
    lights: &[DVec3],
    sky: bool,
) -> Vec<Room> {
    let size = hi - lo;
    let step = size.max_element() / GRID;
    if !(step > 0.0 && step.is_finite()) {
        return Vec::new();
    }
    let counts = (size / step).ceil().max(DVec3::ONE);
    let (nx, ny, nz) = (counts.x as usize, counts.y as usize, counts.z as usize);
    let directions = sphere_directions(RAYS);
    // Free points, the mean distance their rays travel, and whether one of
    // them rises into the sky.
    let mut free: Vec<(DVec3, f64, bool)> = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let cell = DVec3::new(i as f64, j as f64, k as f64) + 0.5;
                let p = lo + cell * size / counts;
                let (mut met, mut backs, mut travelled) = (0usize, 0usize, 0.0);
                let mut sees_sky = false;
                for d in &directions {
                    if let Some(m) = tracer.first(p, *d) {
                        met += 1;
                        backs += usize::from(m.back);
                        travelled += m.t;
                    } else {
                        sees_sky |= sky && d.y > 0.0;
                    }
                }
                let enclosed = met as f64 >= ENCLOSED * RAYS as f64;
                if enclosed && (backs as f64) < SOLID * RAYS as f64 {
                    free.push((p, travelled / met as f64, sees_sky));
                }
            }
        }
    }
    let mut taken = vec![false; free.len()];
    let mut rooms = Vec::new();
    while rooms.len() < MAX_ROOMS {
        let seed = (0..free.len())
            .filter(|&i| !taken[i])
            .max_by(|&a, &b| free[a].1.total_cmp(&free[b].1).then(b.cmp(&a)));
        let Some(seed) = seed else { break };
        let centre = free[seed].0;
        let (mut points, mut openness) = (Vec::new(), Vec::new());
        let mut sees_sky = false;
        for (i, (p, open, sky)) in free.iter().enumerate() {
            if !taken[i] && (i == seed || tracer.sees(centre, *p)) {
                taken[i] = true;
                points.push(*p);
                openness.push(*open);
                sees_sky |= sky;
            }
        }
        let lit = sees_sky
            || points
                .iter()
                .any(|p| lights.iter().take(SOURCES).any(|l| tracer.sees(*p, *l)));
        rooms.push(Room {
            centre,
            points,
            openness,
            lit,
        });
    }
    rooms.sort_by_key(|r| std::cmp::Reverse(r.points.len()));
    rooms
}
