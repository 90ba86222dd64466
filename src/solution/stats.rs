//! Figures of a solve, serialisable as the stats JSON.

use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::Mesh;
use crate::solve::{GatherTotals, PatchSystem, Radiosity, SolveReport};
use serde::Serialize;

/// Wall-clock seconds per stage.
#[derive(Clone, Debug, Default, Serialize)]
pub struct StageSeconds {
    /// Cutting surfaces into patches and the initial elements.
    pub mesh: f64,
    /// Hemi-cube rows, all passes.
    pub form_factors: f64,
    /// Gauss-Seidel and gathers, all passes.
    pub solve: f64,
    /// The whole library solve.
    pub total: f64,
}

/// Hemi-cube figures.
#[derive(Clone, Debug, Default, Serialize)]
pub struct HemicubeFigures {
    /// Pixels across the top face.
    pub resolution: usize,
    /// Hemi-cubes rendered (one per leaf element row).
    pub hemicubes: u64,
    /// Polygon-face pairs scan converted.
    pub polygons_rasterized: u64,
    /// Pixels depth-tested.
    pub pixels_tested: u64,
    /// Polygon-hemi-cube pairs dropped before projection: the polygon is on
    /// the receiver's own surface, wholly behind or on its plane, or edge-on.
    pub polygons_culled: u64,
    /// Polygon-hemi-cube pairs never drawn because what the hemi-cube had
    /// already drawn hid their whole BVH node (occlusion culling).
    pub polygons_hidden: u64,
    /// Element-to-patch form factors stored.
    pub element_form_factors: usize,
    /// Patch-to-patch form factors stored.
    pub patch_form_factors: usize,
    /// Mean element row sum: 1 in a closed scene where no element sees a
    /// back face (the energy balance says where the rest goes).
    pub mean_row_sum: f64,
    /// Largest element row sum.
    pub max_row_sum: f64,
    /// Emitter polygons whose visibility from a row's receiving point was
    /// found exactly (by clipping, else by shadow rays), summed over rows.
    pub emitters_exact: u64,
    /// Emitter polygons seen as less than a pixel by a row that sees many
    /// emitter polygons: Lambert's formula times one shadow ray each.
    pub emitters_one_ray: u64,
    /// Emitter polygons of patches the item buffer saw whole or hidden, in
    /// rows that see many emitter polygons: taken as the pixels saw them.
    pub emitters_by_pixels: u64,
}

/// The energy balance of the final gather, per band and summed over bands.
///
/// Emitted light ends absorbed by a surface, absorbed by the back of a
/// single-sided surface (which blocks light and reflects none), or out of
/// the scene. Each element's row says how much of its view each of the
/// three fills, so the balance holds element by element up to the errors
/// of the form factors.
#[derive(Clone, Debug, Default, Serialize)]
pub struct EnergyBalance {
    /// Emitted power per band, sum of `A E`.
    pub emitted_power: Rgb,
    /// Power absorbed by surfaces per band, sum of `A (1 - rho) H`.
    pub absorbed_power: Rgb,
    /// Power absorbed by back faces per band: `A B` times the back faces'
    /// form factor, summed over elements.
    pub back_face_power: Rgb,
    /// Power that leaves the scene per band: `A B` times the form factor of
    /// the part of the view where nothing lies, summed over elements (0 in a
    /// closed scene).
    pub escaped_power: Rgb,
    /// `(absorbed + back faces - emitted) / emitted`, bands summed: 0 in a
    /// closed scene, up to the errors of the form factors; negative where
    /// light escapes an open scene.
    pub relative_difference: f64,
    /// `(absorbed + back faces + escaped - emitted) / emitted`, bands
    /// summed: 0 in any scene, open or closed, up to the errors of the form
    /// factors (the books of an open scene, where `relative_difference`
    /// only says how much escaped).
    pub balance_with_escape: f64,
    /// True when less than [`CLOSED_ESCAPE`] of the emitted power escapes:
    /// `relative_difference` then measures how well the solution conserves
    /// energy, and a warning says so when it is off by more than
    /// [`ENERGY_WARNING`].
    pub closed: bool,
    /// True when the solve kept a fixed number of reflections
    /// ([`Settings::bounces`](crate::Settings::bounces)), or a progressive solve stopped before its
    /// unshot power met the tolerance (a shot limit or a time budget): the
    /// light still travelling is in neither figure, so `relative_difference`
    /// is negative even in a closed scene. It then measures the truncation,
    /// not an error.
    pub truncated: bool,
}

/// A scene from which less than this fraction of the emitted power escapes
/// counts as closed for the energy balance (see [`EnergyBalance::closed`]).
pub const CLOSED_ESCAPE: f64 = 1e-3;

