//! The runs of a sweep, derived from one base setting.

use super::{Method, SweepRun};
use crate::error::{Error, Result};
use crate::pipeline::Settings;
use crate::pipeline::SolverKind;
use crate::scene::Scene;

/// What a sweep varies. Each list gives one run per value; an empty list
/// leaves its method out.
#[derive(Clone, Debug)]
pub struct SweepPlan {
    /// The settings every run starts from.
    pub base: Settings,
    /// [`Method::Uniform`]: depths every patch is split to.
    pub uniform_depths: Vec<u8>,
    /// [`Method::Adaptive`]: refinement tolerances (adaptive from the base's
    /// initial depth to its maximum depth).
    pub adaptive_tolerances: Vec<f64>,
    /// [`Method::Hemicube`]: hemi-cube resolutions, at the base's other settings.
    pub hemicube_resolutions: Vec<usize>,
    /// [`Method::Patches`]: divisors of the base patch size; each run uses
    /// patches of the base size over the divisor and no elements below them.
    pub patch_divisions: Vec<u32>,
    /// [`Method::Progressive`]: unshot-power fractions at which the progressive
    /// solver stops (its tolerance), at the base's mesh and refinement
    /// settings. Each run stops on its fraction alone: the base's shot limit,
    /// time budget and previews are cleared. The fraction, unlike a time
    /// budget, stops at the same point on any machine. With adaptive
    /// refinement the solver runs its remaining refinement passes when the
    /// fraction is first met, so an early stop still pays for a refined mesh.
    pub unshot_fractions: Vec<f64>,
}

impl Default for SweepPlan {
    /// Uniform depths 0 to 3, adaptive tolerances 0.2 to 0.025, hemi-cube
    /// resolutions 32 to 256, progressive stopping points at unshot fractions
    /// 0.3 to 0.001 ([`DEFAULT_UNSHOT_FRACTIONS`]), no small-patch runs, at
    /// default settings.
    fn default() -> Self {
        SweepPlan {
            base: Settings::default(),
            uniform_depths: vec![0, 1, 2, 3],
            adaptive_tolerances: vec![0.2, 0.1, 0.05, 0.025],
            hemicube_resolutions: vec![32, 64, 128, 256],
            patch_divisions: Vec::new(),
            unshot_fractions: DEFAULT_UNSHOT_FRACTIONS.to_vec(),
        }
    }
}

/// The default progressive stopping points: unshot fractions about half a
/// decade apart from 0.3 (a first look) to 0.01, then 0.001 (nearly converged:
/// on the Cornell box the error is then within a few parts in a thousand of the
/// converged solution's).
pub const DEFAULT_UNSHOT_FRACTIONS: [f64; 5] = [0.3, 0.1, 0.03, 0.01, 0.001];

