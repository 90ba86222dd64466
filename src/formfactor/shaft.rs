//! Exact visibility of a convex emitter polygon from a point, by clipping.
//!
//! Shadow rays estimate the visible part of a partly hidden light with noise
//! that no mesh refinement removes (a floor of about 2e-4 of the light-on
//! radiosity on the penumbra scenes with 32 x 32 rays). When few polygons lie
//! in the shaft between the point and the light, the visible part can instead
//! be computed exactly: each occluder is clipped to the shaft, projected from
//! the point onto the light's plane, and cut out of the light; what remains is
//! a set of convex pieces whose form factors Lambert's contour formula gives.

use super::bvh_walk::box_below;
use super::point_to_polygon;
use crate::math::clip_in_place;
use glam::DVec3;
use smallvec::SmallVec;

/// A convex planar polygon.
pub(super) type Piece = SmallVec<[DVec3; 8]>;

/// More occluders or pieces than this and the rays are cheaper.
pub(super) const MAX_OCCLUDERS: usize = 48;
const MAX_PIECES: usize = 256;

/// The shaft from a point to a convex planar light polygon: the planes that
/// bound it and the light's plane, in which occluders are projected.
pub(super) struct Shaft<'a> {
    eye: DVec3,
    /// The receiver's unit normal: nothing below the eye's tangent plane can
    /// hide the part of the light above it, which is all that counts.
    horizon: DVec3,
    light: &'a [DVec3],
    light_normal: DVec3,
    /// Signed distance of the eye from the light's plane (never near 0).
    eye_height: f64,
    /// Side planes through the eye and each light edge, normals inward.
    sides: SmallVec<[DVec3; 4]>,
}

impl<'a> Shaft<'a> {
    /// The shaft from `eye` (on a receiver with unit normal `horizon`) to
    /// `light`, or `None` when the light is not planar or the eye lies (nearly)
    /// in its plane, where projection breaks down.
    pub(super) fn new(
        eye: DVec3,
        horizon: DVec3,
        light: &'a [DVec3],
        light_normal: DVec3,
    ) -> Option<Self> {
        let size = light
            .iter()
            .map(|v| (*v - light[0]).length())
            .fold(0.0, f64::max);
        if size <= 0.0 {
            return None;
        }
        if light
            .iter()
            .any(|v| light_normal.dot(*v - light[0]).abs() > 1e-9 * size)
        {
            return None;
        }
        let eye_height = light_normal.dot(eye - light[0]);
        if eye_height.abs() <= 1e-7 * size {
            return None;
        }
        let centroid = light.iter().copied().sum::<DVec3>() / light.len() as f64;
        let m = light.len();
        let mut sides = SmallVec::new();
        for i in 0..m {
            let n = (light[i] - eye).cross(light[(i + 1) % m] - eye);
            let len = n.length();
            if len <= 0.0 {
                return None;
            }
            let n = n / len;
            sides.push(if n.dot(centroid - eye) >= 0.0 { n } else { -n });
        }
        Some(Shaft {
            eye,
            horizon,
            light,
            light_normal,
            eye_height,
            sides,
        })
    }

    /// True when a polygon within `radius` of `centre` lies wholly outside
    /// one of the planes [`Self::shadow_of`] clips to, so that it hides
    /// nothing: a shaft's bounding box holds many polygons its thin pyramid
    /// misses, and this rejects them without touching their vertices. Kept
    /// conservative by a relative margin, so that it never rejects a polygon
    /// the clipping would keep.
    pub(super) fn misses(&self, centre: DVec3, radius: f64) -> bool {
        let r = radius * (1.0 + 1e-9) + 1e-12 * self.eye_height.abs();
        let toward_eye = self.light_normal * self.eye_height.signum();
        toward_eye.dot(centre - self.light[0]) < -r
            || self.horizon.dot(centre - self.eye) < -r
            || self.sides.iter().any(|n| n.dot(centre - self.eye) < -r)
            || toward_eye.dot(centre - self.eye) > r
    }

