//! Quadrature points over a receiving element, so that a form factor can be
//! the element's mean rather than its centre's value.
//!
//! Constant elements stand for their mean radiosity. Collocating the form
//! factor at the centre misses that mean by about h^2/24 times the Laplacian of
//! the radiosity, an error spread over every lit region whatever the mesh
//! criterion does; a two-point Gauss rule per direction (three points on a
//! triangle) reduces it to fourth order where the radiosity is smooth.

use glam::DVec3;
use smallvec::SmallVec;

/// Points with weights summing to 1.
pub(crate) type Samples = SmallVec<[(DVec3, f64); 4]>;

/// Gauss points over the convex quad or triangle `polygon`, each moved by
/// `lift` (off the surface, as the hemi-cube's eye is). Quads use 2 x 2 Gauss
/// points of the bilinear map weighted by its Jacobian; triangles the
/// three-point rule of degree two.
#[must_use]
pub(crate) fn element_samples(polygon: &[DVec3], lift: DVec3) -> Samples {
    let mut out = Samples::new();
    match polygon.len() {
        4 => {
            let g = 0.5 / 3f64.sqrt();
            let [a, b, c, d] = [polygon[0], polygon[1], polygon[2], polygon[3]];
            let mut total = 0.0;
            for s in [0.5 - g, 0.5 + g] {
                for t in [0.5 - g, 0.5 + g] {
                    let point = a.lerp(b, s).lerp(d.lerp(c, s), t);
                    let ds = (b - a).lerp(c - d, t);
                    let dt = (d - a).lerp(c - b, s);
                    let jacobian = ds.cross(dt).length();
                    total += jacobian;
                    out.push((point + lift, jacobian));
                }
            }
            if total > 0.0 {
                for p in &mut out {
                    p.1 /= total;
                }
            } else {
                for p in &mut out {
                    p.1 = 0.25;
                }
            }
        }
        3 => {
            let [a, b, c] = [polygon[0], polygon[1], polygon[2]];
            for (u, v, w) in [(4.0, 1.0, 1.0), (1.0, 4.0, 1.0), (1.0, 1.0, 4.0)] {
                out.push(((a * u + b * v + c * w) / 6.0 + lift, 1.0 / 3.0));
            }
        }
        _ => {
            let centre = polygon.iter().copied().sum::<DVec3>() / polygon.len().max(1) as f64;
            out.push((centre + lift, 1.0));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Integrates f over the polygon with the samples.
    fn integrate(polygon: &[DVec3], f: impl Fn(DVec3) -> f64) -> f64 {
        element_samples(polygon, DVec3::ZERO)
            .iter()
            .map(|(p, w)| w * f(*p))
            .sum()
    }

    #[test]
    fn quad_rule_integrates_cubics_exactly() {
        // Mean of x^3 + x y^2 over [0,2] x [0,1]: 2 + 1 * 1/3.
        let q = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let mean = integrate(&q, |p| p.x.powi(3) + p.x * p.y * p.y);
        assert!((mean - (2.0 + 1.0 / 3.0)).abs() < 1e-12, "{mean}");
    }

    #[test]
    fn triangle_rule_integrates_quadratics_exactly() {
        // Mean of x^2 over the triangle (0,0), (1,0), (0,1): 1/6.
        let t = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let mean = integrate(&t, |p| p.x * p.x);
        assert!((mean - 1.0 / 6.0).abs() < 1e-12, "{mean}");
    }
}
