//! Progress reports: the library never prints; it calls back.

/// A stage of the solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stage {
    /// Hemi-cube rows for new elements; `pass` 0 is the initial mesh.
    FormFactors {
        /// Refinement pass.
        pass: usize,
    },
    /// Facets that share their group lead's row find their own view of the
    /// emitters (see `crate::formfactor::FormFactors::emitter_shift`).
    SharedRows {
        /// Refinement pass.
        pass: usize,
    },
    /// Coarse solve and gather.
    Solve,
    /// Hemi-cubes drawn again in a shaped gather, to see near patches part
    /// by part (`Settings::part_views`).
    PartViews,
    /// Light groups solved one by one on the refined mesh
    /// ([`crate::light_groups`]).
    LightGroups,
    /// Progressive shooting; `done / total` is the progress of the unshot
    /// fraction from 1 to the tolerance on a log scale.
    Shoot {
        /// Shots so far.
        shots: usize,
        /// Unshot power over emitted power.
        unshot_fraction: f64,
    },
}

/// How far a stage has come.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// The stage.
    pub stage: Stage,
    /// Units done.
    pub done: usize,
    /// Units in all.
    pub total: usize,
}
