//! A linear high-dynamic-range RGB image.

use crate::math::Rgb;

/// A linear RGB image in double precision, row-major with the top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, row by row from the top.
    pub pixels: Vec<Rgb>,
}

impl HdrImage {
    /// A black image.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        HdrImage {
            width,
            height,
            pixels: vec![Rgb::ZERO; width as usize * height as usize],
        }
    }

    /// The index of pixel `(x, y)` in [`HdrImage::pixels`], if it is inside.
    #[must_use]
    pub fn index(&self, x: u32, y: u32) -> Option<usize> {
        (x < self.width && y < self.height).then(|| y as usize * self.width as usize + x as usize)
    }

    /// Pixel `(x, y)`.
    ///
    /// # Panics
    /// If `(x, y)` is outside the image (like slice indexing).
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        let i = self.index(x, y).expect("pixel outside the image");
        self.pixels[i]
    }

    /// Sets pixel `(x, y)`.
    ///
    /// # Panics
    /// If `(x, y)` is outside the image (like slice indexing).
    pub fn set(&mut self, x: u32, y: u32, value: Rgb) {
        let i = self.index(x, y).expect("pixel outside the image");
        self.pixels[i] = value;
    }

    /// The mean pixel value (black for an empty image). Summed in pixel order,
    /// so the result does not depend on the thread count.
    #[must_use]
    pub fn mean(&self) -> Rgb {
        if self.pixels.is_empty() {
            return Rgb::ZERO;
        }
        let mut sum = Rgb::ZERO;
        for p in &self.pixels {
            sum += *p;
        }
        sum / self.pixels.len() as f64
    }

    /// True when the pixel buffer holds exactly `width * height` pixels.
    #[must_use]
    pub(crate) fn is_consistent(&self) -> bool {
        self.pixels.len() == self.width as usize * self.height as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_get_and_mean() {
        let mut img = HdrImage::new(2, 3);
        img.set(1, 2, Rgb::new(6.0, 0.0, 12.0));
        assert_eq!(img.get(1, 2), Rgb::new(6.0, 0.0, 12.0));
        assert_eq!(img.pixels[5], Rgb::new(6.0, 0.0, 12.0));
        assert_eq!(img.mean(), Rgb::new(1.0, 0.0, 2.0));
        assert_eq!(img.index(2, 0), None);
        assert_eq!(img.index(0, 3), None);
    }
}
