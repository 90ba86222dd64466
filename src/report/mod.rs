//! Run time against error: sweeps of solver settings, each run measured against
//! a reference that does not depend on the mesh, written as CSV, Markdown and
//! plots.
//!
//! # Brief overview
//!
//! - [`SweepPlan`] lists what to vary ([`Method`]: uniform subdivision depths,
//!   adaptive tolerances, hemi-cube resolutions, uniformly small patches, the
//!   progressive solver's stopping points) and turns a base
//!   [`Settings`](crate::Settings) into one [`SweepRun`] per value.
//! - [`ReferencePoints`] is the ground truth at a fixed set of points: the exact
//!   oracle on the floor of a built-in penumbra scene
//!   ([`ReferencePoints::exact`]), or the Monte Carlo path tracer of
//!   [`crate::reference`] at points spread over every non-emitting surface
//!   ([`ReferencePoints::monte_carlo`]). It is computed once per sweep.
//! - [`run_sweep`] solves every run, times it (wall clock and
//!   [`process_cpu_seconds`]) and measures its
//!   [`ErrorSummary`] (mean, RMS and largest relative error at the points),
//!   giving one [`RunRecord`] each. With [`ObjectReference`]s it also measures
//!   per-object mean errors.
//! - [`runs_csv`], [`objects_csv`] and [`markdown_report`] format the records;
//!   [`write_time_plot`] and [`write_depth_plot`] draw them as SVG and PNG.
//!
//! # Relative error
//!
//! At a reference point with reference radiosity `R` and solved radiosity `B`
//! the error in band `k` is `|B_k - R_k| / max(R_k, f_k)`, where the floor
//! `f_k` is [`ERROR_FLOOR_FRACTION`] (1 %) of the mean reflected radiosity
//! `R_k - E_k` over all reference points of the scene. The floor keeps points in
//! deep shadow (where `R` is near 0) from dominating the figures: there an error
//! is measured against one hundredth of the scene's typical brightness. A point's
//! error is the mean of its three band errors. Points on emitting surfaces are
//! not used: their radiosity is mostly the emission the scene gives them. Nor
//! are points inside closed objects, such as the floor under a box
//! ([`sees_only_back_faces`]): no light reaches them and no camera outside sees
//! them, but the mesh element that straddles the object's outline gives them a
//! value, so their relative error against the floor is large and meaningless.
//!
//! The library never prints; progress is reported through a callback.

mod cpu_time;
mod equal_error;
mod hidden;
mod markdown;
mod method;
mod metrics;
mod objects;
mod plan;
mod plot;
mod plot_style;
mod points;
mod reference_points;
mod sweep;
mod table;

pub use cpu_time::process_cpu_seconds;
pub(crate) use equal_error::{equal_error_speedups, Clock};
pub use hidden::sees_only_back_faces;
pub use markdown::markdown_report;
pub use method::{Method, SweepRun};
pub use metrics::{point_errors, ErrorMetric, ErrorSummary, PointError, ERROR_FLOOR_FRACTION};
pub use objects::{object_reference, ObjectError, ObjectReference};
pub use plan::{SweepPlan, DEFAULT_UNSHOT_FRACTIONS};
pub use plot::{stage_depth_plot, stage_time_plot, write_depth_plot, write_time_plot};
pub use points::floor_points;
pub use reference_points::{MonteCarloPoints, ReferenceKind, ReferencePoint, ReferencePoints};
pub use sweep::{run_sweep, RunRecord, SweepEvent};
pub use table::{objects_csv, runs_csv, RUN_COLUMNS};
