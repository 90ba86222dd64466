//! Where other objects touch a surface, and how much of a receiving element
//! they cover.
//!
//! A column stands on its plinth, a bench's legs on the floor, a shaft runs
//! into the block it carries. The part of the plinth's top under the column
//! is shut in: it sees only the column's back faces, receives nothing and
//! sends nothing. An element that the contact line crosses is partly shut
//! in, and its hemi-cube, placed at its centroid, sees either the inside of
//! the column (the whole element went black: a plinth top a column stands
//! on in its middle lost all its light) or the room (the covered part was
//! counted as lit).
//!
//! Elements the contact crosses are found from the geometry: per surface,
//! the pieces of other polygons that lie within a thin slab about its plane
//! and inside it (not merely on its border, where every wall meets its
//! floor). Only for those elements, points spread evenly over the element
//! (16, then 49 where those disagree) are tested with
//! [`Occluders::mostly_open`]; the share of them that are is the element's
//! visible fraction, and its row is taken at the visible point nearest the
//! centre of the visible ones and scaled by that fraction (see
//! [`Row::covered`]). An element's slab is its surface's: a decal lying a
//! millimetre off a floor covers the floor elements under it, however
//! small they are.
//! Its light from emitters, which changes fast around what stands on it, is
//! the mean over up to eight of the visible points.

use super::backfaces::reversed;
use super::bvh_walk::walk;
use super::visibility::unit;
use super::{Occluders, Samples, Sources};
use crate::math::{clip_in_place, polygon_area};
use crate::mesh::Mesh;
use glam::DVec3;
use smallvec::SmallVec;

/// A convex planar polygon.
type Piece = SmallVec<[DVec3; 8]>;

/// Points per side of the grids of test points over an element (quads), or
/// divisions per edge (triangles): a first look at 16 points, which most
/// elements a contact's slab reaches answer alike (wholly visible or wholly
/// shut in); where they disagree, 49, so that the visible share is known to
/// a few percent. (With 64 the 10k atrium's per-object errors differ from
/// these by less than a change of seed moves them, at more rays; 36
/// misplaced the receiving point of a corner element, see the suite's test
/// of a partly covered element's visible part.)
const FIRST_SIDE: usize = 4;
const SIDE: usize = 7;

/// Visible test points at which a partly covered element's light from
/// emitters is measured.
const EMITTER_POINTS: usize = 8;

/// How far the rays testing a point go, in element sizes (square roots of
/// its area).
const REACH: f64 = 4.0;

/// The slab about a surface's plane, and the inset of its border, relative
/// to the surface's size: a contact nearer the border than this is the
/// border's (a wall on the floor's edge), one farther off the plane is no
/// contact.
const SLAB: f64 = 1e-3;

/// The pieces of other polygons that touch the inside of each surface.
pub(crate) struct Contacts {
    /// Per surface of the mesh: each piece with its bounding box and the
    /// diameter of the polygon it is cut from.
    pieces: Vec<Vec<(Piece, DVec3, DVec3, f64)>>,
    /// Per surface, the half-thickness of its slab.
    slab: Vec<f64>,
}

impl Contacts {
    /// Finds, for every surface of `mesh`, the polygons of `sources` (other
    /// surfaces) that reach into the slab about its plane inside its border.
    #[must_use]
    pub(crate) fn new(mesh: &Mesh, sources: &Sources, occluders: &Occluders) -> Self {
        let slab: Vec<f64> = mesh
            .surfaces
            .iter()
            .map(|lattice| SLAB * polygon_area(&lattice.vertices).sqrt())
            .collect();
        let pieces = mesh
            .surfaces
            .iter()
            .enumerate()
            .map(|(s, lattice)| {
                let v = &lattice.vertices;
                let n = lattice.normal;
                let eps = slab[s];
                if eps <= 0.0 {
                    return Vec::new();
                }
                let planes = inset_planes(v, n, eps);
                let (lo, hi) = bounds(v);
                let (lo, hi) = (lo - DVec3::splat(eps), hi + DVec3::splat(eps));
                let mut found = Vec::new();
                walk(
                    &occluders.bvh,
                    occluders.centre,
                    |a, b| a.cmple(hi).all() && b.cmpge(lo).all(),
                    |id| {
                        let p = &sources.polygons[id];
                        // Its own polygons, and its back-to-back twin (the
                        // other side of a double-sided surface), cover
                        // nothing of its front.
                        if p.surface as usize == s
                            || reversed(v, &mesh.surfaces[p.surface as usize].vertices)
                        {
                            return true;
                        }
                        let mut piece: Piece =
                            p.vertices[..p.count as usize].iter().copied().collect();
                        clip_in_place(&mut piece, v[0] + n * eps, -n);
                        clip_in_place(&mut piece, v[0] - n * eps, n);
                        for &(origin, inward) in &planes {
                            if piece.len() < 3 {
                                break;
                            }
                            clip_in_place(&mut piece, origin, inward);
                        }
                        if piece.len() >= 3 {
                            let (a, b) = bounds(&piece);
                            found.push((piece, a, b, 2.0 * p.radius));
                        }
                        true
                    },
                );
                found
            })
            .collect();
        Contacts { pieces, slab }
    }

