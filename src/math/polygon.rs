//! Planar polygon helpers in double precision: area, normal, centroid, convexity,
//! and clipping against a half-space (used for near planes and receiver horizons).

use glam::DVec3;
use smallvec::SmallVec;

/// The Newell normal of a polygon: its direction is the polygon's front (vertices
/// counter-clockwise seen from the front), its length twice the area. Robust for
/// slightly non-planar input.
#[must_use]
pub(crate) fn newell_normal(v: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for i in 0..v.len() {
        let a = v[i];
        let b = v[(i + 1) % v.len()];
        n += a.cross(b);
    }
    n
}

/// The area of a planar polygon.
#[must_use]
pub fn polygon_area(v: &[DVec3]) -> f64 {
    0.5 * newell_normal(v).length()
}

/// The area centroid of a planar polygon (fan decomposition from the first vertex).
#[must_use]
pub fn polygon_centroid(v: &[DVec3]) -> DVec3 {
    let n = newell_normal(v);
    let mut acc = DVec3::ZERO;
    let mut total = 0.0;
    for i in 1..v.len().saturating_sub(1) {
        let a = (v[i] - v[0]).cross(v[i + 1] - v[0]).dot(n);
        acc += (v[0] + v[i] + v[i + 1]) * (a / 3.0);
        total += a;
    }
    if total.abs() > 0.0 {
        acc / total
    } else {
        v.iter().copied().sum::<DVec3>() / v.len().max(1) as f64
    }
}

/// The largest distance of a vertex from the best plane through the polygon,
/// relative to the polygon's diameter. Zero for an exactly planar polygon.
#[must_use]
pub(crate) fn planarity_error(v: &[DVec3]) -> f64 {
    let n = newell_normal(v).normalize_or_zero();
    let c = v.iter().copied().sum::<DVec3>() / v.len() as f64;
    let mut diam: f64 = 0.0;
    let mut dev: f64 = 0.0;
    for (i, p) in v.iter().enumerate() {
        dev = dev.max((*p - c).dot(n).abs());
        for q in &v[i + 1..] {
            diam = diam.max((*p - *q).length());
        }
    }
    if diam > 0.0 {
        dev / diam
    } else {
        0.0
    }
}

/// True when the polygon is strictly convex with respect to `normal` (every turn
/// goes the same way and no edge is degenerate).
#[must_use]
pub(crate) fn is_convex(v: &[DVec3], normal: DVec3) -> bool {
    let m = v.len();
    if m < 3 {
        return false;
    }
    let scale = v
        .iter()
        .map(|p| (*p - v[0]).length_squared())
        .fold(0.0, f64::max);
    for i in 0..m {
        let a = v[i];
        let b = v[(i + 1) % m];
        let c = v[(i + 2) % m];
        let turn = (b - a).cross(c - b).dot(normal);
        if turn <= 1e-12 * scale {
            return false;
        }
    }
    true
}

/// Clips a convex or concave polygon to the half-space `n . (x - p) >= 0`
/// (Sutherland-Hodgman against one plane). Returns the kept part, which may be
/// empty.
#[must_use]
pub(crate) fn clip_to_halfspace(v: &[DVec3], p: DVec3, n: DVec3) -> SmallVec<[DVec3; 8]> {
    let mut out = SmallVec::new();
    let m = v.len();
    for i in 0..m {
        let a = v[i];
        let b = v[(i + 1) % m];
        let da = n.dot(a - p);
        let db = n.dot(b - p);
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            let t = da / (da - db);
            out.push(a + (b - a) * t);
        }
    }
    out
}

/// [`clip_to_halfspace`] in place. A polygon wholly inside the half-space is
/// left as it is and one wholly outside is emptied, with nothing copied: in
/// shaft clipping most clips are one or the other. The result is the copying
/// form's, bit for bit.
pub(crate) fn clip_in_place(v: &mut SmallVec<[DVec3; 8]>, p: DVec3, n: DVec3) {
    let (mut inside, mut outside) = (false, false);
    for x in v.iter() {
        if n.dot(*x - p) >= 0.0 {
            inside = true;
        } else {
            outside = true;
        }
    }
    if !outside {
        return;
    }
    if !inside {
        v.clear();
        return;
    }
    *v = clip_to_halfspace(v, p, n);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<DVec3> {
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ]
    }

    #[test]
    fn clipping_in_place_gives_the_copying_result() {
        let s: SmallVec<[DVec3; 8]> = SmallVec::from_vec(square());
        for (p, n) in [
            (DVec3::new(1.0, 0.0, 0.0), DVec3::X),
            (DVec3::new(1.0, 0.0, 0.0), DVec3::NEG_X),
            (DVec3::new(-1.0, 0.0, 0.0), DVec3::X),
            (DVec3::new(3.0, 0.0, 0.0), DVec3::X),
            (
                DVec3::new(0.5, 0.5, 0.0),
                DVec3::new(1.0, 1.0, 0.0).normalize(),
            ),
            (DVec3::new(2.0, 0.0, 0.0), DVec3::X),
        ] {
            let mut v = s.clone();
            clip_in_place(&mut v, p, n);
            assert_eq!(
                v.as_slice(),
                clip_to_halfspace(&s, p, n).as_slice(),
                "{p} {n}"
            );
        }
    }

    #[test]
    fn area_normal_centroid_of_a_rectangle() {
        let s = square();
        assert!((polygon_area(&s) - 2.0).abs() < 1e-15);
        assert!((newell_normal(&s).normalize() - DVec3::Z).length() < 1e-15);
        assert!((polygon_centroid(&s) - DVec3::new(1.0, 0.5, 0.0)).length() < 1e-15);
        assert!(is_convex(&s, DVec3::Z));
        assert!(!is_convex(&s, -DVec3::Z));
        assert_eq!(planarity_error(&s), 0.0);
    }

    #[test]
    fn clipping_halves_the_rectangle() {
        let c = clip_to_halfspace(&square(), DVec3::new(1.0, 0.0, 0.0), DVec3::X);
        assert!((polygon_area(&c) - 1.0).abs() < 1e-15);
        let none = clip_to_halfspace(&square(), DVec3::new(3.0, 0.0, 0.0), DVec3::X);
        assert!(none.is_empty());
    }
}
