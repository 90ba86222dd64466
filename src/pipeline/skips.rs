//! Work a solve leaves out because the scene does not need it, each with a
//! switch (all on by default) so that tests and measurements can compare the
//! two paths.

use super::Settings;
use crate::formfactor::hemicube::{DeltaTable, HemicubeStats};
use crate::formfactor::{is_convex_enclosure, FormFactorMethod, RowSettings, RowSkips};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::pipeline::SolverKind;
use std::sync::Arc;

/// Which work a solve may leave out. Each skip gives the answer of the full
/// work: the same bits for all but `convex`, which gives the exact
/// unoccluded form factors where the hemi-cube approximates them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Skips {
    /// Elements of surfaces that neither reflect (in any band) nor emit get
    /// no row: their radiosity is 0 whatever they receive. The power they
    /// absorb, which the energy balance needs, is summed from the other
    /// elements' rows by reciprocity. (Emitters keep their rows even when
    /// they reflect nothing: the rows say how much of their light reaches
    /// front faces, which the balance of the rows needs, and how much back
    /// faces or the sky take.)
    pub zero_reflectance: bool,
    /// When every reflectance and emission is grey (equal bands),
    /// Gauss-Seidel and the gather run on one band and copy it.
    pub grey: bool,
    /// When the surfaces form a convex enclosure, nothing occludes anything:
    /// hybrid rows are Lambert's exact point-to-polygon form factors, with no
    /// hemi-cube (classic hemi-cube rows are left alone).
    pub convex: bool,
    /// Hemi-cubes clear and read out only the rectangle of each face that
    /// was drawn into, not whole faces.
    pub empty_faces: bool,
    /// Hemi-cubes do not draw the back faces of a closed convex object seen
    /// from outside it, which its front faces always hide. (Where a front and
    /// a back face meet at the silhouette, rounding no longer lets the back
    /// face take a pixel from the front one, so rows may differ there.)
    pub hidden_back_faces: bool,
}

impl Default for Skips {
    fn default() -> Self {
        Skips {
            zero_reflectance: true,
            grey: true,
            convex: true,
            empty_faces: true,
            hidden_back_faces: true,
        }
    }
}

impl Skips {
    /// Every skip off: the full work everywhere.
    pub const NONE: Skips = Skips {
        zero_reflectance: false,
        grey: false,
        convex: false,
        empty_faces: false,
        hidden_back_faces: false,
    };
}

/// What the rows of a solve cost and left out, over all passes.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct RowTally {
    /// Hemi-cube work, and what the hemi-cubes skipped.
    pub hemicube: HemicubeStats,
    /// Rows not computed because their surface reflects nothing.
    pub zero_reflectance_rows: u64,
}

/// How the rows of a solve are computed, with the skips decided for its
/// scene once.
pub(crate) struct RowPlan {
    /// Settings of every row.
    pub settings: RowSettings,
    /// Work the rows leave out.
    pub skips: RowSkips,
    /// Per surface, true when its elements get no rows (zero reflectance).
    rowless_surface: Vec<bool>,
    /// Per patch, the same (`None` when no surface is rowless).
    pub rowless_patch: Option<Vec<bool>>,
    /// Every reflectance and emission is grey and the skip is on.
    pub grey: bool,
}

impl RowPlan {
    /// The plan for `mesh` under `settings`. The patch flags must be brought
    /// up to date with [`RowPlan::patches_changed`] when patches are split.
    ///
    /// The progressive solver tracks the irradiance of every leaf for its
    /// energy balance and shoots in three bands, so surfaces that reflect
    /// nothing get rows there and no solve runs on one band.
    pub(super) fn new(mesh: &Mesh, settings: &Settings) -> Self {
        let skips = &settings.skips;
        let gathering = settings.solver_kind == SolverKind::GaussSeidel;
        let rowless_surface = if skips.zero_reflectance && gathering {
            rowless_surfaces(mesh)
        } else {
            vec![false; mesh.surfaces.len()]
        };
        let mut plan = RowPlan {
            settings: RowSettings {
                table: Arc::new(DeltaTable::new(settings.hemicube_resolution)),
                seed: settings.seed,
                method: settings.form_factors,
                emitter_sampling: settings.emitter_sampling,
                level_of_detail: settings.level_of_detail,
            },
            skips: RowSkips {
                unoccluded: skips.convex
                    && settings.form_factors == FormFactorMethod::Hybrid
                    && is_convex_enclosure(mesh),
                hidden_back_faces: skips.hidden_back_faces,
                empty_faces: skips.empty_faces,
            },
            rowless_surface,
            rowless_patch: None,
            grey: skips.grey
                && gathering
                && mesh.surfaces.iter().all(|s| {
                    s.texture.is_none()
                        && s.emissive_texture.is_none()
                        && s.reflectance.is_grey()
                        && s.emission.is_grey()
                }),
        };
        plan.patches_changed(mesh);
        plan
    }

    /// Recomputes the per-patch flags after patches were split.
    pub(super) fn patches_changed(&mut self, mesh: &Mesh) {
        self.rowless_patch = self.rowless_surface.iter().any(|r| *r).then(|| {
            mesh.patches
                .iter()
                .map(|p| self.rowless_surface[p.surface as usize])
                .collect()
        });
    }

    /// The keys that need rows, and those left out.
    pub(super) fn needing_rows(
        &self,
        mesh: &Mesh,
        keys: &[ElementKey],
    ) -> (Vec<ElementKey>, Vec<ElementKey>) {
        keys.iter()
            .partition(|k| !self.rowless_surface[mesh.elements[**k].surface as usize])
    }
}

/// Per surface, whether its elements can go without rows: it neither
/// reflects nor emits, so its radiosity is 0, and it takes no part in the
/// balance of the rows (see [`crate::solve::balance`]); what it absorbs is
/// summed from the other elements' rows by reciprocity.
fn rowless_surfaces(mesh: &Mesh) -> Vec<bool> {
    mesh.surfaces
        .iter()
        .map(|s| s.reflectance == Rgb::ZERO && s.emission == Rgb::ZERO)
        .collect()
}
