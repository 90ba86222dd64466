//! The view across a room: where to stand and which way to look so that
//! the frame shows the room lit.
//!
//! From each of the room's most open points, the eye looks level in one of
//! [`DIRECTIONS`] directions, backed up from that point to a tenth of the
//! way short of the wall behind it, with a field of view that takes in the
//! far wall's height and the room's width. Each such view is scored by the
//! share of a coarse grid of its rays whose first surface is lit directly
//! (sees one of the room's light points from the eye's side, or, under a
//! sky, sees the sky through one of a few rising rays), with a small
//! bonus for a longer view; the best one wins, the first of equals in a
//! fixed order (glTF's front view, -z, first). Seeing through a door into a
//! dark room, or standing in the doorway, scores low by itself.

use super::rooms::{sphere_directions, Room, Tracer};
use super::Camera;
use glam::DVec3;

/// Level directions tried from each point.
const DIRECTIONS: usize = 16;

/// Points of the room a view is tried from: its most open ones.
const STANDPOINTS: usize = 8;

/// Rays across and down each tried view (a 4:3 frame).
const SCORE_RAYS: (usize, usize) = (12, 9);

/// Weight of the view's length (over the longest tried) in its score,
/// against the lit share: only breaks near ties.
const LENGTH_BONUS: f64 = 0.05;

/// Directions (of an even spread over the sphere, the rising half kept) a
/// surface looks for the sky along.
const SKY_RAYS: usize = 16;

/// The best view across `room` lit from `lights`, and from the sky when
/// `sky` (see the module notes).
pub(crate) fn across_room(tracer: &Tracer, room: &Room, lights: &[DVec3], sky: bool) -> Camera {
    let mut order: Vec<usize> = (0..room.points.len()).collect();
    order.sort_by(|&a, &b| {
        room.openness[b]
            .total_cmp(&room.openness[a])
            .then(a.cmp(&b))
    });
    let directions: Vec<DVec3> = (0..DIRECTIONS)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / DIRECTIONS as f64;
            DVec3::new(a.sin(), 0.0, -a.cos())
        })
        .collect();
    let mut views: Vec<(Camera, f64)> = Vec::new();
    for &i in order.iter().take(STANDPOINTS) {
        let c = room.points[i];
        for d in &directions {
            views.push(view_from(tracer, c, *d));
        }
    }
    let longest = views.iter().map(|v| v.1).fold(0.0, f64::max).max(1e-9);
    let rising: Vec<DVec3> = if sky {
        sphere_directions(SKY_RAYS)
            .into_iter()
            .filter(|d| d.y > 0.0)
            .collect()
    } else {
        Vec::new()
    };
    let mut best: Option<(f64, Camera)> = None;
    for (camera, length) in views {
        let score = lit_share(tracer, &camera, lights, &rising) + LENGTH_BONUS * length / longest;
        if best.as_ref().is_none_or(|b| score > b.0 + 1e-12) {
            best = Some((score, camera));
        }
    }
    best.map_or_else(
        || Camera::look_at(room.centre, room.centre + DVec3::NEG_Z, DVec3::Y, 60.0),
        |b| b.1,
    )
}

/// The level view along `forward` from the wall behind `c`, and how far it
/// looks.
fn view_from(tracer: &Tracer, c: DVec3, forward: DVec3) -> (Camera, f64) {
    let reach = |d: DVec3| tracer.first(c, d).map_or(0.0, |m| m.t);
    let behind = reach(-forward);
    let eye = c - forward * (0.9 * behind);
    let across = 0.9 * behind + reach(forward);
    let side = forward.cross(DVec3::Y).normalize();
    let width = reach(side) + reach(-side);
    let height = reach(DVec3::Y) + reach(DVec3::NEG_Y);
    let half = (0.5 * height).max(0.5 * width * 0.75).max(1e-9);
    let yfov = (2.0 * (half / across.max(1e-9)).atan() * 1.05)
        .to_degrees()
        .clamp(40.0, 90.0);
    let camera = Camera::look_at(eye, eye + forward, DVec3::Y, yfov);
    (camera, across)
}

/// The share of a coarse grid of the camera's rays (4:3) whose first
/// surface sees one of `lights`, or the sky along one of `rising`, from the
/// eye's side.
fn lit_share(tracer: &Tracer, camera: &Camera, lights: &[DVec3], rising: &[DVec3]) -> f64 {
    let (w, h) = SCORE_RAYS;
    let tan = (camera.yfov * 0.5).tan();
    let right = camera.right();
    let mut lit = 0usize;
    for j in 0..h {
        for i in 0..w {
            let sx = ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * tan * 4.0 / 3.0;
            let sy = (1.0 - (j as f64 + 0.5) / h as f64 * 2.0) * tan;
            let dir = (camera.forward + right * sx + camera.up * sy).normalize();
            let Some(hit) = tracer.first(camera.position, dir) else {
                continue;
            };
            // Just short of the surface, on the eye's side.
            let p = camera.position + dir * (hit.t * (1.0 - 1e-6));
            let eye_side = hit.normal.dot(camera.position - p).signum();
            let seen = lights
                .iter()
                .any(|l| hit.normal.dot(*l - p).signum() == eye_side && tracer.sees(p, *l))
                || rising.iter().any(|d| {
                    hit.normal.dot(*d).signum() == eye_side && tracer.first(p, *d).is_none()
                });
            lit += usize::from(seen);
        }
    }
    lit as f64 / (w * h) as f64
}
