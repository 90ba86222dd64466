//! A default view of a scene that has no camera, framed as a person would:
//! from inside the main lit room of an interior, looking across it; from
//! outside an object, looking at it from three-quarters.
//!
//! - **What to frame.** The surfaces that do not emit, and the emitters
//!   near them (within ten times their size): a sky quad or a sun proxy far
//!   away lights the scene but does not shrink it in the frame, while a
//!   lamp whose body glows is framed whole.
//! - **Open boxes.** A scene whose inward-facing walls enclose it (see
//!   *small enclosures* below) but leave one side open, as a Cornell box,
//!   is seen through that opening, from outside.
//! - **Rooms.** Rays from a grid of points find the enclosed spaces whatever
//!   way their walls face (double-sided walls included), and which of them
//!   see a light or the sky ([`super::rooms`]). The largest lit room at
//!   least [`ROOM_SIZE`](super::rooms::ROOM_SIZE) across and of at least
//!   [`MIN_ROOM_POINTS`](super::rooms::MIN_ROOM_POINTS) grid points (else,
//!   in a scene with no light at all, the largest such room) is viewed from
//!   inside, across it: of the level views from its most open points, each
//!   backed up to just short of the wall behind, the one whose frame shows
//!   the most directly lit surfaces ([`super::room_view`]).
//! - **Small enclosures.** Otherwise, the signed solid angle that the framed
//!   surfaces' fronts subtend at a point, over 4 pi, is the winding number
//!   of the surface around it: 1 inside a closed box whose walls face
//!   inwards, about 0.8 inside a box open on one side, 0 outside
//!   everything, -1 inside a closed object. It is taken at the centre of the
//!   bounds and at six points around it; above one half at any of them, the
//!   scene is an enclosure (a Cornell box), seen from its open side (standing
//!   back until the opening fills a 45 degree view) or from just inside the
//!   side with the least wall.
//! - **Outside.** From three-quarters in front (glTF's +z), a little above,
//!   far enough back that the bounding box of the framed surfaces (the
//!   emitting parts among them) fits a 45 degree view.

use super::room_view::across_room;
use super::rooms::{find_rooms, Room, Tracer, MIN_ROOM_POINTS, ROOM_SIZE, SOURCES};
use super::{Camera, Scene, Surface};
use glam::DVec3;

/// Winding number above which a point counts as inside an enclosure.
const INSIDE: f64 = 0.5;

impl Camera {
    /// A default view of `scene`, framed as a person would (see the module
    /// notes): inside the main lit room of an interior, looking across it;
    /// else inside a small enclosure such as a Cornell box, from its open
    /// side; else the framed surfaces from three-quarters in front
    /// ([`Camera::framing_box`] of their bounds). Far-away emitters
    /// (beyond ten times the non-emitting surfaces' size from them: a sky
    /// quad, a sun) are left out of the framing but still light rooms.
    #[must_use]
    pub fn framing(scene: &Scene) -> Self {
        let framed = framed_surfaces(scene);
        let (lo, hi) = bounds(&framed);
        if lo.x > hi.x {
            return Camera::framing_box(DVec3::ZERO, DVec3::ONE);
        }
        let enclosure = is_enclosure(&framed, lo, hi);
        // A box open on one side (a Cornell box) is seen through its opening.
        if let Some(mut camera) = enclosure
            .then(|| from_inside(&framed, lo, hi, true))
            .flatten()
        {
            camera.name = "framing".to_string();
            return camera;
        }
        let tracer = Tracer::new(scene, &framed, lo, hi);
        let lights = light_points(scene);
        let sky = scene.sky.is_some();
        let rooms = find_rooms(&tracer, lo, hi, &lights, sky);
        let step = (hi - lo).max_element() / 14.0;
        let roomy = |r: &&Room| {
            let (a, b) = r.bounds();
            let span = b - a + step;
            r.points.len() >= MIN_ROOM_POINTS
                && span.x.min(span.z) >= ROOM_SIZE
                && span.y >= ROOM_SIZE
        };
        // An unlit room is shown only when nothing in the scene gives light:
        // where there is light that no room sees, the "rooms" are hollows
        // inside an object (a voxel figure's cavities) or spaces the light
        // never reaches, and the object is better seen from outside.
        let unlit_allowed = lights.is_empty() && !sky;
        let room = rooms
            .iter()
            .filter(roomy)
            .find(|r| r.lit)
            .or_else(|| rooms.iter().filter(|_| unlit_allowed).find(roomy));
        let mut camera = match room {
            Some(room) => across_room(&tracer, room, &lights, sky),
            None => enclosure
                .then(|| from_inside(&framed, lo, hi, false))
                .flatten()
                .unwrap_or_else(|| Camera::framing_box(lo, hi)),
        };
        camera.name = "framing".to_string();
        camera
    }

