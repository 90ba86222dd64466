//! What a solve works on, whichever solver runs: the checked scene and
//! settings, the mesh, the form-factor store, the figures and the progress
//! callback. Set-up, checks, meshing, rows and refinement steps live here
//! once, for both solvers.

use super::memory;
use super::row_groups::RowGroups;
use super::scale::EmissionScale;
use super::skips::{RowPlan, RowTally};
use super::{Progress, Settings, SolveStats, Stage};
use crate::error::{Error, GeometryFault, LimitKind, Result};
use crate::formfactor::{compute_rows_with, emitter_shifts, FormFactors, RowState, Sources};
use crate::mesh::{ElementKey, Mesh};
use crate::refine::{mark_facing, mark_for_split, Marks, SplitLimits, NEAR_SHARE};
use crate::scene::{check_coplanar_overlaps, Scene};
use crate::solution::Solution;
use crate::solve::{DirectLight, GatherTotals, PatchSystem, Radiosity, SolveReport};
use std::time::Instant;

/// The shared state of one solve.
pub(crate) struct Workspace<'a> {
    pub scene: &'a Scene,
    pub settings: &'a Settings,
    pub progress: &'a (dyn Fn(Progress) + Sync),
    /// When the solve began.
    pub started: Instant,
    pub mesh: Mesh,
    /// The leaves' rows and their states.
    pub form_factors: FormFactors,
    /// The solution so far: element and patch radiosities.
    pub radiosity: Radiosity,
    /// The patches as polygons for the hemi-cubes.
    pub sources: Sources,
    /// How rows are computed, and what they may leave out.
    pub plan: RowPlan,
    /// What the rows cost and left out, over all passes.
    pub tally: RowTally,
    pub stats: SolveStats,
    /// Smallest element area refinement may make.
    pub min_area: f64,
    /// The punctual lights' irradiance per leaf (`None` when the scene has
    /// no punctual light: nothing of the solve changes then).
    pub direct: Option<DirectLight>,
    /// The power of two the mesh's emissions were scaled by for the solve.
    pub scale: EmissionScale,
    /// Facets of face clusters that share one row.
    pub row_groups: RowGroups,
    /// Punctual lights that reached no leaf of the first mesh, looked at
    /// again on the final one (see `light_checks`).
    pub dark_candidates: Vec<usize>,
}

