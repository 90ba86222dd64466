//! Exact reference solutions (test oracles), independent of the hemi-cube.
//!
//! Everything here is either a closed form or an exact geometric construction
//! evaluated in double precision, so that the approximate stages of the solver
//! can be checked against values that do not share any of their code:
//!
//! - [`rectangles`]: closed-form form factors between rectangles (Howell C-11 and
//!   C-14) and from a point to a parallel rectangle opposite its corner;
//! - [`lambert`]: the form factor from a point to any polygon, by Lambert's
//!   contour formula after clipping the polygon to the point's horizon;
//! - [`convex_clip`]: Sutherland-Hodgman intersection of convex polygons, in a
//!   plane or against the cone from an apex through a polygon;
//! - [`penumbra`]: the exact visible form factor from a point to a polygonal light
//!   partly hidden by planar convex occluders (full light, penumbra and umbra);
//! - [`cube`]: the exact discrete solution of the 6-patch unit cube;
//! - [`furnace`]: enclosure identities (`E / (1 - rho)` and the area mean);
//! - [`quadrature`]: adaptive integration over a planar element, robust to the
//!   kinks a penumbra puts into the integrand.
//!
//! Formulas and check values come from the project's research brief (section 4);
//! the tests reproduce its tables.

pub mod convex_clip;
pub mod cube;
pub mod furnace;
pub mod lambert;
pub mod penumbra;
pub mod quadrature;
pub mod rectangles;

pub use cube::{unit_cube_ceiling_lit, unit_cube_radiosity, CubeFace};
pub use furnace::{enclosure_mean_radiosity, furnace_radiosity};
pub use lambert::point_to_polygon;
pub use penumbra::OccludedLight;
pub use quadrature::{integrate_over_polygon, integrate_unit_square, Integral, QuadratureSettings};
pub use rectangles::{parallel_rectangles, perpendicular_rectangles, point_to_rectangle_corner};

use crate::error::{Error, GeometryFault, Result};

/// Checks that a length is finite and strictly positive; the error names it.
fn positive_length(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::geometry(
            GeometryFault::OutOfRange,
            format!("{name} must be a finite positive length, got {value}"),
        ))
    }
}