    /// The point the shaft starts from.
    pub(super) fn eye(&self) -> DVec3 {
        self.eye
    }

    /// True when the box (`lo`, `hi`) lies wholly outside one of the planes
    /// [`Self::shadow_of`] clips to, so that nothing in it hides anything:
    /// the same rule as [`Self::misses`], for a BVH node.
    pub(super) fn misses_box(&self, lo: DVec3, hi: DVec3) -> bool {
        let r = 1e-12 * self.eye_height.abs();
        let toward_eye = self.light_normal * self.eye_height.signum();
        box_below(lo, hi, self.light[0], toward_eye, r)
            || box_below(lo, hi, self.eye, self.horizon, r)
            || self
                .sides
                .iter()
                .any(|n| box_below(lo, hi, self.eye, *n, r))
            || box_below(lo, hi, self.eye, -toward_eye, r)
    }

    /// The part of the light that `occluder` hides, as a convex polygon in the
    /// light's plane, or `None` if it hides nothing.
    pub(super) fn shadow_of(&self, occluder: &[DVec3]) -> Option<Piece> {
        // Keep the part strictly between the light's plane and the eye.
        let toward_eye = self.light_normal * self.eye_height.signum();
        let margin = 1e-9 * self.eye_height.abs();
        let near = self.eye - toward_eye * margin;
        // An occluder wholly outside any one of the planes hides nothing.
        // Most that reach here lie so (a wall beside the shaft, crossing
        // the light's plane): finding it before clipping to the others
        // saves the clipping.
        let outside = |p: DVec3, n: DVec3| occluder.iter().all(|x| n.dot(*x - p) < 0.0);
        if outside(self.light[0] + toward_eye * margin, toward_eye)
            || outside(self.eye, self.horizon)
            || self.sides.iter().any(|n| outside(self.eye, *n))
            || outside(near, -toward_eye)
        {
            return None;
        }
        let mut p: Piece = SmallVec::from_slice(occluder);
        clip_in_place(&mut p, self.light[0] + toward_eye * margin, toward_eye);
        if p.len() < 3 {
            return None;
        }
        // Without this, an occluder lying in the receiver's own plane (a
        // neighbouring surface) keeps a rounding-sized piece beside the eye,
        // which projects onto the whole light.
        clip_in_place(&mut p, self.eye, self.horizon);
        if p.len() < 3 {
            return None;
        }
        for n in &self.sides {
            clip_in_place(&mut p, self.eye, *n);
            if p.len() < 3 {
                return None;
            }
        }
        clip_in_place(&mut p, near, -toward_eye);
        if p.len() < 3 {
            return None;
        }
        // Central projection from the eye onto the light's plane.
        let shadow: Piece = p
            .iter()
            .map(|x| {
                let d = x - self.eye;
                let along = -self.light_normal.dot(d);
                self.eye + d * (self.eye_height / along)
            })
            .collect();
        (area(&shadow) > 0.0).then_some(shadow)
    }
}

/// The smallest doubled area of a piece of `light` worth keeping.
pub(super) fn sliver_area(light: &[DVec3]) -> f64 {
    SLIVER * area(light)
}

/// Twice the area of a planar polygon.
fn area(v: &[DVec3]) -> f64 {
    let mut sum = DVec3::ZERO;
    for i in 1..v.len().saturating_sub(1) {
        sum += (v[i] - v[0]).cross(v[i + 1] - v[0]);
    }
    sum.length()
}

/// Pieces smaller than this fraction of the light are dropped: they are the
/// rounding slivers left where the shadows of abutting occluder patches meet,
/// and kept they would make a receiver sealed inside an object see the light.
const SLIVER: f64 = 1e-9;

