//! Cutting the footprint of the surfaces on top out of the surface below.
//!
//! The difference of two convex polygons is a union of convex pieces: for
//! each edge of the cutter in turn, the part of what is left that lies outside
//! that edge is one piece, and what lies inside goes on to the next edge.
//! The clipping planes stand on the lower surface, through the cutter's edges,
//! so every piece lies exactly in the lower surface's own plane. Pieces become
//! triangles and convex quads (what [`Surface`] takes) by a fan.

use super::pairs::Found;
use super::COPLANAR_GAP;
use crate::math::{clip_to_halfspace, polygon_area};
use crate::scene::{Scene, Surface};
use glam::DVec3;
use smallvec::SmallVec;
use std::collections::{HashMap, HashSet};

type Polygon = SmallVec<[DVec3; 8]>;

/// What cutting did.
#[derive(Debug, Default)]
pub(super) struct Outcome {
    /// Pieces thinner than the coplanar gap, dropped.
    pub slivers: usize,
}

/// Replaces every surface below another by its pieces outside the ones on
/// top, and drops the duplicates, keeping the scene's order otherwise.
pub(super) fn apply(scene: &mut Scene, found: &Found) -> Outcome {
    let thin = COPLANAR_GAP * scene.extent();
    let dropped: HashSet<usize> = found.duplicates.iter().map(|&(d, _)| d).collect();
    let mut cutters: HashMap<usize, Vec<usize>> = HashMap::new();
    for &(below, on_top) in &found.pairs {
        cutters.entry(below).or_default().push(on_top);
    }
    let mut outcome = Outcome::default();
    let old = std::mem::take(&mut scene.surfaces);
    let mut surfaces = Vec::with_capacity(old.len());
    for (i, s) in old.iter().enumerate() {
        if dropped.contains(&i) {
            continue;
        }
        match cutters.get(&i) {
            None => surfaces.push(s.clone()),
            Some(on_top) => {
                let uppers: Vec<&Surface> = on_top.iter().map(|&k| &old[k]).collect();
                surfaces.extend(cut_away(s, &uppers, thin, &mut outcome));
            }
        }
    }
    scene.surfaces = surfaces;
    outcome
}

/// The pieces of `lower` outside every one of `uppers`, as surfaces of its
/// material and object.
///
/// Each piece is cut only by the cutters that reach it. Cutting every
/// piece by every cutter in turn (a piece far from a cutter still split
/// along the lines of its edges) made the pieces grow with the cutters and
/// cost their product: 4 000 decals on one floor took 15 s. Here a piece
/// is cut by the first of its cutters, and each resulting piece goes on with
/// those of the later cutters whose bounds meet its own; a piece no later
/// cutter reaches is done. The pieces are taken depth first, so their order
/// follows the cutters' order as before.
fn cut_away(
    lower: &Surface,
    uppers: &[&Surface],
    thin: f64,
    outcome: &mut Outcome,
) -> Vec<Surface> {
    let normal = lower.normal;
    let bounds: Vec<Bounds> = uppers.iter().map(|u| Bounds::of(&u.vertices)).collect();
    let whole: Polygon = lower.vertices.iter().copied().collect();
    let reach = |piece: &Polygon, cutters: &[usize]| -> Vec<usize> {
        let b = Bounds::of(piece);
        cutters
            .iter()
            .copied()
            .filter(|&k| bounds[k].meets(&b, thin))
            .collect()
    };
    let all: Vec<usize> = (0..uppers.len()).collect();
    let mut stack = vec![(reach(&whole, &all), whole)];
    let mut pieces: Vec<Polygon> = Vec::new();
    while let Some((cutters, piece)) = stack.pop() {
        let Some((&first, later)) = cutters.split_first() else {
            pieces.push(piece);
            continue;
        };
        // Slivers go at once: clipping along a cutter's edge leaves pieces
        // of no area, and kept, later cutters would cut each of them again
        // (41 stacked layers ran out of memory).
        let parts: Vec<Polygon> = difference(&piece, &uppers[first].vertices, normal)
            .iter()
            .filter_map(|p| kept_piece(p, normal, thin, outcome))
            .collect();
        for part in parts.into_iter().rev() {
            stack.push((reach(&part, later), part));
        }
    }
    let mut out = Vec::new();
    for piece in pieces {
        fan(&piece, lower, &mut out, outcome);
    }
    out
}

