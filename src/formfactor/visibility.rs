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

use super::bvh_walk::walk;
use super::shaft::{pieces_form_factor, sliver_area, subtract, Piece, Shaft, MAX_OCCLUDERS};
use super::{point_to_polygon, Sources};
use glam::DVec3;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::ray::Ray;
use obvhs::{Boundable, BvhBuildParams};
use smallvec::SmallVec;
use std::time::Duration;

/// Rays along each side of the stratified grid that decides the visible
/// fraction of an emitter the item buffer saw in part (or that a first small
/// set of rays could not settle). A straight shadow edge crosses about this
/// many strata, so the fraction's standard error is about `0.5 sqrt(n) / n^2`
/// (0.8% at 16, 0.3% at 32), per element, and averages out over a surface.
const PARTIAL_RAYS: usize = 16;

struct Bounds(Aabb);

impl Boundable for Bounds {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// What the item buffer saw of an emitter patch, which sets how far the rays
/// must go before their answer is trusted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PixelHint {
    /// Every pixel it covered it won. An occluder may still hide less than a
    /// pixel row of it, so 4 x 4 rays check; any blocked ray means a full count.
    Whole,
    /// It covered pixels but won none: 8 x 8 rays, trusted if all are blocked.
    Hidden,
    /// It won some of its pixels: 16 x 16 rays.
    Partial,
    /// Too small to cover a pixel centre: 8 x 8 rays, trusted if they agree.
    Unseen,
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

/// Past this many surfaces casting a shadow on the first point of a
/// receiving element, [`Occluders::mean_visible_form_factor`] asked to keep
/// to few casters (shadowed sampling) stops and leaves the light to the
/// element's centre (see [`PointsMean::Crowded`]). Each point clips every
/// shadow of its own, so a shaft crowded by a tessellated mesh's facets costs
/// four times the centre's clipping for an edge no sharper than the facets'
/// staircase; the sharp edges that a centre misses (a box's side across a
/// dim element) come from a few large planar surfaces, however many patches
/// they are split into.
pub(crate) const FEW_CASTERS: usize = 4;

/// What [`Occluders::mean_visible_form_factor`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PointsMean {
    /// The points' mean visible form factor, and whether anything hides
    /// part of the light from any point (or a point sees none of its front).
    Visible {
        /// The mean.
        mean: f64,
        /// Whether the light's visibility changes across the points.
        shadowed: bool,
    },
    /// Asked to keep to few casters, more than [`FEW_CASTERS`] surfaces
    /// shadow the first point: the centre must decide.
    Crowded,
    /// Clipping cannot decide (too many shadows or pieces, or geometry too
    /// thin to project): the rays must.
    Undecided,
}

impl PointsMean {
    /// The mean found, if one was.
    pub(crate) fn found(self) -> Option<f64> {
        match self {
            PointsMean::Visible { mean, .. } => Some(mean),
            PointsMean::Crowded | PointsMean::Undecided => None,
        }
    }
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

/// How many of the patches under a BVH node its summary keeps.
pub(crate) const NODE_PATCHES: usize = 8;

/// [`NodePatch::surface`] of a part on several surfaces.
pub(crate) const MIXED: u32 = u32::MAX;

/// One of the patches under a BVH node: what a sample needs of its part
/// there without reading the polygons (which lie scattered in memory, and
/// reading them was most of a sample's time on the million-triangle atrium).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct NodePatch {
    /// The patch.
    pub(crate) patch: u32,
    /// The surface its polygons there lie on, or [`MIXED`] when they lie on
    /// several (a face cluster's facets). A receiver is never under a
    /// sample (it lies within a pixel of its own eye), so only a large
    /// planar surface, whose polygons are one surface's, can come back to
    /// its own receivers through a sample.
    pub(crate) surface: u32,
    /// The patch's area under the node, as far as the children's lists know.
    pub(crate) area: f32,
    /// The sum of its polygons' areas times their unit normals there: which
    /// way the part faces, and its projected area in any direction it faces.
    pub(crate) vector_area: [f32; 3],
    /// The area-weighted mean of its polygons' vertex means there (their
    /// centroids, but for quads that are not parallelograms), relative to
    /// the occluders' centre.
    pub(crate) centroid: [f32; 3],
}

impl NodePatch {
    /// The part's vector area.
    pub(crate) fn vector_area(&self) -> DVec3 {
        DVec3::from(self.vector_area.map(f64::from))
    }

