//! Running a sweep: solve, time and measure every run.

use super::cpu_time::process_cpu_seconds;
use super::metrics::{error_summary, point_errors, ErrorSummary};
use super::objects::{object_errors, ObjectError, ObjectReference};
use super::{Method, ReferencePoints, SweepRun};
use crate::error::{Error, Result};
use crate::pipeline::solve;
use crate::scene::Scene;
use crate::solution::Solution;
use serde::Serialize;
use std::time::Instant;

/// What one run cost and how far it is from the reference.
#[derive(Clone, Debug, Serialize)]
pub struct RunRecord {
    /// The curve it belongs to.
    pub method: Method,
    /// The value of the method's parameter.
    pub parameter: f64,
    /// Wall-clock seconds of the library solve: the shortest of the repeats,
    /// the one least slowed by other work on the machine.
    pub seconds: f64,
    /// CPU seconds (user plus system, over every thread of the process) of
    /// the library solve: the smallest of the repeats. `None` where the
    /// platform does not tell (see [`process_cpu_seconds`]).
    pub cpu_seconds: Option<f64>,
    /// Patches of the final mesh.
    pub patches: usize,
    /// Leaf elements of the final mesh.
    pub elements: usize,
    /// Hemi-cubes rendered over all passes.
    pub hemicubes: u64,
    /// Element-to-patch form factors stored.
    pub form_factors: usize,
    /// Patch-to-patch form factors of the coarse system.
    pub patch_form_factors: usize,
    /// The deepest leaf below its patch.
    pub max_depth: u8,
    /// Relative errors at the reference points.
    pub errors: ErrorSummary,
    /// Per-object mean errors (empty unless object references were given).
    pub objects: Vec<ObjectError>,
}

/// Progress of [`run_sweep`].
#[derive(Clone, Copy, Debug)]
pub enum SweepEvent<'a> {
    /// Run `index` (from 0) of `total` is about to be solved.
    Started {
        /// Its position in the sweep.
        index: usize,
        /// Runs in the sweep.
        total: usize,
        /// The run.
        run: &'a SweepRun,
    },
    /// Run `index` of `total` is measured.
    Finished {
        /// Its position in the sweep.
        index: usize,
        /// Runs in the sweep.
        total: usize,
        /// What it measured.
        record: &'a RunRecord,
    },
}

/// Solves every run `repeats` times (keeping the shortest wall-clock and the
/// smallest CPU time, each over the repeats; the solution is the same bits each
/// time) and measures it against `reference`, and against `objects` when given.
/// Runs are solved one after another, each using every worker thread, so their
/// times are comparable. Every method's error is measured the same way, from
/// the solution's element radiosities ([`point_errors`]).
///
/// Fails on `repeats == 0` and on the first run that fails, naming it.
pub fn run_sweep(
    scene: &Scene,
    runs: &[SweepRun],
    reference: &ReferencePoints,
    objects: Option<&[ObjectReference]>,
    repeats: usize,
    progress: &dyn Fn(SweepEvent<'_>),
) -> Result<Vec<RunRecord>> {
    if repeats == 0 {
        return Err(Error::Setting {
            name: "repeats",
            message: "each run must be solved at least once".into(),
        });
    }
    let total = runs.len();
    let mut records = Vec::with_capacity(total);
    for (index, run) in runs.iter().enumerate() {
        progress(SweepEvent::Started { index, total, run });
        let record = measure_run(scene, run, reference, objects, repeats)
            .map_err(|e| name_the_run(e, run))?;
        progress(SweepEvent::Finished {
            index,
            total,
            record: &record,
        });
        records.push(record);
    }
    Ok(records)
}

fn measure_run(
    scene: &Scene,
    run: &SweepRun,
    reference: &ReferencePoints,
    objects: Option<&[ObjectReference]>,
    repeats: usize,
) -> Result<RunRecord> {
    let mut times = Vec::with_capacity(repeats);
    let mut cpu_times = Vec::with_capacity(repeats);
    let mut last: Option<Solution> = None;
    for _ in 0..repeats {
        // The previous solution is freed before timing the next one.
        drop(last.take());
        let cpu_started = process_cpu_seconds();
        let started = Instant::now();
        let solution = solve(scene, &run.settings, &|_| {})?;
        times.push(started.elapsed().as_secs_f64());
        if let (Some(a), Some(b)) = (cpu_started, process_cpu_seconds()) {
            cpu_times.push((b - a).max(0.0));
        }
        last = Some(solution);
    }
    let solution = last.expect("repeats >= 1");
    let errors = error_summary(reference, &point_errors(&solution, reference)?);
    let objects = match objects {
        Some(r) => object_errors(&solution, scene, r)?,
        None => Vec::new(),
    };
    let stats = &solution.stats;
    let mesh = &solution.mesh;
    let max_depth = mesh
        .elements
        .values()
        .filter(|e| e.is_leaf())
        .map(|e| e.depth)
        .max()
        .unwrap_or(0);
    Ok(RunRecord {
        method: run.method,
        parameter: run.parameter,
        seconds: times.iter().copied().fold(f64::INFINITY, f64::min),
        cpu_seconds: (cpu_times.len() == repeats)
            .then(|| cpu_times.iter().copied().fold(f64::INFINITY, f64::min)),
        patches: stats.patches,
        elements: stats.elements,
        hemicubes: stats.hemicube.hemicubes,
        form_factors: stats.hemicube.element_form_factors,
        patch_form_factors: stats.hemicube.patch_form_factors,
        max_depth,
        errors,
        objects,
    })
}

/// Prefixes the message of `e` with the run it came from.
fn name_the_run(e: Error, run: &SweepRun) -> Error {
    let what = format!("{} run at {}", run.method, run.parameter);
    match e {
        Error::Limit { limit, message } => Error::Limit {
            limit,
            message: format!("{what}: {message}"),
        },
        Error::Solver { fault, message } => Error::Solver {
            fault,
            message: format!("{what}: {message}"),
        },
        Error::Geometry { fault, message } => Error::Geometry {
            fault,
            message: format!("{what}: {message}"),
        },
        Error::Setting { name, message } => Error::Setting {
            name,
            message: format!("{message} ({what})"),
        },
        other => other,
    }
}