/// An axis-aligned box around a polygon.
struct Bounds {
    lo: DVec3,
    hi: DVec3,
}

impl Bounds {
    fn of(points: &[DVec3]) -> Bounds {
        Bounds {
            lo: points.iter().fold(DVec3::INFINITY, |a, p| a.min(*p)),
            hi: points.iter().fold(DVec3::NEG_INFINITY, |a, p| a.max(*p)),
        }
    }

    /// Whether the boxes meet, or come within `gap` of each other.
    fn meets(&self, other: &Bounds, gap: f64) -> bool {
        (self.lo - gap).cmple(other.hi).all() && (other.lo - gap).cmple(self.hi).all()
    }
}

/// `piece` without needless vertices, or `None` (counted as a sliver if it
/// had any area) when it is thinner than `thin`.
fn kept_piece(piece: &Polygon, normal: DVec3, thin: f64, outcome: &mut Outcome) -> Option<Polygon> {
    let piece = without_needless_vertices(piece, normal);
    if piece.len() < 3 {
        return None;
    }
    let area = polygon_area(&piece);
    if area <= thin * longest_span(&piece) {
        if area > 0.0 {
            outcome.slivers += 1;
        }
        return None;
    }
    Some(piece)
}

/// The convex pieces of convex polygon `p` outside convex polygon `cutter`
/// (counter-clockwise around `normal`). Pieces may be degenerate; the caller
/// drops those.
fn difference(p: &Polygon, cutter: &[DVec3], normal: DVec3) -> Vec<Polygon> {
    let mut rest = p.clone();
    let mut out = Vec::new();
    let m = cutter.len();
    for k in 0..m {
        let (a, b) = (cutter[k], cutter[(k + 1) % m]);
        // The cutter's inside is to the left of each edge, seen from the front.
        let inward = normal.cross(b - a);
        let outside = clip_to_halfspace(&rest, a, -inward);
        if outside.len() >= 3 {
            out.push(outside);
        }
        rest = clip_to_halfspace(&rest, a, inward);
        if rest.len() < 3 {
            break;
        }
    }
    out
}

/// Drops repeated vertices and vertices on the line through their
/// neighbours (clipping leaves both), which a quad may not have.
fn without_needless_vertices(p: &Polygon, normal: DVec3) -> Polygon {
    let mut v: Polygon = p.clone();
    let size = longest_span(p);
    loop {
        let m = v.len();
        if m < 3 {
            return v;
        }
        let needless = (0..m).find(|&i| {
            let (a, b, c) = (v[(i + m - 1) % m], v[i], v[(i + 1) % m]);
            let turn = (b - a).cross(c - b).dot(normal);
            (b - a).length() <= 1e-12 * size || turn <= 1e-9 * (b - a).length() * (c - b).length()
        });
        match needless {
            Some(i) => {
                v.remove(i);
            }
            None => return v,
        }
    }
}

fn longest_span(p: &[DVec3]) -> f64 {
    p.iter()
        .flat_map(|a| p.iter().map(move |b| (*a - *b).length()))
        .fold(0.0, f64::max)
}

/// A convex polygon as a fan of quads from its first vertex, and a triangle
/// for an odd remainder; a quad the surface check refuses becomes two
/// triangles.
fn fan(p: &Polygon, like: &Surface, out: &mut Vec<Surface>, outcome: &mut Outcome) {
    let mut push = |vertices: &[DVec3]| match Surface::new(vertices, like.material, like.object) {
        Ok(s) => {
            out.push(s);
            true
        }
        Err(_) => false,
    };
    let n = p.len();
    let mut i = 1;
    while i + 1 < n {
        if i + 2 < n {
            let quad = [p[0], p[i], p[i + 1], p[i + 2]];
            if !push(&quad) {
                for tri in [[p[0], p[i], p[i + 1]], [p[0], p[i + 1], p[i + 2]]] {
                    if !push(&tri) {
                        outcome.slivers += 1;
                    }
                }
            }
            i += 2;
        } else {
            if !push(&[p[0], p[i], p[i + 1]]) {
                outcome.slivers += 1;
            }
            i += 1;
        }
    }
}
