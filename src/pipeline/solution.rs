//! The view-independent solution: element and vertex radiosities.

use super::SolveStats;
use crate::formfactor::{FormFactors, RowState};
use crate::math::Rgb;
use crate::mesh::{Element, ElementKey, Mesh, ShadingMesh};
use crate::scene::Scene;
use crate::solve::{PatchSystem, Radiosity};
use serde::Serialize;
use std::f64::consts::PI;

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

impl ObjectRadiosity {
    /// The mean radiance a camera sees on the object: radiosity / pi, since
    /// its surfaces are diffuse.
    #[must_use]
    pub fn radiance(&self) -> Rgb {
        self.radiosity / PI
    }
}

/// A solved scene.
#[derive(Clone, Debug)]
pub struct Solution {
    pub(crate) mesh: Mesh,
    pub(crate) form_factors: FormFactors,
    pub(crate) radiosity: Radiosity,
    pub(crate) system: PatchSystem,
    pub(crate) stats: SolveStats,
}

/// A leaf element of a solution with what the solve found for it. Derefs to
/// the [`Element`]'s geometry (area, centroid, surface, cell).
#[derive(Clone, Copy, Debug)]
pub struct Leaf<'a> {
    /// Its key in the mesh.
    pub key: ElementKey,
    /// Its geometry.
    pub element: &'a Element,
    /// Its radiosity (exitance), per band.
    pub radiosity: Rgb,
    /// Its form-factor row and the row's state.
    pub row: &'a RowState,
}

impl std::ops::Deref for Leaf<'_> {
    type Target = Element;

    fn deref(&self) -> &Element {
        self.element
    }
}

impl Leaf<'_> {
    /// Its radiance (radiosity / pi): what a camera sees on a diffuse surface.
    #[must_use]
    pub fn radiance(&self) -> Rgb {
        self.radiosity / PI
    }

    /// Its row's `(patch, form factor)` entries (none unless its row is
    /// held: see [`RowState`]).
    #[must_use]
    pub fn entries(&self) -> &[(u32, f32)] {
        match self.row {
            RowState::Computed(row) => row.entries(),
            _ => &[],
        }
    }

    /// The sum of its row: the part of its hemisphere that sees a front face
    /// (0 when its row is not held).
    #[must_use]
    pub fn row_sum(&self) -> f64 {
        match self.row {
            RowState::Computed(row) => row.sum(),
            _ => 0.0,
        }
    }
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
        let mut sums = vec![(0.0, Rgb::ZERO); scene.objects.len()];
        for (k, e) in self.mesh.elements.iter().filter(|(_, e)| e.is_leaf()) {
            let o = self.mesh.surfaces[e.surface as usize].object as usize;
            sums[o].0 += e.area;
            sums[o].1 += self.radiosity.element(k) * e.area;
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
        let vr = self.mesh.vertex_radiosity(|k| self.radiosity.element(k));
        self.mesh.shading_mesh(&vr)
    }
}
