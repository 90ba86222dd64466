//! Solving the coarse patch system and gathering element radiosities.
//!
//! The patch system `B_i = E_i + rho_i sum_j F_ij B_j` is solved by Gauss-Seidel
//! for the three bands at once; its rows are the area-weighted sums of the
//! element rows. Element radiosities then come from one gather,
//! `B_e = E_e + rho_e sum_j F_ej B_j`. [`progressive`] solves the same system
//! by shooting instead. [`bounces`] keeps a fixed number of reflections
//! instead of solving (direct light only, for comparison).

pub mod bounces;
mod gather;
mod gauss_seidel;
pub mod progressive;
mod radiosity;
mod system;

pub use bounces::{bounced_radiosity, gather_bounces, MAX_BOUNCES};
pub use gather::{gather, gather_with, GatherOptions, GatherTotals};
pub use gauss_seidel::{
    gauss_seidel, gauss_seidel_grey, SolveReport, SolverSettings, MAX_CONTRACTION, PLAIN_SWEEPS,
    STALL_SWEEPS,
};
pub use progressive::{ProgressiveSettings, SolverKind};
pub use radiosity::Radiosity;
pub use system::PatchSystem;