    /// The part's centroid in the scene, for occluders centred at `centre`.
    pub(crate) fn centroid(&self, centre: DVec3) -> DVec3 {
        DVec3::from(self.centroid.map(f64::from)) + centre
    }

    /// Adds `other`, a part of the same patch.
    fn absorb(&mut self, other: &NodePatch) {
        let (a, b) = (f64::from(self.area), f64::from(other.area));
        let total = a + b;
        if total > 0.0 {
            for axis in 0..3 {
                let (p, q) = (
                    f64::from(self.centroid[axis]),
                    f64::from(other.centroid[axis]),
                );
                self.centroid[axis] = ((p * a + q * b) / total) as f32;
            }
        }
        for axis in 0..3 {
            self.vector_area[axis] += other.vector_area[axis];
        }
        self.area = total as f32;
        if self.surface != other.surface {
            self.surface = MIXED;
        }
    }
}

/// What the polygons under one BVH node add up to, for drawing the node as a
/// single sample (see `hemicube/cull.rs`).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct NodeSummary {
    /// The patches with the most area under the node, largest first (of each
    /// child's list, what the two lists hold); `len` of them are set.
    pub(crate) patches: [NodePatch; NODE_PATCHES],
    /// How many of `patches` are set.
    pub(crate) len: u8,
    /// The area of all the polygons under the node.
    pub(crate) area: f32,
    /// Polygons under the node.
    pub(crate) polygons: u32,
}

impl NodeSummary {
    /// The patches kept, largest first.
    pub(crate) fn patches(&self) -> &[NodePatch] {
        &self.patches[..self.len as usize]
    }

    /// Keeps the [`NODE_PATCHES`] largest of `list`, adding up the parts of
    /// one patch; ties go to the lower patch index, so the choice does not
    /// depend on the order of the list.
    fn keep_largest(&mut self, list: &mut SmallVec<[NodePatch; 16]>) {
        list.sort_unstable_by_key(|e| e.patch);
        list.dedup_by(|b, a| {
            let same = a.patch == b.patch;
            if same {
                a.absorb(b);
            }
            same
        });
        list.sort_by(|a, b| b.area.total_cmp(&a.area).then(a.patch.cmp(&b.patch)));
        let len = list.len().min(NODE_PATCHES);
        self.patches[..len].copy_from_slice(&list[..len]);
        self.len = len as u8;
    }
}

impl std::fmt::Debug for Occluders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Occluders")
            .field("centre", &self.centre)
            .finish()
    }
}

