//! Adaptive subdivision: where neighbouring elements differ by more than a
//! tolerance, split them, keeping the quadtree balanced.

mod contrast;
mod criterion;
mod facing;
mod sources;

pub(crate) use contrast::Contrast;
pub(crate) use criterion::{mark_for_split, Marks, SplitLimits};
pub(crate) use facing::mark_facing;
pub(crate) use sources::mark_sources;

use crate::error::{Error, Result};

/// How the mesh is refined.
#[derive(Clone, Debug, PartialEq)]
pub struct RefineSettings {
    /// `None` for adaptive refinement; `Some(d)` subdivides every patch to depth
    /// `d` uniformly and does not adapt (for comparisons).
    pub uniform_depth: Option<u8>,
    /// Depth every patch is split to before the first solve (adaptive mode);
    /// face clusters stay whole, their surfaces being their elements.
    pub initial_depth: u8,
    /// Split when neighbouring radiosities differ by more than this fraction of
    /// the brighter neighbour's reflected radiosity, or of `dim_floor` times
    /// the scene's brightest where that is more, in any band.
    pub tolerance: f64,
    /// The least scale a difference is measured against, as a fraction of the
    /// scene's brightest reflected radiosity, in (0, 1]. At 1 (the default)
    /// every difference is measured against the brightest; lower values
    /// refine dim regions as finely as bright ones, down to that fraction,
    /// for many more elements.
    pub dim_floor: f64,
    /// The same floor for a pair of neighbours of which either sees
    /// surfaces close by: nearer than its own size over more than
    /// [`NEAR_SHARE`] of its view (its row's [`crate::formfactor::Row::near`]).
    /// There the light changes across the element (a bench's shadow on the
    /// floor under it, the inside of a corner), and a dim region's contact
    /// shadows are refined as bright ones are, without refining every dim
    /// surface; the lower of this and `dim_floor` applies.
    pub near_floor: f64,
    /// Also split leaves that a surface facing them stands closer to than
    /// they are wide (a seat over a floor, a bench's back before a wall),
    /// whatever their radiosities say: a shadow narrower than a leaf leaves
    /// no mark on neighbour differences (see `crate::refine::mark_facing`).
    /// On by default.
    pub facing_split: bool,
    /// Deepest element below a patch.
    pub max_depth: u8,
    /// Smallest element area (square metres); `None` derives it from the scene.
    pub min_element_area: Option<f64>,
    /// Most leaf elements the mesh may hold (no limit by default: the memory
    /// limit, `crate::Settings::max_memory`, decides).
    pub max_elements: usize,
    /// Most refinement passes.
    pub max_passes: usize,
    /// Split a source patch whose own elements spread by more than this
    /// fraction of the brightest reflected radiosity (its children become
    /// patches). `None` never splits sources.
    pub source_tolerance: Option<f64>,
    /// Source-splitting rounds before element refinement (each recomputes every
    /// row, since rows refer to patches).
    pub source_passes: usize,
    /// Deepest level, below the initial patch cut, that a patch may reach.
    pub max_patch_depth: u8,
}

impl Default for RefineSettings {
    fn default() -> Self {
        RefineSettings {
            uniform_depth: None,
            initial_depth: 1,
            tolerance: 0.05,
            dim_floor: DEFAULT_DIM_FLOOR,
            near_floor: DEFAULT_NEAR_FLOOR,
            facing_split: true,
            max_depth: 4,
            min_element_area: None,
            max_elements: usize::MAX,
            max_passes: 8,
            // Off by default: with exposure-weighted patch rows, smaller patches
            // buy more accuracy per second on the Cornell box (see the README).
            source_tolerance: None,
            source_passes: 2,
            max_patch_depth: 2,
        }
    }
}

/// The default [`RefineSettings::dim_floor`].
pub(crate) const DEFAULT_DIM_FLOOR: f64 = 1.0;

/// The default [`RefineSettings::near_floor`]: 1, the same scale as the
/// rest. At 0.1 the atrium's error falls by a third at 10 000 triangles for
/// 1.07x the CPU time, but in a room lit from inside (the Cornell box) most
/// leaves along its edges and corners are near and their refinement costs
/// 1.3x (see `papers/substructuring.md`).
pub(crate) const DEFAULT_NEAR_FLOOR: f64 = 1.0;

/// The share of a leaf's view (form factor) that surfaces nearer than the
/// leaf's own size must exceed for [`RefineSettings::near_floor`] to apply
/// to it. A floor leaf beside one wall sees about 0.21 of its view that
/// close and one in the corner of two walls about 0.4, at the threshold (the
/// hemi-cube's pixels decide); one under the middle of a seat whose height
/// is below the leaf's size sees 0.4 to 0.6. Lower, every wall's foot is
/// refined in every dim room; higher, the benches' shadows are not (0.5
/// kept nearly none of the atrium's gain).
pub const NEAR_SHARE: f64 = 0.4;

impl RefineSettings {
    /// Checks ranges; the error names the setting.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, message: String| Err(Error::Setting { name, message });
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return bad(
                "refine.tolerance",
                format!("must be positive, got {}", self.tolerance),
            );
        }
        if !(self.dim_floor > 0.0 && self.dim_floor <= 1.0) {
            return bad(
                "refine.dim_floor",
                format!("must be in (0, 1], got {}", self.dim_floor),
            );
        }
        if !(self.near_floor > 0.0 && self.near_floor <= 1.0) {
            return bad(
                "refine.near_floor",
                format!("must be in (0, 1], got {}", self.near_floor),
            );
        }
        let deepest = self
            .uniform_depth
            .unwrap_or(self.max_depth)
            .max(self.initial_depth);
        if self.uniform_depth.is_none() && self.initial_depth > self.max_depth {
            return bad(
                "refine.initial_depth",
                format!(
                    "{} is deeper than `refine.max_depth`, {}: refinement could never split below \
                     it, and the elements it makes are deeper than allowed",
                    self.initial_depth, self.max_depth
                ),
            );
        }
        if deepest > crate::mesh::MAX_DEPTH {
            return bad(
                "refine.max_depth",
                format!("{deepest} exceeds the lattice's {}", crate::mesh::MAX_DEPTH),
            );
        }
        if let Some(a) = self.min_element_area {
            if !(a.is_finite() && a >= 0.0) {
                return bad("refine.min_element_area", format!("must be >= 0, got {a}"));
            }
        }
        Ok(())
    }
}
