//! Ray casting: an `obvhs` BVH2 over padded single-precision boxes as the broad
//! phase, and exact double-precision polygon tests for every decision.
//!
//! The boxes are stored relative to the scene's centre and padded by 4e-6 of the
//! scene diameter, over ten times the worst f32 rounding of a centred
//! coordinate, ray origin or direction over one diameter. The BVH therefore only
//! ever visits too much, never too little; which surface is hit, and where, is
//! decided in f64 by [`SurfaceGeometry::intersect`].
//!
//! The BVH2 (not obvhs's compressed wide BVH, whose traversal skips anything
//! nearer than a fixed 1e-4 scene units and so fails millimetre scenes) is built
//! single-threaded, so its layout is the same on every run.

use super::geometry::{SurfaceGeometry, Tolerances};
use glam::DVec3;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::ray::{Ray, RayHit};
use obvhs::{Boundable, BvhBuildParams};
use std::time::Duration;

/// The nearest surface along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Hit {
    /// Index of the surface.
    pub(crate) surface: u32,
    /// Distance along the (unit) ray direction.
    pub(crate) t: f64,
    /// True when the ray meets the surface's front (its normal faces the ray).
    pub(crate) front: bool,
}

impl Hit {
    /// Whether `self` should replace `current` as the nearest hit. Hits closer
    /// than `tie` in distance are the same place (back-to-back twins of a
    /// double-sided surface, shared edges); there the front face wins, then the
    /// lower index, so the answer never depends on the BVH's visiting order.
    fn beats(&self, current: &Option<Hit>, tie: f64) -> bool {
        let Some(c) = current else { return true };
        if self.t < c.t - tie {
            return true;
        }
        if self.t > c.t + tie {
            return false;
        }
        (!self.front, self.surface) < (!c.front, c.surface)
    }
}

/// One padded box per surface, in the centred frame.
struct PaddedBox(Aabb);

impl Boundable for PaddedBox {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// The scene's surfaces in a BVH.
pub(crate) struct Accel {
    bvh: Bvh2,
    centre: DVec3,
    pad: f64,
    tolerances: Tolerances,
}

impl Accel {
    /// A BVH over `geometry` for a scene whose bounds are `lo..hi`.
    pub(crate) fn new(
        geometry: &[SurfaceGeometry],
        lo: DVec3,
        hi: DVec3,
        tolerances: Tolerances,
    ) -> Accel {
        let centre = (lo + hi) * 0.5;
        let pad = 4e-6 * (hi - lo).length();
        let boxes: Vec<PaddedBox> = geometry
            .iter()
            .map(|g| {
                let (a, b) = g.bounds();
                let min = (a - centre - DVec3::splat(pad)).as_vec3a();
                let max = (b - centre + DVec3::splat(pad)).as_vec3a();
                PaddedBox(Aabb::new(min, max))
            })
            .collect();
        let bvh = obvhs::bvh2::builder::build_bvh2(
            &boxes,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        Accel {
            bvh,
            centre,
            pad,
            tolerances,
        }
    }

    fn f32_ray(&self, origin: DVec3, dir: DVec3, t_max: f32) -> Ray {
        Ray::new(
            (origin - self.centre).as_vec3a(),
            dir.as_vec3a(),
            0.0,
            t_max,
        )
    }

    /// The nearest surface other than `skip` met at a distance t > 0 along the
    /// unit direction `dir` from `origin`.
    pub(crate) fn nearest(
        &self,
        geometry: &[SurfaceGeometry],
        origin: DVec3,
        dir: DVec3,
        skip: u32,
    ) -> Option<Hit> {
        let slack = self.tolerances.slack;
        let mut best: Option<Hit> = None;
        let mut record = RayHit::none();
        let ray = self.f32_ray(origin, dir, f32::INFINITY);
        self.bvh.ray_traverse(ray, &mut record, |_, slot| {
            let surface = self.bvh.primitive_indices[slot];
            if surface != skip {
                let g = &geometry[surface as usize];
                if let Some(t) = g.intersect(origin, dir, slack) {
                    let hit = Hit {
                        surface,
                        t,
                        front: g.normal.dot(dir) < 0.0,
                    };
                    if t > 0.0 && hit.beats(&best, slack) {
                        best = Some(hit);
                    }
                }
            }
            // Let the traversal prune beyond the best hit, keeping a margin for
            // ties and f32 rounding.
            best.map_or(f32::INFINITY, |b| (b.t + slack + self.pad) as f32)
        });
        best
    }

    /// True when nothing other than `skip` lies strictly between `origin` and
    /// `target`, leaving a margin of one ray offset at the target end (the
    /// target's own surface and any back-to-back twin sit in that margin).
    pub(crate) fn unblocked(
        &self,
        geometry: &[SurfaceGeometry],
        origin: DVec3,
        target: DVec3,
        skip: u32,
    ) -> bool {
        let span = target - origin;
        let distance = span.length();
        let t_max = distance - self.tolerances.offset;
        if t_max.is_nan() || t_max <= 0.0 {
            return true;
        }
        let dir = span / distance;
        let slack = self.tolerances.slack;
        let ray = self.f32_ray(origin, dir, (t_max + self.pad) as f32);
        self.bvh.ray_traverse_miss(ray, |_, slot| {
            let surface = self.bvh.primitive_indices[slot];
            if surface == skip {
                return f32::INFINITY;
            }
            match geometry[surface as usize].intersect(origin, dir, slack) {
                Some(t) if t > 0.0 && t < t_max => 0.0,
                _ => f32::INFINITY,
            }
        })
    }
}
