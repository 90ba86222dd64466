//! Whether a receiving point is shut in: whether it sees nothing but back
//! faces.
//!
//! A point of the floor under a box standing on it sees only the box's back
//! faces. Its gathering hemi-cube finds no front face, its row stays empty,
//! and by reciprocity nothing sees it either, so it takes no part in the
//! exchange (see `solve::PatchSystem`). The shooting solver has no gathering
//! hemi-cube per element and asks the same question with rays: from the point,
//! along a fixed fan of directions over its hemisphere, what does each ray meet
//! first? The point is shut in when every ray meets a back face. One ray that
//! meets a front face, or nothing (the point looks out into an open scene),
//! is enough to show it is not: a sparse fan may miss a small light far away,
//! but it cannot miss the open sky around it.
//!
//! The fan is dense near the horizon, where a shut-in point's rays travel
//! furthest and a gap between an object and the surface it stands on would
//! show.

use super::{Occluders, Sources};
use glam::DVec3;
use obvhs::ray::{Ray, RayHit};
use smallvec::SmallVec;
use std::sync::OnceLock;

/// Elevations above the horizon (radians) and azimuth counts of the rings of
/// the fan; the normal itself is the first ray.
const RINGS: [(f64, usize); 4] = [(1.05, 6), (0.6, 10), (0.25, 16), (0.06, 16)];

/// Per ray of the fan over [`RINGS`] (the normal first, then each ring in
/// turn): the sine and cosine of its elevation and of its azimuth, found
/// once: every test point of every element casts some of the same rays.
fn fan_angles() -> &'static [[f64; 4]] {
    static ANGLES: OnceLock<Vec<[f64; 4]>> = OnceLock::new();
    ANGLES.get_or_init(|| {
        let mut angles = vec![[1.0, 0.0, 0.0, 1.0]];
        for &(elevation, count) in &RINGS {
            let (sin_e, cos_e) = elevation.sin_cos();
            for k in 0..count {
                let azimuth = std::f64::consts::TAU * (k as f64 + 0.5) / count as f64;
                let (sin_a, cos_a) = azimuth.sin_cos();
                angles.push([sin_e, cos_e, sin_a, cos_a]);
            }
        }
        angles
    })
}

/// The first `count` directions of the fan about unit `normal` (the normal,
/// then the rings of [`RINGS`] from the highest down).
fn fan(normal: DVec3, count: usize) -> impl Iterator<Item = DVec3> {
    let (t1, t2) = normal.any_orthonormal_pair();
    fan_angles()[..count]
        .iter()
        .enumerate()
        .map(move |(i, &[sin_e, cos_e, sin_a, cos_a])| {
            if i == 0 {
                normal
            } else {
                normal * sin_e + (t1 * cos_a + t2 * sin_a) * cos_e
            }
        })
}

/// The rays [`Occluders::mostly_open`] casts first, as indices into the
/// fan: the normal and two opposite rays of the highest ring. Where all
/// three agree they decide. Measured over every test point of the Cornell
/// box (20 000) and of the 10 000-triangle atrium (320 000): they agreed
/// at 86% and 71% of the points, and never against the majority of the
/// whole upper fan, at a third of its rays.
const PROBES: [usize; 3] = [0, 1, 4];

impl Occluders {
    /// True when every ray of the fan from `eye` over the hemisphere about
    /// unit `normal` first meets a back face (ignoring polygons of
    /// `own_surface`, the plane the point lies on).
    #[must_use]
    pub(crate) fn is_shut_in(
        &self,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        own_surface: u32,
    ) -> bool {
        let total = 1 + RINGS.iter().map(|r| r.1).sum::<usize>();
        fan(normal, total).all(|dir| {
            self.first_face(sources, eye, dir, own_surface, f64::INFINITY) == Some(false)
        })
    }

