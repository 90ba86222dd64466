//! Planar surfaces: triangles and convex quads.

use crate::error::{Error, GeometryFault, Result};
use crate::math::{is_convex, newell_normal, planarity_error, polygon_area, polygon_centroid};
use glam::{DVec2, DVec3};
use smallvec::SmallVec;

/// Relative out-of-plane deviation above which a quad is refused as non-planar
/// (the builder splits such quads into two triangles instead).
pub(super) const PLANARITY_TOLERANCE: f64 = 1e-6;

/// The largest coordinate magnitude, in metres, a surface may have.
///
/// The geometry is kept in `f64`, but ray casting runs its broad phase on a
/// single-precision BVH, whose builder computes box areas (products of two
/// extents) in `f32`: coordinates near `sqrt(f32::MAX)` ~ 1.8e19 overflow it to
/// infinity and the builder fails. 1e15 m (a tenth of a light year) keeps those
/// products below 1e31, seven orders of magnitude inside `f32`, and is beyond
/// any scene the radiosity method is used for.
pub const MAX_COORDINATE: f64 = 1e15;

/// A planar triangle or convex quad. Vertices run counter-clockwise seen from the
/// front, which is the side the unit `normal` points to. Only the front emits and
/// reflects; the back blocks light.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// Three or four vertices in world space (metres).
    pub vertices: SmallVec<[DVec3; 4]>,
    /// Unit front normal.
    pub normal: DVec3,
    /// Area in square metres.
    pub area: f64,
    /// Index into `Scene::materials`.
    pub material: u32,
    /// Index into `Scene::objects`.
    pub object: u32,
    /// Texture coordinates per vertex (the set its material's base-colour
    /// texture reads), or empty: the material's mean reflectance then holds
    /// over the whole surface.
    pub uv: SmallVec<[DVec2; 4]>,
}

impl Surface {
    /// A surface from 3 or 4 vertices. Fails on non-finite coordinates or ones
    /// beyond [`MAX_COORDINATE`], zero area, a non-planar or non-convex quad.
    pub fn new(vertices: &[DVec3], material: u32, object: u32) -> Result<Self> {
        if !(3..=4).contains(&vertices.len()) {
            let fault = if vertices.len() < 3 {
                GeometryFault::Degenerate
            } else {
                GeometryFault::Unsupported
            };
            return Err(Error::geometry(
                fault,
                format!("a surface needs 3 or 4 vertices, got {}", vertices.len()),
            ));
        }
        if vertices.iter().any(|v| !v.is_finite()) {
            return Err(Error::geometry(
                GeometryFault::NonFinite,
                format!("non-finite vertex in {vertices:?}"),
            ));
        }
        if vertices
            .iter()
            .any(|v| v.abs().max_element() > MAX_COORDINATE)
        {
            return Err(Error::geometry(
                GeometryFault::OutOfRange,
                format!(
                    "vertex beyond +-{MAX_COORDINATE:e} m (the largest coordinate the solver \
                 represents) in {vertices:?}"
                ),
            ));
        }
        let n = newell_normal(vertices);
        let area = 0.5 * n.length();
        let diam2 = vertices
            .iter()
            .flat_map(|a| vertices.iter().map(move |b| (*a - *b).length_squared()))
            .fold(0.0, f64::max);
        if area.is_nan() || area <= 1e-12 * diam2 || area <= 0.0 {
            return Err(Error::geometry(
                GeometryFault::Degenerate,
                format!("degenerate polygon (zero area) {vertices:?}"),
            ));
        }
        let normal = n / (2.0 * area);
        if vertices.len() == 4 {
            if planarity_error(vertices) > PLANARITY_TOLERANCE {
                return Err(Error::geometry(
                    GeometryFault::NonPlanar,
                    format!("non-planar quad {vertices:?}"),
                ));
            }
            if !is_convex(vertices, normal) {
                return Err(Error::geometry(
                    GeometryFault::NonConvex,
                    format!("non-convex quad {vertices:?}"),
                ));
            }
        }
        Ok(Surface {
            vertices: vertices.iter().copied().collect(),
            normal,
            area,
            material,
            object,
            uv: SmallVec::new(),
        })
    }

    /// The surface with texture coordinates `uv`, one per vertex in vertex
    /// order; any other count leaves it without.
    #[must_use]
    pub fn with_uv(mut self, uv: &[DVec2]) -> Surface {
        if uv.len() == self.vertices.len() && uv.iter().all(|t| t.is_finite()) {
            self.uv = uv.iter().copied().collect();
        }
        self
    }

    /// The area centroid.
    #[must_use]
    pub fn centroid(&self) -> DVec3 {
        polygon_centroid(&self.vertices)
    }

    /// True for a quad, false for a triangle.
    #[must_use]
    pub fn is_quad(&self) -> bool {
        self.vertices.len() == 4
    }

    /// The same surface facing the other way (for double-sided materials).
    #[must_use]
    pub fn flipped(&self) -> Surface {
        let mut s = self.clone();
        s.vertices.reverse();
        s.uv.reverse();
        s.normal = -s.normal;
        s
    }

    /// Recomputes the area from the vertices (after a transform).
    #[must_use]
    pub fn polygon_area(&self) -> f64 {
        polygon_area(&self.vertices)
    }
}
