//! The form factor from a point to a polygon by Lambert's contour formula.
//!
//! For a receiving point `p` with unit normal `n` and a polygon entirely on the
//! front side of `p`'s tangent plane, with `R_i = v_i - p`:
//!
//! `F = | (1 / 2 pi) sum_i beta_i (n . u_i) |`,
//!
//! where `beta_i` is the angle edge `i` subtends at `p` and `u_i` the unit normal
//! of the plane through `p` and that edge. The formula integrates
//! `cos(theta_p)` over the polygon's solid angle, which is only the form factor
//! where `cos(theta_p) >= 0`: the polygon must first be clipped to the horizon,
//! otherwise the part below it counts negatively.

use crate::error::{Error, GeometryFault, Result};
use crate::math::{clip_to_halfspace, planarity_error};
use glam::DVec3;
use std::f64::consts::PI;

/// Largest relative out-of-plane deviation accepted for a polygon.
const PLANARITY_TOLERANCE: f64 = 1e-6;

/// The form factor from a differential area at `point` with normal `normal`
/// (any length) to the planar polygon `polygon` (any winding, 3 or more
/// vertices, not self-intersecting).
///
/// The polygon is clipped to the half-space in front of the point first, so
/// polygons partly or wholly below the horizon are handled. Visibility is not
/// considered (see [`super::OccludedLight`] for occluders). The result is
/// geometric: it does not matter which side of the polygon faces the point.
///
/// Fails on non-finite input, a zero normal, fewer than three vertices or a
/// non-planar polygon.
pub fn point_to_polygon(point: DVec3, normal: DVec3, polygon: &[DVec3]) -> Result<f64> {
    let unit_normal = checked_receiver(point, normal)?;
    check_polygon("polygon", polygon)?;
    Ok(horizon_clipped_form_factor(point, unit_normal, polygon))
}

/// Checks a receiving point and returns its unit normal.
pub(crate) fn checked_receiver(point: DVec3, normal: DVec3) -> Result<DVec3> {
    if !point.is_finite() {
        return Err(Error::geometry(
            GeometryFault::NonFinite,
            format!("receiving point {point} is not finite"),
        ));
    }
    normal.try_normalize().ok_or_else(|| {
        let fault = if normal.is_finite() {
            GeometryFault::Degenerate
        } else {
            GeometryFault::NonFinite
        };
        Error::geometry(
            fault,
            format!("receiver normal {normal} has no direction (zero or not finite)"),
        )
    })
}

/// Checks that `polygon` has at least three finite vertices and is planar; the
/// error names it by `what`.
pub(crate) fn check_polygon(what: &str, polygon: &[DVec3]) -> Result<()> {
    if polygon.len() < 3 {
        return Err(Error::geometry(
            GeometryFault::Degenerate,
            format!("{what} needs at least 3 vertices, got {}", polygon.len()),
        ));
    }
    if let Some(v) = polygon.iter().find(|v| !v.is_finite()) {
        return Err(Error::geometry(
            GeometryFault::NonFinite,
            format!("{what} has a non-finite vertex {v}"),
        ));
    }
    let deviation = planarity_error(polygon);
    if deviation > PLANARITY_TOLERANCE {
        return Err(Error::geometry(
            GeometryFault::NonPlanar,
            format!("{what} is not planar (relative deviation {deviation:.2e})"),
        ));
    }
    Ok(())
}

/// Lambert's formula after clipping `polygon` to the front of `point`'s tangent
/// plane. `unit_normal` must have length one; the input is not checked.
pub(crate) fn horizon_clipped_form_factor(
    point: DVec3,
    unit_normal: DVec3,
    polygon: &[DVec3],
) -> f64 {
    let visible = clip_to_halfspace(polygon, point, unit_normal);
    if visible.len() < 3 {
        return 0.0;
    }
    // A polygon lying in the tangent plane itself is seen at grazing angle and
    // receives nothing; the contour sum would instead report the winding number
    // of the point around it.
    let scale = visible
        .iter()
        .map(|v| (*v - point).length())
        .fold(0.0, f64::max);
    let height = visible
        .iter()
        .map(|v| unit_normal.dot(*v - point))
        .fold(0.0, f64::max);
    if height <= 1e-12 * scale {
        return 0.0;
    }
    contour_sum(point, unit_normal, &visible)
}

/// `|1/(2 pi) sum beta_i n.u_i|` over the edges of a polygon that lies wholly on
/// the front side of the point.
fn contour_sum(point: DVec3, unit_normal: DVec3, polygon: &[DVec3]) -> f64 {
    let m = polygon.len();
    let mut sum = 0.0;
    for i in 0..m {
        let a = polygon[i] - point;
        let b = polygon[(i + 1) % m] - point;
        let c = a.cross(b);
        let c_len = c.length();
        // The point on the edge's line: the edge subtends no solid angle, or a
        // degenerate one whose plane is undefined. Either way it adds nothing.
        if c_len <= 1e-15 * a.length() * b.length() {
            continue;
        }
        let beta = c_len.atan2(a.dot(b));
        sum += beta * unit_normal.dot(c) / c_len;
    }
    (sum / (2.0 * PI)).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square_at(height: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(-0.5, height, -0.5),
            DVec3::new(0.5, height, -0.5),
            DVec3::new(0.5, height, 0.5),
            DVec3::new(-0.5, height, 0.5),
        ]
    }

    #[test]
    fn winding_does_not_matter() {
        let p = DVec3::new(0.1, 0.0, 0.2);
        let mut sq = unit_square_at(1.0);
        let f1 = point_to_polygon(p, DVec3::Y, &sq).unwrap();
        sq.reverse();
        let f2 = point_to_polygon(p, DVec3::Y, &sq).unwrap();
        assert_eq!(f1, f2);
        assert!(f1 > 0.0);
    }

    #[test]
    fn polygon_behind_the_point_gives_zero() {
        let f = point_to_polygon(DVec3::ZERO, DVec3::Y, &unit_square_at(-1.0)).unwrap();
        assert_eq!(f, 0.0);
    }

    #[test]
    fn polygon_in_the_tangent_plane_gives_zero() {
        let f = point_to_polygon(DVec3::ZERO, DVec3::Y, &unit_square_at(0.0)).unwrap();
        assert_eq!(f, 0.0);
    }

    #[test]
    fn normal_length_does_not_matter() {
        let sq = unit_square_at(2.0);
        let p = DVec3::new(0.3, 0.0, -0.2);
        let f1 = point_to_polygon(p, DVec3::Y, &sq).unwrap();
        let f2 = point_to_polygon(p, DVec3::Y * 7.5, &sq).unwrap();
        assert!((f1 - f2).abs() < 1e-16);
    }

    #[test]
    fn bad_input_is_refused() {
        let sq = unit_square_at(1.0);
        assert!(point_to_polygon(DVec3::ZERO, DVec3::ZERO, &sq).is_err());
        assert!(point_to_polygon(DVec3::splat(f64::NAN), DVec3::Y, &sq).is_err());
        assert!(point_to_polygon(DVec3::ZERO, DVec3::Y, &sq[..2]).is_err());
        let mut warped = sq.clone();
        warped[2].y += 0.1;
        assert!(point_to_polygon(DVec3::ZERO, DVec3::Y, &warped).is_err());
    }
}
