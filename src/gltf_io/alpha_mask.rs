//! `alphaMode` `MASK` as geometry: the parts of a triangle where the alpha
//! (the base-colour texture's alpha times `baseColorFactor`'s) is below
//! `alphaCutoff` are cut away at import, so that light passes through the
//! holes of foliage and fences with no change to the solver.
//!
//! Each triangle is divided into `n x n` equal sub-triangles on a regular
//! lattice (`n` from the triangle's size in texels, at most what the
//! file's cut budget leaves a triangle); the alpha is sampled at the
//! lattice points as a viewer filters it, and each sub-triangle is clipped
//! to where the alpha, taken linear between its corners, reaches the
//! cutoff. A triangle whose samples all pass is kept whole; one whose
//! samples all fail is dropped.

use super::document::Document;
use super::nodes::Placed;
use super::primitives::triangle_count;
use crate::scene::Texture;
use glam::{DVec2, DVec3};
use gltf_json::mesh::Semantic;
use gltf_json::validation::Checked;

/// Most triangles the cuts of one file may make in all: the solver's cost
/// grows with the number of surfaces, so finer cuts are traded for a bound.
pub(super) const MAX_CUT_TRIANGLES: usize = 200_000;

/// Largest lattice division of one triangle: 2 x 32^2 pieces at most.
const MAX_DIVISIONS: usize = 32;

/// Texels along a sub-triangle's longest edge, when the budget allows.
const TEXELS_PER_DIVISION: f64 = 2.0;

/// What a `MASK` material cuts by.
#[derive(Clone, Debug)]
pub(super) struct Mask {
    /// `alphaCutoff` (glTF's default 0.5).
    pub cutoff: f64,
    /// The texture's alpha as a grey texture (its factor the
    /// `baseColorFactor` alpha), or `None` when only the factor gives alpha.
    pub alpha: Option<Texture>,
    /// `baseColorFactor`'s alpha.
    pub factor_alpha: f64,
}

/// A triangle (or a piece of one): corners counter-clockwise and their
/// texture coordinates.
pub(super) type Piece = ([DVec3; 3], [DVec2; 3]);

/// What cutting one triangle gave.
#[derive(Debug, PartialEq)]
pub(super) enum Cut {
    /// Every sample passes: the triangle as it is.
    Whole,
    /// Every sample fails: nothing.
    Dropped,
    /// The pieces where the alpha reaches the cutoff.
    Pieces(Vec<Piece>),
}

impl Mask {
    /// The alpha at texture coordinates `uv`, less the cutoff.
    fn excess(&self, uv: DVec2) -> f64 {
        let alpha = match &self.alpha {
            Some(t) => t.value_at(uv).0[0],
            None => self.factor_alpha,
        };
        alpha - self.cutoff
    }

    /// True when the mask cannot vary over a surface: no alpha texture.
    pub(super) fn is_uniform(&self) -> bool {
        self.alpha.is_none()
    }

    /// Whether a surface passes where the alpha is the factor's alone.
    pub(super) fn uniform_passes(&self) -> bool {
        self.factor_alpha >= self.cutoff
    }

    /// The lattice division for a triangle with texture coordinates `uv`,
    /// at most `most`.
    fn divisions(&self, uv: &[DVec2; 3], most: usize) -> usize {
        let Some(t) = &self.alpha else {
            return 1;
        };
        let size = DVec2::new(f64::from(t.image.width), f64::from(t.image.height));
        let texel = |p: DVec2| t.transform.transform_point2(p) * size;
        let (a, b, c) = (texel(uv[0]), texel(uv[1]), texel(uv[2]));
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        let wanted = (longest / TEXELS_PER_DIVISION).ceil();
        if wanted.is_finite() {
            (wanted as usize).clamp(1, most.clamp(1, MAX_DIVISIONS))
        } else {
            1
        }
    }

