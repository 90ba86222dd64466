//! Reflectance and emission per point: a surface whose material has a
//! base-colour or emissive texture, and which carries texture coordinates,
//! reflects and emits what the texture holds at each point's coordinates.
//!
//! A point's texture coordinates follow the map the solver's lattice uses
//! (`SurfaceLattice::uv`), so that both tools read the same texel at the same
//! place: linear over a triangle (`v0 + s (v1 - v0) + t (v2 - v0)`), and
//! bilinear over a quad (`(1-t) [(1-s) v0 + s v1] + t [(1-s) v3 + s v2]`),
//! the texture coordinates interpolated with the same `(s, t)`. On a quad that
//! is not a parallelogram the bilinear map is not affine, so `(s, t)` comes
//! from inverting it (a quadratic in `s`), not from the two triangles the
//! quad is sampled and traced as.
//!
//! Without a texture or coordinates a surface keeps its material's constant
//! reflectance and emission, the very values (and bits) used before textures.

use super::sampling::tangent_frame;
use crate::math::Rgb;
use crate::scene::rays::SurfaceGeometry;
use crate::scene::{Material, Surface, Texture};
use glam::{DVec2, DVec3};
use std::sync::Arc;

/// The 2D cross product (the z of the 3D one).
fn cross2(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Maps a point of a surface's plane to its texture coordinates.
#[derive(Clone, Debug)]
pub(crate) struct UvMap {
    /// Vertex 0, the origin of the in-plane coordinates.
    origin: DVec3,
    /// Two orthonormal in-plane axes.
    axes: (DVec3, DVec3),
    /// In-plane coordinates of vertices 1, 2 (and 3) relative to vertex 0.
    corners: [DVec2; 3],
    /// Texture coordinates per vertex.
    uv: [DVec2; 4],
    /// A quad (bilinear map) rather than a triangle (linear map).
    quad: bool,
}

impl UvMap {
    /// The map of a surface whose (projected) vertices are `vertices`, with
    /// normal `normal` and texture coordinates `uv` (one per vertex), or
    /// `None` when the counts disagree.
    pub(crate) fn new(vertices: &[DVec3], normal: DVec3, uv: &[DVec2]) -> Option<UvMap> {
        let n = vertices.len();
        if !(3..=4).contains(&n) || uv.len() != n {
            return None;
        }
        let axes = tangent_frame(normal);
        let origin = vertices[0];
        let local = |p: DVec3| {
            let d = p - origin;
            DVec2::new(d.dot(axes.0), d.dot(axes.1))
        };
        let mut corners = [DVec2::ZERO; 3];
        for (slot, v) in corners.iter_mut().zip(&vertices[1..]) {
            *slot = local(*v);
        }
        let mut coords = [DVec2::ZERO; 4];
        coords[..n].copy_from_slice(uv);
        Some(UvMap {
            origin,
            axes,
            corners,
            uv: coords,
            quad: n == 4,
        })
    }

    /// The lattice parameters `(s, t)` of the point of the plane nearest to
    /// `position`, each clamped to [0, 1] (points lie on the surface, up to
    /// the ray-offset and edge tolerances).
    pub(crate) fn parameters(&self, position: DVec3) -> (f64, f64) {
        let d = position - self.origin;
        let h = DVec2::new(d.dot(self.axes.0), d.dot(self.axes.1));
        let (s, t) = if self.quad {
            self.bilinear_inverse(h)
        } else {
            let (e, f) = (self.corners[0], self.corners[1]);
            let det = cross2(e, f);
            (cross2(h, f) / det, cross2(e, h) / det)
        };
        (clamp_unit(s), clamp_unit(t))
    }

    /// Solves `h = s e + t f + s t g` (vertex 0 at the origin, `e` and `f`
    /// the edges to vertices 1 and 3, `g = v2 - v1 - v3`) for `(s, t)`.
    ///
    /// `h - s e = t (f + s g)`, so the two are parallel:
    /// `cross(h - s e, f + s g) = 0`, the quadratic
    /// `k2 s^2 + k1 s + k0 = 0` with `k2 = -cross(e, g)`,
    /// `k1 = cross(h, g) - cross(e, f)` and `k0 = cross(h, f)`. Its roots are
    /// taken in the cancellation-free form `q / k2` and `k0 / q` with
    /// `q = -(k1 + sign(k1) sqrt(k1^2 - 4 k2 k0)) / 2`, which tends to the
    /// linear root `-k0 / k1` as a parallelogram's `k2` tends to 0. Each root
    /// gives `t` as the least-squares solution of the parallel pair, and the
    /// pair nearest the unit square wins (inside a convex quad exactly one
    /// lies in it).
    fn bilinear_inverse(&self, h: DVec2) -> (f64, f64) {
        let (e, f) = (self.corners[0], self.corners[2]);
        let g = self.corners[1] - e - f;
        let k2 = -cross2(e, g);
        let k1 = cross2(h, g) - cross2(e, f);
        let k0 = cross2(h, f);
        let root = (k1 * k1 - 4.0 * k2 * k0).max(0.0).sqrt();
        let q = -0.5 * (k1 + root.copysign(k1));
        let outside = |r: f64| (r - r.clamp(0.0, 1.0)).abs();
        let mut best = (f64::INFINITY, 0.5, 0.5);
        for s in [q / k2, k0 / q] {
            if !s.is_finite() {
                continue;
            }
            let towards = f + g * s;
            let length_squared = towards.length_squared();
            if length_squared <= 0.0 {
                continue;
            }
            let t = (h - e * s).dot(towards) / length_squared;
            let miss = outside(s) + outside(t);
            if miss < best.0 {
                best = (miss, s, t);
            }
        }
        (best.1, best.2)
    }

    /// The texture coordinates at `position` (on the surface's plane).
    pub(crate) fn uv_at(&self, position: DVec3) -> DVec2 {
        let (s, t) = self.parameters(position);
        let uv = &self.uv;
        if self.quad {
            uv[0].lerp(uv[1], s).lerp(uv[3].lerp(uv[2], s), t)
        } else {
            uv[0] + (uv[1] - uv[0]) * s + (uv[2] - uv[0]) * t
        }
    }
}

/// `x` clamped to [0, 1]; NaN becomes 0.
fn clamp_unit(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(0.0, 1.0)
    }
}

