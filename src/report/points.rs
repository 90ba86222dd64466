//! Sample points on a penumbra scene's floor, independent of any mesh.

use crate::scenes::penumbra::PenumbraSpec;
use glam::DVec3;

/// The plastic number, the real root of `x^3 = x + 1`. Its inverse powers give
/// the two-dimensional golden-ratio ("R2") sequence, which covers the square
/// evenly for every prefix and has no rational steps, so its points never line
/// up with the dyadic lattice the mesh is cut on.
const PLASTIC: f64 = 1.324_717_957_244_746;

/// `count` points spread evenly over the floor quad of `spec`: the R2
/// low-discrepancy sequence mapped bilinearly onto the quad. The same count
/// gives the same points; a longer list starts with the shorter one.
#[must_use]
pub fn floor_points(spec: &PenumbraSpec, count: usize) -> Vec<DVec3> {
    let (a1, a2) = (1.0 / PLASTIC, 1.0 / (PLASTIC * PLASTIC));
    let f = &spec.floor;
    (1..=count)
        .map(|n| {
            let s = (0.5 + a1 * n as f64).fract();
            let t = (0.5 + a2 * n as f64).fract();
            f[0].lerp(f[1], s).lerp(f[3].lerp(f[2], s), t)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::penumbra::penumbra_parallel;

    #[test]
    fn points_lie_on_the_floor_and_fill_every_quarter_evenly() {
        let spec = penumbra_parallel();
        let points = floor_points(&spec, 400);
        let mut quarters = [0usize; 4];
        for p in &points {
            assert!(p.y == 0.0 && p.x.abs() <= 2.0 && p.z.abs() <= 2.0, "{p}");
            quarters[usize::from(p.x > 0.0) + 2 * usize::from(p.z > 0.0)] += 1;
        }
        for q in quarters {
            assert!((90..=110).contains(&q), "{quarters:?}");
        }
        assert_eq!(floor_points(&spec, 10)[..], points[..10]);
    }
}