    /// When a contact of surface `surface` reaches into `polygon` (an
    /// element of it, convex, with the surface's unit `normal`): the largest
    /// diameter of the polygons it comes from, which bounds how far a ray
    /// from a point under the object travels before it meets the object.
    #[must_use]
    pub(crate) fn touching(&self, surface: u32, polygon: &[DVec3], normal: DVec3) -> Option<f64> {
        let pieces = self.pieces.get(surface as usize)?;
        if pieces.is_empty() {
            return None;
        }
        let (lo, hi) = bounds(polygon);
        // The pieces lie anywhere in the surface's slab (a decal 1 mm off a
        // floor), which a slab of the element's own size would miss.
        let pad = DVec3::splat(self.slab[surface as usize]);
        let planes = inset_planes(polygon, normal, 0.0);
        let mut largest: Option<f64> = None;
        for (piece, a, b, size) in pieces {
            if !(a.cmple(hi + pad).all() && b.cmpge(lo - pad).all()) {
                continue;
            }
            if largest.is_some_and(|l| l >= *size) {
                continue;
            }
            let mut p = piece.clone();
            let mut inside = true;
            for &(origin, inward) in &planes {
                clip_in_place(&mut p, origin, inward);
                if p.len() < 3 {
                    inside = false;
                    break;
                }
            }
            if inside {
                largest = Some(*size);
            }
        }
        largest
    }

    /// True when no surface has a contact.
    #[must_use]
    pub(crate) fn is_empty(&self) -> bool {
        self.pieces.iter().all(Vec::is_empty)
    }
}

/// The half-spaces (a point on the plane, its unit normal pointing inward)
/// of the convex polygon `v` (unit `normal`) moved inward by `inset`.
fn inset_planes(v: &[DVec3], normal: DVec3, inset: f64) -> SmallVec<[(DVec3, DVec3); 4]> {
    let centre = v.iter().copied().sum::<DVec3>() / v.len() as f64;
    let m = v.len();
    (0..m)
        .filter_map(|i| {
            let edge = v[(i + 1) % m] - v[i];
            let inward = normal.cross(edge).try_normalize()?;
            let inward = if inward.dot(centre - v[i]) < 0.0 {
                -inward
            } else {
                inward
            };
            Some((v[i] + inward * inset, inward))
        })
        .collect()
}

fn bounds(v: &[DVec3]) -> (DVec3, DVec3) {
    v.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), x| (lo.min(*x), hi.max(*x)),
    )
}

/// Points spread evenly over the convex element `polygon`, one jittered
/// (by `seed`) in each cell of a grid of `side` x `side` (a quad: bilinear
/// cells; a triangle: its subdivision into `side^2` equal triangles). The
/// jitter keeps the visible share unbiased where a contact line runs along
/// the grid.
#[must_use]
pub(crate) fn test_points(polygon: &[DVec3], side: usize, seed: u64) -> SmallVec<[DVec3; 64]> {
    let mut out = SmallVec::new();
    let mut state = seed;
    let n = side as f64;
    if polygon.len() == 4 {
        for i in 0..side {
            for j in 0..side {
                let s = (i as f64 + unit(&mut state)) / n;
                let t = (j as f64 + unit(&mut state)) / n;
                let a = polygon[0].lerp(polygon[1], s);
                let b = polygon[3].lerp(polygon[2], s);
                out.push(a.lerp(b, t));
            }
        }
    } else {
        let (a, e1, e2) = (polygon[0], polygon[1] - polygon[0], polygon[2] - polygon[0]);
        let at = |i: f64, j: f64| a + e1 * (i / n) + e2 * (j / n);
        let inside = |p: [DVec3; 3], state: &mut u64| {
            let (mut r, mut q) = (unit(state), unit(state));
            if r + q > 1.0 {
                (r, q) = (1.0 - r, 1.0 - q);
            }
            p[0] + (p[1] - p[0]) * r + (p[2] - p[0]) * q
        };
        for i in 0..side {
            for j in 0..side - i {
                let (x, y) = (i as f64, j as f64);
                // The upright sub-triangle at (i, j) and, where there is
                // room, the inverted one beside it.
                let upright = [at(x, y), at(x + 1.0, y), at(x, y + 1.0)];
                out.push(inside(upright, &mut state));
                if i + j + 1 < side {
                    let inverted = [at(x + 1.0, y), at(x + 1.0, y + 1.0), at(x, y + 1.0)];
                    out.push(inside(inverted, &mut state));
                }
            }
        }
    }
    out
}

