//! Floor errors of a solved penumbra scene against its exact oracle.
//!
//! Every error is a fraction of the scene's *light-on value*: the exact
//! radiosity the floor would have, with the occluders taken away, at the floor
//! point straight below the light's centroid. It is about the brightest the
//! floor can be, so "1 %" means one hundredth of full light whatever the
//! variant.
//!
//! Besides the solver's error (element value against the exact element mean)
//! the error is split in two, through the exact value at the element's
//! centroid, where the solver's hemi-cube sits:
//!
//! - *sampling*: exact centroid value against exact element mean, the error a
//!   collocation solver with exact form factors would make; it depends on the
//!   element size only;
//! - *form factor*: element value against exact centroid value, the error of
//!   the hemi-cube rows (with [`radiosity::formfactor::FormFactorMethod::Hybrid`],
//!   the pixel-counted visible fraction of a partly hidden light).

use glam::DVec3;
use radiosity::math::polygon_centroid;
use radiosity::mesh::ElementKey;
use radiosity::scene::Scene;
use radiosity::scenes::penumbra::PenumbraSpec;
use radiosity::{Settings, Solution};
use rayon::prelude::*;
use std::time::Instant;

/// One floor leaf: its key, polygon, and radiosities (band 0; the penumbra
/// scenes are grey).
pub struct FloorElement {
    pub key: ElementKey,
    pub polygon: Vec<DVec3>,
    pub area: f64,
    /// The solver's element value.
    pub solved: f64,
    /// The exact mean over the element.
    pub exact: f64,
    /// The exact value at the element's centroid.
    pub exact_at_centroid: f64,
}

/// A solved penumbra scene compared with its oracle. Errors are fractions of
/// `light_on`.
pub struct FloorErrors {
    pub solution: Solution,
    pub light_on: f64,
    pub floor: Vec<FloorElement>,
    /// Area-weighted mean of `|solved - exact|`.
    pub mean: f64,
    /// Largest `|solved - exact|`.
    pub max: f64,
    /// Area-weighted mean of `|exact_at_centroid - exact|`.
    pub sampling_mean: f64,
    /// Area-weighted mean of `|solved - exact_at_centroid|`.
    pub form_factor_mean: f64,
    /// Area-weighted mean of the exact floor radiosity.
    pub exact_mean: f64,
    /// Leaf elements of the whole scene (every surface).
    pub elements: usize,
    /// Wall-clock seconds of the solve alone (for reports, never asserted).
    pub solve_seconds: f64,
}

/// The exact radiosity of the unoccluded floor below the light's centroid.
pub fn light_on_value(spec: &PenumbraSpec) -> f64 {
    let centre = polygon_centroid(&spec.light);
    let below = DVec3::new(centre.x, spec.floor[0].y, centre.z);
    let f = spec
        .oracle()
        .unwrap()
        .unoccluded_form_factor(below, spec.floor_normal())
        .unwrap();
    spec.floor_reflectance[0] * spec.light_exitance()[0] * f
}

/// Solves `spec`'s scene with `settings` and measures the floor's errors.
pub fn measure(spec: &PenumbraSpec, settings: &Settings) -> FloorErrors {
    measure_scene(spec, &spec.scene().unwrap(), settings)
}

/// Solves `scene`, which holds `spec`'s objects and perhaps others that do
/// not light its floor, and measures the floor's errors against `spec`'s
/// oracle.
pub fn measure_scene(spec: &PenumbraSpec, scene: &Scene, settings: &Settings) -> FloorErrors {
    let started = Instant::now();
    let solution = radiosity::solve(scene, settings, &|_| {}).unwrap();
    let solve_seconds = started.elapsed().as_secs_f64();
    let floor_object = scene
        .objects
        .iter()
        .position(|o| o.name == "floor")
        .expect("penumbra scenes have a floor") as u32;
    let mesh = &solution.mesh();
    let leaves = mesh.leaves();
    let floor_leaves: Vec<ElementKey> = leaves
        .iter()
        .copied()
        .filter(|k| mesh.surfaces()[mesh[*k].surface() as usize].object == floor_object)
        .collect();
    // The exact means are independent quadratures: spread them over the cores
    // (the result is collected in order, so sums below do not depend on it).
    let floor: Vec<FloorElement> = floor_leaves
        .par_iter()
        .map(|&key| {
            let e = &mesh[key];
            let polygon = mesh.surfaces()[e.surface() as usize]
                .polygon(&e.cell())
                .to_vec();
            let exact = spec.exact_element_mean(&polygon).unwrap()[0];
            let exact_at_centroid = spec.exact_radiosity(e.centroid()).unwrap()[0];
            FloorElement {
                key,
                polygon,
                area: e.area(),
                solved: solution.radiosity().element(key)[0],
                exact,
                exact_at_centroid,
            }
        })
        .collect();
    let light_on = light_on_value(spec);
    let area: f64 = floor.iter().map(|e| e.area).sum();
    let area_mean = |f: &dyn Fn(&FloorElement) -> f64| {
        floor.iter().map(|e| f(e) * e.area).sum::<f64>() / area / light_on
    };
    let mean = area_mean(&|e| (e.solved - e.exact).abs());
    let sampling_mean = area_mean(&|e| (e.exact_at_centroid - e.exact).abs());
    let form_factor_mean = area_mean(&|e| (e.solved - e.exact_at_centroid).abs());
    let exact_mean = area_mean(&|e| e.exact);
    let max = floor
        .iter()
        .map(|e| (e.solved - e.exact).abs())
        .fold(0.0, f64::max)
        / light_on;
    FloorErrors {
        elements: leaves.len(),
        solution,
        light_on,
        floor,
        mean,
        max,
        sampling_mean,
        form_factor_mean,
        exact_mean,
        solve_seconds,
    }
}