impl SweepPlan {
    /// The runs, method by method in [`Method::ALL`] order and in list order
    /// within a method. Fails, naming the run, if any run's settings are out of
    /// range, or if a patch divisor is 0.
    pub fn runs(&self, scene: &Scene) -> Result<Vec<SweepRun>> {
        let mut runs = Vec::new();
        for method in Method::ALL {
            match method {
                Method::Uniform => {
                    for &depth in &self.uniform_depths {
                        let mut settings = self.base.clone();
                        settings.refine.uniform_depth = Some(depth);
                        runs.push(run(method, f64::from(depth), settings));
                    }
                }
                Method::Adaptive => {
                    for &tolerance in &self.adaptive_tolerances {
                        let mut settings = self.base.clone();
                        settings.refine.uniform_depth = None;
                        settings.refine.tolerance = tolerance;
                        runs.push(run(method, tolerance, settings));
                    }
                }
                Method::Hemicube => {
                    for &resolution in &self.hemicube_resolutions {
                        let mut settings = self.base.clone();
                        settings.hemicube_resolution = resolution;
                        runs.push(run(method, resolution as f64, settings));
                    }
                }
                Method::Patches => {
                    let size = self.base.patch_size_for(scene);
                    for &divisor in &self.patch_divisions {
                        if divisor == 0 {
                            return Err(Error::Setting {
                                name: "patch_divisions",
                                message: "a divisor of the patch size must be at least 1".into(),
                            });
                        }
                        let mut settings = self.base.clone();
                        settings.patch_size = Some(size / f64::from(divisor));
                        settings.refine.uniform_depth = Some(0);
                        runs.push(run(method, size / f64::from(divisor), settings));
                    }
                }
                Method::Progressive => {
                    for &fraction in &self.unshot_fractions {
                        let mut settings = self.base.clone();
                        settings.solver_kind = SolverKind::Progressive;
                        settings.progressive.tolerance = fraction;
                        settings.progressive.max_shots = None;
                        settings.progressive.time_budget = None;
                        settings.progressive.preview_every = None;
                        runs.push(run(method, fraction, settings));
                    }
                }
            }
        }
        for r in &runs {
            r.settings.validate().map_err(|e| match e {
                Error::Setting { name, message } => Error::Setting {
                    name,
                    message: format!("{message} (in the {} run at {})", r.method, r.parameter),
                },
                other => other,
            })?;
        }
        Ok(runs)
    }
}

fn run(method: Method, parameter: f64, settings: Settings) -> SweepRun {
    SweepRun {
        method,
        parameter,
        settings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_list_value_gives_one_run_with_its_setting() {
        let scene = crate::scenes::cornell_box();
        let plan = SweepPlan {
            uniform_depths: vec![0, 2],
            adaptive_tolerances: vec![0.1],
            hemicube_resolutions: vec![64],
            patch_divisions: vec![2],
            unshot_fractions: vec![0.01],
            ..SweepPlan::default()
        };
        let runs = plan.runs(&scene).unwrap();
        let methods: Vec<Method> = runs.iter().map(|r| r.method).collect();
        assert_eq!(
            methods,
            [
                Method::Uniform,
                Method::Uniform,
                Method::Adaptive,
                Method::Hemicube,
                Method::Patches,
                Method::Progressive
            ]
        );
        assert_eq!(runs[1].settings.refine.uniform_depth, Some(2));
        assert_eq!(runs[2].settings.refine.uniform_depth, None);
        assert_eq!(runs[2].settings.refine.tolerance, 0.1);
        assert_eq!(runs[3].settings.hemicube_resolution, 64);
        let base_size = plan.base.patch_size_for(&scene);
        assert_eq!(runs[4].settings.patch_size, Some(base_size / 2.0));
        assert_eq!(runs[4].parameter, base_size / 2.0);
        assert_eq!(runs[4].settings.refine.uniform_depth, Some(0));
        assert_eq!(runs[5].settings.solver_kind, SolverKind::Progressive);
        assert_eq!(runs[5].settings.progressive.tolerance, 0.01);
        assert_eq!(runs[5].parameter, 0.01);
        // Only the progressive run changes the solver.
        assert!(runs[..5]
            .iter()
            .all(|r| r.settings.solver_kind == SolverKind::GaussSeidel));
    }

    #[test]
    fn bad_values_are_refused_naming_the_run() {
        let scene = crate::scenes::cornell_box();
        let plan = SweepPlan {
            hemicube_resolutions: vec![63],
            ..SweepPlan::default()
        };
        let e = plan.runs(&scene).unwrap_err().to_string();
        assert!(e.contains("hemicube run at 63"), "{e}");
        let plan = SweepPlan {
            patch_divisions: vec![0],
            ..SweepPlan::default()
        };
        assert!(plan.runs(&scene).is_err());
        let plan = SweepPlan {
            unshot_fractions: vec![0.1, 1.5],
            ..SweepPlan::default()
        };
        let e = plan.runs(&scene).unwrap_err().to_string();
        assert!(e.contains("progressive run at 1.5"), "{e}");
    }
}