impl<'a> Workspace<'a> {
    /// Checks everything that can be known before the first form factor
    /// (settings, the scene, its light and reflectances, overlapping
    /// surfaces), then cuts the mesh and
    /// splits it to the initial depth.
    pub(super) fn prepare(
        scene: &'a Scene,
        settings: &'a Settings,
        progress: &'a (dyn Fn(Progress) + Sync),
    ) -> Result<Self> {
        settings.validate()?;
        if scene.surfaces.is_empty() {
            return Err(Error::geometry(
                GeometryFault::NoSurfaces,
                format!("scene '{}' has no surfaces", scene.name),
            ));
        }
        scene.check_lights()?;
        scene.check_light()?;
        scene.check_reflectance()?;
        scene.check_materials()?;
        check_coplanar_overlaps(scene)?;
        let started = Instant::now();
        let refine = &settings.refine;
        let min_area = refine
            .min_element_area
            .unwrap_or_else(|| (scene.extent() * 1e-3).powi(2));
        let t = Instant::now();
        // No more patches than memory could hold with one leaf each: checked
        // surface by surface before the lattice is allocated.
        let fit = memory::patches_that_fit(settings.max_memory);
        let mut mesh = Mesh::build(
            scene,
            settings.patch_size_for(scene),
            settings.max_patches.min(fit),
            settings.face_clusters,
        )
        .map_err(|e| match e {
            Error::Limit { message: text, .. } if fit < settings.max_patches => Error::limit(
                LimitKind::Memory,
                format!(
                    "{text} ({fit} patches is what the memory limit of {} can hold; \
                 `max_memory` raises it)",
                    memory::gigabytes(settings.max_memory)
                ),
            ),
            e => e,
        })?;
        let depth = refine.uniform_depth.unwrap_or(refine.initial_depth);
        let adaptive = refine
            .uniform_depth
            .is_none()
            .then(|| settings.patch_size_for(scene));
        let splits = initial_splits(&mesh, depth, adaptive);
        // Checked before the split allocates what it would not hold.
        let needs = memory::needs_at_depth(&mesh, depth, &splits, settings);
        memory::check_needs(&needs, depth, settings.max_memory)?;
        split_uniformly(&mut mesh, depth, refine.max_elements, &splits)?;
        let mut stats = SolveStats::default();
        let scale = EmissionScale::normalise(&mut mesh, scene, &mut stats.warnings);
        stats.seconds.mesh = t.elapsed().as_secs_f64();
        let mut plan = RowPlan::new(&mesh, settings);
        // Coloured punctual lights make coloured reflected light.
        plan.grey &= scene.lights.iter().all(|l| l.colour.is_grey())
            && scene.sky.is_none_or(|s| s.zenith.is_grey());
        let sources = Sources::from_mesh(&mesh);
        let radiosity = Radiosity::emitted(&mesh);
        let row_groups = if refine.uniform_depth.is_none() {
            RowGroups::new(&mesh, settings, settings.patch_size_for(scene))
        } else {
            RowGroups::default()
        };
        stats.skips.row_groups = row_groups.len();
        let mut ws = Workspace {
            scene,
            settings,
            progress,
            started,
            mesh,
            form_factors: FormFactors::new(),
            radiosity,
            sources,
            plan,
            tally: RowTally::default(),
            stats,
            min_area,
            direct: (!scene.lights.is_empty() || scene.sky.is_some()).then(DirectLight::default),
            scale,
            row_groups,
            dark_candidates: Vec::new(),
        };
        ws.update_direct();
        if let Some(e) = ws.overflowing_light() {
            return Err(e);
        }
        let all: Vec<usize> = (0..scene.lights.len()).collect();
        ws.dark_candidates = ws.dark_lights(&all);
        Ok(ws)
    }

    /// Computes the punctual lights' irradiance on the leaves that have none
    /// yet: every leaf at first, then the new ones of each split (their
    /// solver then sets their radiosity with it). The first time, before any
    /// solve, its reflection is the leaves' and patches' first reflected
    /// light.
    pub(super) fn update_direct(&mut self) {
        let Some(direct) = &mut self.direct else {
            return;
        };
        let t = Instant::now();
        direct.update(
            &self.mesh,
            &self.sources,
            &self.scene.lights,
            self.scene.sky.as_ref(),
        );
        if self.stats.direct.is_none() {
            for k in self.mesh.leaves() {
                self.radiosity
                    .add_to_element(k, direct.exitance(&self.mesh, k));
            }
            let patches: Vec<_> = self
                .radiosity
                .patches()
                .iter()
                .zip(direct.patch_area_means(&self.mesh))
                .map(|(b, d)| *b + d)
                .collect();
            self.radiosity.set_patches(&patches);
        }
        let figures = self.stats.direct.get_or_insert_with(Default::default);
        figures.lights = self.scene.lights.len();
        figures.shadow_rays = direct.shadow_rays;
        figures.seconds += t.elapsed().as_secs_f64();
    }

    /// True while refinement passes may still run: the mesh adapts, and the
    /// passes so far are fewer than allowed.
    pub(super) fn may_refine(&self) -> bool {
        let refine = &self.settings.refine;
        refine.uniform_depth.is_none() && self.stats.passes.len() < refine.max_passes
    }

