//! Settings of a solve, with defaults derived from the scene.

use super::progressive::DEFAULT_UNSHOT_TOLERANCE;
use super::Skips;
use super::{ProgressiveSettings, SolverKind};
use crate::error::{Error, Result};
use crate::formfactor::{EmitterSampling, FormFactorMethod};
use crate::refine::RefineSettings;
use crate::scene::Scene;
use crate::solve::SolverSettings;

/// What [`Settings::max_memory`] is unless set: 8 GiB.
pub const DEFAULT_MAX_MEMORY: u64 = 8 << 30;

/// Everything a solve can be told.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Hemi-cube resolution: pixels across the top face (even).
    pub hemicube_resolution: usize,
    /// Largest patch edge in metres; `None` derives it from the scene's size.
    pub patch_size: Option<f64>,
    /// Group small adjacent surfaces of one object and material whose normals
    /// agree into face clusters, each one patch (see
    /// [`crate::mesh::clusters`]): the sources then follow the patch size,
    /// not the triangle count. Off makes every surface a patch (or lattice of
    /// patches) of its own, for comparison.
    pub face_clusters: bool,
    /// Seed of the hemi-cube rotations.
    pub seed: u64,
    /// How hemi-cube pixels become form factors.
    pub form_factors: FormFactorMethod,
    /// How the visibility of emitters that a hemi-cube saw only in part is
    /// found (hybrid method only), so that penumbrae are not limited to the
    /// hemi-cube's pixels.
    pub emitter_sampling: EmitterSampling,
    /// Draw BVH subtrees of polygons that would cover less than a pixel of a
    /// hemi-cube as one sample each, instead of polygon by polygon, and
    /// leave out subtrees that what is already drawn hides wholly (drawing
    /// nearest first): the hemi-cube's work then follows its pixel count and
    /// what it sees, not the scene's polygon count. Off draws every polygon
    /// above the horizon (for comparison; on scenes whose patches all cover
    /// pixels and hide nothing, the same rows).
    pub level_of_detail: bool,
    /// Gauss-Seidel stopping rules.
    pub solver: SolverSettings,
    /// Gathering (Gauss-Seidel) or shooting (progressive refinement).
    pub solver_kind: SolverKind,
    /// Stopping rules and previews of the progressive solver.
    pub progressive: ProgressiveSettings,
    /// Refinement.
    pub refine: RefineSettings,
    /// Most patches the mesh may hold (no limit by default: memory decides,
    /// see `max_memory`).
    pub max_patches: usize,
    /// Bytes the solve may hold. The scene is refused before the first form
    /// factor when the mesh's estimate does not fit, and refinement adds
    /// elements only while the bytes measured per element still fit. The
    /// library's default is [`DEFAULT_MAX_MEMORY`]; the command-line tool
    /// uses most of the machine's memory.
    pub max_memory: u64,
    /// `None`: the full solution. `Some(n)`: emitted light and exactly `n`
    /// reflections, no more (`Some(1)` is direct light only, what a ray tracer
    /// without an ambient term computes for diffuse surfaces); gathering solver
    /// only. See `crate::solve::bounces`.
    pub bounces: Option<u32>,
    /// Gathers after the last solve that take each unevenly lit source
    /// patch, seen from close by, by its parts rather than its mean (see
    /// `crate::solve::source_shape`); `Some(0)` gathers every patch's mean,
    /// as the substructuring method does. Each gather starts from the last
    /// one's element radiosities. `None` (the default) is
    /// [`DEFAULT_SHAPED_GATHERS`] for the full solution and 0 for a fixed
    /// number of bounces (see [`Settings::shaped_gather_count`]), where a
    /// positive count is refused by [`Settings::validate`]. The progressive
    /// solver makes them once it has converged: the gathering solver takes
    /// its solution over with every leaf's row (see `crate::pipeline`'s
    /// progressive driver); by default none when told to stop early (see
    /// [`DEFAULT_UNSHOT_TOLERANCE`]); a solve stopped by a shot limit or a
    /// time budget makes none, and says so.
    pub shaped_gathers: Option<usize>,
    /// In a shaped gather, a receiver whose row sees clearly less of a near
    /// patch than the parts' unoccluded form factors add up to draws its
    /// hemi-cube again with the patch's parts in place of the patch, and
    /// weighs each part by the share of its pixels it won (see
    /// `crate::solve::source_shape`). `None` (the default) draws them
    /// wherever the solve makes shaped gathers (see
    /// [`Settings::uses_part_views`]); `Some(false)` weighs the parts by
    /// their unoccluded form factors alone; `Some(true)` where the solve
    /// makes no shaped gather is refused by [`Settings::validate`]. On by
    /// default since 2026-12-05: per-object error falls on every scene
    /// measured (the 10 000-triangle atrium 1.07% -> 0.72% mean, many_boxes
    /// 0.66% -> 0.40%, the Ferren sculpture 0.96% -> 0.80%) for about one
    /// more hemi-cube per receiver that a pier or plinth hides part of a
    /// near patch from (1.09x the CPU time of the 200 000-triangle atrium).
    pub part_views: Option<bool>,
    /// Neighbouring facets of a face cluster whose normals agree share one
    /// row, rendered at the facet nearest their centre, until the solution
    /// says they differ (see `crate::pipeline`'s row groups): one hemi-cube
    /// per group instead of one per facet. Off renders every facet's own
    /// row, for comparison.
    pub shared_rows: bool,
    /// Work the solve may leave out where the scene does not need it (all
    /// on; off only to compare or measure).
    pub skips: Skips,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            hemicube_resolution: 64,
            patch_size: None,
            face_clusters: true,
            seed: 1,
            form_factors: FormFactorMethod::default(),
            emitter_sampling: EmitterSampling::default(),
            level_of_detail: true,
            solver: SolverSettings::default(),
            solver_kind: SolverKind::default(),
            progressive: ProgressiveSettings::default(),
            refine: RefineSettings::default(),
            max_patches: usize::MAX,
            max_memory: DEFAULT_MAX_MEMORY,
            bounces: None,
            shaped_gathers: None,
            part_views: None,
            shared_rows: true,
            skips: Skips::default(),
        }
    }
}