/// Removes the convex `hole` (in the plane with unit `normal`) from each of
/// `pieces`, splitting each into convex pieces outside it; pieces whose doubled
/// area is below `min_area` are dropped. Returns `false` when the pieces would
/// exceed the limit.
pub(super) fn subtract(
    pieces: &mut Vec<Piece>,
    hole: &[DVec3],
    normal: DVec3,
    min_area: f64,
) -> bool {
    let m = hole.len();
    // A hole below the sliver size hides nothing worth its rounding: its edge
    // directions are noise, and cutting along them could remove anything.
    if area(hole) <= min_area {
        return true;
    }
    let centroid = hole.iter().copied().sum::<DVec3>() / m as f64;
    let perimeter: f64 = (0..m).map(|i| (hole[(i + 1) % m] - hole[i]).length()).sum();
    // Edge planes perpendicular to the light's plane, normals pointing out of
    // the hole. Rounding-length edges are left out: leaving one out only
    // shrinks the cut to the other edges' wedge, which still holds the hole.
    let mut outward: SmallVec<[(DVec3, DVec3); 8]> = SmallVec::new();
    for i in 0..m {
        let (a, b) = (hole[i], hole[(i + 1) % m]);
        if (b - a).length() <= 1e-9 * perimeter {
            continue;
        }
        let n = (b - a).cross(normal);
        let len = n.length();
        if len <= 0.0 {
            continue;
        }
        let n = n / len;
        outward.push((a, if n.dot(a - centroid) >= 0.0 { n } else { -n }));
    }
    if outward.len() < 3 {
        return true;
    }
    let mut out = Vec::with_capacity(pieces.len() + 4);
    for piece in pieces.drain(..) {
        // Wholly outside one of the hole's edges: untouched, kept whole.
        // Every edge is asked before any is cut along; cutting first would
        // split a piece beside the hole along an edge line that crosses it
        // though the hole does not, and the pieces (each clipped by every
        // later hole, and summed) would multiply for nothing.
        if outward
            .iter()
            .any(|&(a, n)| piece.iter().all(|x| n.dot(*x - a) >= 0.0))
        {
            out.push(piece);
            continue;
        }
        let mut rest = piece;
        for &(a, n) in &outward {
            // Wholly on one side of the edge's plane (most pieces, for most
            // edges): no clipping, and the same result as clipping.
            let (mut ahead, mut behind) = (false, false);
            for x in &rest {
                let d = n.dot(*x - a);
                ahead |= d >= 0.0;
                behind |= d <= 0.0;
            }
            if !behind {
                if rest.len() >= 3 && area(&rest) > min_area {
                    out.push(std::mem::take(&mut rest));
                }
                break;
            }
            if !ahead {
                continue;
            }
            let (outside, inside) = split(&rest, a, n);
            if outside.len() >= 3 && area(&outside) > min_area {
                if outside.len() == rest.len() && same(&outside, &rest) {
                    // Wholly outside this edge: untouched by the hole.
                    rest.clear();
                    out.push(outside);
                    break;
                }
                out.push(outside);
            }
            rest = inside;
            if rest.len() < 3 {
                break;
            }
        }
        if out.len() > MAX_PIECES {
            return false;
        }
    }
    *pieces = out;
    true
}

/// The parts of `v` on each side of the plane through `p` with normal `n`:
/// what `clip_to_halfspace` gives for `n` and for `-n`, bit for bit (the
/// distances to the plane only change sign, which rounds alike), from one
/// pass over the vertices.
fn split(v: &[DVec3], p: DVec3, n: DVec3) -> (Piece, Piece) {
    let (mut ahead, mut behind) = (Piece::new(), Piece::new());
    let m = v.len();
    for i in 0..m {
        let (a, b) = (v[i], v[(i + 1) % m]);
        let (da, db) = (n.dot(a - p), n.dot(b - p));
        if da >= 0.0 {
            ahead.push(a);
        }
        if da <= 0.0 {
            behind.push(a);
        }
        let crosses_ahead = (da >= 0.0) != (db >= 0.0);
        let crosses_behind = (da <= 0.0) != (db <= 0.0);
        if crosses_ahead || crosses_behind {
            let x = a + (b - a) * (da / (da - db));
            if crosses_ahead {
                ahead.push(x);
            }
            if crosses_behind {
                behind.push(x);
            }
        }
    }
    (ahead, behind)
}

