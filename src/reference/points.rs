//! Points on surfaces: stratified sample sets over a whole scene, and attaching a
//! free probe position to the surface it lies on.

use super::rng::{Domain, Rng};
use super::sampling::Cdf;
use super::Reference;
use crate::error::{Error, GeometryFault, Result};
use crate::scene::rays::SurfaceGeometry;
use crate::scene::Scene;
use glam::DVec3;

/// A point on a surface of the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Index into `Scene::surfaces`.
    pub surface: u32,
    /// The position, on the surface's plane.
    pub position: DVec3,
    /// The surface's unit front normal (informational: estimates always use the
    /// surface's own normal).
    pub normal: DVec3,
}

/// Relative tolerance of [`Reference::locate`], times the scene diameter.
pub const LOCATE_TOLERANCE: f64 = 1e-5;

/// Cosine of the largest angle [`Reference::locate`] allows between a probe's
/// normal and the surface's (5 degrees).
const LOCATE_MIN_COSINE: f64 = 0.996_194_698_091_745_5;

/// `count` points spread over all surfaces of `scene`, independent of any mesh.
///
/// The points are stratified by area: the k-th point takes the uniform
/// `(k + xi)/count` along the running area of all surfaces, so every surface gets
/// its area's share of the points to within one, and points on one surface are
/// spread along one direction. Within a surface the second coordinate is random.
/// The same `(scene, count, seed)` gives the same points.
///
/// Fails, naming the surface, on geometry the reference cannot use, and on a
/// scene with no surfaces.
pub fn sample_points(scene: &Scene, count: usize, seed: u64) -> Result<Vec<SurfacePoint>> {
    let geometry = super::scene_geometry(scene)?;
    let areas: Vec<f64> = geometry.iter().map(|g| g.area).collect();
    let cdf = Cdf::new(&areas).ok_or_else(|| {
        Error::geometry(
            GeometryFault::Degenerate,
            "the scene's total area is not positive".into(),
        )
    })?;
    Ok((0..count)
        .map(|k| {
            let mut rng = Rng::for_stream(seed, Domain::SamplePoints, 0, k as u64);
            let u = (k as f64 + rng.uniform()) / count as f64;
            let (surface, u1) = cdf.pick(u);
            point_on(&geometry, surface as u32, u1, rng.uniform())
        })
        .collect())
}

/// The point of `geometry[surface]` given by two uniforms.
pub(crate) fn point_on(
    geometry: &[SurfaceGeometry],
    surface: u32,
    u1: f64,
    u2: f64,
) -> SurfacePoint {
    let g = &geometry[surface as usize];
    SurfacePoint {
        surface,
        position: g.sample(u1, u2),
        normal: g.normal,
    }
}

impl Reference {
    /// Attaches a free probe (a position and the direction it faces) to a
    /// surface, with a tolerance of [`LOCATE_TOLERANCE`] times the scene
    /// diameter. See [`Reference::locate_within`].
    #[must_use]
    pub fn locate(&self, position: DVec3, normal: DVec3) -> Option<SurfacePoint> {
        self.locate_within(position, normal, LOCATE_TOLERANCE * self.diameter)
    }

    /// The surface nearest to `position` among those whose front normal is within
    /// 5 degrees of `normal` and whose polygon lies within `tolerance` of it (off
    /// the plane and beyond the edges together). The point returned is `position`
    /// projected onto that surface's plane. Where several qualify (coplanar
    /// neighbours, or a point on a shared edge), the nearest wins, then the one
    /// the point lies deeper inside, then the lower index. `None` when nothing
    /// qualifies or the input is not finite.
    #[must_use]
    pub fn locate_within(
        &self,
        position: DVec3,
        normal: DVec3,
        tolerance: f64,
    ) -> Option<SurfacePoint> {
        let normal = normal.normalize_or_zero();
        if !position.is_finite() || normal == DVec3::ZERO || tolerance.is_nan() || tolerance < 0.0 {
            return None;
        }
        let mut best: Option<(f64, f64, u32, DVec3)> = None;
        for (i, g) in self.geometry.iter().enumerate() {
            if g.normal.dot(normal) < LOCATE_MIN_COSINE {
                continue;
            }
            let (height, on_plane) = g.project(position);
            let margin = g.inside_margin(on_plane - g.anchor);
            let distance = height.hypot(margin.min(0.0));
            if distance > tolerance {
                continue;
            }
            let key = (distance, -margin, i as u32, on_plane);
            let better = match &best {
                None => true,
                Some(b) => (key.0, key.1) < (b.0, b.1),
            };
            if better {
                best = Some(key);
            }
        }
        best.map(|(_, _, surface, on_plane)| SurfacePoint {
            surface,
            position: on_plane,
            normal: self.geometry[surface as usize].normal,
        })
    }
}
