//! Small numeric helpers shared by every stage: colour triples and planar polygons.

mod polygon;
mod rgb;

pub(crate) use polygon::{
    clip_in_place, clip_to_halfspace, is_convex, newell_normal, planarity_error,
};
pub use polygon::{polygon_area, polygon_centroid};
pub use rgb::Rgb;