    /// Cuts triangle `points` (texture coordinates `uv`) into at most
    /// `2 * most^2` pieces.
    pub(super) fn cut(&self, points: &[DVec3; 3], uv: &[DVec2; 3], most: usize) -> Cut {
        let n = self.divisions(uv, most);
        // Lattice point (i, j) is a + i/n (b - a) + j/n (c - a), i + j <= n.
        let at = |i: usize, j: usize| -> (DVec3, DVec2) {
            let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
            (
                points[0] + (points[1] - points[0]) * s + (points[2] - points[0]) * t,
                uv[0] + (uv[1] - uv[0]) * s + (uv[2] - uv[0]) * t,
            )
        };
        let row = |j: usize| (0..j).map(|k| n + 1 - k).sum::<usize>();
        let mut lattice = Vec::with_capacity((n + 1) * (n + 2) / 2);
        for j in 0..=n {
            for i in 0..=n - j {
                let (p, q) = at(i, j);
                lattice.push((p, q, self.excess(q)));
            }
        }
        if lattice.iter().all(|l| l.2 >= 0.0) {
            return Cut::Whole;
        }
        if lattice.iter().all(|l| l.2 < 0.0) {
            return Cut::Dropped;
        }
        let index = |i: usize, j: usize| row(j) + i;
        let mut pieces = Vec::new();
        for j in 0..n {
            for i in 0..n - j {
                let up = [index(i, j), index(i + 1, j), index(i, j + 1)];
                clip(&up.map(|k| lattice[k]), &mut pieces);
                if i + j + 1 < n {
                    let down = [index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)];
                    clip(&down.map(|k| lattice[k]), &mut pieces);
                }
            }
        }
        Cut::Pieces(pieces)
    }
}

/// The part of triangle `corners` (position, texture coordinates, alpha less
/// the cutoff) where the alpha, linear between the corners, reaches the
/// cutoff: nothing, a triangle, or a quad as two triangles, with the
/// triangle's winding.
fn clip(corners: &[(DVec3, DVec2, f64); 3], out: &mut Vec<Piece>) {
    if corners.iter().all(|c| c.2 >= 0.0) {
        out.push((corners.map(|c| c.0), corners.map(|c| c.1)));
        return;
    }
    let mut polygon: Vec<(DVec3, DVec2)> = Vec::with_capacity(4);
    for k in 0..3 {
        let (p, q) = (corners[k], corners[(k + 1) % 3]);
        if p.2 >= 0.0 {
            polygon.push((p.0, p.1));
        }
        if (p.2 >= 0.0) != (q.2 >= 0.0) {
            let t = p.2 / (p.2 - q.2);
            polygon.push((p.0.lerp(q.0, t), p.1.lerp(q.1, t)));
        }
    }
    for k in 1..polygon.len().saturating_sub(1) {
        let (a, b, c) = (polygon[0], polygon[k], polygon[k + 1]);
        out.push(([a.0, b.0, c.0], [a.1, b.1, c.1]));
    }
}

/// The lattice division the budget leaves each of `triangles` masked
/// triangles: `n` with `2 n^2` pieces each fitting [`MAX_CUT_TRIANGLES`].
pub(super) fn budget_divisions(triangles: usize) -> usize {
    let per_triangle = MAX_CUT_TRIANGLES / triangles.max(1);
    ((per_triangle as f64 / 2.0).sqrt().floor() as usize).clamp(1, MAX_DIVISIONS)
}

/// What the masks of one material did, over the whole file.
#[derive(Debug, Default)]
pub(super) struct MaskTally {
    /// Triangles kept whole.
    pub whole: usize,
    /// Triangles dropped as transparent.
    pub dropped: usize,
    /// Triangles cut, and the pieces they gave.
    pub cut: usize,
    /// Pieces of cut triangles.
    pub pieces: usize,
}

impl MaskTally {
    pub(super) fn add(&mut self, other: &MaskTally) {
        self.whole += other.whole;
        self.dropped += other.dropped;
        self.cut += other.cut;
        self.pieces += other.pieces;
    }
}