/// Shaped gathers a solve makes unless told: one takes most of
/// the gain (the 100 000-triangle atrium's mean per-object error falls from
/// 5.8% to 1.8%, the Ferren sculpture's from 4.1% to 2.3%) for a few percent
/// of the time; a second moves the atrium's by another tenth.
pub const DEFAULT_SHAPED_GATHERS: usize = 1;

/// The most shaped gathers: each changes the next by less (two already
/// agree closely), so more only cost time.
pub const MAX_SHAPED_GATHERS: usize = 8;

/// The default patch size is the scene's bounding-box diagonal over this.
pub(super) const PATCHES_PER_DIAMETER: f64 = 10.0;

impl Settings {
    /// The patch size to use for `scene`.
    #[must_use]
    pub fn patch_size_for(&self, scene: &Scene) -> f64 {
        self.patch_size
            .unwrap_or_else(|| scene.extent() / PATCHES_PER_DIAMETER)
    }

    /// How many shaped gathers the solve makes: [`Settings::shaped_gathers`]
    /// when set, else [`DEFAULT_SHAPED_GATHERS`] for the full solution (of
    /// either solver), and 0 with a fixed number of bounces or a progressive
    /// solve told to stop early (an unshot tolerance above
    /// [`DEFAULT_UNSHOT_TOLERANCE`]).
    #[must_use]
    pub fn shaped_gather_count(&self) -> usize {
        let early = self.solver_kind == SolverKind::Progressive
            && self.progressive.tolerance > DEFAULT_UNSHOT_TOLERANCE;
        self.shaped_gathers
            .unwrap_or(if self.bounces.is_some() || early {
                0
            } else {
                DEFAULT_SHAPED_GATHERS
            })
    }

    /// Whether shaped gathers draw part views (see [`Settings::part_views`]):
    /// as told, else wherever the solve makes shaped gathers.
    #[must_use]
    pub fn uses_part_views(&self) -> bool {
        self.part_views.unwrap_or(true) && self.shaped_gather_count() > 0
    }

    /// Checks every setting's range; the error names the setting.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, message: String| Err(Error::Setting { name, message });
        let n = self.hemicube_resolution;
        if !(8..=4096).contains(&n) || !n.is_multiple_of(2) {
            return bad(
                "hemicube_resolution",
                format!("must be even, 8 to 4096, got {n}"),
            );
        }
        if let Some(p) = self.patch_size {
            if !(p.is_finite() && p > 0.0) {
                return bad("patch_size", format!("must be a positive length, got {p}"));
            }
        }
        let s = &self.solver;
        if s.max_iterations == 0 {
            return bad("solver.max_iterations", "must be at least 1".to_string());
        }
        if !(s.tolerance.is_finite() && s.tolerance > 0.0) {
            return bad(
                "tolerance",
                format!("must be positive, got {}", s.tolerance),
            );
        }
        if self.solver_kind == SolverKind::Progressive && self.refine.source_tolerance.is_some() {
            return bad(
                "refine.source_tolerance",
                "source-patch splitting applies to the gathering solver (gauss-seidel) only"
                    .to_string(),
            );
        }
        let shaped = self.shaped_gathers.unwrap_or(0);
        if shaped > MAX_SHAPED_GATHERS {
            return bad(
                "shaped_gathers",
                format!("must be at most {MAX_SHAPED_GATHERS}, got {shaped}"),
            );
        }
        if shaped > 0 && self.bounces.is_some() {
            return bad(
                "shaped_gathers",
                "shaped gathers refine the full solution; with a fixed number of bounces \
                 every patch is gathered by its mean"
                    .to_string(),
            );
        }
        if self.part_views == Some(true) && self.shaped_gather_count() == 0 {
            return bad(
                "part_views",
                "part views weigh the parts of unevenly lit patches in shaped gathers, and \
                 this solve makes none (`bounces` or `shaped_gathers` 0)"
                    .to_string(),
            );
        }
        if let Some(n) = self.bounces {
            crate::solve::bounces::check_bounces(n)?;
            if self.solver_kind == SolverKind::Progressive {
                return bad(
                    "bounces",
                    "a fixed number of reflections applies to the gathering solver \
                     (gauss-seidel) only; the progressive solver shoots until the unshot \
                     power is small"
                        .to_string(),
                );
            }
        }
        if self.max_memory == 0 {
            return bad("max_memory", "must be more than 0 bytes".to_string());
        }
        self.progressive.validate()?;
        self.refine.validate()
    }
}