/// A closed scene whose absorbed power (surfaces and back faces) differs from
/// its emitted power by more than this fraction gets a warning: the form
/// factors lose or create that much light.
pub const ENERGY_WARNING: f64 = 0.01;

/// Work the solve left out because the scene did not need it (see
/// [`crate::pipeline::Skips`]).
#[derive(Clone, Debug, Default, Serialize)]
pub struct SkipStats {
    /// Element rows not computed: their surface reflects nothing.
    pub zero_reflectance_rows: u64,
    /// Coarse solves and gathers run on one band instead of three: every
    /// material is grey.
    pub grey_solves: usize,
    /// Rows given by the exact unoccluded form factor with no hemi-cube (a
    /// convex enclosure).
    pub exact_rows: u64,
    /// Hemi-cube faces nothing was drawn into, neither cleared nor read out.
    pub empty_faces: u64,
    /// Hemi-cube pixels outside the rectangle drawn into on their face
    /// (empty faces included), neither cleared nor read out.
    pub pixels_skipped: u64,
    /// Back faces hemi-cubes did not draw because front faces of their own
    /// closed object hid them (summed over hemi-cubes).
    pub back_faces_skipped: u64,
    /// Patch rows re-summed by refinement passes (only patches with new
    /// leaves; each pass would otherwise re-sum them all).
    pub patch_rows_refreshed: usize,
    /// Groups of neighbouring facets that started with one shared row
    /// ([`crate::Settings::shared_rows`]).
    pub row_groups: usize,
    /// Rows copied from a group's lead instead of rendered.
    pub rows_shared: u64,
    /// Facets that later got rows of their own because their group differed
    /// from a neighbouring one.
    pub groups_unshared: usize,
}

/// One refinement pass.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PassStats {
    /// Pass number, from 1.
    pub pass: usize,
    /// Leaves the criterion split.
    pub split: usize,
    /// Of those, the leaves split because a surface facing them stands
    /// closer than they are wide ([`crate::refine::RefineSettings::facing_split`]).
    pub facing: usize,
    /// Leaf elements after the pass (including splits for balance).
    pub elements: usize,
    /// Hemi-cubes computed in the pass.
    pub new_hemicubes: usize,
    /// Seconds the pass took.
    pub seconds: f64,
    /// Largest neighbour difference before the pass, relative to the brightest
    /// reflected radiosity.
    pub max_neighbour_difference: f64,
    /// Leaves over the tolerance that could not split (depth, size, budget).
    pub blocked: usize,
}

/// One round of source-patch splitting.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SourcePassStats {
    /// Patches split into four.
    pub patches_split: usize,
    /// Patches after the round.
    pub patches: usize,
    /// Leaf elements.
    pub elements: usize,
    /// Leaves whose rows were rendered anew (new leaves, and those that saw a
    /// split patch in part or a split emitter); the others had their entries
    /// for the split patches derived exactly.
    pub rows_rendered: usize,
    /// Seconds the round took.
    pub seconds: f64,
}

/// What the punctual lights' direct light cost and brought.
#[derive(Clone, Debug, Default, Serialize)]
pub struct DirectFigures {
    /// Punctual lights in the scene.
    pub lights: usize,
    /// Shadow rays cast from the leaves' quadrature points to the lights.
    pub shadow_rays: u64,
    /// Seconds spent on the direct light (included in no other stage).
    pub seconds: f64,
    /// Power the lights deliver to the final leaves, `sum A Hd` per band
    /// (lm, in the scene's units; see [`crate::scene::Light`]).
    pub incident_power: crate::math::Rgb,
}

/// Everything the library measured.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SolveStats {
    /// Scene surfaces.
    pub surfaces: usize,
    /// Patches.
    pub patches: usize,
    /// Leaf elements.
    pub elements: usize,
    /// Patch size used, metres.
    pub patch_size: f64,
    /// Seconds per stage.
    pub seconds: StageSeconds,
    /// Hemi-cube figures.
    pub hemicube: HemicubeFigures,
    /// The final coarse solve.
    pub solver: SolveReport,
    /// Gauss-Seidel sweeps over all passes.
    pub total_iterations: usize,
    /// Energy balance of the final solution.
    pub energy: EnergyBalance,
    /// Source-splitting rounds.
    pub source_passes: Vec<SourcePassStats>,
    /// Refinement passes.
    pub passes: Vec<PassStats>,
    /// Per shaped gather ([`Settings::shaped_gathers`](crate::Settings::shaped_gathers)), the patches seen by
    /// their parts because their elements differ.
    pub shaped_sources: Vec<usize>,
    /// Per shaped gather, how many times the patch radiosities were solved
    /// again for what it changed and its ratios taken again from the new
    /// values (see `crate::solve::source_shape`).
    pub shaped_corrections: Vec<usize>,
    /// Per shaped gather, how many receivers drew a hemi-cube again to see
    /// a near patch part by part, something hiding part of it from them.
    pub shaped_views: Vec<usize>,
    /// Largest remaining neighbour difference (relative), at the last check.
    pub final_max_difference: f64,
    /// What was computed: `None` (JSON `null`) the full solution, `Some(n)`
    /// emitted light and exactly `n` reflections ([`Settings::bounces`](crate::Settings::bounces)).
    pub bounces: Option<u32>,
    /// Work left out because the scene did not need it.
    pub skips: SkipStats,
    /// Shots, unshot power and the other figures of a progressive solve
    /// (`None` for Gauss-Seidel).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub progressive: Option<super::ProgressiveStats>,
    /// Punctual lights' direct light (`None` when the scene has none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub direct: Option<DirectFigures>,
    /// Heap bytes held by the final mesh and patch system (an estimate).
    pub memory: MemoryFigures,
    /// What the caller should know about the result: a closed scene whose
    /// energy balance is off by more than [`ENERGY_WARNING`], refinement
    /// stopped by the element or memory budget.
    pub warnings: Vec<String>,
}

