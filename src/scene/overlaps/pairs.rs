//! Finding the overlapping coplanar pairs, and which of each pair is on top.
//!
//! Surfaces are sorted by rounded normal and plane offset into runs of
//! candidate planes (`O(n log n)`). Within a run, surfaces with exactly the
//! same vertices are grouped by hashing (so that ten thousand coincident
//! copies cost ten thousand hash look-ups, not fifty million pair tests), and
//! the others are paired through a tree of their bounding boxes in the plane;
//! only pairs whose boxes overlap get the exact test.

use super::COPLANAR_GAP;
use crate::scene::{Scene, Surface};
use glam::{DVec2, DVec3};
use std::cmp::Ordering;
use std::collections::HashMap;

/// Which pairs count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scope {
    /// Every pair (resolving).
    All,
    /// Pairs whose materials differ in reflectance or emission (refusing:
    /// pairs that look the same whichever wins are harmless to the solve).
    DifferentMaterials,
}

/// The overlaps of one scene.
#[derive(Debug, Default)]
pub(super) struct Found {
    /// `(below, on_top)` surface indices of overlapping pairs that are not
    /// duplicates.
    pub pairs: Vec<(usize, usize)>,
    /// `(dropped, kept)`: surfaces with exactly the vertices of a surface on
    /// top of them.
    pub duplicates: Vec<(usize, usize)>,
}

impl Found {
    pub(super) fn is_empty(&self) -> bool {
        self.pairs.is_empty() && self.duplicates.is_empty()
    }
}

/// The overlapping pairs of `scene` within `scope`.
pub(super) fn find_overlaps(scene: &Scene, scope: Scope) -> Found {
    let extent = scene.extent();
    let gap = COPLANAR_GAP * extent;
    let touch = 1e-9 * extent;
    let mut found = Found::default();
    for run in coplanar_runs(scene, gap) {
        find_in_run(scene, &run, gap, touch, scope, &mut found);
    }
    found.pairs.sort_unstable();
    found.duplicates.sort_unstable();
    found
}

/// The normal rounded to 1e-3: surfaces facing the same way share it.
fn normal_key(s: &Surface) -> (i64, i64, i64) {
    let q = (s.normal * 1e3).round();
    (q.x as i64, q.y as i64, q.z as i64)
}

fn offset(s: &Surface) -> f64 {
    s.normal.dot(s.vertices[0])
}

/// Runs of surfaces with the same rounded normal whose plane offsets chain
/// within `gap`: the only candidates for overlapping. Runs of one are left out.
fn coplanar_runs(scene: &Scene, gap: f64) -> Vec<Vec<usize>> {
    let surfaces = &scene.surfaces;
    let mut order: Vec<usize> = (0..surfaces.len()).collect();
    order.sort_by(|&a, &b| {
        let (sa, sb) = (&surfaces[a], &surfaces[b]);
        normal_key(sa)
            .cmp(&normal_key(sb))
            .then(offset(sa).total_cmp(&offset(sb)))
    });
    let mut runs = Vec::new();
    let mut start = 0;
    while start < order.len() {
        let first = &surfaces[order[start]];
        let mut end = start + 1;
        while end < order.len() {
            let (prev, next) = (&surfaces[order[end - 1]], &surfaces[order[end]]);
            if normal_key(next) != normal_key(first) || offset(next) - offset(prev) > gap {
                break;
            }
            end += 1;
        }
        if end - start > 1 {
            runs.push(order[start..end].to_vec());
        }
        start = end;
    }
    runs
}

/// A surface of a run, flattened into the run's plane.
struct Flat {
    index: usize,
    points: Vec<DVec2>,
    lo: DVec2,
    hi: DVec2,
}

