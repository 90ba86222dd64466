//! The exact form factor from a point to a polygonal light partly hidden by
//! planar convex occluders: full light, penumbra and umbra.
//!
//! # Construction
//!
//! For a receiving point `x` with unit normal `n`:
//!
//! 1. Clip the light `L` to `x`'s horizon (`n . (y - x) >= 0`).
//! 2. Each occluder `O` hides from `x` the part of the light plane inside the
//!    cone of rays from `x` through `O`. Only the part of `O` in the slab between
//!    the plane through `x` parallel to the light and the light plane itself can
//!    hide anything: a point of `O` beyond the light plane is behind the light,
//!    and a point on `x`'s side of that parallel plane lies on rays that move
//!    away from the light. So `O` is clipped to the slab first. The remaining
//!    polygon is convex, and so is its cone; clipping `L` by the cone's planes
//!    (one plane through `x` and each edge) gives `L` intersected with the
//!    central projection of `O` onto the light plane, without forming projected
//!    vertices, which run off to infinity as an occluder edge comes level with
//!    `x`.
//! 3. Several occluders hide the **union** of their projections. The union is
//!    measured by inclusion-exclusion, `F(L ∩ ∪ P_k) = Σ F(L ∩ P_k) -
//!    Σ F(L ∩ P_j ∩ P_k) + ...`, which is exact because the form factor is an
//!    additive measure over regions of the light, and each intersection of
//!    convex projections is convex. Empty intersections prune their supersets.
//!    This costs up to `2^k` terms, which is fine for a handful of occluders.
//! 4. `F_visible = F(L) - F(L ∩ ∪ P_k)`, each term by Lambert's formula.
//!
//! Occluders block from both sides; the form factor is geometric, so the caller
//! decides whether the light's emitting side faces the point.

use super::convex_clip::{intersect_with_cone, ClippedPolygon};
use super::lambert::{check_polygon, checked_receiver, horizon_clipped_form_factor};
use crate::error::{Error, GeometryFault, Result};
use crate::math::{clip_to_halfspace, is_convex, newell_normal};
use glam::DVec3;

/// The most occluders an [`OccludedLight`] accepts (inclusion-exclusion costs up
/// to `2^k` terms per point).
pub const MAX_OCCLUDERS: usize = 12;

/// A convex polygonal light with planar convex occluders, validated once so that
/// it can be evaluated at many receiving points.
#[derive(Clone, Debug, PartialEq)]
pub struct OccludedLight {
    light: Vec<DVec3>,
    light_point: DVec3,
    light_normal: DVec3,
    occluders: Vec<Vec<DVec3>>,
}

impl OccludedLight {
    /// A light polygon and its occluders (any winding each).
    ///
    /// Fails if the light or an occluder has fewer than three finite vertices,
    /// is not planar or not strictly convex, or if there are more than
    /// [`MAX_OCCLUDERS`] occluders.
    pub fn new<P: AsRef<[DVec3]>>(light: &[DVec3], occluders: &[P]) -> Result<Self> {
        let light_normal = convex_normal("light", light)?;
        if occluders.len() > MAX_OCCLUDERS {
            return Err(Error::geometry(
                GeometryFault::Unsupported,
                format!(
                    "{} occluders given, the exact penumbra oracle takes at most {MAX_OCCLUDERS}",
                    occluders.len()
                ),
            ));
        }
        for (k, o) in occluders.iter().enumerate() {
            convex_normal(&format!("occluder {k}"), o.as_ref())?;
        }
        Ok(OccludedLight {
            light: light.to_vec(),
            light_point: light.iter().copied().sum::<DVec3>() / light.len() as f64,
            light_normal,
            occluders: occluders.iter().map(|o| o.as_ref().to_vec()).collect(),
        })
    }

    /// The light polygon.
    #[must_use]
    pub fn light(&self) -> &[DVec3] {
        &self.light
    }

    /// The occluder polygons.
    #[must_use]
    pub fn occluders(&self) -> &[Vec<DVec3>] {
        &self.occluders
    }