    /// A default view that frames the bounds `lo..hi` from outside: from
    /// three-quarters in front (glTF's +Z side, to the right), a little
    /// above, looking at their centre with a 45 degree field of view, just
    /// far enough back that every corner of the box falls within the middle
    /// 90% of a square frame (a wider frame only adds margin at the sides).
    #[must_use]
    pub fn framing_box(lo: DVec3, hi: DVec3) -> Self {
        let centre = (lo + hi) * 0.5;
        let dir = DVec3::new(0.6, 0.35, 0.8).normalize();
        let probe = Camera::look_at(centre + dir, centre, DVec3::Y, 45.0);
        let (right, up) = (probe.right(), probe.up);
        let tan = 22.5f64.to_radians().tan() * 0.9;
        let mut dist: f64 = 1e-9;
        for k in 0..8 {
            let corner = DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let r = corner - centre;
            let off_axis = r.dot(right).abs().max(r.dot(up).abs());
            dist = dist.max(r.dot(dir) + off_axis / tan);
        }
        let mut c = Camera::look_at(centre + dir * dist, centre, DVec3::Y, 45.0);
        c.name = "framing".to_string();
        c
    }
}

/// Where a room is lit from: the punctual lights, then points just in front
/// of the emitting surfaces, brightest first (at most [`SOURCES`] of them).
fn light_points(scene: &Scene) -> Vec<DVec3> {
    let mut points: Vec<DVec3> = scene.lights.iter().map(|l| l.position).collect();
    let mut emitters: Vec<(f64, DVec3)> = scene
        .surfaces
        .iter()
        .filter(|s| scene.material_of(s).is_emitter())
        .map(|s| {
            let power = scene.material_of(s).emission.max_band() * s.area;
            let size = s.area.sqrt();
            (power, s.centroid() + s.normal * (1e-3 * size))
        })
        .collect();
    emitters.sort_by(|a, b| b.0.total_cmp(&a.0));
    points.extend(emitters.into_iter().map(|(_, p)| p));
    points.truncate(SOURCES);
    points
}

/// How far from the non-emitting surfaces' bounds, in their diameters, an
/// emitter counts as far away (a sky quad, a sun proxy) and is left out of
/// the framing.
const FAR_EMITTER: f64 = 10.0;

/// The non-emitting surfaces, and the emitters that are not far from them
/// (within [`FAR_EMITTER`] times their bounds' diameter of those bounds: a
/// lamp whose body glows is framed whole, a sky 1 km over a room is not);
/// every surface when no surface is plain.
fn framed_surfaces(scene: &Scene) -> Vec<&Surface> {
    let (plain, emitters): (Vec<&Surface>, Vec<&Surface>) = scene
        .surfaces
        .iter()
        .partition(|s| !scene.material_of(s).is_emitter());
    if plain.is_empty() {
        return emitters;
    }
    let (lo, hi) = bounds(&plain);
    let margin = DVec3::splat(FAR_EMITTER * (hi - lo).length());
    let (lo, hi) = (lo - margin, hi + margin);
    let near = |s: &&Surface| {
        s.vertices
            .iter()
            .all(|p| p.cmpge(lo).all() && p.cmple(hi).all())
    };
    plain
        .into_iter()
        .chain(emitters.into_iter().filter(near))
        .collect()
}