fn find_in_run(
    scene: &Scene,
    run: &[usize],
    gap: f64,
    touch: f64,
    scope: Scope,
    found: &mut Found,
) {
    let rank = Rank::new(scene, run);
    let kept = deduplicate(scene, run, &rank, scope, found);
    let normal = scene.surfaces[kept.first().copied().unwrap_or(run[0])].normal;
    let u_axis = normal.any_orthonormal_vector();
    let w_axis = normal.cross(u_axis);
    let flat: Vec<Flat> = kept
        .iter()
        .map(|&index| {
            let points: Vec<DVec2> = scene.surfaces[index]
                .vertices
                .iter()
                .map(|p| DVec2::new(p.dot(u_axis), p.dot(w_axis)))
                .collect();
            let lo = points.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
            let hi = points.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
            Flat {
                index,
                points,
                lo,
                hi,
            }
        })
        .collect();
    let boxes: Vec<(DVec2, DVec2)> = flat.iter().map(|f| (f.lo, f.hi)).collect();
    BoxTree::new(&boxes).for_each_overlap(touch, |a, b| {
        let (fa, fb) = (&flat[a], &flat[b]);
        let (sa, sb) = (&scene.surfaces[fa.index], &scene.surfaces[fb.index]);
        if scope == Scope::DifferentMaterials && looks_the_same(scene, sa, sb) {
            return;
        }
        if same_plane(sa, sb, pair_gap(sa, sb, gap)) && overlap(&fa.points, &fb.points, touch) {
            found.pairs.push(rank.below_and_on_top(fa.index, fb.index));
        }
    });
}

/// Groups the run's surfaces with bit-identical vertex sets; in each group the
/// one on top is kept and the others are recorded as duplicates (in the
/// refusing scope, only those whose material differs from the kept one's).
/// Returns the surfaces left to pair.
fn deduplicate(
    scene: &Scene,
    run: &[usize],
    rank: &Rank,
    scope: Scope,
    found: &mut Found,
) -> Vec<usize> {
    let key = |i: usize| {
        let mut k: Vec<[u64; 3]> = scene.surfaces[i]
            .vertices
            .iter()
            // Adding 0.0 turns -0.0 into 0.0.
            .map(|p| {
                [
                    (p.x + 0.0).to_bits(),
                    (p.y + 0.0).to_bits(),
                    (p.z + 0.0).to_bits(),
                ]
            })
            .collect();
        k.sort_unstable();
        k
    };
    let mut groups: HashMap<Vec<[u64; 3]>, Vec<usize>> = HashMap::new();
    for &i in run {
        groups.entry(key(i)).or_default().push(i);
    }
    let mut kept = Vec::with_capacity(groups.len());
    // The run's order, so that results do not depend on the hash order.
    for &i in run {
        let Some(group) = groups.remove(&key(i)) else {
            continue;
        };
        let top = group
            .iter()
            .copied()
            .max_by(|&a, &b| rank.compare(a, b))
            .unwrap_or(i);
        kept.push(top);
        for other in group.into_iter().filter(|&o| o != top) {
            let (so, st) = (&scene.surfaces[other], &scene.surfaces[top]);
            if scope == Scope::All || !looks_the_same(scene, so, st) {
                found.duplicates.push((other, top));
            }
        }
    }
    kept
}

/// Same reflectance and emission: the hemi-cube's choice between the two
/// cannot change what anything receives.
fn looks_the_same(scene: &Scene, a: &Surface, b: &Surface) -> bool {
    let (ma, mb) = (scene.material_of(a), scene.material_of(b));
    ma.reflectance == mb.reflectance && ma.emission == mb.emission
}

/// The order "on top of" within one run (see
/// [`Scene::resolve_overlaps`](crate::scene::Scene::resolve_overlaps)):
/// smaller object area in the plane, then smaller surface, then later.
struct Rank<'a> {
    scene: &'a Scene,
    object_area: HashMap<u32, f64>,
}

impl<'a> Rank<'a> {
    fn new(scene: &'a Scene, run: &[usize]) -> Self {
        let mut object_area: HashMap<u32, f64> = HashMap::new();
        for &i in run {
            let s = &scene.surfaces[i];
            *object_area.entry(s.object).or_default() += s.area;
        }
        Rank { scene, object_area }
    }