    /// Computes the rows of those `keys` that need one (the plan leaves out
    /// surfaces that reflect nothing) into the store, reporting progress as
    /// refinement pass `pass`. Adds the seconds to the stats.
    pub(super) fn compute_rows(&mut self, keys: &[ElementKey], pass: usize) {
        let started = Instant::now();
        let (keys, left_out) = self.plan.needing_rows(&self.mesh, keys);
        for k in &left_out {
            self.form_factors.skip(*k);
        }
        self.tally.zero_reflectance_rows += left_out.len() as u64;
        let (keys, copies) = self.row_groups.borrowers(keys, &self.form_factors);
        self.render_rows(keys, pass);
        // A lead that other objects cover in part, or that sees no front
        // face, is no fair sample of its group: its members render their own.
        let (copies, own): (Vec<_>, Vec<_>) = copies.into_iter().partition(|&(_, lead)| {
            self.form_factors
                .row(lead)
                .is_some_and(|row| row.visible() >= 1.0)
        });
        self.render_rows(own.into_iter().map(|(k, _)| k).collect(), pass);
        for &(k, lead) in &copies {
            self.form_factors.share(k, lead);
        }
        // A facet's direct light is its own even where it borrows the rest
        // of its lead's row: it changes with the facet's tilt and place far
        // more than what the rest of the view gathers (a tessellated head
        // under a lamp read 3% bright where its facets borrowed it).
        let progress = self.progress;
        let total = copies.len();
        let report = |done| {
            progress(Progress {
                stage: Stage::SharedRows { pass },
                done,
                total,
            });
        };
        let shifts = emitter_shifts(
            &self.mesh,
            &self.sources,
            &copies,
            &self.form_factors,
            &self.plan.settings,
            &self.plan.skips,
            &report,
        );
        for (&(k, _), shift) in copies.iter().zip(shifts) {
            self.form_factors.set_emitter_shift(k, shift);
        }
        self.stats.skips.rows_shared += copies.len() as u64;
        self.stats.seconds.form_factors += started.elapsed().as_secs_f64();
    }

    /// Renders the rows of `keys` into the store, reporting progress as
    /// refinement pass `pass`.
    fn render_rows(&mut self, keys: Vec<ElementKey>, pass: usize) {
        if keys.is_empty() {
            return;
        }
        let total = keys.len();
        let progress = self.progress;
        let report = |done| {
            progress(Progress {
                stage: Stage::FormFactors { pass },
                done,
                total,
            });
        };
        report(0);
        let (rows, s) = compute_rows_with(
            &self.mesh,
            &self.sources,
            &keys,
            &self.plan.settings,
            &self.plan.skips,
            &report,
        );
        for (k, row) in keys.into_iter().zip(rows) {
            self.form_factors.set_row(k, row);
        }
        self.tally.hemicube += s;
    }

    /// Marks the leaves that differ from a neighbour by more than the
    /// refinement tolerance, within the element budget.
    pub(super) fn mark(&mut self) -> Marks {
        let refine = &self.settings.refine;
        let room = refine
            .max_elements
            .saturating_sub(self.mesh.leaf_count())
            .min(self.leaves_that_fit());
        let limits = SplitLimits {
            tolerance: refine.tolerance,
            floor: refine.dim_floor,
            near_floor: refine.near_floor,
            max_depth: refine.max_depth,
            min_area: self.min_area,
            room,
        };
        let form_factors = &self.form_factors;
        let is_near = |k| match form_factors.state(k) {
            RowState::Computed(row) => row.near() > NEAR_SHARE,
            RowState::ShutIn(view) => f64::from(view.near) > NEAR_SHARE,
            RowState::Pending | RowState::Skipped => false,
        };
        let mut marks = mark_for_split(&self.mesh, &self.radiosity, limits, &is_near);
        // Leaves that a facing surface stands closer to than they are wide
        // split too, within what the budget has left.
        let entries = |k| form_factors.entries(k);
        let facing = if refine.facing_split {
            mark_facing(
                &self.mesh,
                &self.mesh.leaves(),
                &entries,
                refine.max_depth,
                self.min_area,
            )
        } else {
            Vec::new()
        };
        let mut left = room.saturating_sub(3 * marks.split.len());
        let already: std::collections::HashSet<ElementKey> = marks.split.iter().copied().collect();
        for k in facing {
            if already.contains(&k) {
                continue;
            }
            if left < 3 {
                marks.over_budget += 1;
                marks.blocked += 1;
                continue;
            }
            left -= 3;
            marks.split.push(k);
            marks.facing += 1;
        }
        self.stats.final_max_difference = marks.max_difference;
        if marks.over_budget > 0 && !self.stats.warnings.iter().any(|w| w.starts_with(BUDGET)) {
            self.stats.warnings.push(format!(
                "{BUDGET}: {} leaves that differ from a neighbour by more than the refinement \
                 tolerance, or that a facing surface stands close to, were left whole (the \
                 memory limit is {}; `max_memory` or `max_elements` raise the budget)",
                marks.over_budget,
                memory::gigabytes(self.settings.max_memory)
            ));
        }
        marks
    }