    /// True when the rays from `eye` about unit `normal` meet a front face
    /// or nothing (ignoring `own_surface`): by the three rays of [`PROBES`]
    /// where they agree, else by at least half the rays of the upper part of
    /// the fan (the normal and the two rings highest above the horizon).
    /// The test of a point of a partly covered element (see
    /// `contacts.rs`). Unlike [`Self::is_shut_in`], a ray or two slipping out
    /// where a solid meets the surface at a glancing angle (a capital's rim
    /// under its abacus) do not make a point inside the solid visible. Rays
    /// stop at `reach`: what covers part of an element is met within a few
    /// times its size, and a ray that meets nothing by then counts as open.
    #[must_use]
    pub(crate) fn mostly_open(
        &self,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        own_surface: u32,
        reach: f64,
    ) -> bool {
        // The normal and the two upper rings: a point inside a solid meets
        // its back faces in every direction, one in the open in most.
        let total = 1 + RINGS[..2].iter().map(|r| r.1).sum::<usize>();
        let needed = total.div_ceil(2);
        let is_open =
            |dir: DVec3| self.first_face(sources, eye, dir, own_surface, reach) != Some(false);
        let dirs: SmallVec<[DVec3; 17]> = fan(normal, total).collect();
        let probed = PROBES.map(|i| is_open(dirs[i]));
        if probed.iter().all(|&o| o == probed[0]) {
            return probed[0];
        }
        let mut open = probed.iter().filter(|&&o| o).count();
        let mut blocked = PROBES.len() - open;
        for (i, &dir) in dirs.iter().enumerate() {
            if PROBES.contains(&i) {
                continue;
            }
            if is_open(dir) {
                open += 1;
            } else {
                blocked += 1;
            }
            if open >= needed || blocked > total - needed {
                break;
            }
        }
        open >= needed
    }

    /// What the ray from `eye` along unit `dir` meets first within `reach`:
    /// `Some(true)` a front face, `Some(false)` a back face, `None` nothing.
    fn first_face(
        &self,
        sources: &Sources,
        eye: DVec3,
        dir: DVec3,
        skip: u32,
        reach: f64,
    ) -> Option<bool> {
        let ray = Ray::new(
            (eye - self.centre).as_vec3a(),
            dir.as_vec3a(),
            0.0,
            reach as f32,
        );
        // The BVH prunes in single precision; the nearest hit is decided here
        // in double precision, with the single-precision bound padded so that
        // near ties are all examined.
        let mut nearest: Option<(f64, bool)> = None;
        let mut hit = RayHit::none();
        self.bvh.ray_traverse(ray, &mut hit, |_, slot| {
            let id = self.bvh.primitive_indices[slot] as usize;
            let p = &sources.polygons[id];
            if p.surface == skip {
                return f32::INFINITY;
            }
            let front = p.normal.dot(dir) < 0.0;
            // A hit beyond the nearest so far changes nothing: neither
            // `nearest` nor the ray's end, which it already set nearer. A
            // front face at the nearest's depth (within rounding) takes the
            // place of a back face there: it is the front of a double-sided
            // surface whose back-to-back twin the ray met first, and the
            // twin's back hides nothing behind that front. Left to the
            // order of the BVH, such ties shut in half the points of a
            // narrow double-sided tube.
            let beyond = nearest.map_or(f64::INFINITY, |(best, best_front)| {
                if front && !best_front {
                    best + tie(best)
                } else {
                    best
                }
            });
            let Some(t) = hit_distance(&p.vertices[..p.count as usize], p.normal, eye, dir, beyond)
            else {
                return f32::INFINITY;
            };
            let t = match nearest {
                // Keep the tie's depth, so that ties do not creep along.
                Some((best, _)) if t > best => best,
                _ => t,
            };
            nearest = Some((t, front));
            (t + tie(t) + self.pad) as f32
        });
        nearest.map(|(_, front)| front)
    }
}

/// How far apart two hits along a ray may lie and still be one depth: the
/// rounding of two back-to-back copies of one polygon, whose planes are
/// computed from different first vertices.
fn tie(t: f64) -> f64 {
    1e-9 * t
}

