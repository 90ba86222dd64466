//! Exact ray casting over a scene's surfaces: each surface as an exactly
//! planar convex polygon (`geometry`) and a BVH broad phase over them
//! (`accel`). The reference path tracer casts its paths with it, and the
//! framing's room finder its probe rays.

mod accel;
mod geometry;

pub(crate) use accel::Accel;
pub(crate) use geometry::{SurfaceGeometry, Tolerances};