    /// How many more leaves the memory limit holds, at the bytes per leaf
    /// the rows computed so far take.
    fn leaves_that_fit(&self) -> usize {
        let rows = self.form_factors.row_bytes();
        let leaves = self.mesh.leaf_count().max(1) as f64;
        let per_leaf = memory::leaf_bytes() as f64 + rows as f64 / leaves;
        let hemicubes = memory::hemicube_bytes(
            self.settings.hemicube_resolution,
            self.mesh.patches().len(),
            rayon::current_num_threads(),
        );
        let used = memory::held(&self.mesh, rows as u64) + hemicubes as u64;
        memory::leaves_that_fit(self.settings.max_memory, used, per_leaf)
    }

    /// Ends row sharing for the facet groups that differ from a neighbour
    /// by more than the refinement tolerance; returns the members that need
    /// rows of their own, their old copies forgotten.
    pub(super) fn unshare_groups(&mut self) -> Vec<ElementKey> {
        let fresh = self
            .row_groups
            .unshare(&self.mesh, &self.radiosity, &self.settings.refine);
        for &k in &fresh {
            self.form_factors.forget(k);
        }
        self.stats.skips.groups_unshared += fresh.len();
        fresh
    }

    /// Splits the marked leaves and whatever the 2:1 balance then needs;
    /// the split leaves' rows are forgotten, and their children start with
    /// their radiosity. Returns the new leaves.
    pub(super) fn split_marked(&mut self, marks: &Marks) -> Vec<ElementKey> {
        let mut fresh: Vec<ElementKey> = Vec::new();
        for &k in &marks.split {
            let children = self.mesh.split(k);
            self.split_done(k, &children);
            fresh.extend(children);
        }
        for k in self.mesh.balance(fresh.clone()) {
            let children = self.mesh.elements[k].children.clone();
            self.split_done(k, &children);
            fresh.extend(children);
        }
        fresh.retain(|k| self.mesh.elements[*k].is_leaf());
        self.update_direct();
        fresh
    }

    /// Splits the leaf `key` and its descendants down to `depth`.
    pub(super) fn split_to(&mut self, key: ElementKey, depth: u8) {
        if self.mesh.elements[key].depth >= depth {
            return;
        }
        let children = self.mesh.split(key);
        self.split_done(key, &children);
        for k in children {
            self.split_to(k, depth);
        }
    }

    /// Brings the stores up to leaf `k` having split into `children`.
    pub(super) fn split_done(&mut self, k: ElementKey, children: &[ElementKey]) {
        self.form_factors.forget(k);
        self.radiosity.inherit(k, children);
    }

    /// Fills in the stats of the finished solve from its final patch
    /// system, last solver report, sweeps over all solves and power totals.
    pub(super) fn finish_stats(
        &mut self,
        system: &PatchSystem,
        report: SolveReport,
        iterations: usize,
        totals: GatherTotals,
    ) {
        self.stats.finish(
            &self.mesh,
            &self.form_factors,
            &self.radiosity,
            system,
            self.scene,
            self.settings,
            report,
            iterations,
            totals,
            self.tally.hemicube,
        );
        self.stats.skips.add_rows(&self.tally);
        if let (Some(direct), Some(figures)) = (&self.direct, &mut self.stats.direct) {
            figures.incident_power = direct.incident_power(&self.mesh);
        }
        self.stats.seconds.total = self.started.elapsed().as_secs_f64();
    }
}

/// How the warning about refinement held back by the budget starts.
const BUDGET: &str = "refinement stopped at the element budget";

impl Workspace<'_> {
    /// The solution of the finished solve with the final patch `system`, at
    /// the scene's own emission scale.
    pub(super) fn into_solution(mut self, mut system: PatchSystem) -> Solution {
        self.scale.restore_solution(
            &mut self.mesh,
            &mut self.radiosity,
            &mut system,
            &mut self.stats,
        );
        Solution {
            mesh: self.mesh,
            form_factors: self.form_factors,
            radiosity: self.radiosity,
            system,
            stats: self.stats,
            texel_surfaces: crate::solution::texel_surfaces(self.scene),
            light_groups: Default::default(),
        }
    }
}