fn same(a: &[DVec3], b: &[DVec3]) -> bool {
    a.iter().zip(b).all(|(x, y)| x == y)
}

/// The form factor from (`eye`, `normal`) to the parts of `pieces` (convex,
/// disjoint) above the eye's horizon.
pub(super) fn pieces_form_factor(eye: DVec3, normal: DVec3, pieces: &[Piece]) -> f64 {
    pieces
        .iter()
        .map(|p| point_to_polygon(eye, normal, p))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytic;
    use crate::math::clip_to_halfspace;

    #[test]
    fn one_split_gives_both_clips_bit_for_bit() {
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut cut = 0;
        for _ in 0..2000 {
            // A random convex quad in z = 0 and a random vertical plane,
            // sometimes through a vertex.
            let c = [(0.0, 0.0), (1.0, 0.1), (1.1, 1.0), (-0.1, 0.9)];
            let v: Vec<DVec3> = c
                .iter()
                .map(|&(x, y)| DVec3::new(x + 0.1 * next(), y + 0.1 * next(), 0.0))
                .collect();
            let n = DVec3::new(next(), next(), 0.0).normalize();
            let p = if next() > 0.3 {
                v[0]
            } else {
                DVec3::new(0.5 + next(), 0.5 + next(), 0.0)
            };
            let (ahead, behind) = split(&v, p, n);
            let bits = |x: &[DVec3]| {
                x.iter()
                    .map(|q| q.to_array().map(f64::to_bits))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&ahead), bits(&clip_to_halfspace(&v, p, n)));
            assert_eq!(bits(&behind), bits(&clip_to_halfspace(&v, p, -n)));
            cut += usize::from(ahead.len() >= 3 && behind.len() >= 3);
        }
        assert!(cut > 500, "{cut} of 2000 cut in two");
    }

    fn square(z: f64, x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(x0, y0, z),
            DVec3::new(x1, y0, z),
            DVec3::new(x1, y1, z),
            DVec3::new(x0, y1, z),
        ]
    }

    #[test]
    fn the_bounding_sphere_test_rejects_only_what_clipping_rejects() {
        // Small triangles scattered through and around a shaft from the origin
        // to a unit light at z = 2: whenever `misses` rejects one, clipping
        // keeps nothing of it; and it rejects many.
        let light = square(2.0, 0.0, 0.0, 1.0, 1.0);
        let shaft = Shaft::new(DVec3::ZERO, DVec3::Z, &light, DVec3::Z).unwrap();
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut rejected, mut kept_by_clipping) = (0, 0);
        for _ in 0..4000 {
            let c = DVec3::new(3.0 * next() - 1.0, 3.0 * next() - 1.0, 3.0 * next() - 0.5);
            let size = 0.3 * next();
            let tri: Vec<DVec3> = (0..3)
                .map(|_| c + DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * size)
                .collect();
            let centre = tri.iter().copied().sum::<DVec3>() / 3.0;
            let radius = tri
                .iter()
                .map(|v| (*v - centre).length())
                .fold(0.0, f64::max);
            let kept = shaft.shadow_of(&tri).is_some();
            kept_by_clipping += usize::from(kept);
            if shaft.misses(centre, radius) {
                rejected += 1;
                assert!(!kept, "rejected a triangle clipping keeps: {tri:?}");
            }
        }
        assert!(
            rejected > 2000 && kept_by_clipping > 100,
            "{rejected} {kept_by_clipping}"
        );
    }

    #[test]
    fn an_occluder_halfway_hides_the_light_scaled_by_two() {
        // Light [0,1]^2 at z = 2, occluder [0.25,0.5] x [0,0.5] at z = 1:
        // from the origin it hides [0.5,1] x [0,1] of the light.
        let light = square(2.0, 0.0, 0.0, 1.0, 1.0);
        let shaft = Shaft::new(DVec3::ZERO, DVec3::Z, &light, DVec3::Z).unwrap();
        let hole = shaft.shadow_of(&square(1.0, 0.25, 0.0, 0.5, 0.5)).unwrap();
        let mut pieces = vec![Piece::from_slice(&light)];
        assert!(subtract(&mut pieces, &hole, DVec3::Z, 0.0));
        let visible = pieces_form_factor(DVec3::ZERO, DVec3::Z, &pieces);
        let expected = point_to_polygon(DVec3::ZERO, DVec3::Z, &square(2.0, 0.0, 0.0, 0.5, 1.0));
        assert!(
            (visible - expected).abs() < 1e-12,
            "{visible} vs {expected}"
        );
    }

    #[test]
    fn a_hole_beside_a_piece_leaves_it_whole() {
        // A hole right of the light whose first edge lies on the line
        // y = 0.5, across the light: the light stays one piece.
        let light = square(1.0, 0.0, 0.0, 1.0, 1.0);
        let hole = vec![
            DVec3::new(2.0, 0.5, 1.0),
            DVec3::new(3.0, 0.5, 1.0),
            DVec3::new(2.5, 3.0, 1.0),
        ];
        let mut pieces = vec![Piece::from_slice(&light)];
        assert!(subtract(&mut pieces, &hole, DVec3::Z, 0.0));
        assert_eq!(pieces.len(), 1);
        assert_eq!(pieces[0].as_slice(), light.as_slice());
    }

    #[test]
    fn a_hole_inside_the_light_leaves_light_minus_hole() {
        let light = square(1.0, -1.0, -1.0, 1.0, 1.0);
        let hole = square(1.0, -0.3, -0.2, 0.4, 0.5);
        let mut pieces = vec![Piece::from_slice(&light)];
        assert!(subtract(&mut pieces, &hole, DVec3::Z, 0.0));
        let eye = DVec3::new(0.1, 0.2, 0.0);
        let visible = pieces_form_factor(eye, DVec3::Z, &pieces);
        let expected =
            point_to_polygon(eye, DVec3::Z, &light) - point_to_polygon(eye, DVec3::Z, &hole);
        assert!(
            (visible - expected).abs() < 1e-12,
            "{visible} vs {expected}"
        );
    }

    #[test]
    fn matches_the_exact_penumbra_oracle() {
        // The brief's penumbra configuration: the analytic module's
        // inclusion-exclusion oracle, written independently.
        let light = square(2.0, -0.5, -0.5, 0.5, 0.5);
        let occluder = square(1.0, -1.0, -1.0, 0.0, 1.0);
        for x in [-0.6, -0.3, -0.1, 0.0, 0.05, 0.2, 0.45, 0.7] {
            let eye = DVec3::new(x, 0.1, 0.0);
            let exact = analytic::OccludedLight::new(&light, std::slice::from_ref(&occluder))
                .unwrap()
                .visible_form_factor(eye, DVec3::Z)
                .unwrap();
            let shaft = Shaft::new(eye, DVec3::Z, &light, DVec3::Z).unwrap();
            let mut pieces = vec![Piece::from_slice(&light)];
            if let Some(hole) = shaft.shadow_of(&occluder) {
                assert!(subtract(&mut pieces, &hole, DVec3::Z, 0.0));
            }
            let got = pieces_form_factor(eye, DVec3::Z, &pieces);
            assert!((got - exact).abs() < 1e-12, "x = {x}: {got} vs {exact}");
        }
    }
}
