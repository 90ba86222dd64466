//! Visibility of emitters from a receiving point: exact by clipping where few
//! polygons lie in the shaft (see `shaft.rs`), else by shadow rays.
//!
//! The hemi-cube knows visibility only to a pixel: a light partly hidden by an
//! occluder is seen through a staircase of pixels, and the shadow's penumbra
//! inherits that staircase however finely the receivers are subdivided. For
//! emitter patches that a hemi-cube saw only in part (or not at all, though they
//! lie above the receiver's horizon), the visible fraction is instead measured by
//! casting rays to stratified, jittered points on the emitter, weighted by the
//! form-factor kernel. Rays go through a BVH (the `obvhs` crate) over the patch
//! polygons; every hit is decided in double precision against the polygon.

mod clipping;
mod node_summary;
mod rays;
#[cfg(test)]
mod tests;

use super::Sources;
use glam::DVec3;
use node_summary::{summarise, NodeSummary};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::ray::Ray;
use obvhs::{Boundable, BvhBuildParams};
use std::time::Duration;

pub(crate) use clipping::PointsMean;
pub(crate) use rays::PixelHint;

struct Bounds(Aabb);

impl Boundable for Bounds {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// What the hybrid form factors need to treat emitters exactly: the occluders,
/// the row's seed for the rays, and quadrature points over the receiving
/// element (point, weight; the weights sum to 1), so that an emitter's entry is
/// the element's mean form factor rather than its centre's.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EmitterVisibility<'a> {
    /// Every patch polygon, for shaft and ray queries.
    pub occluders: &'a Occluders,
    /// Seed of the row's rays.
    pub seed: u64,
    /// Quadrature points over the receiving element and their weights; when
    /// empty, emitter visibility is ray cast at the centre instead of clipped
    /// exactly at the points.
    pub samples: &'a [(DVec3, f64)],
    /// Shadowed sampling (see [`super::EmitterSampling::Shadowed`]): the
    /// points' means only in rows where something hides part of an emitter
    /// from some point, and few surfaces do; the centre's values elsewhere.
    pub shadowed_sampling: bool,
}

/// Every patch polygon as an occluder, for shadow rays.
pub(crate) struct Occluders {
    pub(super) bvh: Bvh2,
    /// Coordinates are stored relative to this centre so that the BVH's single
    /// precision boxes keep their accuracy far from the origin.
    pub(super) centre: DVec3,
    pub(super) pad: f64,
    /// Per BVH node, what its polygons add up to (see [`NodeSummary`]).
    pub(super) summaries: Vec<NodeSummary>,
}

impl std::fmt::Debug for Occluders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Occluders")
            .field("centre", &self.centre)
            .finish()
    }
}

/// A small hash-based random number in [0, 1) from a 64-bit state.
pub(super) fn unit(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

impl Occluders {
    /// A BVH over every patch polygon of `sources`.
    #[must_use]
    pub(crate) fn new(sources: &Sources) -> Self {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in &sources.polygons {
            for v in &p.vertices[..p.count as usize] {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
        }
        let centre = (lo + hi) * 0.5;
        let pad = 4e-6 * (hi - lo).length().max(f64::MIN_POSITIVE);
        let boxes: Vec<Bounds> = sources
            .polygons
            .iter()
            .map(|p| {
                let v = &p.vertices[..p.count as usize];
                let a = v.iter().fold(DVec3::splat(f64::INFINITY), |m, x| m.min(*x));
                let b = v
                    .iter()
                    .fold(DVec3::splat(f64::NEG_INFINITY), |m, x| m.max(*x));
                Bounds(Aabb::new(
                    (a - centre - DVec3::splat(pad)).as_vec3a(),
                    (b - centre + DVec3::splat(pad)).as_vec3a(),
                ))
            })
            .collect();
        let bvh = obvhs::bvh2::builder::build_bvh2(
            &boxes,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let summaries = summarise(&bvh, sources, centre);
        Occluders {
            bvh,
            centre,
            pad,
            summaries,
        }
    }

    /// True when no polygon (other than those on the two skipped surfaces)
    /// crosses the open segment from `a` to `b`.
    pub(crate) fn clear(&self, sources: &Sources, a: DVec3, b: DVec3, skip: [u32; 2]) -> bool {
        let span = b - a;
        let length = span.length();
        if length <= 0.0 {
            return true;
        }
        let dir = span / length;
        let ray = Ray::new(
            (a - self.centre).as_vec3a(),
            dir.as_vec3a(),
            0.0,
            (length + self.pad) as f32,
        );
        self.bvh.ray_traverse_miss(ray, |_, slot| {
            let id = self.bvh.primitive_indices[slot] as usize;
            let p = &sources.polygons[id];
            if skip.contains(&p.surface) {
                return f32::INFINITY;
            }
            if crosses(&p.vertices[..p.count as usize], p.normal, a, dir, length) {
                0.0
            } else {
                f32::INFINITY
            }
        })
    }

    /// True when the emitter polygon `q` faces `eye` and no polygon (other
    /// than on `own_surface`) crosses the ray from `eye` to its centre.
    ///
    /// The ray stops short of the emitter's plane by twice the boxes' padding:
    /// polygons in that plane (a fan's other blades, the rest of a
    /// tessellated lamp) cannot hide it, but their boxes all reach the ray's
    /// end and would each be tested; nothing thinner than the padding fits in
    /// the gap left.
    pub(crate) fn emitter_centre_visible(
        &self,
        sources: &Sources,
        eye: DVec3,
        own_surface: u32,
        q: u32,
    ) -> bool {
        let poly = &sources.polygons[q as usize];
        let corners = poly.corners();
        let centre = corners.iter().copied().sum::<DVec3>() / corners.len() as f64;
        // An emitter shines from its front only.
        let height = poly.normal.dot(eye - centre);
        if height <= 0.0 {
            return false;
        }
        let gap = 2.0 * self.pad;
        let end = if height > 2.0 * gap {
            centre + (eye - centre) * (gap / height)
        } else {
            centre
        };
        self.clear(sources, eye, end, [own_surface, poly.surface])
    }
}

/// True when the segment from `a` along unit `dir`, open at both ends (a
/// relative margin keeps surfaces at the endpoints from counting), crosses the
/// convex planar polygon `v` with unit `normal`.
pub(crate) fn crosses(v: &[DVec3], normal: DVec3, a: DVec3, dir: DVec3, length: f64) -> bool {
    let denom = normal.dot(dir);
    if denom.abs() < 1e-15 {
        return false;
    }
    let t = normal.dot(v[0] - a) / denom;
    let margin = 1e-9 * length;
    if t <= margin || t >= length - margin {
        return false;
    }
    let p = a + dir * t;
    let m = v.len();
    (0..m).all(|i| (v[(i + 1) % m] - v[i]).cross(p - v[i]).dot(normal) >= 0.0)
}