/// The textures that vary over one surface, and its texture-coordinate map.
#[derive(Clone, Debug)]
struct Textured {
    map: UvMap,
    /// The base-colour texture, or `None` for a constant reflectance.
    base: Option<Arc<Texture>>,
    /// The emissive texture, or `None` for a constant emission.
    emissive: Option<Arc<Texture>>,
}

/// A surface's reflectance and emitted exitance: constant, or per point.
#[derive(Clone, Debug)]
pub(crate) struct Shade {
    /// The material's reflectance (with a base-colour texture, its mean).
    reflectance: Rgb,
    /// The material's exitance (with an emissive texture, its mean): what
    /// emitter choice weighs surfaces by.
    emission: Rgb,
    /// Present when a texture of the material varies over this surface.
    textured: Option<Box<Textured>>,
}

impl Shade {
    /// The shade of `surface` (traced as `geometry`) made of `material`.
    pub(crate) fn new(material: &Material, surface: &Surface, geometry: &SurfaceGeometry) -> Shade {
        let textured = if material.base_texture.is_some() || material.emissive_texture.is_some() {
            UvMap::new(geometry.vertices(), geometry.normal, &surface.uv).map(|map| {
                Box::new(Textured {
                    map,
                    base: material.base_texture.clone(),
                    emissive: material.emissive_texture.clone(),
                })
            })
        } else {
            None
        };
        Shade {
            reflectance: material.reflectance,
            emission: material.emission,
            textured,
        }
    }

    /// The material's mean exitance (constant over the surface unless an
    /// emissive texture applies). Positive wherever [`Shade::emission_at`]
    /// can be: texels are never negative, so a texture whose mean is zero is
    /// zero everywhere.
    pub(crate) fn mean_emission(&self) -> Rgb {
        self.emission
    }

    /// The emitted exitance at `position` on the surface.
    #[inline]
    pub(crate) fn emission_at(&self, position: DVec3) -> Rgb {
        match self.textured.as_deref() {
            Some(Textured {
                map,
                emissive: Some(texture),
                ..
            }) => texture.value_at(map.uv_at(position)),
            _ => self.emission,
        }
    }

