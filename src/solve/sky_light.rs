//! The sky's direct light on an element: the closed-form irradiance of the
//! whole sky, times the share of it the element sees past the scene.
//!
//! The share is found by rays: [`SKY_RAYS`] directions stratified over the
//! element's hemisphere with the cosine's density (so each carries an equal
//! part of an even sky's irradiance), spread over the element's quadrature
//! points, each weighed by the sky's radiance there. The share is the
//! weighted rays that leave the scene over all the weighted rays: a ratio,
//! so an element that nothing hides gets the closed form exactly (a lone
//! floor under a uniform sky receives `pi L`), one shut in gets none, and
//! only partial views (a window, a courtyard) carry sampling error. The
//! pattern is the same for every element of a surface, turned by an angle
//! of the surface's own: neighbours err alike, so the error does not show
//! as noise between them, nor mislead refinement into splitting it.

use crate::formfactor::{Occluders, Samples, Sources};
use crate::math::Rgb;
use crate::scene::Sky;
use glam::DVec3;

/// Directions per element: a 16 x 16 stratification of the hemisphere.
pub(crate) const SKY_RAYS: usize = 256;

/// Strata along each side of the unit square the directions come from.
const SIDE: usize = 16;

/// The sky's irradiance on an element of surface `surface` facing `normal`,
/// sampled at `samples` (its quadrature points, lifted off the surface, and
/// their weights); and the rays cast. `far` takes a ray from anywhere in the
/// scene out of it.
pub(crate) fn sky_irradiance(
    sky: &Sky,
    sources: &Sources,
    occluders: &Occluders,
    far: f64,
    surface: u32,
    normal: DVec3,
    samples: &Samples,
) -> (Rgb, u64) {
    let whole = sky.unobstructed_irradiance(normal);
    if whole == Rgb::ZERO || samples.is_empty() {
        return (Rgb::ZERO, 0);
    }
    let (t, b) = turned_frame(normal, surface);
    let skip = [surface, surface];
    let (mut seen, mut total, mut rays) = (0.0, 0.0, 0u64);
    for i in 0..SKY_RAYS {
        let (x, y) = concentric_disk((i % SIDE) as f64, (i / SIDE) as f64);
        let w = (t * x + b * y + normal * (1.0 - x * x - y * y).max(0.0).sqrt()).normalize();
        let (point, weight) = samples[i % samples.len()];
        let s = sky.relative_radiance(w) * weight;
        if s <= 0.0 {
            continue;
        }
        total += s;
        rays += 1;
        if occluders.clear(sources, point, point + w * far, skip) {
            seen += s;
        }
    }
    if total <= 0.0 {
        return (Rgb::ZERO, rays);
    }
    (whole * (seen / total), rays)
}

/// A tangent frame about `normal`, turned by an angle that depends on
/// `surface` alone.
fn turned_frame(normal: DVec3, surface: u32) -> (DVec3, DVec3) {
    let t0 = normal.any_orthonormal_vector();
    let b0 = normal.cross(t0);
    // A fixed odd multiplier spreads consecutive surfaces over the circle.
    let turn = (u64::from(surface).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) as f64
        * (1.0 / (1u64 << 53) as f64)
        * std::f64::consts::TAU;
    let (s, c) = turn.sin_cos();
    let t = t0 * c + b0 * s;
    (t, normal.cross(t))
}

/// The centre of stratum `(i, j)` of the unit square mapped to the unit disk
/// by Shirley and Chiu's concentric map (equal areas to equal areas); lifted
/// to the hemisphere, equal areas of the disk are equal cosine-weighted solid
/// angles.
fn concentric_disk(i: f64, j: f64) -> (f64, f64) {
    let u = 2.0 * (i + 0.5) / SIDE as f64 - 1.0;
    let v = 2.0 * (j + 0.5) / SIDE as f64 - 1.0;
    let quarter = std::f64::consts::FRAC_PI_4;
    let (r, phi) = if u.abs() > v.abs() {
        (u, quarter * (v / u))
    } else {
        (v, 2.0 * quarter - quarter * (u / v))
    };
    (r * phi.cos(), r * phi.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_directions_carry_equal_shares_of_an_even_sky() {
        // Lifted to the hemisphere, the strata's directions have the cosine's
        // density: their mean cosine is 2/3, as E[cos] under cos/pi. Stratum
        // centres lean about 1% towards the normal (the ratio the sky's
        // share is taken as cancels that to first order).
        let mean: f64 = (0..SKY_RAYS)
            .map(|i| {
                let (x, y) = concentric_disk((i % SIDE) as f64, (i / SIDE) as f64);
                (1.0 - x * x - y * y).max(0.0).sqrt()
            })
            .sum::<f64>()
            / SKY_RAYS as f64;
        assert!((mean - 2.0 / 3.0).abs() < 1.5e-2, "mean cosine {mean}");
    }
}