    /// The form factor from `point` (with `normal`, any length) to the whole
    /// light, ignoring the occluders. Fails on a non-finite point or a zero
    /// normal.
    pub fn unoccluded_form_factor(&self, point: DVec3, normal: DVec3) -> Result<f64> {
        let n = checked_receiver(point, normal)?;
        Ok(horizon_clipped_form_factor(point, n, &self.light))
    }

    /// The form factor from `point` (with `normal`, any length) to the part of
    /// the light its occluders leave visible. Fails on a non-finite point or a
    /// zero normal.
    pub fn visible_form_factor(&self, point: DVec3, normal: DVec3) -> Result<f64> {
        let n = checked_receiver(point, normal)?;
        Ok(self.visible_form_factor_unchecked(point, n))
    }

    /// [`Self::visible_form_factor`] for a finite point and a unit normal.
    pub(crate) fn visible_form_factor_unchecked(&self, point: DVec3, unit_normal: DVec3) -> f64 {
        let lit = clip_to_halfspace(&self.light, point, unit_normal);
        if lit.len() < 3 {
            return 0.0;
        }
        let full = horizon_clipped_form_factor(point, unit_normal, &lit);
        if full == 0.0 {
            return 0.0;
        }
        let blockers = self.blockers_seen_from(point);
        if blockers.is_empty() {
            return full;
        }
        let mut blocked = 0.0;
        add_union_terms(point, unit_normal, &lit, &blockers, 0, 1.0, &mut blocked);
        (full - blocked).clamp(0.0, full)
    }

    /// Each occluder clipped to the slab between the plane through `point`
    /// parallel to the light and the light plane: the only part that can hide
    /// the light from `point`. Occluders with nothing left are dropped.
    fn blockers_seen_from(&self, point: DVec3) -> Vec<ClippedPolygon> {
        let signed_depth = self.light_normal.dot(self.light_point - point);
        if signed_depth == 0.0 {
            // The point is in the light plane and sees the light edge-on.
            return Vec::new();
        }
        // `towards` points from `point` towards the light plane.
        let towards = self.light_normal * signed_depth.signum();
        let depth = signed_depth.abs();
        let far_plane = point + towards * depth;
        self.occluders
            .iter()
            .filter_map(|o| {
                let near = clip_to_halfspace(o, point, towards);
                let slab = clip_to_halfspace(&near, far_plane, -towards);
                (slab.len() >= 3).then_some(slab)
            })
            .collect()
    }
}

/// Adds the inclusion-exclusion terms for every set of blockers whose smallest
/// index is at least `first`, each intersected with `region` (already the light
/// cut by the blockers chosen so far), with alternating `sign`.
fn add_union_terms(
    apex: DVec3,
    unit_normal: DVec3,
    region: &[DVec3],
    blockers: &[ClippedPolygon],
    first: usize,
    sign: f64,
    total: &mut f64,
) {
    for k in first..blockers.len() {
        let hidden = intersect_with_cone(region, apex, &blockers[k]);
        if hidden.len() < 3 {
            // Every larger set of blockers hides a subset of this: also nothing.
            continue;
        }
        *total += sign * horizon_clipped_form_factor(apex, unit_normal, &hidden);
        add_union_terms(apex, unit_normal, &hidden, blockers, k + 1, -sign, total);
    }
}