/// Distance along the ray from `a` along unit `dir` to the convex planar
/// polygon `v` (counter-clockwise about unit `normal`), if it hits beyond a
/// rounding margin and before `beyond` (a hit already found: a polygon
/// whose plane lies beyond it is not tested further).
fn hit_distance(v: &[DVec3], normal: DVec3, a: DVec3, dir: DVec3, beyond: f64) -> Option<f64> {
    let denom = normal.dot(dir);
    if denom.abs() < 1e-15 {
        return None;
    }
    let t = normal.dot(v[0] - a) / denom;
    // False for NaN, which the next test turns away.
    if t >= beyond {
        return None;
    }
    let scale = (v[0] - a).length();
    if t.is_nan() || t <= 1e-12 * scale {
        return None;
    }
    let p = a + dir * t;
    let m = v.len();
    (0..m)
        .all(|i| (v[(i + 1) % m] - v[i]).cross(p - v[i]).dot(normal) >= 0.0)
        .then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::SourcePolygon;

    fn square(centre: DVec3, half: f64, normal: DVec3, surface: u32) -> SourcePolygon {
        let (t1, t2) = normal.any_orthonormal_pair();
        // Counter-clockwise about the normal: t1 x t2 = normal.
        let vertices = [
            centre - t1 * half - t2 * half,
            centre + t1 * half - t2 * half,
            centre + t1 * half + t2 * half,
            centre - t1 * half + t2 * half,
        ];
        SourcePolygon {
            vertices,
            count: 4,
            normal,
            surface,
            centre,
            radius: half * 2f64.sqrt(),
            patch: 0,
        }
    }

    /// A unit box standing on the floor z = 0 (no bottom), faces pointing out,
    /// plus the floor itself as surface 0.
    fn box_on_floor() -> Sources {
        let c = DVec3::new(0.0, 0.0, 0.5);
        let mut polygons = vec![square(DVec3::ZERO, 5.0, DVec3::Z, 0)];
        let faces = [DVec3::Z, DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y];
        for (i, n) in faces.into_iter().enumerate() {
            polygons.push(square(c + n * 0.5, 0.5, n, i as u32 + 1));
        }
        Sources::one_per_patch(polygons)
    }

    #[test]
    fn a_point_under_a_box_is_shut_in_and_one_beside_it_is_exposed() {
        let sources = box_on_floor();
        let occluders = Occluders::new(&sources);
        let lift = DVec3::Z * 1e-7;
        let under = DVec3::new(0.49, 0.3, 0.0) + lift;
        let beside = DVec3::new(0.51, 0.3, 0.0) + lift;
        assert!(occluders.is_shut_in(&sources, under, DVec3::Z, 0));
        assert!(!occluders.is_shut_in(&sources, beside, DVec3::Z, 0));
    }

    #[test]
    fn a_point_facing_only_the_void_is_not_shut_in() {
        let sources = box_on_floor();
        let occluders = Occluders::new(&sources);
        // On the floor's plane but facing down: nothing lies below.
        let below = DVec3::new(3.0, 3.0, -1e-7);
        assert!(!occluders.is_shut_in(&sources, below, DVec3::NEG_Z, 0));
    }

    #[test]
    fn a_point_under_a_lid_is_not_shut_in_if_one_ray_gets_out() {
        // A downward-facing lid (its back face up, toward the inside) over a
        // floor point, open at the sides: the rays out sideways escape.
        let sources = Sources::one_per_patch(box_on_floor().polygons[..2].to_vec());
        let occluders = Occluders::new(&sources);
        let eye = DVec3::new(0.0, 0.0, 1e-7);
        assert!(!occluders.is_shut_in(&sources, eye, DVec3::Z, 0));
        // With the four walls as well it is.
        let sources = box_on_floor();
        let occluders = Occluders::new(&sources);
        assert!(occluders.is_shut_in(&sources, eye, DVec3::Z, 0));
    }

    #[test]
    fn where_the_probes_disagree_the_majority_of_the_upper_fan_decides() {
        let eye = DVec3::new(0.0, 0.0, 1e-7);
        // A small lid straight above, its back face down: it stops the
        // normal only, and the other rays get out.
        let lid = square(DVec3::Z, 0.1, DVec3::Z, 1);
        let sources = Sources::one_per_patch(vec![square(DVec3::ZERO, 5.0, DVec3::Z, 0), lid]);
        let occluders = Occluders::new(&sources);
        assert!(occluders.mostly_open(&sources, eye, DVec3::Z, 0, 10.0));
        // A tall open-topped shaft of outward-facing walls: the normal gets
        // out and every other ray of the upper fan meets a wall's back.
        let (h, w) = (3.0, 0.5);
        let c = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let rectangle = |corners: [DVec3; 4], normal: DVec3, surface: u32| {
            SourcePolygon::new(&corners, normal, surface)
        };
        let walls = vec![
            square(DVec3::ZERO, 5.0, DVec3::Z, 0),
            rectangle(
                [c(w, -w, 0.0), c(w, w, 0.0), c(w, w, h), c(w, -w, h)],
                DVec3::X,
                1,
            ),
            rectangle(
                [c(-w, w, 0.0), c(-w, -w, 0.0), c(-w, -w, h), c(-w, w, h)],
                DVec3::NEG_X,
                2,
            ),
            rectangle(
                [c(w, w, 0.0), c(-w, w, 0.0), c(-w, w, h), c(w, w, h)],
                DVec3::Y,
                3,
            ),
            rectangle(
                [c(-w, -w, 0.0), c(w, -w, 0.0), c(w, -w, h), c(-w, -w, h)],
                DVec3::NEG_Y,
                4,
            ),
        ];
        let sources = Sources::one_per_patch(walls);
        let occluders = Occluders::new(&sources);
        assert!(!occluders.mostly_open(&sources, eye, DVec3::Z, 0, 10.0));
        // Without the walls' backs in the way it is open.
        assert!(occluders.mostly_open(&sources, DVec3::new(2.0, 0.0, 1e-7), DVec3::Z, 0, 10.0));
    }

    #[test]
    fn inside_a_shaft_of_double_sided_walls_a_point_sees_the_walls_fronts() {
        // The shaft of the test above, each wall with its back-to-back twin
        // facing in: every ray from inside meets a twin pair at one depth,
        // and the front must win whichever copy the BVH offers first.
        let (h, w) = (3.0, 0.5);
        let c = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let walls = [
            [c(w, -w, 0.0), c(w, w, 0.0), c(w, w, h), c(w, -w, h)],
            [c(-w, w, 0.0), c(-w, -w, 0.0), c(-w, -w, h), c(-w, w, h)],
            [c(w, w, 0.0), c(-w, w, 0.0), c(-w, w, h), c(w, w, h)],
            [c(-w, -w, 0.0), c(w, -w, 0.0), c(w, -w, h), c(-w, -w, h)],
        ];
        let normals = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y];
        for fronts_first in [false, true] {
            let mut polygons = vec![square(DVec3::ZERO, 5.0, DVec3::Z, 0)];
            let mut outward = Vec::new();
            let mut inward = Vec::new();
            for (i, (corners, n)) in walls.iter().zip(normals).enumerate() {
                let mut back = *corners;
                back.reverse();
                outward.push(SourcePolygon::new(corners, n, 1 + 2 * i as u32));
                inward.push(SourcePolygon::new(&back, -n, 2 + 2 * i as u32));
            }
            if fronts_first {
                polygons.extend(inward.into_iter().chain(outward));
            } else {
                polygons.extend(outward.into_iter().chain(inward));
            }
            let sources = Sources::one_per_patch(polygons);
            let occluders = Occluders::new(&sources);
            let floor = DVec3::new(0.1, -0.2, 1e-7);
            assert!(occluders.mostly_open(&sources, floor, DVec3::Z, 0, 10.0));
            assert!(!occluders.is_shut_in(&sources, floor, DVec3::Z, 0));
            // On the inward face of the +x wall, half way up.
            let wall = DVec3::new(w - 1e-7, 0.1, 1.5);
            assert!(occluders.mostly_open(&sources, wall, DVec3::NEG_X, 2, 0.5));
        }
    }
}
