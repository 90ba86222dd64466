//! Merging pairs of triangles back into quads.
//!
//! Exporters triangulate quads; radiosity meshes quads better (fewer, better shaped
//! patches), so two triangles of one primitive are merged when they share an edge
//! (the same two vertex keys, traversed in opposite directions, which means the same
//! winding), their normals agree within [`NORMAL_TOLERANCE`], and their union is a
//! planar, strictly convex quad. Matching is greedy in triangle order, so the result
//! is deterministic.

use crate::scene::Surface;
use glam::DVec3;
use smallvec::SmallVec;
use std::collections::HashMap;

/// Largest sine of the angle between the normals of two triangles that merge.
pub(super) const NORMAL_TOLERANCE: f64 = 1e-6;

/// A triangle of one primitive: vertex keys (equal keys mean a shared vertex) and
/// world positions, counter-clockwise around the front.
#[derive(Clone, Debug)]
pub(super) struct Triangle {
    /// Vertex identities.
    pub keys: [u32; 3],
    /// World positions.
    pub points: [DVec3; 3],
}

/// A triangle or quad.
pub(super) type Polygon = SmallVec<[DVec3; 4]>;

/// The polygons of one primitive (quads where pairs merge, else triangles, in
/// the order of their first triangle) and the number of merges.
pub(super) fn merge_into_quads(tris: &[Triangle]) -> (Vec<Polygon>, usize) {
    let normals: Vec<DVec3> = tris
        .iter()
        .map(|t| {
            (t.points[1] - t.points[0])
                .cross(t.points[2] - t.points[0])
                .normalize_or_zero()
        })
        .collect();
    let mut by_edge: HashMap<(u32, u32), SmallVec<[usize; 2]>> = HashMap::new();
    for (i, t) in tris.iter().enumerate() {
        for e in 0..3 {
            by_edge
                .entry((t.keys[e], t.keys[(e + 1) % 3]))
                .or_default()
                .push(i);
        }
    }
    let mut used = vec![false; tris.len()];
    let mut out = Vec::with_capacity(tris.len());
    let mut merged = 0;
    for i in 0..tris.len() {
        if used[i] {
            continue;
        }
        used[i] = true;
        let quad = (0..3).find_map(|e| {
            let t = &tris[i];
            let (a, b) = (t.keys[e], t.keys[(e + 1) % 3]);
            let partners = by_edge.get(&(b, a))?;
            partners.iter().find_map(|&j| {
                if used[j] {
                    return None;
                }
                let quad = try_merge(t, &tris[j], e, normals[i], normals[j])?;
                Some((j, quad))
            })
        });
        match quad {
            Some((j, quad)) => {
                used[j] = true;
                merged += 1;
                out.push(quad);
            }
            None => out.push(tris[i].points.iter().copied().collect()),
        }
    }
    (out, merged)
}

/// The quad made by triangle `t` and triangle `u`, which holds `t`'s edge `e`
/// reversed, if it is planar and strictly convex (as [`Surface::new`] requires). The quad starts at `t`'s first
/// vertex, so a quad `a b c d` split as `a b c` + `a c d` comes back as `a b c d`.
fn try_merge(t: &Triangle, u: &Triangle, e: usize, nt: DVec3, nu: DVec3) -> Option<Polygon> {
    let (a, b) = (t.keys[e], t.keys[(e + 1) % 3]);
    let third_key = t.keys[(e + 2) % 3];
    let k = (0..3).find(|&k| u.keys[k] != a && u.keys[k] != b)?;
    if u.keys[k] == third_key || u.keys.iter().filter(|&&x| x == a || x == b).count() != 2 {
        return None;
    }
    if nt.dot(nu) <= 0.0 || nt.cross(nu).length() > NORMAL_TOLERANCE {
        return None;
    }
    let q = u.points[k];
    let p = &t.points;
    // Replace t's edge p[e] -> p[e+1] by p[e] -> q -> p[e+1].
    let quad: Polygon = match e {
        0 => [p[0], q, p[1], p[2]].into_iter().collect(),
        1 => [p[0], p[1], q, p[2]].into_iter().collect(),
        _ => [p[0], p[1], p[2], q].into_iter().collect(),
    };
    // The surface constructor's planarity and strict convexity checks decide, so a
    // merged quad is always a valid surface.
    Surface::new(&quad, 0, 0).is_ok().then_some(quad)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(keys: [u32; 3], pts: &[DVec3]) -> Triangle {
        Triangle {
            keys,
            points: [
                pts[keys[0] as usize],
                pts[keys[1] as usize],
                pts[keys[2] as usize],
            ],
        }
    }

    #[test]
    fn a_split_square_merges_back_in_its_original_order() {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let (polys, merged) = merge_into_quads(&[tri([0, 1, 2], &p), tri([0, 2, 3], &p)]);
        assert_eq!(merged, 1);
        assert_eq!(polys.len(), 1);
        assert_eq!(polys[0].as_slice(), &p[..]);
    }

    #[test]
    fn opposite_winding_folded_and_concave_pairs_stay_triangles() {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.5),
            DVec3::new(0.9, 0.1, 0.0),
        ];
        // Opposite winding: the shared edge runs the same way in both.
        let (_, m) = merge_into_quads(&[tri([0, 1, 2], &p), tri([0, 3, 2], &p)]);
        assert_eq!(m, 0);
        // Folded along the diagonal.
        let (_, m) = merge_into_quads(&[tri([0, 1, 2], &p), tri([0, 2, 4], &p)]);
        assert_eq!(m, 0);
        // Union is a dart (vertex 5 lies inside the triangle 0 1 2's corner).
        let (polys, m) = merge_into_quads(&[tri([0, 5, 2], &p), tri([0, 1, 5], &p)]);
        assert_eq!(m, 0);
        assert_eq!(polys.len(), 2);
    }
}
