//! Solving the coarse patch system and gathering element radiosities.
//!
//! The patch system `B_i = E_i + rho_i sum_j F_ij B_j` is solved by Gauss-Seidel
//! for the three bands at once; its rows are the element rows averaged with
//! weights by exposure (area times row sum, see [`PatchSystem`]). Element
//! radiosities then come from one gather,
//! `B_e = E_e + rho_e sum_j F_ej B_j`. The progressive solver
//! (`pipeline::progressive`) solves the same system by shooting instead. `bounces` keeps a fixed number of reflections
//! instead of solving (direct light only, for comparison).

pub mod balance;
pub(crate) mod bounces;
mod direct;
mod gather;
mod gauss_seidel;
mod kept_shapes;
mod radiosity;
mod ragged;
mod sky_light;
pub(crate) mod source_shape;
mod system;

pub(crate) use bounces::gather_bounces;
pub(crate) use direct::DirectLight;
pub use gather::{gather, GatherTotals};
pub(crate) use gather::{gather_with, shaped_factors, shaped_weights, GatherOptions};
pub use gauss_seidel::{gauss_seidel, SolveReport, SolverSettings, MAX_CONTRACTION};
pub(crate) use gauss_seidel::{gauss_seidel_grey, gauss_seidel_with_source, refuse_unbounded_row};
pub(crate) use kept_shapes::KeptShapes;
pub use radiosity::Radiosity;
pub use system::PatchSystem;
pub(crate) use system::{dark_patches, scene_is_closed, weight};
