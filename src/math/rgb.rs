//! Linear RGB triples used for reflectance, emission and radiosity.

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, MulAssign, Sub};

/// A linear RGB triple in double precision. Radiosity is solved per band, so this
/// is the unit of every per-band quantity (reflectance, exitance, radiosity).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Rgb(pub [f64; 3]);

impl Rgb {
    /// Black.
    pub const ZERO: Rgb = Rgb([0.0; 3]);
    /// One in every band.
    pub const ONE: Rgb = Rgb([1.0; 3]);

    /// A triple from its three bands.
    #[must_use]
    pub const fn new(r: f64, g: f64, b: f64) -> Self {
        Rgb([r, g, b])
    }

    /// The same value in every band.
    #[must_use]
    pub const fn splat(v: f64) -> Self {
        Rgb([v, v, v])
    }

    /// The largest band.
    #[must_use]
    pub fn max_band(self) -> f64 {
        self.0[0].max(self.0[1]).max(self.0[2])
    }

    /// The smallest band.
    #[must_use]
    pub fn min_band(self) -> f64 {
        self.0[0].min(self.0[1]).min(self.0[2])
    }

    /// The mean of the three bands.
    #[must_use]
    pub fn mean(self) -> f64 {
        (self.0[0] + self.0[1] + self.0[2]) / 3.0
    }

    /// Rec. 709 luminance of a linear triple.
    #[must_use]
    pub fn luminance(self) -> f64 {
        0.2126 * self.0[0] + 0.7152 * self.0[1] + 0.0722 * self.0[2]
    }

    /// True when every band is finite.
    #[must_use]
    pub fn is_finite(self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }

    /// True when all three bands are equal (a grey value).
    #[must_use]
    pub(crate) fn is_grey(self) -> bool {
        self.0[0] == self.0[1] && self.0[1] == self.0[2]
    }

    /// Band-wise maximum.
    #[must_use]
    pub fn max(self, o: Rgb) -> Rgb {
        Rgb([
            self.0[0].max(o.0[0]),
            self.0[1].max(o.0[1]),
            self.0[2].max(o.0[2]),
        ])
    }

    /// Band-wise absolute value.
    #[must_use]
    pub fn abs(self) -> Rgb {
        Rgb([self.0[0].abs(), self.0[1].abs(), self.0[2].abs()])
    }

    /// The triple in single precision, for image buffers.
    #[must_use]
    pub fn to_f32(self) -> [f32; 3] {
        [self.0[0] as f32, self.0[1] as f32, self.0[2] as f32]
    }
}

impl Add for Rgb {
    type Output = Rgb;
    fn add(self, o: Rgb) -> Rgb {
        Rgb([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}

impl AddAssign for Rgb {
    fn add_assign(&mut self, o: Rgb) {
        for k in 0..3 {
            self.0[k] += o.0[k];
        }
    }
}

impl Sub for Rgb {
    type Output = Rgb;
    fn sub(self, o: Rgb) -> Rgb {
        Rgb([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }
}

impl Mul<f64> for Rgb {
    type Output = Rgb;
    fn mul(self, s: f64) -> Rgb {
        Rgb([self.0[0] * s, self.0[1] * s, self.0[2] * s])
    }
}

impl MulAssign<f64> for Rgb {
    fn mul_assign(&mut self, s: f64) {
        for k in 0..3 {
            self.0[k] *= s;
        }
    }
}

impl Mul<Rgb> for Rgb {
    type Output = Rgb;
    fn mul(self, o: Rgb) -> Rgb {
        Rgb([self.0[0] * o.0[0], self.0[1] * o.0[1], self.0[2] * o.0[2]])
    }
}

impl Div<f64> for Rgb {
    type Output = Rgb;
    fn div(self, s: f64) -> Rgb {
        Rgb([self.0[0] / s, self.0[1] / s, self.0[2] / s])
    }
}

impl Index<usize> for Rgb {
    type Output = f64;
    fn index(&self, k: usize) -> &f64 {
        &self.0[k]
    }
}

impl IndexMut<usize> for Rgb {
    fn index_mut(&mut self, k: usize) -> &mut f64 {
        &mut self.0[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic_is_per_band() {
        let a = Rgb::new(1.0, 2.0, 3.0);
        let b = Rgb::new(0.5, 0.25, 2.0);
        assert_eq!((a * b).0, [0.5, 0.5, 6.0]);
        assert_eq!((a + b).0, [1.5, 2.25, 5.0]);
        assert_eq!(a.max_band(), 3.0);
        assert!(Rgb::splat(0.3).is_grey());
        assert!(!a.is_grey());
    }
}