/// How many triangles of the placed meshes a textured mask may cut (each
/// instance counted), from the accessors' counts, before any is read.
pub(super) fn masked_triangles(doc: &Document, placed: &[Placed], masks: &[Option<Mask>]) -> usize {
    let textured = |m: Option<usize>| {
        m.and_then(|m| masks.get(m))
            .and_then(Option::as_ref)
            .is_some_and(|mask| !mask.is_uniform())
    };
    let mut total = 0usize;
    for p in placed {
        let Some(mesh) = doc.root.nodes[p.node]
            .mesh
            .and_then(|m| doc.root.meshes.get(m.value()))
        else {
            continue;
        };
        for prim in &mesh.primitives {
            let (Checked::Valid(mode), true) =
                (prim.mode, textured(prim.material.map(|m| m.value())))
            else {
                continue;
            };
            let stream = prim
                .indices
                .or_else(|| {
                    prim.attributes
                        .get(&Checked::Valid(Semantic::Positions))
                        .copied()
                })
                .and_then(|a| doc.root.accessors.get(a.value()))
                .map_or(0, |a| a.count.0 as usize);
            total = total.saturating_add(triangle_count(mode, stream));
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;

    /// A mask whose alpha is 0 on the left half of the texture and 1 on the
    /// right (16 texels across, nearest).
    fn half_mask() -> Mask {
        let texels = (0..16)
            .map(|x| [if x < 8 { 0.0 } else { 1.0 }; 3])
            .collect();
        let mut alpha = Texture::nearest(16, 1, texels);
        alpha.factor = Rgb::ONE;
        alpha.max_value = f64::INFINITY;
        alpha.wrap = [crate::scene::Wrap::ClampToEdge; 2];
        Mask {
            cutoff: 0.5,
            alpha: Some(alpha),
            factor_alpha: 1.0,
        }
    }

    fn area(p: &[DVec3; 3]) -> f64 {
        0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length()
    }

    #[test]
    fn a_triangle_over_a_hard_edge_keeps_its_opaque_part_and_winding() {
        // A unit right triangle whose texture coordinates are its x and y:
        // the kept part is where x >= 1/2, the triangle (1/2,0) (1,0) (1/2,1/2)
        // of area 1/8, up to the lattice's resolution of the edge.
        let p = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let uv = [DVec2::ZERO, DVec2::X, DVec2::Y];
        let Cut::Pieces(pieces) = half_mask().cut(&p, &uv, 8) else {
            panic!("the triangle straddles the edge");
        };
        let kept: f64 = pieces.iter().map(|(q, _)| area(q)).sum();
        // The nearest-texel alpha steps at x = 1/2, which is a lattice line
        // (n = 8); the clip places the edge linearly between the lattice
        // lines x = 3/8 (alpha 0) and 1/2 (alpha 1), at x = 7/16: the kept
        // area is (1 - 7/16)^2 / 2.
        let expected = 0.5 * (9.0f64 / 16.0).powi(2);
        assert!((kept - expected).abs() < 1e-12, "{kept} {expected}");
        for (q, t) in &pieces {
            assert!((q[1] - q[0]).cross(q[2] - q[0]).z > 0.0, "winding kept");
            for (point, coordinate) in q.iter().zip(t) {
                assert!(point.x >= 0.5 - 1.0 / 8.0 - 1e-12, "{point}");
                assert!((point.truncate() - *coordinate).length() < 1e-12);
            }
        }
    }

    #[test]
    fn opaque_and_transparent_triangles_are_kept_whole_or_dropped() {
        let mask = half_mask();
        let right = [
            DVec3::new(0.6, 0.0, 0.0),
            DVec3::X,
            DVec3::new(0.6, 1.0, 0.0),
        ];
        let uv = right.map(|p| p.truncate());
        assert_eq!(mask.cut(&right, &uv, 8), Cut::Whole);
        let left = right.map(|p| p - DVec3::new(0.6, 0.0, 0.0));
        let uv = left.map(|p| p.truncate());
        assert_eq!(mask.cut(&left, &uv, 8), Cut::Dropped);
    }

    #[test]
    fn a_linear_alpha_is_cut_exactly_where_it_crosses_the_cutoff() {
        // A clip of one corner: alpha -1, 1, 1 less the cutoff puts the cut
        // halfway along the two edges from the first corner; the kept quad
        // has area 1 - 1/4 of the triangle's.
        let corners = [
            (DVec3::ZERO, DVec2::ZERO, -1.0),
            (DVec3::X, DVec2::X, 1.0),
            (DVec3::Y, DVec2::Y, 1.0),
        ];
        let mut out = Vec::new();
        clip(&corners, &mut out);
        assert_eq!(out.len(), 2);
        let kept: f64 = out.iter().map(|(q, _)| area(q)).sum();
        assert!((kept - 0.375).abs() < 1e-12, "{kept}");
    }

    #[test]
    fn the_budget_bounds_pieces_per_triangle() {
        assert_eq!(budget_divisions(1), MAX_DIVISIONS);
        let n = budget_divisions(10_000);
        assert!(2 * n * n * 10_000 <= MAX_CUT_TRIANGLES, "{n}");
        assert_eq!(budget_divisions(1_000_000), 1);
    }
}
