//! Form factors: the hemi-cube (item buffer of patch ids at a receiving point),
//! the sparse rows it produces, and the source polygons it rasterizes.

mod backfaces;
mod exposure;
mod eye;
pub mod hemicube;
mod method;
mod point_polygon;
mod quadrature;
mod row;
mod rows;
mod shaft;
mod sources;
mod split_rows;
mod store;
mod unoccluded;
mod visibility;

pub use backfaces::{ClosedObjects, MAX_OBJECT_SURFACES};
pub use eye::{eye_lift, receiving_point, EYE_LIFT};
pub use method::{EmitterSampling, FormFactorMethod};
pub use point_polygon::point_to_polygon;
pub use quadrature::{element_samples, Samples};
pub use row::Row;
pub use rows::{compute_rows, compute_rows_with, element_seed, RowSettings, RowSkips};
pub use sources::{SourcePolygon, Sources};
pub(crate) use split_rows::{update_rows_for_splits, SplitPatch};
pub use store::{FormFactors, RowState};
pub use unoccluded::{is_convex_enclosure, scene_scale, unoccluded_row, CONVEX_TOLERANCE};
pub use visibility::{EmitterVisibility, Occluders, PixelHint};