/// Per patch of `mesh`, whether the initial split takes its roots down to
/// `depth`.
///
/// A uniform solve (`adaptive` `None`) splits every patch. An adaptive one
/// (`adaptive` the patch size) leaves whole the patches that are as fine as
/// the initial depth aims for already: the roots of face clusters (a
/// cluster's surfaces divide it into elements, each smaller than the patch);
/// the patches of a surface cut finer than a patch halved `depth` times to
/// place its emissive texture's light (see `crate::mesh`'s emission grid);
/// and small facets (see [`SMALL_FACET`]). Splitting them would multiply the
/// rows of a finely tessellated scene by four where nothing yet says the
/// light changes: a lamp of 6 000 triangles whose emissive texture cut
/// 1 249 of them into 6 451 patches took 30 000 rows in its first pass.
pub(crate) fn initial_splits(mesh: &Mesh, depth: u8, adaptive: Option<f64>) -> Vec<bool> {
    let target = adaptive.map(|size| size / f64::from(1u32 << depth.min(30)));
    let mut facets_per_object: Vec<usize> = Vec::new();
    for s in &mesh.surfaces {
        let o = s.object as usize;
        if facets_per_object.len() <= o {
            facets_per_object.resize(o + 1, 0);
        }
        facets_per_object[o] += 1;
    }
    mesh.patches
        .iter()
        .map(|p| match target {
            None => true,
            Some(target) => {
                let lattice = &mesh.surfaces[p.surface as usize];
                let tessellated = facets_per_object[lattice.object as usize] >= TESSELLATED;
                !p.is_cluster()
                    && lattice.patch_size > target * (1.0 + 1e-9)
                    && !(tessellated && longest_edge(&p.polygon) < SMALL_FACET * target)
            }
        })
        .collect()
}

/// Splits the roots of every patch that `splits` marks (see
/// [`initial_splits`]) to `depth`, failing if that would exceed
/// `max_elements`.
pub(crate) fn split_uniformly(
    mesh: &mut Mesh,
    depth: u8,
    max_elements: usize,
    splits: &[bool],
) -> Result<()> {
    let leaves = super::memory::leaves_at_depth(mesh, depth, splits);
    if leaves > max_elements as f64 {
        return Err(Error::limit(
            LimitKind::Elements,
            format!(
                "{} patches split to depth {depth} give {leaves} elements, more than the \
             element budget of {max_elements}",
                mesh.patches.len()
            ),
        ));
    }
    for k in mesh.leaves() {
        if splits[mesh.elements[k].patch as usize] {
            let top = mesh.elements[k].depth;
            split_to_depth(mesh, k, top + depth);
        }
    }
    Ok(())
}

/// A patch of a tessellated object (see [`TESSELLATED`]) whose longest edge
/// is below this fraction of the initial elements' size is left whole like
/// a face cluster's facets: a small facet of a real mesh that joined no
/// cluster (its neighbours wound the other way, or bent too far) is finer
/// than the elements already, and its neighbours carry the light's changes.
const SMALL_FACET: f64 = 0.5;

/// The number of surfaces from which an object counts as tessellated. An
/// object of a few faces (a box, a pier under large patches) has no
/// neighbouring facets to carry the light's changes: its small faces are
/// split as before, since their shaped gathers need the elements (a pier's
/// top left whole put the pier 2.3% off its path-traced mean, against 2%).
const TESSELLATED: usize = 24;

/// The longest edge of a polygon.
fn longest_edge(polygon: &[glam::DVec3]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| (polygon[(i + 1) % n] - polygon[i]).length())
        .fold(0.0, f64::max)
}

/// Splits leaf `k` and its descendants down to tree depth `depth`.
fn split_to_depth(mesh: &mut Mesh, k: ElementKey, depth: u8) {
    if mesh.elements[k].depth >= depth {
        return;
    }
    for child in mesh.split(k) {
        split_to_depth(mesh, child, depth);
    }
}
