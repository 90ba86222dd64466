//! A solution's light groups: each group's radiosity on the one refined
//! mesh, and views of the solution as if only one group shone.

use super::emission_mask::{mask, unmask};
use super::Solution;
use crate::mesh::ShadingMesh;
use crate::scene::light_groups::LightGroups;
use crate::solve::KeptShapes;
use crate::solve::Radiosity;
use std::sync::Arc;

/// What a solution holds of its light groups.
#[derive(Clone, Debug, Default)]
pub(crate) struct GroupParts {
    /// The last shaped gather's factors, kept by the driver for the groups
    /// and dropped once they are solved.
    pub kept_shapes: Option<Arc<KeptShapes>>,
    /// The groups solved (empty when the solve made none).
    pub groups: LightGroups,
    /// Per scene surface, the group whose light it emits.
    pub surface_group: Vec<Option<u32>>,
    /// Per group, its radiosity on every element and patch.
    pub radiosity: Vec<Radiosity>,
    /// Seconds the groups took after the solve.
    pub seconds: f64,
}

impl Solution {
    /// The light groups this solution was solved with (none unless it came
    /// from [`crate::light_groups::solve_with_light_groups`]). The solution's
    /// own radiosity is then their sum.
    #[must_use]
    pub fn light_groups(&self) -> &LightGroups {
        &self.light_groups.groups
    }

    /// Group `g`'s radiosity on every element and patch.
    ///
    /// # Panics
    ///
    /// For `g` not below the number of [`Self::light_groups`].
    #[must_use]
    pub fn group_radiosity(&self, g: usize) -> &Radiosity {
        &self.light_groups.radiosity[g]
    }

    /// Seconds the light groups took once the mesh was refined (0 without
    /// groups).
    #[must_use]
    pub fn light_group_seconds(&self) -> f64 {
        self.light_groups.seconds
    }

    /// Runs `f` on this solution as if only light group `g` shone: its
    /// radiosity in place of the sum, and emission only on the group's
    /// surfaces (so that what is derived from radiosity minus emission, the
    /// light under textures and on partly covered leaves, is the group's).
    /// Everything is put back before returning.
    ///
    /// # Panics
    ///
    /// For `g` not below the number of [`Self::light_groups`].
    pub fn with_group<R>(&mut self, g: usize, f: impl FnOnce(&Solution) -> R) -> R {
        let saved = mask(
            &mut self.mesh,
            &self.light_groups.surface_group,
            Some(g as u32),
            1.0,
        );
        std::mem::swap(&mut self.radiosity, &mut self.light_groups.radiosity[g]);
        let out = f(self);
        std::mem::swap(&mut self.radiosity, &mut self.light_groups.radiosity[g]);
        unmask(&mut self.mesh, saved);
        out
    }

    /// The display mesh of each light group (see [`Self::shading_mesh`]):
    /// the same vertices and triangles as the whole solution's, with the
    /// group's radiosity (and, on textured surfaces, irradiance).
    pub fn group_shading_meshes(&mut self) -> Vec<ShadingMesh> {
        (0..self.light_groups.radiosity.len())
            .map(|g| self.with_group(g, Solution::shading_mesh))
            .collect()
    }
}
