//! The view-independent solution: element and vertex radiosities.

use super::SolveStats;
use crate::math::Rgb;
use crate::mesh::{Mesh, ShadingMesh};
use crate::scene::Scene;
use crate::solve::PatchSystem;
use serde::Serialize;

/// Area and mean radiosity of one scene object (a glTF node with a mesh).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ObjectRadiosity {
    /// The object's name.
    pub name: String,
    /// Its area in square metres.
    pub area: f64,
    /// Its area-weighted mean radiosity (exitance), per band.
    pub radiosity: Rgb,
}

/// A solved scene.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The refined mesh with leaf radiosities.
    pub mesh: Mesh,
    /// Solved patch radiosities.
    pub patch_radiosity: Vec<Rgb>,
    /// The final patch system.
    pub system: PatchSystem,
    /// What the solve measured.
    pub stats: SolveStats,
}

impl Solution {
    /// Area-weighted mean radiosity of every object of `scene`, from the leaves.
    #[must_use]
    pub fn object_radiosity(&self, scene: &Scene) -> Vec<ObjectRadiosity> {
        let mut sums = vec![(0.0, Rgb::ZERO); scene.objects.len()];
        for e in self.mesh.elements.values().filter(|e| e.is_leaf()) {
            let o = self.mesh.surfaces[e.surface as usize].object as usize;
            sums[o].0 += e.area;
            sums[o].1 += e.radiosity * e.area;
        }
        scene
            .objects
            .iter()
            .zip(sums)
            .map(|(obj, (area, sum))| ObjectRadiosity {
                name: obj.name.clone(),
                area,
                radiosity: if area > 0.0 { sum / area } else { Rgb::ZERO },
            })
            .collect()
    }

    /// The crack-free display mesh with vertex radiosities.
    #[must_use]
    pub fn shading_mesh(&self) -> ShadingMesh {
        let vr = self.mesh.vertex_radiosity();
        self.mesh.shading_mesh(&vr)
    }
}