fn bounds(surfaces: &[&Surface]) -> (DVec3, DVec3) {
    surfaces
        .iter()
        .flat_map(|s| s.vertices.iter())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        })
}

/// The winding number of the surfaces' fronts around `point`: the solid
/// angle of the fronts seen from it, less that of the backs, over 4 pi.
pub(crate) fn winding_number(surfaces: &[&Surface], point: DVec3) -> f64 {
    let mut omega = 0.0;
    for s in surfaces {
        let v = &s.vertices;
        for k in 1..v.len() - 1 {
            omega += triangle_solid_angle(v[0] - point, v[k] - point, v[k + 1] - point);
        }
    }
    omega / (4.0 * std::f64::consts::PI)
}

/// The signed solid angle of triangle `a b c` (relative to the eye):
/// positive when its front (counter-clockwise side) faces the eye (van
/// Oosterom and Strackee's formula).
fn triangle_solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let numerator = a.dot(b.cross(c));
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    // Counter-clockwise seen from the eye means a . (b x c) < 0.
    -2.0 * numerator.atan2(denominator)
}

fn is_enclosure(surfaces: &[&Surface], lo: DVec3, hi: DVec3) -> bool {
    let centre = (lo + hi) * 0.5;
    let quarter = (hi - lo) * 0.25;
    let mut points = vec![centre];
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        points.push(centre + axis * quarter);
        points.push(centre - axis * quarter);
    }
    points
        .into_iter()
        .any(|p| winding_number(surfaces, p) > INSIDE)
}

