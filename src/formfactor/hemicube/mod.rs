//! The hemi-cube of Cohen & Greenberg (1985): five faces of a unit half-cube around
//! a receiving point, an item buffer of patch ids with a depth test, and a table of
//! delta form factors that turns covered pixels into form factors.

mod faces;
mod raster;
mod table;

pub(crate) use raster::Coverage;
pub use raster::{Hemicube, HemicubeStats};
pub use table::DeltaTable;
