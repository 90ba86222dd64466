//! Surfaces that lie on top of each other, facing the same way: a light flush
//! with the ceiling it hangs from, a decal on a wall, the stacked layers of a
//! logo, coincident duplicates. The hemi-cube's depth test cannot order them:
//! whichever is drawn first wins every pixel, so the other is hidden from the
//! whole scene (a flush light leaves the room black).
//!
//! [`Overlaps::Resolve`] (the default) repairs the scene: the surface on top
//! covers its footprint, which is cut out of the surface below (see
//! [`Scene::resolve_overlaps`] for the rule); [`Overlaps::Error`] refuses the
//! scene with a message naming the pairs, as the solve does for a scene that
//! still has them.
//!
//! Finding the pairs takes `O(n log n)` for `n` surfaces plus the pairs of
//! coplanar surfaces whose bounding boxes overlap: surfaces are sorted into
//! planes, exact duplicates are found by hashing, and the rest are paired
//! through a bounding-box tree per plane ([`pairs`]).

mod cut;
mod pairs;
mod report;

use crate::error::Result;
use crate::scene::Scene;
use pairs::{find_overlaps, Scope};
use std::str::FromStr;

/// Planes closer than this fraction of the size of the two surfaces (the
/// diagonal of the box of both; at most of the scene's size,
/// [`Scene::extent`]) count as one. The item buffer keeps 1/depth in single
/// precision, stepped along each span, so it can misorder surfaces whose
/// depths differ by less than about `n * 1.2e-7` relative at a resolution of
/// `n` (1.5e-5 at 128): such a gap is as good as none for a receiver as far
/// away as the surfaces are large. Receivers farther away see them as a
/// speck, where a misordered pixel matters little.
pub const COPLANAR_GAP: f64 = 1e-5;

/// What to do with coplanar surfaces that overlap, facing the same way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Overlaps {
    /// Cut the footprint of the surface on top out of the one below, and keep
    /// one of coincident duplicates; one warning lists the pairs.
    #[default]
    Resolve,
    /// Refuse the scene, naming every pair whose materials differ (pairs of
    /// one material look the same whichever the hemi-cube draws, and are
    /// left as they are).
    Error,
}

impl FromStr for Overlaps {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "resolve" => Ok(Overlaps::Resolve),
            "error" => Ok(Overlaps::Error),
            _ => Err(format!("unknown overlap policy '{s}' (resolve or error)")),
        }
    }
}

/// Fails with an [`Error::Geometry`](crate::Error::Geometry) naming the pairs
/// of objects that overlap in one plane, facing the same way, with materials
/// that differ.
pub(crate) fn check_coplanar_overlaps(scene: &Scene) -> Result<()> {
    let found = find_overlaps(scene, Scope::DifferentMaterials);
    if found.is_empty() {
        Ok(())
    } else {
        Err(report::refusal(scene, &found))
    }
}

impl Scene {
    /// Resolves (or, with [`Overlaps::Error`], refuses) coplanar surfaces that
    /// overlap, facing the same way.
    ///
    /// Two surfaces are coplanar when their normals agree to 1e-3 and every
    /// vertex of each lies within [`COPLANAR_GAP`] of their own size (at most
    /// of the scene's, [`Scene::extent`]) of the other's plane; they overlap
    /// when their polygons share more than 1e-9 of the scene's size across
    /// (sharing an edge is not overlapping).
    ///
    /// Of two overlapping coplanar surfaces, the one **on top** is, in order:
    ///
    /// 1. the one whose object has the smaller area in that plane (a decal, a
    ///    light, a logo's detail layer lies on a larger wall, ceiling or
    ///    background, whichever is nearer the viewer by less than the gap);
    /// 2. at equal object areas (one object, or copies of one), the smaller
    ///    surface;
    /// 3. at equal areas, the later surface in the scene's order (for a glTF
    ///    file, the layer that comes later in the file).
    ///
    /// The covered part of the surface below neither receives nor emits light:
    /// it is cut away, and the surface is replaced by the convex pieces of it
    /// outside every surface on top of it, each a triangle or convex quad of
    /// its material and object (pieces thinner than [`COPLANAR_GAP`] of the
    /// scene's size are dropped). Surfaces with exactly the same vertices count
    /// once: the one on top stays. One warning in [`Scene::warnings`] gives
    /// the number of pairs and names the first few by object;
    /// [`ImportStats`](crate::scene::ImportStats) counts them.
    ///
    /// # Errors
    ///
    /// With [`Overlaps::Error`], an [`Error::Geometry`](crate::Error::Geometry)
    /// naming the pairs whose materials differ (the solve's own check).
    pub fn resolve_overlaps(&mut self, policy: Overlaps) -> Result<()> {
        match policy {
            Overlaps::Error => check_coplanar_overlaps(self),
            Overlaps::Resolve => {
                let found = find_overlaps(self, Scope::All);
                if found.is_empty() {
                    return Ok(());
                }
                let warning = report::resolved(self, &found);
                let outcome = cut::apply(self, &found);
                self.import_stats.overlapping_pairs += found.pairs.len();
                self.import_stats.duplicate_surfaces += found.duplicates.len();
                self.import_stats.sliver_pieces_dropped += outcome.slivers;
                self.warnings.push(warning);
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests;
