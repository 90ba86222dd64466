//! Form factors: the hemi-cube (item buffer of patch ids at a receiving point),
//! the sparse rows it produces, and the source polygons it rasterizes.

pub mod hemicube;
mod method;
mod point_polygon;
mod quadrature;
mod row;
mod rows;
mod shaft;
mod sources;
mod visibility;

pub use method::FormFactorMethod;
pub use point_polygon::point_to_polygon;
pub use quadrature::{element_samples, Samples};
pub use row::Row;
pub use rows::{compute_rows, element_seed, RowSettings};
pub use sources::{SourcePolygon, Sources};
pub use visibility::{EmitterVisibility, Occluders, PixelHint};
