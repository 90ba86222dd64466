//! Perspective-correct Gouraud interpolation of one triangle.
//!
//! With the view-space vertices as the columns of `M = [P0 P1 P2]` and `D` the
//! direction through a sample scaled to unit depth, the point where the ray
//! meets the triangle's plane is `z D` with barycentric coordinates
//! `z M^-1 D`. So `u = M^-1 D` is linear in `D`, hence affine in sample
//! coordinates, and
//!
//! - `1 / z = u0 + u1 + u2` (the depth buffer's quantity),
//! - `value = (u0 V0 + u1 V1 + u2 V2) / (1 / z)`.
//!
//! The rows of `M^-1` are `P1 x P2`, `P2 x P0`, `P0 x P1` over
//! `det M = P0 . (P1 x P2)`. Attributes never pass through clipping: a clipped
//! triangle keeps the plane equations of the whole triangle.
//!
//! On a textured triangle the texture coordinates are interpolated the same
//! way, and the value drawn is the emission there plus the reflectance there
//! times the interpolated light (see [`super::Texels`]).

use super::view::View;
use crate::math::Rgb;
use crate::scene::Material;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;
use std::sync::Arc;

/// An affine function `a x + b y + c` of sample coordinates.
type Affine = [f64; 3];

#[inline]
fn eval(f: &Affine, x: f64, y: f64) -> f64 {
    f[0] * x + f[1] * y + f[2]
}

/// The interpolants of one triangle over the sample grid.
#[derive(Clone, Debug)]
pub(crate) struct TriangleShading {
    inverse_depth: Affine,
    /// `sum u_i V_i` per channel; unused for back faces.
    numerators: [Affine; 3],
    /// True when the camera sees the triangle's front (its vertices
    /// counter-clockwise).
    pub front: bool,
    /// `1 / z` over the visible part lies in this range; clamping to it keeps
    /// samples snapped just outside a grazing triangle from extrapolating wildly.
    inverse_depth_range: (f64, f64),
    lowest: Rgb,
    highest: Rgb,
    /// The texture lookup of a textured triangle.
    texel: Option<TexelLookup>,
}

/// Texture coordinates over a triangle and the material they look up.
#[derive(Clone, Debug)]
struct TexelLookup {
    /// `sum u_i uv_i` per coordinate.
    numerators: [Affine; 2],
    lowest: DVec2,
    highest: DVec2,
    material: Arc<Material>,
}

impl TriangleShading {
    /// The interpolants of the triangle with view-space vertices `p` and values
    /// `v`, whose visible part has `1 / z` within `inverse_depth_range`, and on
    /// a textured triangle the vertices' texture coordinates and the material.
    /// `None` when the triangle's plane passes through the eye (seen edge-on).
    pub(super) fn new(
        view: &View,
        p: [DVec3; 3],
        v: [Rgb; 3],
        inverse_depth_range: (f64, f64),
        texel: Option<([DVec2; 3], Arc<Material>)>,
    ) -> Option<Self> {
        let rows = [p[1].cross(p[2]), p[2].cross(p[0]), p[0].cross(p[1])];
        let det = p[0].dot(rows[0]);
        let inv_det = 1.0 / det;
        if det == 0.0 || !inv_det.is_finite() {
            return None;
        }
        let rows = rows.map(|r| r * inv_det);
        let inverse_depth = view.affine_in_pixels(rows[0] + rows[1] + rows[2]);
        let numerators = [0, 1, 2].map(|k| {
            view.affine_in_pixels(rows[0] * v[0][k] + rows[1] * v[1][k] + rows[2] * v[2][k])
        });
        // View space is left-handed (x right, y up, z forward), so a triangle
        // counter-clockwise around a normal facing the eye has det M > 0.
        let front = det > 0.0;
        let lowest = Rgb([0, 1, 2].map(|k| v[0][k].min(v[1][k]).min(v[2][k])));
        let highest = Rgb([0, 1, 2].map(|k| v[0][k].max(v[1][k]).max(v[2][k])));
        let texel = texel.map(|(uv, material)| TexelLookup {
            numerators: [0, 1].map(|k| {
                view.affine_in_pixels(rows[0] * uv[0][k] + rows[1] * uv[1][k] + rows[2] * uv[2][k])
            }),
            lowest: uv[0].min(uv[1]).min(uv[2]),
            highest: uv[0].max(uv[1]).max(uv[2]),
            material,
        });
        Some(TriangleShading {
            inverse_depth,
            numerators,
            front,
            inverse_depth_range,
            lowest,
            highest,
            texel,
        })
    }

    /// `1 / z` at sample point `(x, y)`.
    #[inline]
    pub(super) fn inverse_depth_at(&self, x: f64, y: f64) -> f64 {
        let (lo, hi) = self.inverse_depth_range;
        eval(&self.inverse_depth, x, y).clamp(lo, hi)
    }

    /// The interpolated value at sample point `(x, y)`, where `1 / z` is
    /// `inverse_depth`; on a textured triangle, the emitted radiance there
    /// plus the reflectance there times the interpolated light.
    #[inline]
    pub(super) fn value_at(&self, x: f64, y: f64, inverse_depth: f64) -> Rgb {
        let mut out = Rgb::ZERO;
        for k in 0..3 {
            let v = eval(&self.numerators[k], x, y) / inverse_depth;
            out[k] = v.clamp(self.lowest[k], self.highest[k]);
        }
        match &self.texel {
            None => out,
            Some(t) => {
                let uv = DVec2::new(
                    eval(&t.numerators[0], x, y) / inverse_depth,
                    eval(&t.numerators[1], x, y) / inverse_depth,
                )
                .clamp(t.lowest, t.highest);
                let m = &t.material;
                m.emission_at(Some(uv)) / PI + m.reflectance_at(Some(uv)) * out
            }
        }
    }
}
