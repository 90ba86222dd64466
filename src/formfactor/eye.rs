//! Where a receiver's hemi-cube sits: just off its surface.

use glam::DVec3;

/// The eye is lifted off the surface by this fraction of the square root of
/// the receiver's area: far enough that the surface's own plane and its
/// neighbours in it are behind the eye, close enough to change no form
/// factor, and relative to the receiver's size so that results do not
/// depend on the scene's scale.
pub(super) const EYE_LIFT: f64 = 1e-6;

/// The offset from a receiver's surface to its eye, for a receiver of `area`
/// on a surface with unit `normal`.
#[inline]
#[must_use]
pub(crate) fn eye_lift(normal: DVec3, area: f64) -> DVec3 {
    normal * (EYE_LIFT * area.sqrt())
}

/// The eye of a receiver of `area` whose centroid is `centroid`, on a
/// surface with unit `normal`.
#[inline]
#[must_use]
pub(crate) fn receiving_point(centroid: DVec3, normal: DVec3, area: f64) -> DVec3 {
    centroid + eye_lift(normal, area)
}