    /// `Greater` when surface `a` lies on top of surface `b`.
    fn compare(&self, a: usize, b: usize) -> Ordering {
        let (sa, sb) = (&self.scene.surfaces[a], &self.scene.surfaces[b]);
        let object = |s: &Surface| self.object_area.get(&s.object).copied().unwrap_or(0.0);
        // Smaller is higher: compare b's with a's.
        object(sb)
            .total_cmp(&object(sa))
            .then(sb.area.total_cmp(&sa.area))
            .then(a.cmp(&b))
    }

    fn below_and_on_top(&self, a: usize, b: usize) -> (usize, usize) {
        if self.compare(a, b) == Ordering::Greater {
            (b, a)
        } else {
            (a, b)
        }
    }
}

/// Both face the same way and every vertex of each lies within `gap` of the
/// other's plane.
/// The coplanar gap of two surfaces: [`COPLANAR_GAP`] of their own size (the
/// diagonal of the box of both), at most `gap`, the scene's. A lamp a
/// millimetre under its ceiling is not one plane with it because the scene
/// around them spans a hundred metres: only receivers hundreds of metres
/// away could misorder the two, and to them the lamp is a speck.
fn pair_gap(a: &Surface, b: &Surface, gap: f64) -> f64 {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for v in a.vertices.iter().chain(&b.vertices) {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    (COPLANAR_GAP * (hi - lo).length()).min(gap)
}

fn same_plane(a: &Surface, b: &Surface, gap: f64) -> bool {
    let near = |s: &Surface, t: &Surface| {
        t.vertices
            .iter()
            .all(|p| s.normal.dot(*p - s.vertices[0]).abs() <= gap)
    };
    a.normal.dot(b.normal) > 0.0 && near(a, b) && near(b, a)
}

/// Convex polygons overlapping by more than `touch` (separating axes: the edge
/// normals of both).
pub(super) fn overlap(a: &[DVec2], b: &[DVec2], touch: f64) -> bool {
    let project = |p: &[DVec2], axis: DVec2| {
        p.iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| {
                let x = q.dot(axis);
                (lo.min(x), hi.max(x))
            })
    };
    for poly in [a, b] {
        for i in 0..poly.len() {
            let e = poly[(i + 1) % poly.len()] - poly[i];
            let axis = DVec2::new(-e.y, e.x).normalize_or_zero();
            if axis == DVec2::ZERO {
                continue;
            }
            let (a0, a1) = project(a, axis);
            let (b0, b1) = project(b, axis);
            if a1 <= b0 + touch || b1 <= a0 + touch {
                return false;
            }
        }
    }
    true
}

/// A bounding-volume tree over 2D boxes, split at the median of the longer
/// side: `O(n log n)` to build, and each query visits `O(log n)` nodes plus
/// those holding boxes it overlaps.
struct BoxTree<'a> {
    boxes: &'a [(DVec2, DVec2)],
    order: Vec<usize>,
    nodes: Vec<Node>,
}

struct Node {
    lo: DVec2,
    hi: DVec2,
    /// Leaves: `order[start..end]`; inner nodes: children `left` and `left + 1`.
    start: usize,
    end: usize,
    left: Option<usize>,
}

/// Boxes per leaf.
const LEAF: usize = 8;

impl<'a> BoxTree<'a> {
    fn new(boxes: &'a [(DVec2, DVec2)]) -> Self {
        let mut tree = BoxTree {
            boxes,
            order: (0..boxes.len()).collect(),
            nodes: Vec::new(),
        };
        if !boxes.is_empty() {
            tree.nodes.push(tree.leaf(0, boxes.len()));
            tree.split(0);
        }
        tree
    }

