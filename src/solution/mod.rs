//! The view-independent solution: element, patch and vertex radiosities,
//! per-object means, probes at points, and a view of each leaf.

mod emission_mask;
mod groups;
mod leaf;
mod objects;
mod probe;
mod progressive_stats;
mod stats;
mod texels;

pub(crate) use emission_mask::{mask, unmask};
pub(crate) use groups::GroupParts;
pub use leaf::Leaf;
pub(crate) use objects::object_means;
pub use objects::ObjectRadiosity;
pub use probe::{ProbeHit, ProbeTolerance, SolutionProbe};
pub use progressive_stats::{HistoryPoint, ProgressiveStats, ShootingPass, StopReason};
pub use stats::{
    DirectFigures, EnergyBalance, HemicubeFigures, MemoryFigures, PassStats, SkipStats, SolveStats,
    SourcePassStats, StageSeconds,
};
pub use stats::{CLOSED_ESCAPE, ENERGY_WARNING};
pub(crate) use texels::texel_surfaces;

use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh, ShadingMesh, TexelSurface, VertexRadiosity};
use crate::render::ShadedMesh;
use crate::scene::Scene;
use crate::solve::{PatchSystem, Radiosity};

/// A solved scene.
#[derive(Clone, Debug)]
pub struct Solution {
    pub(crate) mesh: Mesh,
    pub(crate) form_factors: FormFactors,
    pub(crate) radiosity: Radiosity,
    pub(crate) system: PatchSystem,
    pub(crate) stats: SolveStats,
    /// Per scene surface, what a textured one shows; empty when no surface
    /// is textured.
    pub(crate) texel_surfaces: Vec<Option<TexelSurface>>,
    /// The light groups' solutions, if the solve made them (see
    /// [`crate::light_groups`]).
    pub(crate) light_groups: GroupParts,
}

impl Solution {
    /// The refined mesh.
    #[must_use]
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The leaves' form-factor rows and their states (the progressive solver
    /// keeps only the states: its shots hold the entries).
    #[must_use]
    pub fn form_factors(&self) -> &FormFactors {
        &self.form_factors
    }

    /// Element and patch radiosities.
    #[must_use]
    pub fn radiosity(&self) -> &Radiosity {
        &self.radiosity
    }

    /// The solved patch radiosities, by patch id.
    #[must_use]
    pub fn patch_radiosity(&self) -> &[Rgb] {
        self.radiosity.patches()
    }

    /// The final coarse patch system (its rows are empty after a progressive
    /// solve).
    #[must_use]
    pub fn patch_system(&self) -> &PatchSystem {
        &self.system
    }

    /// What the solve measured.
    #[must_use]
    pub fn stats(&self) -> &SolveStats {
        &self.stats
    }

    /// Every leaf element with its radiosity and row, patch by patch in a
    /// stable order.
    #[must_use]
    pub fn leaves(&self) -> Vec<Leaf<'_>> {
        self.mesh
            .leaves()
            .into_iter()
            .map(|k| self.leaf(k))
            .collect()
    }

    /// Leaf `key` with its radiosity and row. Panics for a key of another
    /// mesh.
    #[must_use]
    pub fn leaf(&self, key: ElementKey) -> Leaf<'_> {
        Leaf {
            key,
            element: &self.mesh[key],
            radiosity: self.radiosity.element(key),
            row: self.form_factors.state(key),
        }
    }

    /// Area-weighted mean radiosity of every object of `scene`, from the leaves.
    #[must_use]
    pub fn object_radiosity(&self, scene: &Scene) -> Vec<ObjectRadiosity> {
        object_means(scene, &self.mesh, |k, _| self.radiosity.element(k))
    }

    /// The crack-free display mesh with vertex radiosities; on textured
    /// surfaces (a base-colour or emissive texture and texture coordinates)
    /// its vertices also carry the irradiance and texture coordinates
    /// ([`ShadingMesh::texels`]), so that displays can draw the texture's
    /// detail under smooth light.
    #[must_use]
    pub fn shading_mesh(&self) -> ShadingMesh {
        let vr = self.vertex_radiosity();
        if self.texel_surfaces.iter().all(Option::is_none) {
            return self.mesh.shading_mesh(&vr);
        }
        let light = self.mesh.vertex_irradiance(
            |s| self.texel_surfaces[s as usize].is_some(),
            |k| self.shown(k),
        );
        self.mesh
            .textured_shading_mesh(&vr, &light, &self.texel_surfaces)
    }

    /// The radiosity at the leaves' vertices that pictures and probes show:
    /// each leaf's visible part's radiosity ([`Leaf::visible_radiosity`]),
    /// weighted by its visible area (see [`Mesh::vertex_radiosity_seen`]).
    #[must_use]
    pub fn vertex_radiosity(&self) -> VertexRadiosity {
        self.mesh.vertex_radiosity_seen(|k| self.shown(k))
    }

    /// What leaf `k` shows and the share of it that can be seen: the
    /// weights of the vertex means pictures and probes are drawn from.
    fn shown(&self, k: ElementKey) -> (Rgb, f64) {
        let leaf = self.leaf(k);
        (leaf.visible_radiosity(), leaf.visible())
    }

    /// The display mesh with the radiance a camera sees at each vertex
    /// (radiosity / pi: the surfaces are diffuse), ready for
    /// [`render::render`](crate::render::render); on textured surfaces the
    /// renderer looks the texture up at every sample (see
    /// [`ShadedMesh::texels`]).
    #[must_use]
    pub fn radiance_mesh(&self) -> ShadedMesh {
        ShadedMesh::radiance_of(self.shading_mesh())
    }
}