impl EnergyBalance {
    /// The balance of a solution's power `totals`; `truncated` when it kept a
    /// fixed number of reflections.
    #[must_use]
    pub fn of(totals: &GatherTotals, truncated: bool) -> Self {
        let sum = |x: Rgb| x.0.iter().sum::<f64>();
        let e = sum(totals.emitted);
        let ended = sum(totals.absorbed) + sum(totals.back_faces);
        EnergyBalance {
            emitted_power: totals.emitted,
            absorbed_power: totals.absorbed,
            back_face_power: totals.back_faces,
            escaped_power: totals.escaped,
            relative_difference: if e > 0.0 { (ended - e) / e } else { 0.0 },
            balance_with_escape: if e > 0.0 {
                (ended + sum(totals.escaped) - e) / e
            } else {
                0.0
            },
            closed: e > 0.0 && sum(totals.escaped) <= CLOSED_ESCAPE * e,
            truncated,
        }
    }

    /// The warning for a closed scene whose balance is off by more than
    /// [`ENERGY_WARNING`] (none for a truncated solution, which leaves light
    /// in flight on purpose).
    #[must_use]
    pub fn warning(&self) -> Option<String> {
        let off = self.relative_difference;
        let off_by_much = off.is_nan() || off.abs() > ENERGY_WARNING;
        (self.closed && !self.truncated && off_by_much).then(|| {
            format!(
                "the scene is closed, but the power absorbed differs from the power emitted \
                 by {:+.2}% (more than {}%): the form factors {} light; finer patches or a \
                 finer hemi-cube may help",
                100.0 * off,
                100.0 * ENERGY_WARNING,
                if off < 0.0 { "lose" } else { "create" }
            )
        })
    }
}

/// Heap bytes held by a mesh and its patch system, estimated from the
/// capacities of their containers and the sizes of their types (`size_of`):
/// what the allocator was asked for, without its own overhead. Every element
/// node (interior ones too) counts, but only leaves hold rows.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MemoryFigures {
    /// The element arena: one slot per allocated element node (capacity plus
    /// the arena's reserved slot), each `size_of::<Element>()` plus the
    /// arena's 32-bit version, padded to the element's alignment. Children
    /// (up to four keys) and the row's header are inside the element.
    pub element_arena_bytes: usize,
    /// The leaves' form-factor rows: 8 bytes per stored entry (a 32-bit patch
    /// id and a single-precision factor), allocated exactly.
    pub row_bytes: usize,
    /// The row store's table: one slot per element key, with the row's
    /// state.
    pub row_table_bytes: usize,
    /// Element and patch radiosities: one value per element node (in a
    /// table keyed by element) and per patch.
    pub radiosity_bytes: usize,
    /// Stored row entries over all elements.
    pub row_entries: usize,
    /// Patches: `size_of::<Patch>()` per slot of capacity, plus the polygons
    /// of more than four vertices that left their inline storage.
    pub patch_bytes: usize,
    /// Surface lattices (the surfaces' vertices and patch cuts, with the
    /// triangle cuts' cell maps at one control byte per entry) and the
    /// quadtree roots.
    pub lattice_bytes: usize,
    /// The sum of the figures above: the mesh and what the solve keeps per
    /// element.
    pub mesh_bytes: usize,
    /// The patch system: double-precision patch rows (16 bytes per entry),
    /// reflectances and emissions.
    pub system_bytes: usize,
    /// `mesh_bytes` over leaf elements (0 with none).
    pub mesh_bytes_per_element: f64,
    /// `row_bytes` over leaf elements (0 with none).
    pub row_bytes_per_element: f64,
}

