//! Patches small enough to place textured emission where it is.
//!
//! Receivers gather light from patches, each seen as one constant radiosity:
//! a patch's emission is the mean of its emissive texture. A quad that is
//! black but for a small bright square, cut into patches of the usual size,
//! would spread the square's power over a whole patch and light its
//! surroundings from the wrong place. A surface with an emissive texture is
//! therefore cut finer, halving the patch size (at most
//! [`MAX_HALVINGS`] times, and while its patch count stays within
//! [`MAX_EMISSION_PATCHES`]) until the emission within every patch is even:
//! each patch's four quarters differ from its mean by at most
//! [`EVEN_EMISSION`] of the surface's brightest patch. Elements below the
//! patches take their own footprint's emission, so the light drawn on the
//! emitter keeps its detail either way.

use super::lattice::{patch_count, SurfaceLattice};
use super::Cell;
use crate::math::Rgb;
use crate::scene::{Scene, Surface, Texture, EMISSION_DEPTH};

/// The patch size of a surface with an emissive texture is halved at most
/// this many times (patches 16 times smaller along each edge).
pub(crate) const MAX_HALVINGS: u32 = 4;

/// A surface is cut finer for its emission only while it keeps at most this
/// many patches.
pub(crate) const MAX_EMISSION_PATCHES: u64 = 4096;

/// Emission counts as even over a patch when its quarters differ from its
/// mean by at most this fraction of the surface's brightest patch.
pub(crate) const EVEN_EMISSION: f64 = 0.1;

/// The patch size for `surface` (whose texture coordinates `emissive` reads):
/// `patch_size`, or a power-of-two fraction of it small enough that the
/// emission within each patch is even.
pub(crate) fn resolving_patch_size(surface: &Surface, emissive: &Texture, patch_size: f64) -> f64 {
    let mut size = patch_size;
    for _ in 0..MAX_HALVINGS {
        if is_even(surface, emissive, size) {
            break;
        }
        let finer = size / 2.0;
        if patch_count(surface, finer) > MAX_EMISSION_PATCHES {
            break;
        }
        size = finer;
    }
    size
}

/// True when, cut at `size`, every patch of `surface` emits evenly.
pub(crate) fn is_even(surface: &Surface, emissive: &Texture, size: f64) -> bool {
    let (mut lattice, cells) = SurfaceLattice::new(surface, Rgb::ZERO, Rgb::ZERO, size, 0);
    lattice.uv = surface.uv.clone();
    let mean = |cell: &Cell| emissive.mean_over_refined(&lattice.cell_uv(cell), EMISSION_DEPTH);
    let means: Vec<Rgb> = cells.iter().map(mean).collect();
    let brightest = means.iter().map(|m| m.max_band()).fold(0.0, f64::max);
    if brightest <= 0.0 {
        return true;
    }
    cells.iter().zip(&means).all(|(cell, &m)| {
        cell.children()
            .iter()
            .all(|q| (mean(q) - m).abs().max_band() <= EVEN_EMISSION * brightest)
    })
}

/// The emissive texture of `surface`'s material when the surface has the
/// coordinates to read it.
pub(crate) fn emissive_texture<'a>(scene: &'a Scene, surface: &Surface) -> Option<&'a Texture> {
    let texture = scene.material_of(surface).emissive_texture.as_deref()?;
    (surface.uv.len() == surface.vertices.len()).then_some(texture)
}
