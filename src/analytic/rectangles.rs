//! Closed-form form factors between rectangles (Howell's catalogue, C-11 and
//! C-14) and from a point to a parallel rectangle opposite one of its corners.

use super::positive_length;
use crate::error::Result;
use std::f64::consts::PI;

/// Form factor between two identical, coaxial, parallel rectangles `a x b`
/// facing each other at separation `c` (Howell C-11). Symmetric, so it is the
/// form factor either way.
///
/// With `X = a/c`, `Y = b/c`:
/// `F = 2/(pi X Y) [ 1/2 ln((1+X^2)(1+Y^2)/(1+X^2+Y^2)) + X sqrt(1+Y^2) atan(X/sqrt(1+Y^2))
///  + Y sqrt(1+X^2) atan(Y/sqrt(1+X^2)) - X atan X - Y atan Y ]`.
///
/// Fails unless every length is finite and positive.
pub fn parallel_rectangles(a: f64, b: f64, c: f64) -> Result<f64> {
    let x = positive_length("rectangle side a", a)? / positive_length("separation c", c)?;
    let y = positive_length("rectangle side b", b)? / c;
    Ok(parallel_ratios(x, y))
}

/// Howell C-11 in the side-to-separation ratios `X`, `Y` (both positive).
pub(crate) fn parallel_ratios(x: f64, y: f64) -> f64 {
    let x1 = 1.0 + x * x;
    let y1 = 1.0 + y * y;
    let sx1 = x1.sqrt();
    let sy1 = y1.sqrt();
    let bracket = 0.5 * (x1 * y1 / (x1 + y1 - 1.0)).ln()
        + x * sy1 * (x / sy1).atan()
        + y * sx1 * (y / sx1).atan()
        - x * x.atan()
        - y * y.atan();
    2.0 / (PI * x * y) * bracket
}

/// Form factor from rectangle 1 (`w x l`) to rectangle 2 (`h x l`) when they
/// share an edge of length `l` at a right angle (Howell C-14).
///
/// With `W = w/l`, `H = h/l`:
/// `F12 = 1/(pi W) [ W atan(1/W) + H atan(1/H) - sqrt(H^2+W^2) atan(1/sqrt(H^2+W^2))
///  + 1/4 ln( (1+W^2)(1+H^2)/(1+W^2+H^2)
///  * (W^2(1+W^2+H^2)/((1+W^2)(W^2+H^2)))^(W^2)
///  * (H^2(1+W^2+H^2)/((1+H^2)(W^2+H^2)))^(H^2) ) ]`.
///
/// Reciprocity holds: `w F(w, h, l) = h F(h, w, l)`. Fails unless every length
/// is finite and positive.
pub fn perpendicular_rectangles(w: f64, h: f64, l: f64) -> Result<f64> {
    let l = positive_length("shared edge l", l)?;
    let ww = positive_length("rectangle 1 width w", w)? / l;
    let hh = positive_length("rectangle 2 height h", h)? / l;
    Ok(perpendicular_ratios(ww, hh))
}

/// Howell C-14 in the ratios `W = w/l`, `H = h/l` (both positive).
pub(crate) fn perpendicular_ratios(ww: f64, hh: f64) -> f64 {
    let w2 = ww * ww;
    let h2 = hh * hh;
    let s2 = w2 + h2;
    let s = s2.sqrt();
    let arctans = ww * (1.0 / ww).atan() + hh * (1.0 / hh).atan() - s * (1.0 / s).atan();
    // The logarithm of the product is taken as a sum of logarithms: the powers
    // W^2 and H^2 would overflow for long thin rectangles.
    let log_term = ((1.0 + w2) * (1.0 + h2) / (1.0 + s2)).ln()
        + w2 * (w2 * (1.0 + s2) / ((1.0 + w2) * s2)).ln()
        + h2 * (h2 * (1.0 + s2) / ((1.0 + h2) * s2)).ln();
    (arctans + 0.25 * log_term) / (PI * ww)
}

/// Form factor from a differential area to a parallel rectangle `a x b` at
/// distance `c`, the area's normal pointing at one corner of the rectangle
/// (the foot of the normal is that corner).
///
/// With `X = a/c`, `Y = b/c`:
/// `F = 1/(2 pi) [ X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2)) ]`.
///
/// Sum four of these for a point whose foot lies inside a rectangle. Fails
/// unless every length is finite and positive.
pub fn point_to_rectangle_corner(a: f64, b: f64, c: f64) -> Result<f64> {
    let x = positive_length("rectangle side a", a)? / positive_length("distance c", c)?;
    let y = positive_length("rectangle side b", b)? / c;
    let sx1 = (1.0 + x * x).sqrt();
    let sy1 = (1.0 + y * y).sqrt();
    Ok((x / sx1 * (y / sx1).atan() + y / sy1 * (x / sy1).atan()) / (2.0 * PI))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_cube_rows_sum_to_one() {
        // Opposite face plus four adjacent faces close the cube exactly.
        let sum = parallel_rectangles(1.0, 1.0, 1.0).unwrap()
            + 4.0 * perpendicular_rectangles(1.0, 1.0, 1.0).unwrap();
        assert!((sum - 1.0).abs() < 1e-14, "row sum {sum}");
    }

    #[test]
    fn bad_lengths_are_refused() {
        assert!(parallel_rectangles(0.0, 1.0, 1.0).is_err());
        assert!(perpendicular_rectangles(1.0, f64::NAN, 1.0).is_err());
        assert!(point_to_rectangle_corner(1.0, 1.0, -2.0).is_err());
    }

    #[test]
    fn long_thin_rectangles_stay_finite() {
        // Without the sum of logarithms (W^2)^(W^2) overflows at W = 100.
        let f = perpendicular_rectangles(100.0, 1.0, 1.0).unwrap();
        assert!(f.is_finite() && f > 0.0 && f < 0.01, "{f}");
    }
}
