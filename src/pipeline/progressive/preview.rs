//! What the caller's preview callback sees of a progressive solve under way.

use crate::math::Rgb;
use crate::mesh::{Mesh, ShadingMesh};
use crate::scene::Scene;
use crate::solution::{object_means, ObjectRadiosity};
use crate::solve::Radiosity;

/// A look at a progressive solve under way, handed to the preview callback.
#[derive(Clone, Copy, Debug)]
pub struct Preview<'a> {
    /// Shots so far.
    pub shots: usize,
    /// Unshot power over emitted power.
    pub unshot_fraction: f64,
    /// The ambient term now (display only; not in the leaves' radiosities).
    pub ambient: Rgb,
    /// Seconds since the solve began.
    pub seconds: f64,
    /// The mesh.
    pub mesh: &'a Mesh,
    /// Leaf radiosities as shot so far (interior nodes are not kept up to
    /// date during shooting).
    pub radiosity: &'a Radiosity,
}

impl Preview<'_> {
    /// The display mesh, with `rho * ambient` added to every vertex when
    /// `with_ambient`.
    #[must_use]
    pub fn shading_mesh(&self, with_ambient: bool) -> ShadingMesh {
        let mut vr = self.mesh.vertex_radiosity(|k| self.radiosity.element(k));
        if with_ambient {
            for (id, value) in &mut vr.values {
                *value += self.mesh.surfaces[id.0 as usize].reflectance * self.ambient;
            }
        }
        self.mesh.shading_mesh(&vr)
    }

    /// Area-weighted mean radiosity of every object of `scene`, with
    /// `rho * ambient` added when `with_ambient`.
    #[must_use]
    pub fn object_radiosity(&self, scene: &Scene, with_ambient: bool) -> Vec<ObjectRadiosity> {
        let ambient = if with_ambient {
            self.ambient
        } else {
            Rgb::ZERO
        };
        object_means(scene, self.mesh, |k, surface| {
            self.radiosity.element(k) + surface.reflectance * ambient
        })
    }
}
