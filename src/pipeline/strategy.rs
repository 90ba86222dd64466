//! The interface between the one driver and a solver: the driver owns set-up,
//! refinement passes and figures; a solver turns form factors into
//! radiosities on whatever mesh the driver hands it.

use super::workspace::Workspace;
use crate::error::Result;
use crate::mesh::ElementKey;
use crate::solution::Solution;

/// What a solver wants next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Next {
    /// A refinement pass: the driver marks and splits leaves, then calls
    /// [`Solver::refined`] or [`Solver::nothing_to_refine`].
    Refine,
    /// The solve is over.
    Stop,
}

/// A solver run by the driver (gathering or shooting), once it has started
/// on the initial mesh.
pub(crate) trait Solver {
    /// Works on until a refinement pass is due or the solve is over.
    fn advance(&mut self, ws: &mut Workspace<'_>) -> Result<Next>;

    /// Brings the solution up to refinement pass `pass`, which made the new
    /// leaves `fresh`. Returns the hemi-cubes it rendered.
    fn refined(
        &mut self,
        ws: &mut Workspace<'_>,
        fresh: &[ElementKey],
        pass: usize,
    ) -> Result<usize>;

    /// A refinement pass found nothing to split.
    fn nothing_to_refine(&mut self, ws: &mut Workspace<'_>) -> Result<()>;

    /// The solution, with the solver's figures in the stats.
    fn finish(self, ws: Workspace<'_>) -> Solution;
}
