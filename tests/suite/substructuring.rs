//! Substructuring invariants and adaptive refinement.

use super::common::{closed_box, FaceMaterial};
use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::refine::RefineSettings;
use radiosity::solve::SolverSettings;
use radiosity::Settings;

#[test]
fn patch_radiosity_is_the_area_mean_of_its_elements() {
    let mut faces = [FaceMaterial::grey(0.6, 0.0); 6];
    faces[1] = FaceMaterial {
        reflectance: Rgb::splat(0.4),
        exitance: Rgb::new(3.0, 2.0, 1.0),
    };
    faces[4].reflectance = Rgb::new(0.8, 0.1, 0.1);
    let scene = closed_box(DVec3::new(1.0, 1.0, 1.0), faces);
    // Without shaped gathers the gather from the solved patches averages
    // back to them (the substructuring system's consistency); with them each
    // patch takes its elements' mean.
    for shaped_gathers in [0, 2] {
        let s = Settings {
            patch_size: Some(0.34),
            shaped_gathers: Some(shaped_gathers),
            refine: RefineSettings {
                tolerance: 0.01,
                ..RefineSettings::default()
            },
            solver: SolverSettings {
                tolerance: 1e-9,
                ..SolverSettings::default()
            },
            ..Settings::default()
        };
        let sol = radiosity::solve(&scene, &s, &|_| {}).unwrap();
        assert!(
            !sol.stats().passes.is_empty(),
            "the test needs a refined mesh"
        );
        for (i, p) in sol.mesh().patches().iter().enumerate() {
            let mut sum = Rgb::ZERO;
            for k in sol.mesh().patch_leaves(i as u32) {
                sum += sol.radiosity().element(k) * sol.mesh()[k].area();
            }
            let mean = sum / p.area();
            let b = sol.patch_radiosity()[i];
            for band in 0..3 {
                assert!(
                    (mean[band] - b[band]).abs() <= 1e-6 * b.max_band().max(1e-12),
                    "shaped gathers {shaped_gathers}, patch {i} band {band}: elements {} patch {}",
                    mean[band],
                    b[band]
                );
            }
        }
    }
}