/// Checks a convex planar polygon and returns its unit normal.
fn convex_normal(what: &str, polygon: &[DVec3]) -> Result<DVec3> {
    check_polygon(what, polygon)?;
    let n = newell_normal(polygon);
    if !is_convex(polygon, n) {
        return Err(Error::geometry(
            GeometryFault::NonConvex,
            format!("{what} is not strictly convex (or has repeated vertices)"),
        ));
    }
    n.try_normalize()
        .ok_or_else(|| Error::geometry(GeometryFault::Degenerate, format!("{what} has zero area")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, x1: f64, z0: f64, z1: f64, y: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(x0, y, z0),
            DVec3::new(x1, y, z0),
            DVec3::new(x1, y, z1),
            DVec3::new(x0, y, z1),
        ]
    }

    fn light() -> Vec<DVec3> {
        square(-0.5, 0.5, -0.5, 0.5, 4.0)
    }

    const P: DVec3 = DVec3::new(0.2, 0.0, -0.1);

    fn visible(occluders: &[Vec<DVec3>]) -> f64 {
        OccludedLight::new(&light(), occluders)
            .unwrap()
            .visible_form_factor(P, DVec3::Y)
            .unwrap()
    }

    #[test]
    fn no_occluder_is_the_plain_form_factor() {
        let none: [Vec<DVec3>; 0] = [];
        let f = visible(&none);
        let g = super::super::point_to_polygon(P, DVec3::Y, &light()).unwrap();
        assert_eq!(f, g);
    }

    #[test]
    fn occluders_outside_the_slab_do_nothing() {
        let none: [Vec<DVec3>; 0] = [];
        let free = visible(&none);
        let below = square(-3.0, 3.0, -3.0, 3.0, -1.0);
        let above = square(-3.0, 3.0, -3.0, 3.0, 5.0);
        assert_eq!(visible(&[below, above]), free);
    }

    #[test]
    fn a_covering_occluder_leaves_nothing() {
        assert_eq!(visible(&[square(-3.0, 3.0, -3.0, 3.0, 2.0)]), 0.0);
    }

    #[test]
    fn the_part_beyond_the_light_plane_is_ignored() {
        // A vertical occluder crossing the light plane acts as its part below it.
        let tall = vec![
            DVec3::new(0.1, 1.0, -3.0),
            DVec3::new(0.1, 1.0, 3.0),
            DVec3::new(0.1, 9.0, 3.0),
            DVec3::new(0.1, 9.0, -3.0),
        ];
        let cut = vec![
            DVec3::new(0.1, 1.0, -3.0),
            DVec3::new(0.1, 1.0, 3.0),
            DVec3::new(0.1, 4.0, 3.0),
            DVec3::new(0.1, 4.0, -3.0),
        ];
        let a = visible(&[tall]);
        let b = visible(&[cut]);
        assert!((a - b).abs() < 1e-15, "{a} {b}");
        assert!(a > 0.0);
    }

    #[test]
    fn a_repeated_occluder_hides_no_more_than_one() {
        let o = square(0.0, 2.0, -2.0, 2.0, 2.0);
        let one = visible(std::slice::from_ref(&o));
        let two = visible(&[o.clone(), o]);
        assert!((one - two).abs() < 1e-15, "{one} {two}");
    }

    #[test]
    fn occluder_order_does_not_matter() {
        let a = square(0.0, 2.0, -2.0, 2.0, 2.0);
        let b = square(-1.0, 0.5, -2.0, 0.0, 1.0);
        let c = square(-2.0, 2.0, 0.05, 2.0, 3.0);
        let f1 = visible(&[a.clone(), b.clone(), c.clone()]);
        let f2 = visible(&[c, a, b]);
        assert!((f1 - f2).abs() < 1e-15, "{f1} {f2}");
    }

    #[test]
    fn too_many_or_bad_occluders_are_refused() {
        let o = square(0.0, 1.0, 0.0, 1.0, 2.0);
        let many = vec![o; MAX_OCCLUDERS + 1];
        assert!(OccludedLight::new(&light(), &many).is_err());
        let dart = vec![
            DVec3::new(0.0, 2.0, 0.0),
            DVec3::new(2.0, 2.0, 0.0),
            DVec3::new(0.5, 2.0, 0.5),
            DVec3::new(0.0, 2.0, 2.0),
        ];
        assert!(OccludedLight::new(&light(), &[dart]).is_err());
        let ok = OccludedLight::new(&light(), &[square(0.0, 1.0, 0.0, 1.0, 2.0)]).unwrap();
        assert!(ok.visible_form_factor(P, DVec3::ZERO).is_err());
    }
}
