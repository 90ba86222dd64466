//! Emission on the sources of one light group only: the mesh's emissions
//! set to 0 on every other source, and put back afterwards.

use crate::math::Rgb;
use crate::mesh::Mesh;

/// The emissions a [`mask`] replaced, for [`unmask`].
#[derive(Debug)]
pub(crate) struct SavedEmission {
    /// Per surface lattice: its emission and emissive-texture scale.
    surfaces: Vec<(Rgb, f64)>,
    /// Per element node, in the mesh's order.
    elements: Vec<Rgb>,
}

/// Keeps the emission of the surfaces whose entry in `surface_group` is
/// `keep`, each multiplied by `scale` (a power of two, see
/// `crate::light_groups`), and sets every other emission of `mesh` to 0: the
/// surfaces' (and their emissive textures' scale) and their elements'.
/// `keep` of `None` keeps every surface that emits for no group, i.e. none.
pub(crate) fn mask(
    mesh: &mut Mesh,
    surface_group: &[Option<u32>],
    keep: Option<u32>,
    scale: f64,
) -> SavedEmission {
    let kept = |s: u32| surface_group.get(s as usize).copied().flatten() == keep;
    let surfaces = mesh
        .surfaces
        .iter_mut()
        .enumerate()
        .map(|(s, lattice)| {
            let saved = (lattice.emission, lattice.emission_scale);
            let factor = if kept(s as u32) { scale } else { 0.0 };
            lattice.emission *= factor;
            lattice.emission_scale *= factor;
            saved
        })
        .collect();
    let elements = mesh
        .elements
        .values_mut()
        .map(|e| {
            let saved = e.emission;
            e.emission = if kept(e.surface) {
                e.emission * scale
            } else {
                Rgb::ZERO
            };
            saved
        })
        .collect();
    SavedEmission { surfaces, elements }
}

/// Puts back the emissions [`mask`] replaced.
pub(crate) fn unmask(mesh: &mut Mesh, saved: SavedEmission) {
    for (lattice, (emission, scale)) in mesh.surfaces.iter_mut().zip(saved.surfaces) {
        lattice.emission = emission;
        lattice.emission_scale = scale;
    }
    for (e, emission) in mesh.elements.values_mut().zip(saved.elements) {
        e.emission = emission;
    }
}
