//! Progress reports: the library never prints; it calls back.

/// A stage of the solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Hemi-cube rows for new elements; `pass` 0 is the initial mesh.
    FormFactors {
        /// Refinement pass.
        pass: usize,
    },
    /// Coarse solve and gather.
    Solve,
}

/// How far a stage has come.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// The stage.
    pub stage: Stage,
    /// Units done.
    pub done: usize,
    /// Units in all.
    pub total: usize,
}