impl MemoryFigures {
    /// The figures of `mesh` and `system` as they stand.
    #[must_use]
    pub fn of(
        mesh: &Mesh,
        form_factors: &FormFactors,
        radiosity: &Radiosity,
        system: &PatchSystem,
    ) -> Self {
        use crate::mesh::{Element, Patch, PatchGrid, SurfaceLattice};
        use std::mem::{align_of, size_of};
        let slot = (size_of::<Element>() + 4).next_multiple_of(align_of::<Element>().max(4));
        let element_arena_bytes = (mesh.elements.capacity() + 1) * slot;
        let leaves = mesh.elements.values().filter(|e| e.is_leaf()).count();
        let row_bytes = form_factors.row_bytes();
        let row_table_bytes = form_factors.table_bytes();
        let radiosity_bytes = radiosity.heap_bytes();
        let row_entries = form_factors.row_entries();
        let vertex = size_of::<glam::DVec3>();
        let patch_bytes = mesh.patches.capacity() * size_of::<Patch>()
            + mesh
                .patches
                .iter()
                .filter(|p| p.polygon.spilled())
                .map(|p| p.polygon.capacity() * vertex)
                .sum::<usize>();
        let lattice_bytes = mesh.surfaces.capacity() * size_of::<SurfaceLattice>()
            + mesh
                .surfaces
                .iter()
                .map(|s| {
                    let spilled = if s.vertices.spilled() {
                        s.vertices.capacity() * vertex
                    } else {
                        0
                    };
                    let cells = match &s.grid {
                        PatchGrid::Tri { cells, .. } => {
                            cells.capacity() * (size_of::<(crate::mesh::Cell, u32)>() + 1)
                        }
                        PatchGrid::Quad { .. } => 0,
                    };
                    spilled + cells
                })
                .sum::<usize>()
            + mesh.top_roots.capacity() * size_of::<crate::mesh::ElementKey>();
        let mesh_bytes = element_arena_bytes
            + row_bytes
            + row_table_bytes
            + radiosity_bytes
            + patch_bytes
            + lattice_bytes;
        let rgb = size_of::<Rgb>();
        let system_bytes = system.rows.capacity() * size_of::<Vec<(u32, f64)>>()
            + system
                .rows
                .iter()
                .map(|r| r.capacity() * size_of::<(u32, f64)>())
                .sum::<usize>()
            + (system.reflectance.capacity() + system.emission.capacity()) * rgb;
        let per = |bytes: usize| {
            if leaves == 0 {
                0.0
            } else {
                bytes as f64 / leaves as f64
            }
        };
        MemoryFigures {
            element_arena_bytes,
            row_bytes,
            row_table_bytes,
            radiosity_bytes,
            row_entries,
            patch_bytes,
            lattice_bytes,
            mesh_bytes,
            system_bytes,
            mesh_bytes_per_element: per(mesh_bytes),
            row_bytes_per_element: per(row_bytes),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn totals(emitted: f64, absorbed: f64, back_faces: f64, escaped: f64) -> GatherTotals {
        GatherTotals {
            emitted: Rgb::splat(emitted),
            absorbed: Rgb::splat(absorbed),
            back_faces: Rgb::splat(back_faces),
            escaped: Rgb::splat(escaped),
        }
    }

    #[test]
    fn back_faces_count_as_absorbers_in_the_balance() {
        let e = EnergyBalance::of(&totals(1.0, 0.9, 0.1, 0.0), false);
        assert!(e.closed);
        assert!(e.relative_difference.abs() < 1e-15, "{e:?}");
        assert!(e.warning().is_none());
    }

    #[test]
    fn a_closed_scene_off_by_more_than_the_threshold_is_warned_about() {
        let off = 1.5 * ENERGY_WARNING;
        let lost = EnergyBalance::of(&totals(1.0, 1.0 - off, 0.0, 0.0), false);
        let w = lost.warning().expect("a warning");
        assert!(w.contains("lose") && w.contains("closed"), "{w}");
        let made = EnergyBalance::of(&totals(1.0, 1.0 + off, 0.0, 0.0), false);
        assert!(made.warning().expect("a warning").contains("create"));
        // Within the threshold, truncated on purpose, or open: nothing.
        let near = EnergyBalance::of(&totals(1.0, 1.0 - 0.5 * ENERGY_WARNING, 0.0, 0.0), false);
        assert!(near.warning().is_none());
        assert!(EnergyBalance::of(&totals(1.0, 0.5, 0.0, 0.0), true)
            .warning()
            .is_none());
        let open = EnergyBalance::of(&totals(1.0, 0.6, 0.0, 0.4), false);
        assert!(!open.closed && open.warning().is_none());
    }
}
