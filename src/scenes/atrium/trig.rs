//! Sine and cosine from additions, multiplications and one rounding only, so
//! that the atrium's vertices are the same bits on every platform: the
//! standard library's `sin` and `cos` call the platform's maths library,
//! whose last bit differs between systems.

/// pi / 2 split in two: the high part has 33 significant bits, so `k * HI` is
/// exact for the small multiples `k` used here (Cody and Waite's reduction).
const FRAC_PI_2_HI: f64 = 1.570_796_326_734_125_6;
/// pi / 2 minus [`FRAC_PI_2_HI`].
const FRAC_PI_2_LO: f64 = 6.077_100_506_506_192e-11;

/// `(sin x, cos x)` to within a few units in the last place for |x| below
/// about 1e6 (angles here stay below 100 radians).
pub(super) fn sin_cos(x: f64) -> (f64, f64) {
    let k = (x / std::f64::consts::FRAC_PI_2).round();
    let r = (x - k * FRAC_PI_2_HI) - k * FRAC_PI_2_LO;
    let (s, c) = (sin_reduced(r), cos_reduced(r));
    // k mod 4 picks the quadrant; k is a small whole number, so the cast is exact.
    match (k as i64).rem_euclid(4) {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// Taylor series of sin on |r| <= pi/4, through r^19 (the next term is below
/// 2e-22).
fn sin_reduced(r: f64) -> f64 {
    let r2 = r * r;
    let mut sum = 0.0;
    // Odd factorials 19!, 17!, ..., 3!: the series' denominators, from the top.
    for n in (1..=9).rev() {
        let k = f64::from(2 * n);
        sum = r2 * (1.0 / (k * (k + 1.0)) - sum / (k * (k + 1.0)));
    }
    r * (1.0 - sum)
}

/// Taylor series of cos on |r| <= pi/4, through r^18.
fn cos_reduced(r: f64) -> f64 {
    let r2 = r * r;
    let mut sum = 0.0;
    for n in (1..=9).rev() {
        let k = f64::from(2 * n);
        sum = r2 * (1.0 / ((k - 1.0) * k) - sum / ((k - 1.0) * k));
    }
    1.0 - sum
}

/// The points of a unit circle at angles `2 pi k / n`, k = 0..n, as
/// `(cos, sin)`; the last repeats the first exactly, so that rings close.
pub(super) fn unit_circle(n: usize) -> Vec<(f64, f64)> {
    let mut points: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let (s, c) = sin_cos(std::f64::consts::TAU * k as f64 / n as f64);
            (c, s)
        })
        .collect();
    points.push(points[0]);
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_standard_library_to_a_few_ulps() {
        for i in -2000..=2000 {
            let x = f64::from(i) * 0.0137;
            let (s, c) = sin_cos(x);
            assert!((s - x.sin()).abs() <= 4e-16, "sin {x}: {s} vs {}", x.sin());
            assert!((c - x.cos()).abs() <= 4e-16, "cos {x}: {c} vs {}", x.cos());
        }
    }

    #[test]
    fn quarter_turns_are_exact_enough_and_circles_close() {
        let (s, c) = sin_cos(std::f64::consts::FRAC_PI_2);
        assert_eq!(s, 1.0);
        assert!(c.abs() < 1e-16);
        let circle = unit_circle(12);
        assert_eq!(circle.len(), 13);
        assert_eq!(circle[0], circle[12]);
        assert_eq!(circle[0], (1.0, 0.0));
        for (c, s) in circle {
            assert!((c * c + s * s - 1.0).abs() < 1e-15);
        }
    }
}
