//! Form factors: the hemi-cube (item buffer of patch ids at a receiving point),
//! the sparse rows it produces, and the source polygons it rasterizes.

mod backfaces;
mod bvh_walk;
mod contacts;
mod exposure;
mod eye;
pub mod hemicube;
mod method;
mod point_polygon;
mod quadrature;
mod row;
mod rows;
mod scratch;
mod shaft;
mod sources;
mod split_rows;
mod store;
mod unoccluded;
mod visibility;

pub(crate) use backfaces::{back_to_back_twins, ClosedObjects};
pub(crate) use eye::{eye_lift, receiving_point};
pub(crate) use hemicube::PartSources;
pub use method::{EmitterSampling, FormFactorMethod};
pub use point_polygon::point_to_polygon;
pub(crate) use quadrature::{element_samples, Samples};
pub use row::Row;
pub use rows::{compute_rows, RowSettings};
pub(crate) use rows::{compute_rows_with, element_seed, emitter_shifts, RowScene, RowSkips};
pub use sources::{SourcePolygon, Sources};
pub(crate) use split_rows::{update_rows_for_splits, SplitPatch};
pub(crate) use store::EmitterShift;
pub use store::{FormFactors, RowState, RowView};
pub(crate) use unoccluded::{is_convex_enclosure, unoccluded_row};
pub(crate) use visibility::{EmitterVisibility, Occluders, PixelHint, PointsMean};
