//! Decoded texture images: the texels a [`super::Texture`] samples.

use crate::math::Rgb;

/// An image decoded to linear RGB: texels are converted from sRGB (as glTF
/// stores colour textures), alpha is dropped. Row-major, top row first, as the
/// image file stores it (glTF texture coordinate (0, 0) is the top left).
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// `width * height` linear RGB texels.
    pub texels: Vec<[f32; 3]>,
}

impl LinearImage {
    /// The texel at column `x`, row `y` (both in range).
    #[must_use]
    pub fn texel(&self, x: u32, y: u32) -> [f32; 3] {
        self.texels[y as usize * self.width as usize + x as usize]
    }

    /// The unweighted mean of every texel, summed in double precision.
    #[must_use]
    pub fn mean(&self) -> Rgb {
        let mut sum = [0.0f64; 3];
        for t in &self.texels {
            for (total, c) in sum.iter_mut().zip(t) {
                *total += f64::from(*c);
            }
        }
        Rgb(sum) / self.texels.len().max(1) as f64
    }
}
