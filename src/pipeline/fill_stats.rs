//! How the driver fills in the figures of a solve ([`SolveStats`], defined
//! with the solution it describes).

use super::Settings;
use crate::formfactor::hemicube::HemicubeStats;
use crate::formfactor::{FormFactors, Row};
use crate::mesh::Mesh;
use crate::scene::Scene;
use crate::solution::{EnergyBalance, HemicubeFigures, MemoryFigures, SkipStats, SolveStats};
use crate::solve::{GatherTotals, PatchSystem, Radiosity, SolveReport};

impl SkipStats {
    /// Adds the row figures of a solve.
    pub(crate) fn add_rows(&mut self, tally: &super::skips::RowTally) {
        let h = &tally.hemicube;
        self.zero_reflectance_rows += tally.zero_reflectance_rows;
        self.exact_rows += h.exact_rows;
        self.empty_faces += h.empty_faces;
        self.pixels_skipped += h.pixels_skipped;
        self.back_faces_skipped += h.back_faces_skipped;
    }
}

impl SolveStats {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn finish(
        &mut self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        radiosity: &Radiosity,
        system: &PatchSystem,
        scene: &Scene,
        settings: &Settings,
        report: SolveReport,
        iterations: usize,
        totals: GatherTotals,
        hemicube: HemicubeStats,
    ) {
        self.surfaces = scene.surfaces.len();
        self.patches = mesh.patches.len();
        self.patch_size = settings.patch_size_for(scene);
        let leaves = mesh.leaves();
        self.elements = leaves.len();
        // Leaves left without rows because they reflect nothing have no row
        // sum to report; shut-in leaves sum to 0.
        let sums: Vec<f64> = leaves
            .iter()
            .filter(|k| form_factors.state(**k).is_computed())
            .map(|k| form_factors.row(*k).map_or(0.0, Row::sum))
            .collect();
        self.hemicube = HemicubeFigures {
            resolution: settings.hemicube_resolution,
            hemicubes: hemicube.hemicubes,
            polygons_rasterized: hemicube.polygons_rasterized,
            pixels_tested: hemicube.pixels_tested,
            polygons_culled: hemicube.polygons_culled,
            polygons_hidden: hemicube.polygons_hidden,
            element_form_factors: form_factors.row_entries(),
            patch_form_factors: system.nonzeros(),
            mean_row_sum: sums.iter().sum::<f64>() / sums.len().max(1) as f64,
            max_row_sum: sums.iter().copied().fold(0.0, f64::max),
            emitters_exact: hemicube.emitters_exact,
            emitters_one_ray: hemicube.emitters_one_ray,
            emitters_by_pixels: hemicube.emitters_by_pixels,
        };
        self.memory = MemoryFigures::of(mesh, form_factors, radiosity, system);
        self.solver = report;
        self.total_iterations = iterations;
        self.energy = EnergyBalance::of(&totals, settings.bounces.is_some());
        self.bounces = settings.bounces;
    }

    /// Adds the warnings the figures call for (see [`SolveStats::warnings`]);
    /// once, when they are final.
    pub(crate) fn warn(&mut self) {
        self.warnings.extend(self.energy.warning());
    }
}
