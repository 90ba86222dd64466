//! Progressive refinement (Cohen, Chen, Wallace, Greenberg 1988): instead of
//! solving for every patch at once, the patch with the most unshot power
//! shoots it to every leaf element it sees, and its unshot radiosity becomes
//! zero. Each receiving leaf `e` gains `dB_e = rho_e dB_i F_ei` (with `F_ei =
//! F_ie A_i / A_e` in the classic form), and its patch's unshot radiosity the
//! area-weighted share. No form factor has to be computed before the first
//! shot, so early results come in time linear in the number of patches, and
//! the result converges to the solution of the same radiosity system as
//! gathering. A patch's factors are kept for its later shots (within a byte
//! budget), which then render nothing.
//!
//! Shooter-side hemi-cubes see the receivers from a few points of a large
//! patch, which is where classic implementations lose accuracy in cluttered
//! scenes. By default the shots turn to the gathering rows once the first
//! quick shots are done (see [`ProgressiveSettings::gather_rows`]): at the
//! first refinement pass every leaf renders its own hemi-cube, as in the
//! Gauss-Seidel path, what has been shot is gathered again with the rows, and
//! from then on a shot of patch `j` delivers `F_ej` from each leaf's row. The
//! solve then converges to the Gauss-Seidel solution of its mesh.
//!
//! The parts, one file each:
//!
//! - [`settings`](ProgressiveSettings): [`SolverKind`], stopping rules, shooter
//!   cells, refinement pace;
//! - `ShootingState`: radiosity, unshot and shot radiosity per patch,
//!   irradiance per leaf;
//! - `Receivers`: the leaves as an item-buffer polygon list;
//! - `Shooter`: the form factors of one shot (see its module for the hybrid
//!   and classic forms, and how reciprocals above 1 are handled);
//! - `ShotCache`: each patch's form factors, kept for its next shots;
//! - `visible_fractions`: the visible part of each leaf from the item buffer;
//! - `ambient_term`: the display-only ambient term;
//! - `Stopping`: unshot fraction, shot count, time budget;
//! - `adopt`: new elements of a refinement pass gather what has been shot;
//! - [`ProgressiveStats`]: the figures.
//!
//! The driver that runs these over a scene is `pipeline::progressive`.

mod ambient;
mod cache;
mod cell;
mod newborn;
mod receivers;
mod report;
mod settings;
mod shoot;
mod state;
mod stopping;
mod visibility;

pub(crate) use ambient::ambient_term;
pub(crate) use cache::ShotCache;
pub(crate) use newborn::{adopt, regather, settle};
pub(crate) use receivers::Receivers;
pub use report::{HistoryPoint, ProgressiveStats, ShootingPass};
pub use settings::{ProgressiveSettings, SolverKind, MAX_SHOOTER_DEPTH};
pub(crate) use shoot::Shooter;
pub use shoot::MAX_SHOOTER_SPLITS;
pub(crate) use state::ShootingState;
pub use stopping::StopReason;
pub(crate) use stopping::Stopping;
