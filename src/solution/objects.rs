//! Per-object figures: what users compare against references.

use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh, SurfaceLattice};
use crate::scene::Scene;
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

/// The area-weighted mean over the leaves of each object of `scene` of
/// `value(leaf, its surface)`. Objects are read from `scene`'s surfaces, so a
/// scene regrouped into other objects over the same surfaces (such as
/// [`Scene::regions_by_grid`]) gives the means of those.
pub(crate) fn object_means(
    scene: &Scene,
    mesh: &Mesh,
    value: impl Fn(ElementKey, &SurfaceLattice) -> Rgb,
) -> Vec<ObjectRadiosity> {
    let mut sums = vec![(0.0, Rgb::ZERO); scene.objects.len()];
    for (k, e) in mesh.elements.iter().filter(|(_, e)| e.is_leaf()) {
        let surface = &mesh.surfaces[e.surface as usize];
        let slot = &mut sums[scene.surfaces[e.surface as usize].object as usize];
        slot.0 += e.area;
        slot.1 += value(k, surface) * e.area;
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