/// The view of an enclosure from the side with the least inward-facing
/// area near it: from outside, when that side is open (`None` when
/// `open_only` and it is not), else from just inside it, across the
/// enclosure.
fn from_inside(surfaces: &[&Surface], lo: DVec3, hi: DVec3, open_only: bool) -> Option<Camera> {
    let size = hi - lo;
    let centre = (lo + hi) * 0.5;
    // Sides in order of preference when their walls are alike: +z first.
    let sides = [DVec3::Z, DVec3::X, DVec3::NEG_X, DVec3::NEG_Z];
    let wall_area = |side: DVec3| {
        let extent = size.dot(side.abs());
        let plane = centre + side * (0.5 * extent);
        surfaces
            .iter()
            .filter(|s| {
                s.normal.dot(-side) > 0.5
                    && s.vertices
                        .iter()
                        .all(|p| (p - plane).dot(side).abs() <= 0.05 * extent)
            })
            .map(|s| s.area)
            .sum::<f64>()
    };
    let areas: Vec<f64> = sides.iter().map(|s| wall_area(*s)).collect();
    let best = (0..sides.len())
        .min_by(|&a, &b| areas[a].total_cmp(&areas[b]).then(a.cmp(&b)))
        .unwrap_or(0);
    let side = sides[best];
    let depth = size.dot(side.abs());
    let width = size.dot(side.cross(DVec3::Y).abs());
    // Half the height the view must take in: the enclosure's height, or its
    // width in a 4:3 frame.
    let half = (0.5 * size.y).max(0.5 * width * 0.75).max(1e-9);
    let opening = centre + side * (0.5 * depth);
    if areas[best] < 0.05 * size.y * width {
        // An open side (the front of a Cornell box): stand back from it so
        // that the opening fills a 45 degree view, as the box's own camera.
        let back = half / 22.5f64.to_radians().tan();
        let eye = opening + side * back;
        return Some(Camera::look_at(eye, eye - side, DVec3::Y, 45.0));
    }
    if open_only {
        return None;
    }
    // A closed room: just inside the wall, with a field of view that takes
    // in the far wall (within 40 to 90 degrees).
    let eye = centre + side * (0.45 * depth);
    let across = (0.9 * depth).max(1e-9);
    let yfov = (2.0 * (half / across).atan() * 1.05)
        .to_degrees()
        .clamp(40.0, 90.0);
    Some(Camera::look_at(eye, eye - side, DVec3::Y, yfov))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::SceneBuilder;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    /// A room 4 x 3 x 6 with inward faces, open at +z when `open`, with a
    /// lamp under the ceiling and a box in the middle; and a sky quad 1 km
    /// up when `sky`.
    fn room(open: bool, sky: bool) -> Scene {
        let mut b = SceneBuilder::new("room");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let lamp = b.material("lamp", Rgb::ZERO, Rgb::ONE).unwrap();
        let (x, y, z) = (4.0, 3.0, 6.0);
        b.object("room");
        b.quad(grey, v(0., 0., 0.), v(0., 0., z), v(x, 0., z), v(x, 0., 0.))
            .unwrap(); // floor, up
        b.quad(grey, v(0., y, 0.), v(x, y, 0.), v(x, y, z), v(0., y, z))
            .unwrap(); // ceiling, down
        b.quad(grey, v(0., 0., 0.), v(x, 0., 0.), v(x, y, 0.), v(0., y, 0.))
            .unwrap(); // z = 0, +z
        b.quad(grey, v(0., 0., 0.), v(0., y, 0.), v(0., y, z), v(0., 0., z))
            .unwrap(); // x = 0, +x
        b.quad(grey, v(x, 0., 0.), v(x, 0., z), v(x, y, z), v(x, y, 0.))
            .unwrap(); // x = 4, -x
        if !open {
            b.quad(grey, v(0., 0., z), v(0., y, z), v(x, y, z), v(x, 0., z))
                .unwrap(); // z = 6, -z
        }
        b.object("lamp");
        b.quad(
            lamp,
            v(1.5, 2.9, 2.5),
            v(2.5, 2.9, 2.5),
            v(2.5, 2.9, 3.5),
            v(1.5, 2.9, 3.5),
        )
        .unwrap();
        b.axis_box("table", grey, v(1.5, 0.0, 2.5), v(2.5, 1.6, 3.5))
            .unwrap();
        if sky {
            b.object("sky");
            let (s, h) = (1000.0, 1000.0);
            b.quad(lamp, v(-s, h, -s), v(s, h, -s), v(s, h, s), v(-s, h, s))
                .unwrap();
        }
        b.build().unwrap()
    }

    #[test]
    fn the_winding_number_is_one_inside_a_room_and_zero_outside() {
        let scene = room(false, false);
        // The closed room and the closed table; the lamp is an open sheet.
        let all: Vec<&Surface> = scene
            .surfaces
            .iter()
            .filter(|s| !scene.material_of(s).is_emitter())
            .collect();
        let inside = winding_number(&all, v(1.0, 1.0, 1.0));
        assert!((inside - 1.0).abs() < 1e-9, "{inside}");
        let outside = winding_number(&all, v(10.0, 1.0, 1.0));
        assert!(outside.abs() < 1e-9, "{outside}");
        // Inside the table (outward faces) inside the room: 1 - 1.
        let in_table = winding_number(&all, v(2.0, 0.8, 3.0));
        assert!(in_table.abs() < 1e-9, "{in_table}");
    }

    #[test]
    fn a_room_is_seen_through_its_open_side_or_from_inside_and_a_far_sky_is_left_out() {
        let camera = Camera::framing(&room(true, true));
        // In front of the open side at z = 6, looking in towards -z, far
        // enough back that the 4 x 3 opening fills 45 degrees: half the
        // width in a 4:3 frame (1.5 m) over tan(22.5 degrees).
        let p = camera.position;
        let back = 1.5 / 22.5f64.to_radians().tan();
        assert!((p - v(2.0, 1.5, 6.0 + back)).length() < 1e-9, "{p}");
        assert!(
            camera.forward.dot(DVec3::NEG_Z) > 0.999_999,
            "{:?}",
            camera.forward
        );
        // Closed: a room 4 m x 6 m, seen from inside, level, from outside
        // the table (1.5..2.5 x 0..1.6 x 2.5..3.5).
        let closed = Camera::framing(&room(false, false));
        let p = closed.position;
        let inside = p.cmpgt(v(0.0, 0.0, 0.0)).all() && p.cmplt(v(4.0, 3.0, 6.0)).all();
        assert!(inside, "{p}");
        let in_table = p.cmpgt(v(1.5, 0.0, 2.5)).all() && p.cmplt(v(2.5, 1.6, 3.5)).all();
        assert!(!in_table, "{p}");
        assert!(closed.forward.y.abs() < 1e-12, "{:?}", closed.forward);
    }

    #[test]
    fn an_object_is_seen_from_outside_framed_without_a_far_sky() {
        let mut b = SceneBuilder::new("object");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let lamp = b.material("lamp", Rgb::ZERO, Rgb::ONE).unwrap();
        b.axis_box("box", grey, v(-1.0, 0.0, -1.0), v(1.0, 2.0, 1.0))
            .unwrap();
        b.object("sun");
        b.quad(
            lamp,
            v(-5.0, 500.0, -5.0),
            v(5.0, 500.0, -5.0),
            v(5.0, 500.0, 5.0),
            v(-5.0, 500.0, 5.0),
        )
        .unwrap();
        let scene = b.build().unwrap();
        let camera = Camera::framing(&scene);
        let expected = Camera::framing_box(v(-1.0, 0.0, -1.0), v(1.0, 2.0, 1.0));
        assert_eq!(camera.position, expected.position);
        assert_eq!(camera.forward, expected.forward);
        // Outside the box, looking at its centre from the front.
        assert!(camera.position.z > 1.0);
        let to_centre = (v(0.0, 1.0, 0.0) - camera.position).normalize();
        assert!(camera.forward.dot(to_centre) > 0.999_999);
    }

    /// The walls, floor and ceiling of a room `lo..hi`, facing inwards, as
    /// its own object; the ceiling leaves out the rectangle `hole` (x and z
    /// ranges) when given.
    fn inward_box(b: &mut SceneBuilder, m: u32, lo: DVec3, hi: DVec3, hole: Option<[f64; 4]>) {
        let (a, c) = (lo, hi);
        b.object("room");
        b.quad(
            m,
            v(a.x, a.y, a.z),
            v(a.x, a.y, c.z),
            v(c.x, a.y, c.z),
            v(c.x, a.y, a.z),
        )
        .unwrap(); // floor, up
        b.quad(
            m,
            v(a.x, a.y, a.z),
            v(c.x, a.y, a.z),
            v(c.x, c.y, a.z),
            v(a.x, c.y, a.z),
        )
        .unwrap(); // facing +z
        b.quad(
            m,
            v(a.x, a.y, a.z),
            v(a.x, c.y, a.z),
            v(a.x, c.y, c.z),
            v(a.x, a.y, c.z),
        )
        .unwrap(); // facing +x
        b.quad(
            m,
            v(c.x, a.y, a.z),
            v(c.x, a.y, c.z),
            v(c.x, c.y, c.z),
            v(c.x, c.y, a.z),
        )
        .unwrap(); // facing -x
        b.quad(
            m,
            v(a.x, a.y, c.z),
            v(a.x, c.y, c.z),
            v(c.x, c.y, c.z),
            v(c.x, a.y, c.z),
        )
        .unwrap(); // facing -z
        let mut ceiling = |x0: f64, x1: f64, z0: f64, z1: f64| {
            if x1 > x0 && z1 > z0 {
                let y = c.y;
                b.quad(m, v(x0, y, z0), v(x1, y, z0), v(x1, y, z1), v(x0, y, z1))
                    .unwrap(); // facing down
            }
        };
        match hole {
            None => ceiling(a.x, c.x, a.z, c.z),
            Some([x0, x1, z0, z1]) => {
                ceiling(a.x, c.x, a.z, z0);
                ceiling(a.x, c.x, z1, c.z);
                ceiling(a.x, x0, z0, z1);
                ceiling(x1, c.x, z0, z1);
            }
        }
    }

    fn overcast() -> Option<crate::scene::Sky> {
        Some(crate::scene::Sky::with_horizontal_illuminance(
            crate::scene::SkyModel::Overcast,
            10_000.0,
        ))
    }

    #[test]
    fn a_hollow_inside_an_object_under_a_sky_is_not_taken_for_a_room() {
        // A solid block 12 m across (outward faces) with a closed 4 m hollow
        // inside it (inward faces), as a voxel figure's cavities: the sky
        // lights the block, never the hollow.
        let mut b = SceneBuilder::new("block");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let (lo, hi) = (v(-6.0, 0.0, -6.0), v(6.0, 12.0, 6.0));
        b.axis_box("block", grey, lo, hi).unwrap();
        inward_box(&mut b, grey, v(-2.0, 4.0, -2.0), v(2.0, 8.0, 2.0), None);
        let mut scene = b.build().unwrap();
        scene.sky = overcast();
        let camera = Camera::framing(&scene);
        let expected = Camera::framing_box(lo, hi);
        assert_eq!(camera.position, expected.position);
        assert_eq!(camera.forward, expected.forward);
    }

    #[test]
    fn under_a_sky_the_room_open_to_it_is_viewed_not_a_larger_closed_one() {
        // No lamp: a 4 x 3 x 6 room with a 2 m square opening in its roof,
        // and beside it a larger closed room the sky cannot reach.
        let mut b = SceneBuilder::new("rooms");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let roof_hole = Some([1.0, 3.0, 2.0, 4.0]);
        inward_box(&mut b, grey, v(0.0, 0.0, 0.0), v(4.0, 3.0, 6.0), roof_hole);
        inward_box(&mut b, grey, v(5.0, 0.0, 0.0), v(11.0, 3.0, 8.0), None);
        let mut scene = b.build().unwrap();
        scene.sky = overcast();
        let p = Camera::framing(&scene).position;
        let in_open_room = p.cmpgt(v(0.0, 0.0, 0.0)).all() && p.cmplt(v(4.0, 3.0, 6.0)).all();
        assert!(in_open_room, "{p}");
        // Without the sky nothing gives light, and the larger room is shown.
        scene.sky = None;
        let p = Camera::framing(&scene).position;
        let in_closed_room = p.cmpgt(v(5.0, 0.0, 0.0)).all() && p.cmplt(v(11.0, 3.0, 8.0)).all();
        assert!(in_closed_room, "{p}");
    }

    #[test]
    fn a_lit_nook_of_one_grid_point_in_a_large_object_is_not_taken_for_a_room() {
        // A block 20 m across (grid points 20/14 m apart, more than a room's
        // smallest size) with a closed 1.2 m nook around one grid point,
        // lit by a small lamp on its floor: the nook is enclosed and lit but
        // holds one grid point, so the block is seen from outside.
        let mut b = SceneBuilder::new("statue");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let lamp = b.material("lamp", Rgb::ZERO, Rgb::ONE).unwrap();
        let (lo, hi) = (v(-10.0, 0.0, -10.0), v(10.0, 20.0, 10.0));
        b.axis_box("block", grey, lo, hi).unwrap();
        // Around the grid point (0.714, 10.714, 0.714).
        inward_box(&mut b, grey, v(0.1, 10.1, 0.1), v(1.3, 11.3, 1.3), None);
        b.object("lamp");
        b.quad(
            lamp,
            v(0.5, 10.15, 0.5),
            v(0.5, 10.15, 0.9),
            v(0.9, 10.15, 0.9),
            v(0.9, 10.15, 0.5),
        )
        .unwrap();
        let scene = b.build().unwrap();
        let camera = Camera::framing(&scene);
        let expected = Camera::framing_box(lo, hi);
        assert_eq!(camera.position, expected.position);
    }
}