/// The summary of every node of `bvh` over the polygons of `sources`,
/// children before parents, with positions relative to `centre`.
fn summarise(bvh: &Bvh2, sources: &Sources, centre: DVec3) -> Vec<NodeSummary> {
    let mut out = vec![NodeSummary::default(); bvh.nodes.len()];
    if bvh.nodes.is_empty() {
        return out;
    }
    let mut list: SmallVec<[NodePatch; 16]> = SmallVec::new();
    // Post order: a node is summed once both children are.
    let mut stack: Vec<(u32, bool)> = vec![(0, false)];
    while let Some((index, children_done)) = stack.pop() {
        let node = &bvh.nodes[index as usize];
        list.clear();
        let mut s = NodeSummary::default();
        if node.is_leaf() {
            let first = node.first_index as usize;
            for &prim in &bvh.primitive_indices[first..first + node.prim_count as usize] {
                let p = &sources.polygons[prim as usize];
                let area = crate::math::polygon_area(p.corners());
                s.polygons += 1;
                s.area += area as f32;
                let relative = p.centre - centre;
                list.push(NodePatch {
                    patch: p.patch,
                    surface: p.surface,
                    area: area as f32,
                    vector_area: (p.normal * area).as_vec3().to_array(),
                    centroid: relative.as_vec3().to_array(),
                });
            }
        } else if children_done {
            for child in [node.first_index, node.first_index + 1] {
                let c = &out[child as usize];
                s.polygons += c.polygons;
                s.area += c.area;
                list.extend_from_slice(c.patches());
            }
        } else {
            stack.push((index, true));
            stack.push((node.first_index, false));
            stack.push((node.first_index + 1, false));
            continue;
        }
        s.keep_largest(&mut list);
        out[index as usize] = s;
    }
    out
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

/// The point of a polygon at parameters (s, t) in the unit square: bilinear for
/// a quad, the square folded onto the triangle for a triangle.
fn point_on(v: &[DVec3], s: f64, t: f64) -> DVec3 {
    if v.len() == 4 {
        v[0].lerp(v[1], s).lerp(v[3].lerp(v[2], s), t)
    } else {
        let (s, t) = if s + t > 1.0 {
            (1.0 - s, 1.0 - t)
        } else {
            (s, t)
        };
        v[0] + (v[1] - v[0]) * s + (v[2] - v[0]) * t
    }
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

    /// The mean over `samples` (points of the receiving element, with weights
    /// summing to 1) of the visible form factor to patch `target`, each computed
    /// exactly by clipping; [`PointsMean::Undecided`] if any point needs the
    /// rays instead.
    ///
    /// The BVH is walked once for all the points: a node is entered when any
    /// point's shaft may hold something in it; the first point clips what
    /// its shaft holds there and then, and each other point later clips the
    /// polygons its own shaft may hold. Each point gets the same shadows
    /// in the same order as a walk of its own would give it (a polygon in a
    /// node its shaft misses clips to nothing), so the result is the same as
    /// point by point, for one walk instead of one per point.
    ///
    /// With `few_casters`, more than [`FEW_CASTERS`] surfaces shadowing
    /// the first point end the walk with [`PointsMean::Crowded`].
    #[must_use]
    pub(crate) fn mean_visible_form_factor(
        &self,
        sources: &Sources,
        samples: &[(DVec3, f64)],
        normal: DVec3,
        own_surface: u32,
        target: u32,
        few_casters: bool,
    ) -> PointsMean {
        let poly = &sources.polygons[target as usize];
        let light = &poly.vertices[..poly.count as usize];
        let mut points: SmallVec<[PointShaft<'_>; 4]> = SmallVec::new();
        for &(eye, weight) in samples {
            let full = point_to_polygon(eye, normal, light);
            // An emitter shines from its front only.
            if full <= 0.0 || poly.normal.dot(eye - light[0]) <= 0.0 {
                continue;
            }
            let Some(shaft) = Shaft::new(eye, normal, light, poly.normal) else {
                return PointsMean::Undecided;
            };
            points.push(PointShaft {
                weight,
                full,
                shaft,
            });
        }
        if points.is_empty() {
            // The centre may see the light's front; no point does.
            return PointsMean::Visible {
                mean: 0.0,
                shadowed: true,
            };
        }
        // Shadowed sampling counts the surfaces casting the first point's
        // shadows: a box face split into patches casts one straight edge.
        let crowd_limit = few_casters.then_some(FEW_CASTERS);
        let mut casters: SmallVec<[u32; 8]> = SmallVec::new();
        let mut crowded = false;
        // A point that does not see the light's front at all is as good as
        // a shadow: the light's visibility changes across the element.
        let mut shadowed = points.len() < samples.len();
        // The first point clips what it holds as the walk meets it, so that
        // a shaft holding too many shadows ends the walk early, as it does
        // for the centre alone; the polygons the other points may hold are
        // kept for them. Both in the BVH's order, which is fixed by its
        // build, so that each point's pieces (and the sum over them) come
        // out the same on every run.
        let (first, others) = points.split_first().expect("points is not empty");
        let mut first_shadows: SmallVec<[Piece; 4]> = SmallVec::new();
        let mut held: SmallVec<[u32; 32]> = SmallVec::new();
        let mut overflow = false;
        // Only the nodes some shaft's planes do not cut away: a shaft's
        // bounding box holds many polygons its thin pyramid misses.
        walk(
            &self.bvh,
            self.centre,
            |lo, hi| points.iter().any(|p| !p.shaft.misses_box(lo, hi)),
            |id| {
                let p = &sources.polygons[id];
                if p.surface == own_surface || p.surface == poly.surface {
                    return true;
                }
                if !first.shaft.misses(p.centre, p.radius) {
                    if let Some(shadow) = first.shaft.shadow_of(p.corners()) {
                        first_shadows.push(shadow);
                        if first_shadows.len() > MAX_OCCLUDERS {
                            overflow = true;
                            return false;
                        }
                        if let Some(limit) = crowd_limit {
                            if !casters.contains(&p.surface) {
                                casters.push(p.surface);
                                if casters.len() > limit {
                                    crowded = true;
                                    return false;
                                }
                            }
                        }
                    }
                }
                if others.iter().any(|s| !s.shaft.misses(p.centre, p.radius)) {
                    held.push(id as u32);
                }
                true
            },
        );
        if crowded {
            return PointsMean::Crowded;
        }
        if overflow {
            return PointsMean::Undecided;
        }
        let sum = (|| {
            let mut sum =
                first.weight * first.visible_past(&first_shadows, light, normal, poly.normal)?;
            shadowed |= !first_shadows.is_empty();
            for point in others {
                let shadows = point.shadows(sources, &held)?;
                sum += point.weight * point.visible_past(&shadows, light, normal, poly.normal)?;
                shadowed |= !shadows.is_empty();
            }
            Some(sum)
        })();
        match sum {
            None => PointsMean::Undecided,
            Some(mean) => PointsMean::Visible { mean, shadowed },
        }
    }

    /// The fraction of the form factor from (`eye`, `normal`) to patch `target`
    /// that is not blocked, estimated with shadow rays (`seed`, `hint`): the
    /// fallback of [`Self::mean_visible_form_factor`] and what
    /// [`super::EmitterSampling::Rays`] uses. Stratified jittered rays are
    /// weighted by the point-to-point kernel. A first, small set of rays is
    /// trusted only when its rays agree with each other and with what the item
    /// buffer saw (`hint`); otherwise [`PARTIAL_RAYS`] squared decide, since a thin visible
    /// or hidden sliver can slip between the first samples.
    #[must_use]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn visible_fraction(
        &self,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        own_surface: u32,
        target: u32,
        seed: u64,
        hint: PixelHint,
    ) -> f64 {
        let poly = &sources.polygons[target as usize];
        let v = &poly.vertices[..poly.count as usize];
        let skip = [own_surface, poly.surface];
        let mut state = seed ^ (u64::from(target) << 32);
        let sample = |n: usize, state: &mut u64| {
            let (mut seen, mut total) = (0.0, 0.0);
            let mut all_same = true;
            let mut first: Option<bool> = None;
            for i in 0..n {
                for j in 0..n {
                    let s = (i as f64 + unit(state)) / n as f64;
                    let t = (j as f64 + unit(state)) / n as f64;
                    let x = point_on(v, s, t);
                    let d = x - eye;
                    let r2 = d.length_squared();
                    let w = (normal.dot(d) * -poly.normal.dot(d)).max(0.0) / (r2 * r2);
                    if w <= 0.0 {
                        continue;
                    }
                    let open = self.clear(sources, eye, x, skip);
                    all_same &= first.is_none_or(|f| f == open);
                    first.get_or_insert(open);
                    total += w;
                    if open {
                        seen += w;
                    }
                }
            }
            (seen, total, all_same)
        };
        let first = match hint {
            PixelHint::Whole => 4,
            PixelHint::Hidden | PixelHint::Unseen => 8,
            PixelHint::Partial => 0,
        };
        if first > 0 {
            let (seen, total, all_same) = sample(first, &mut state);
            if total <= 0.0 {
                return 0.0;
            }
            let all_open = all_same && seen > 0.0;
            let all_blocked = all_same && seen == 0.0;
            let trusted = match hint {
                PixelHint::Whole => all_open,
                PixelHint::Hidden => all_blocked,
                PixelHint::Unseen => all_same,
                PixelHint::Partial => false,
            };
            if trusted {
                return seen / total;
            }
        }
        let (seen, total, _) = sample(PARTIAL_RAYS, &mut state);
        if total > 0.0 {
            seen / total
        } else {
            0.0
        }
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

/// One point of a receiving element with its weight and its shaft to a
/// light (see [`Occluders::mean_visible_form_factor`]).
struct PointShaft<'a> {
    weight: f64,
    /// The unoccluded form factor from the point to the light.
    full: f64,
    shaft: Shaft<'a>,
}

impl PointShaft<'_> {
    /// The shadows on the light of the polygons `held` (in the BVH's order)
    /// that the shaft holds; `None` when there are more than
    /// [`MAX_OCCLUDERS`] (the rays decide then).
    fn shadows(&self, sources: &Sources, held: &[u32]) -> Option<SmallVec<[Piece; 4]>> {
        let mut shadows = SmallVec::new();
        for &id in held {
            let p = &sources.polygons[id as usize];
            if self.shaft.misses(p.centre, p.radius) {
                continue;
            }
            if let Some(shadow) = self.shaft.shadow_of(p.corners()) {
                shadows.push(shadow);
                if shadows.len() > MAX_OCCLUDERS {
                    return None;
                }
            }
        }
        Some(shadows)
    }

    /// The form factor from the point to the part of `light` that
    /// `shadows` leave, by cutting them out of it; `None` when the geometry
    /// is degenerate for projection (the rays decide then).
    fn visible_past(
        &self,
        shadows: &[Piece],
        light: &[DVec3],
        normal: DVec3,
        light_normal: DVec3,
    ) -> Option<f64> {
        if shadows.is_empty() {
            return Some(self.full);
        }
        let mut pieces = vec![Piece::from_slice(light)];
        let min_area = sliver_area(light);
        for shadow in shadows {
            if !subtract(&mut pieces, shadow, light_normal, min_area) {
                return None;
            }
            if pieces.is_empty() {
                return Some(0.0);
            }
        }
        // What is left of the light can be no more than all of it.
        Some(pieces_form_factor(self.shaft.eye(), normal, &pieces).clamp(0.0, self.full))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::SourcePolygon;

    /// A square of half-width `half` centred at `centre` in a plane of
    /// constant z, facing `normal` (+Z or -Z).
    fn square(centre: DVec3, half: f64, normal: DVec3, surface: u32) -> SourcePolygon {
        let (t1, t2) = normal.any_orthonormal_pair();
        let corners = [
            centre - t1 * half - t2 * half,
            centre + t1 * half - t2 * half,
            centre + t1 * half + t2 * half,
            centre - t1 * half + t2 * half,
        ];
        SourcePolygon::new(&corners, normal, surface)
    }

    /// A floor (surface 0, polygon 0) under a light facing down at z = 2
    /// (surface 1, polygon 1).
    fn floor_and_light() -> Vec<SourcePolygon> {
        vec![
            square(DVec3::ZERO, 4.0, DVec3::Z, 0),
            square(DVec3::new(0.0, 0.0, 2.0), 0.5, DVec3::NEG_Z, 1),
        ]
    }

    /// A floor (surface 0) under a light facing down at z = 2 (surface 1,
    /// polygon 1), with small screens scattered at z = 1 (facing either
    /// way) that hide parts of the light from parts of the floor.
    fn lit_floor() -> Sources {
        let mut polygons = floor_and_light();
        for i in 0..12u32 {
            let a = f64::from(i) * 0.9;
            let centre = DVec3::new(0.6 * a.cos(), 0.6 * a.sin(), 1.0 + 0.02 * f64::from(i));
            let normal = if i % 2 == 0 { DVec3::Z } else { DVec3::NEG_Z };
            polygons.push(square(centre, 0.08, normal, 2 + i));
        }
        Sources::one_per_patch(polygons)
    }

    /// Four points of a square element of half-width `half` at `(x, y)` on
    /// the floor, with equal weights.
    fn element(x: f64, y: f64, half: f64) -> [(DVec3, f64); 4] {
        let lift = 1e-7;
        let g = half / 3f64.sqrt();
        [(-g, -g), (g, -g), (-g, g), (g, g)]
            .map(|(dx, dy)| (DVec3::new(x + dx, y + dy, lift), 0.25))
    }

    #[test]
    fn one_walk_gives_each_point_what_a_walk_of_its_own_gives() {
        let sources = lit_floor();
        let occluders = Occluders::new(&sources);
        let mut shadowed = 0;
        for i in 0..40 {
            let (x, y) = (-1.5 + 0.075 * f64::from(i), 0.4 - 0.02 * f64::from(i));
            let points = element(x, y, 0.1);
            let together = occluders
                .mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, false)
                .found();
            let mut alone = Some(0.0);
            for &(p, w) in &points {
                let one = occluders
                    .mean_visible_form_factor(&sources, &[(p, 1.0)], DVec3::Z, 0, 1, false)
                    .found();
                alone = alone.zip(one).map(|(sum, f)| sum + w * f);
            }
            assert_eq!(
                together.map(f64::to_bits),
                alone.map(f64::to_bits),
                "at ({x}, {y}): {together:?} against {alone:?}"
            );
            let unoccluded: f64 = points
                .iter()
                .map(|&(p, w)| w * point_to_polygon(p, DVec3::Z, sources.polygons[1].corners()))
                .sum();
            if together.is_some_and(|f| f < unoccluded * (1.0 - 1e-9)) {
                shadowed += 1;
            }
        }
        // The screens hide part of the light from some of the elements.
        assert!(shadowed >= 5, "{shadowed} of 40 elements in shadow");
    }

    #[test]
    fn an_element_is_shadowed_exactly_where_something_hides_the_light() {
        let sources = lit_floor();
        let occluders = Occluders::new(&sources);
        let (mut shadowed, mut clear_ones) = (0, 0);
        for i in 0..40 {
            let (x, y) = (-1.5 + 0.075 * f64::from(i), 0.4 - 0.02 * f64::from(i));
            let points = element(x, y, 0.1);
            let unoccluded: f64 = points
                .iter()
                .map(|&(p, w)| w * point_to_polygon(p, DVec3::Z, sources.polygons[1].corners()))
                .sum();
            // Few screens lie in any one shaft here (the crowded case is
            // the next test's): with or without the limit, the same.
            let found = occluders.mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, true);
            assert_eq!(
                found,
                occluders.mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, false)
            );
            let PointsMean::Visible {
                mean,
                shadowed: hidden,
            } = found
            else {
                panic!("{found:?} at ({x}, {y})");
            };
            if hidden {
                assert!(mean < unoccluded * (1.0 - 1e-12), "shadowed at ({x}, {y})");
                shadowed += 1;
            } else {
                assert_eq!(mean.to_bits(), unoccluded.to_bits(), "clear at ({x}, {y})");
                clear_ones += 1;
            }
        }
        assert!(shadowed > 0 && clear_ones > 0, "{shadowed} {clear_ones}");
    }

    /// The floor and light of [`lit_floor`] with `n` small screens just
    /// under the middle of the light, each on its own surface: every floor
    /// point near the middle sees all of them against the light.
    fn chips(n: u32) -> Sources {
        let mut polygons = floor_and_light();
        for i in 0..n {
            let a = f64::from(i) * std::f64::consts::TAU / f64::from(n);
            let centre = DVec3::new(0.1 * a.cos(), 0.1 * a.sin(), 1.8 + 0.01 * f64::from(i));
            polygons.push(square(centre, 0.02, DVec3::NEG_Z, 2 + i));
        }
        Sources::one_per_patch(polygons)
    }

    /// The occluders of `sources`, the points of an element near the
    /// middle of the floor and their mean visible form factor to the light,
    /// with no limit on the casters.
    fn beside_the_middle(sources: &Sources) -> (Occluders, [(DVec3, f64); 4], f64) {
        let occluders = Occluders::new(sources);
        let points = element(0.05, -0.02, 0.1);
        let mean = occluders
            .mean_visible_form_factor(sources, &points, DVec3::Z, 0, 1, false)
            .found()
            .unwrap();
        (occluders, points, mean)
    }

    #[test]
    fn more_than_a_few_casters_leave_the_element_to_its_centre() {
        for n in [FEW_CASTERS as u32, FEW_CASTERS as u32 + 1] {
            let sources = chips(n);
            let (occluders, points, mean) = beside_the_middle(&sources);
            let unoccluded: f64 = points
                .iter()
                .map(|&(p, w)| w * point_to_polygon(p, DVec3::Z, sources.polygons[1].corners()))
                .sum();
            assert!(mean < unoccluded * (1.0 - 1e-3), "{n}: {mean} {unoccluded}");
            let few = occluders.mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, true);
            if n as usize > FEW_CASTERS {
                assert_eq!(few, PointsMean::Crowded, "{n} chips");
            } else {
                let shadowed = true;
                assert_eq!(few, PointsMean::Visible { mean, shadowed }, "{n} chips");
            }
        }
    }

    #[test]
    fn one_surface_in_many_polygons_is_one_caster() {
        // A screen cut into a 3 x 3 grid of polygons on one surface.
        let mut polygons = floor_and_light();
        for i in 0..3 {
            for j in 0..3 {
                let centre =
                    DVec3::new(0.04 * f64::from(i) - 0.04, 0.04 * f64::from(j) - 0.04, 1.8);
                polygons.push(square(centre, 0.02, DVec3::NEG_Z, 2));
            }
        }
        let sources = Sources::one_per_patch(polygons);
        let (occluders, points, mean) = beside_the_middle(&sources);
        let shadowed = true;
        assert_eq!(
            occluders.mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, true),
            PointsMean::Visible { mean, shadowed }
        );
    }
}