/// Where a partly covered element receives, and how much of it can.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Coverage {
    /// The receiving point: the visible test point nearest the visible
    /// points' mean (lifted off the surface like the usual eye).
    pub eye: DVec3,
    /// The share of the test points that are not shut in, in (0, 1).
    pub visible: f64,
    /// Visible test points spread over the visible part, equally weighted:
    /// where the element's light from emitters is measured, since it changes
    /// fast around what stands on it (one side in the light, the other in
    /// the object's own shadow).
    pub samples: Samples,
}

impl Occluders {
    /// The coverage of an element (`polygon`, on `surface` with unit
    /// `normal`, test points lifted by `lift` as the usual eye is, and
    /// jittered by `seed`, touched by polygons up to `contact_size` across),
    /// or `None` when all its test points agree (wholly visible or wholly
    /// shut in: the usual row serves).
    #[must_use]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn coverage(
        &self,
        sources: &Sources,
        polygon: &[DVec3],
        normal: DVec3,
        surface: u32,
        lift: DVec3,
        seed: u64,
        contact_size: f64,
    ) -> Option<Coverage> {
        // What covers part of the element is met within a few times its
        // size, or within the size of the polygons that touch it; rays that
        // go further need not be followed.
        let reach = (REACH * polygon_area(polygon).sqrt()).max(2.0 * contact_size);
        let open_at = |p: &DVec3| self.mostly_open(sources, *p + lift, normal, surface, reach);
        let first = test_points(polygon, FIRST_SIDE, seed);
        let seen = first.iter().filter(|p| open_at(p)).count();
        if seen == 0 || seen == first.len() {
            return None;
        }
        let points = test_points(polygon, SIDE, seed ^ 0x5851_f42d_4c95_7f2d);
        let open: SmallVec<[DVec3; 64]> = points
            .iter()
            .copied()
            .filter(|p| open_at(p))
            .map(|p| p + lift)
            .collect();
        if open.is_empty() || open.len() == points.len() {
            return None;
        }
        let visible = open.len() as f64 / points.len() as f64;
        // The row is taken at the centre of the visible part: the open
        // point nearest the open points' mean. (Not the centroid where that
        // is open: a centroid on the very edge of what covers the element
        // would be open or shut by rounding alone.)
        let mean = open.iter().copied().sum::<DVec3>() / open.len() as f64;
        let eye = open
            .iter()
            .copied()
            .min_by(|a, b| {
                (*a - mean)
                    .length_squared()
                    .total_cmp(&(*b - mean).length_squared())
            })
            .expect("some points are open");
        let count = open.len().min(EMITTER_POINTS);
        let samples = (0..count)
            .map(|k| (open[k * open.len() / count], 1.0 / count as f64))
            .collect();
        Some(Coverage {
            eye,
            visible,
            samples,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::SceneBuilder;

    /// A 4 m floor (y = 0, facing up) with a wall standing on its edge, and
    /// a 1 m box standing on it with one corner at the floor's centre.
    fn floor_wall_and_box() -> (Mesh, Sources, Occluders) {
        let p = DVec3::new;
        let mut b = SceneBuilder::new("contacts");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("floor");
        b.quad(
            grey,
            p(-2.0, 0.0, -2.0),
            p(-2.0, 0.0, 2.0),
            p(2.0, 0.0, 2.0),
            p(2.0, 0.0, -2.0),
        )
        .unwrap();
        b.object("wall");
        b.quad(
            grey,
            p(-2.0, 0.0, -2.0),
            p(2.0, 0.0, -2.0),
            p(2.0, 2.0, -2.0),
            p(-2.0, 2.0, -2.0),
        )
        .unwrap();
        b.axis_box("box", grey, p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0))
            .unwrap();
        let scene = b.build().unwrap();
        let mesh = Mesh::new(&scene, 10.0, usize::MAX).unwrap();
        let sources = Sources::from_mesh(&mesh);
        let occluders = Occluders::new(&sources);
        (mesh, sources, occluders)
    }

    fn floor_square(x0: f64, z0: f64, side: f64) -> [DVec3; 4] {
        [
            DVec3::new(x0, 0.0, z0),
            DVec3::new(x0, 0.0, z0 + side),
            DVec3::new(x0 + side, 0.0, z0 + side),
            DVec3::new(x0 + side, 0.0, z0),
        ]
    }

    #[test]
    fn a_box_on_the_floor_touches_it_and_a_wall_on_its_edge_does_not() {
        let (mesh, sources, occluders) = floor_wall_and_box();
        let contacts = Contacts::new(&mesh, &sources, &occluders);
        let floor = 0;
        // Across the box's corner: touched, by polygons 1 m across.
        let size = contacts.touching(floor, &floor_square(-0.5, -0.5, 1.0), DVec3::Y);
        assert!(
            size.is_some_and(|s| (s - 2f64.sqrt()).abs() < 1e-9),
            "{size:?}"
        );
        // Along the wall's foot, away from the box: not touched.
        let by_wall = floor_square(-1.5, -2.0, 0.5);
        assert_eq!(contacts.touching(floor, &by_wall, DVec3::Y), None);
        // Wholly under the box: touched by its bottom, which lies on the
        // floor (the test points then agree, and the usual row serves).
        let under = floor_square(0.25, 0.25, 0.5);
        assert!(contacts.touching(floor, &under, DVec3::Y).is_some());
    }

    #[test]
    fn a_floor_element_about_a_quarter_under_the_box_shows_the_rest_visible() {
        let (_, sources, occluders) = floor_wall_and_box();
        // A unit element over the box's corner, placed so that the box's
        // sides (x = 0 and z = 0) run along lines of the grid of test
        // points: the box covers about a quarter of it.
        let n = SIDE as f64;
        let outside = (SIDE / 2) as f64;
        let x0 = -outside / n;
        let element = floor_square(x0, x0, 1.0);
        let lift = DVec3::Y * 1e-6;
        let c = occluders
            .coverage(&sources, &element, DVec3::Y, 0, lift, 11, 1.5)
            .expect("the box covers part of the element");
        // The jittered points fall one per cell, and the box covers the
        // cells beyond those lines exactly.
        let covered = (n - outside).powi(2);
        assert_eq!(c.visible, (n * n - covered) / (n * n));
        // The eye is a visible point near the centre of the visible part,
        // an L (the element less the square [0, x0 + 1]^2): within a cell's
        // diagonal and a little (the points are jittered in their cells).
        assert!(!occluders.is_shut_in(&sources, c.eye, DVec3::Y, 0));
        let side = x0 + 1.0;
        let along = ((x0 + 0.5) - side * side * side / 2.0) / (1.0 - side * side);
        let l_centre = DVec3::new(along, 0.0, along);
        assert!((c.eye - l_centre).length() < 1.5 / n, "{}", c.eye);
        assert!(!c.samples.is_empty() && c.samples.len() <= EMITTER_POINTS);
        let weights: f64 = c.samples.iter().map(|s| s.1).sum();
        assert!((weights - 1.0).abs() < 1e-12);
        // An element in the open, or wholly under the box, needs no coverage.
        let open = floor_square(-1.5, 0.5, 0.5);
        assert_eq!(
            occluders.coverage(&sources, &open, DVec3::Y, 0, lift, 11, 1.5),
            None
        );
        let under = floor_square(0.25, 0.25, 0.5);
        assert_eq!(
            occluders.coverage(&sources, &under, DVec3::Y, 0, lift, 11, 1.5),
            None
        );
    }

    #[test]
    fn test_points_fall_one_in_each_cell_of_a_triangle() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let p = test_points(&t, SIDE, 7);
        assert_eq!(p.len(), SIDE * SIDE);
        assert!(p.iter().all(|x| x.x > 0.0 && x.y > 0.0 && x.x + x.y < 1.0));
        // Every sub-triangle holds exactly one point.
        let n = SIDE as f64;
        let mut cells: Vec<(i64, i64, bool)> = p
            .iter()
            .map(|x| {
                let (i, j) = ((x.x * n).floor(), (x.y * n).floor());
                let inverted = x.x * n - i + x.y * n - j > 1.0;
                (i as i64, j as i64, inverted)
            })
            .collect();
        cells.sort_unstable();
        cells.dedup();
        assert_eq!(cells.len(), SIDE * SIDE);
    }

    #[test]
    fn test_points_fall_one_in_each_cell_of_a_square() {
        let q = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let p = test_points(&q, SIDE, 3);
        let n = SIDE as f64;
        let mut cells: Vec<(i64, i64)> = p
            .iter()
            .map(|x| ((x.x * n).floor() as i64, (x.y * n).floor() as i64))
            .collect();
        cells.sort_unstable();
        cells.dedup();
        assert_eq!(cells.len(), SIDE * SIDE);
        assert_ne!(p, test_points(&q, SIDE, 4), "the jitter follows the seed");
    }
}