    fn leaf(&self, start: usize, end: usize) -> Node {
        let (lo, hi) = self.order[start..end]
            .iter()
            .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &i| {
                (lo.min(self.boxes[i].0), hi.max(self.boxes[i].1))
            });
        Node {
            lo,
            hi,
            start,
            end,
            left: None,
        }
    }

    /// Splits node `n` and its descendants until leaves hold at most `LEAF`
    /// boxes (iteratively: a degenerate input cannot overflow the stack).
    fn split(&mut self, root: usize) {
        let mut stack = vec![root];
        while let Some(n) = stack.pop() {
            let (start, end) = (self.nodes[n].start, self.nodes[n].end);
            if end - start <= LEAF {
                continue;
            }
            let extent = self.nodes[n].hi - self.nodes[n].lo;
            let axis = usize::from(extent.y > extent.x);
            let centre = |b: &(DVec2, DVec2)| (b.0[axis] + b.1[axis]) * 0.5;
            let mid = (start + end) / 2;
            let boxes = self.boxes;
            self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
                centre(&boxes[a]).total_cmp(&centre(&boxes[b]))
            });
            let left = self.nodes.len();
            let (l, r) = (self.leaf(start, mid), self.leaf(mid, end));
            self.nodes.push(l);
            self.nodes.push(r);
            self.nodes[n].left = Some(left);
            stack.push(left);
            stack.push(left + 1);
        }
    }

    /// Calls `visit(a, b)` once for every pair `a < b` of boxes that overlap
    /// by more than `margin` on both axes.
    fn for_each_overlap(&self, margin: f64, mut visit: impl FnMut(usize, usize)) {
        let apart = |alo: DVec2, ahi: DVec2, blo: DVec2, bhi: DVec2| {
            ahi.x <= blo.x + margin
                || bhi.x <= alo.x + margin
                || ahi.y <= blo.y + margin
                || bhi.y <= alo.y + margin
        };
        let mut stack = Vec::new();
        for (a, &(lo, hi)) in self.boxes.iter().enumerate() {
            if self.nodes.is_empty() {
                return;
            }
            stack.clear();
            stack.push(0);
            while let Some(n) = stack.pop() {
                let node = &self.nodes[n];
                if apart(lo, hi, node.lo, node.hi) {
                    continue;
                }
                match node.left {
                    Some(l) => {
                        stack.push(l);
                        stack.push(l + 1);
                    }
                    None => {
                        for &b in &self.order[node.start..node.end] {
                            let (blo, bhi) = self.boxes[b];
                            if b > a && !apart(lo, hi, blo, bhi) {
                                visit(a, b);
                            }
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_tree_finds_the_same_pairs_as_all_pairs() {
        // A deterministic scatter of boxes of mixed sizes, some touching.
        let mut boxes = Vec::new();
        let mut x: u64 = 7;
        let mut next = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..300 {
            let lo = DVec2::new(next() * 10.0, next() * 10.0);
            let size = DVec2::new(next(), next()) * if next() < 0.1 { 4.0 } else { 0.5 };
            boxes.push((lo, lo + size));
        }
        boxes.push((DVec2::new(0.0, 0.0), DVec2::new(1.0, 1.0)));
        boxes.push((DVec2::new(1.0, 0.0), DVec2::new(2.0, 1.0))); // touches the last
        let mut tree_pairs = Vec::new();
        BoxTree::new(&boxes).for_each_overlap(1e-12, |a, b| tree_pairs.push((a, b)));
        tree_pairs.sort_unstable();
        let mut all = Vec::new();
        for a in 0..boxes.len() {
            for b in a + 1..boxes.len() {
                let ((alo, ahi), (blo, bhi)) = (boxes[a], boxes[b]);
                let m = 1e-12;
                if !(ahi.x <= blo.x + m
                    || bhi.x <= alo.x + m
                    || ahi.y <= blo.y + m
                    || bhi.y <= alo.y + m)
                {
                    all.push((a, b));
                }
            }
        }
        assert!(all.len() > 100, "the test needs overlaps: {}", all.len());
        assert_eq!(tree_pairs, all);
    }
}