    /// The exitance and the reflectance at `position`, with one look-up of
    /// the texture coordinates.
    #[inline]
    pub(crate) fn at(&self, position: DVec3) -> (Rgb, Rgb) {
        let Some(textured) = self.textured.as_deref() else {
            return (self.emission, self.reflectance);
        };
        let uv = textured.map.uv_at(position);
        let value = |texture: &Option<Arc<Texture>>, constant: Rgb| match texture {
            Some(t) => t.value_at(uv),
            None => constant,
        };
        (
            value(&textured.emissive, self.emission),
            value(&textured.base, self.reflectance),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Wrap;

    /// The lattice's bilinear map (as `SurfaceLattice::position` writes it).
    fn bilinear<T: Copy + std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>>(
        c: [T; 4],
        s: f64,
        t: f64,
    ) -> T {
        let lerp = |a: T, b: T, x: f64| a * (1.0 - x) + b * x;
        lerp(lerp(c[0], c[1], s), lerp(c[3], c[2], s), t)
    }

    fn geometry(vertices: &[DVec3], uv: &[DVec2]) -> (SurfaceGeometry, Surface) {
        let surface = Surface::new(vertices, 0, 0).unwrap().with_uv(uv);
        (SurfaceGeometry::new(0, &surface).unwrap(), surface)
    }

    #[test]
    fn a_trapezoids_bilinear_map_is_inverted() {
        // A tilted trapezoid (not a parallelogram) with skewed coordinates.
        let tilt = |x: f64, y: f64| DVec3::new(x, y * 0.6, y * 0.8 + 3.0);
        let v = [tilt(0., 0.), tilt(4., 0.), tilt(3., 2.), tilt(0.5, 2.5)];
        let uv = [(0.1, 0.2), (0.9, 0.1), (0.8, 0.7), (0.2, 0.95)].map(|(a, b)| DVec2::new(a, b));
        let (g, s) = geometry(&v, &uv);
        let map = UvMap::new(g.vertices(), g.normal, &s.uv).unwrap();
        for i in 0..=10 {
            for j in 0..=10 {
                let (a, b) = (f64::from(i) / 10.0, f64::from(j) / 10.0);
                let (ra, rb) = map.parameters(bilinear(v, a, b));
                assert!((ra - a).abs() < 1e-12 && (rb - b).abs() < 1e-12, "{a} {b}");
                let want = bilinear(uv, a, b);
                assert!((map.uv_at(bilinear(v, a, b)) - want).length() < 1e-12);
            }
        }
    }

    #[test]
    fn a_squares_map_is_linear_and_a_triangles_barycentric() {
        let p = DVec3::new;
        let square = [p(0., 0., 0.), p(2., 0., 0.), p(2., 2., 0.), p(0., 2., 0.)];
        let uv = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(|(a, b)| DVec2::new(a, b));
        let (g, s) = geometry(&square, &uv);
        let map = UvMap::new(g.vertices(), g.normal, &s.uv).unwrap();
        let got = map.uv_at(p(0.5, 1.5, 0.0));
        assert!((got - DVec2::new(0.25, 0.75)).length() < 1e-15, "{got}");
        let tri = [p(0., 0., 1.), p(0., 3., 1.), p(0., 0., 4.)];
        let tuv = [(0.5, 0.5), (1.0, 0.5), (0.5, 0.0)].map(|(a, b)| DVec2::new(a, b));
        let (g, s) = geometry(&tri, &tuv);
        let map = UvMap::new(g.vertices(), g.normal, &s.uv).unwrap();
        let got = map.uv_at(p(0.0, 1.0, 2.0));
        assert!((got - DVec2::new(0.5 + 1.0 / 6.0, 0.5 - 1.0 / 6.0)).length() < 1e-15);
    }

    #[test]
    fn shades_read_textures_only_with_coordinates() {
        let p = DVec3::new;
        let square = [p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)];
        let uv = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(|(a, b)| DVec2::new(a, b));
        let mut m = Material::from_radiance("m", Rgb::splat(0.5), Rgb::splat(1.0)).unwrap();
        let texture = |texels: Vec<[f32; 3]>, max_value: f64| {
            Arc::new(Texture {
                wrap: [Wrap::ClampToEdge; 2],
                max_value,
                ..Texture::nearest(2, 1, texels)
            })
        };
        let (g, plain) = geometry(&square, &[]);
        let constant = Shade::new(&m, &plain, &g);
        assert_eq!(constant.at(p(0.9, 0.5, 0.)), (m.emission, m.reflectance));
        m.base_texture = Some(texture(vec![[0.25; 3], [0.75; 3]], 1.0));
        m.emissive_texture = Some(texture(vec![[0.0; 3], [7.0; 3]], f64::INFINITY));
        let (g, with_uv) = geometry(&square, &uv);
        let shade = Shade::new(&m, &with_uv, &g);
        let right = p(0.9, 0.5, 0.);
        assert_eq!(shade.at(right), (Rgb::splat(7.0), Rgb::splat(0.75)));
        assert_eq!(shade.emission_at(right), Rgb::splat(7.0));
        assert_eq!(shade.at(p(0.1, 0.5, 0.)), (Rgb::ZERO, Rgb::splat(0.25)));
        assert_eq!(shade.mean_emission(), m.emission);
        // Without coordinates the textures' means hold everywhere.
        let (g, plain) = geometry(&square, &[]);
        let mean = Shade::new(&m, &plain, &g);
        assert_eq!(mean.at(right), (m.emission, m.reflectance));
    }
}
