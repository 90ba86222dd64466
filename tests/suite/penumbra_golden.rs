//! The penumbra regression golden, `tests/goldens/penumbra.json`.
//!
//! It is a *regression* golden, not ground truth: the ground truth is the exact
//! oracle, and the file only records how close the solver came to it (mean and
//! largest element error, as fractions of the light-on value) with the
//! settings it records, and the tolerance each figure is held to. It is
//! rewritten only on request, with `RADIOSITY_UPDATE_GOLDENS=1`.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Tolerance = measured * MARGIN + floor.
pub const MARGIN: f64 = 1.25;
/// Absolute floor added to the mean error's tolerance.
pub const MEAN_FLOOR: f64 = 5e-5;
/// Absolute floor added to the largest error's tolerance.
pub const MAX_FLOOR: f64 = 5e-4;
/// Element counts may grow by this factor (plus [`ELEMENT_SLACK`]) before
/// the test calls it a cost regression.
pub const ELEMENT_MARGIN: f64 = 1.25;
/// See [`ELEMENT_MARGIN`].
pub const ELEMENT_SLACK: usize = 16;

/// The environment variable that rewrites the golden.
pub const UPDATE_VAR: &str = "RADIOSITY_UPDATE_GOLDENS";

/// The whole file.
#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
pub struct GoldenFile {
    pub about: String,
    pub error_unit: String,
    pub tolerance_rule: String,
    pub refresh: String,
    pub scenes: Vec<GoldenScene>,
}

/// One scene's record.
#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
pub struct GoldenScene {
    pub scene: String,
    pub settings: GoldenSettings,
    /// Leaf elements on the floor.
    pub floor_elements: usize,
    pub mean_error: f64,
    pub max_error: f64,
    pub mean_tolerance: f64,
    pub max_tolerance: f64,
}

/// The solve settings a record was measured with.
#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
pub struct GoldenSettings {
    pub patch_size: Option<f64>,
    pub hemicube_resolution: usize,
    pub form_factors: String,
    pub seed: u64,
    pub uniform_depth: Option<u8>,
    pub initial_depth: u8,
    pub max_depth: u8,
    pub refine_tolerance: f64,
    pub max_passes: usize,
    pub solver_tolerance: f64,
}

impl GoldenSettings {
    /// The record of `s`.
    pub fn of(s: &radiosity::Settings) -> Self {
        GoldenSettings {
            patch_size: s.patch_size,
            hemicube_resolution: s.hemicube_resolution,
            form_factors: format!("{:?}", s.form_factors).to_lowercase(),
            seed: s.seed,
            uniform_depth: s.refine.uniform_depth,
            initial_depth: s.refine.initial_depth,
            max_depth: s.refine.max_depth,
            refine_tolerance: s.refine.tolerance,
            max_passes: s.refine.max_passes,
            solver_tolerance: s.solver.tolerance,
        }
    }
}

impl GoldenScene {
    /// A record of fresh measurements, with tolerances by the rule.
    pub fn new(
        scene: &str,
        settings: GoldenSettings,
        floor_elements: usize,
        mean: f64,
        max: f64,
    ) -> Self {
        GoldenScene {
            scene: scene.to_string(),
            settings,
            floor_elements,
            mean_error: mean,
            max_error: max,
            mean_tolerance: mean * MARGIN + MEAN_FLOOR,
            max_tolerance: max * MARGIN + MAX_FLOOR,
        }
    }

    /// Fails if the stored tolerances are not the rule applied to the stored
    /// measurements (a hand-loosened golden).
    pub fn check_rule(&self) -> Result<(), String> {
        let agrees = |tol: f64, measured: f64, floor: f64| {
            (tol - (measured * MARGIN + floor)).abs() <= 1e-12 * tol.abs().max(1e-12)
        };
        if agrees(self.mean_tolerance, self.mean_error, MEAN_FLOOR)
            && agrees(self.max_tolerance, self.max_error, MAX_FLOOR)
        {
            Ok(())
        } else {
            Err(format!(
                "{}: the stored tolerances do not follow the rule \
                 (measured * {MARGIN} + floor); the golden was edited by hand",
                self.scene
            ))
        }
    }

    /// The most floor elements allowed before a cost regression.
    pub fn element_limit(&self) -> usize {
        (self.floor_elements as f64 * ELEMENT_MARGIN) as usize + ELEMENT_SLACK
    }
}

impl GoldenFile {
    /// A file holding `scenes`, with the explanations filled in.
    pub fn new(scenes: Vec<GoldenScene>) -> Self {
        GoldenFile {
            about: "Regression golden for the penumbra tests (tests/suite/penumbra.rs). \
                    NOT ground truth: the truth is the exact oracle \
                    (scenes::penumbra, exact_element_mean); this file records how close \
                    the solver came to it with the recorded settings, and holds it there."
                .to_string(),
            error_unit: "Errors compare each floor leaf element's solved radiosity with the \
                         oracle's exact mean over that element. mean_error is the \
                         area-weighted mean absolute difference, max_error the largest; \
                         both are fractions of the light-on value, the exact radiosity of \
                         the unoccluded floor straight below the light's centroid."
                .to_string(),
            tolerance_rule: format!(
                "mean_tolerance = mean_error * {MARGIN} + {MEAN_FLOOR}; \
                 max_tolerance = max_error * {MARGIN} + {MAX_FLOOR}; \
                 floor_elements may grow to floor_elements * {ELEMENT_MARGIN} + {ELEMENT_SLACK}"
            ),
            refresh: format!(
                "Deliberately only, after a change that is meant to move these figures: \
                 {UPDATE_VAR}=1 cargo test --release --test suite penumbra_scenes_stay"
            ),
            scenes,
        }
    }
}

/// Where the golden lives.
pub fn golden_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("goldens")
        .join("penumbra.json")
}

/// True when the goldens are to be rewritten.
pub fn updating() -> bool {
    std::env::var(UPDATE_VAR).is_ok_and(|v| v == "1")
}

/// Reads the golden; the error says how to make one.
pub fn load() -> Result<GoldenFile, String> {
    let path = golden_path();
    let text = std::fs::read_to_string(&path).map_err(|e| {
        format!(
            "cannot read {} ({e}); create it deliberately with {UPDATE_VAR}=1",
            path.display()
        )
    })?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes the golden.
pub fn save(file: &GoldenFile) {
    let path = golden_path();
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let text = serde_json::to_string_pretty(file).unwrap();
    std::fs::write(&path, text + "\n").unwrap();
}
