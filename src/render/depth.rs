//! The depth buffer returned next to a rendered image.

/// Reciprocal view-space depth per pixel (`1 / z`, with `z` the distance along
/// the viewing direction): larger is nearer, zero means no surface.
///
/// With supersampling each pixel holds the *farthest* of its samples, so that a
/// line lying on a visible surface is never hidden by it; lines behind an
/// occluder are hidden except within a pixel of its silhouette.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthBuffer {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `1 / z` per pixel, row by row from the top.
    pub inverse_depth: Vec<f64>,
}

impl DepthBuffer {
    /// `1 / z` at pixel `(x, y)`, or `None` outside the buffer.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Option<f64> {
        if x < self.width && y < self.height {
            self.inverse_depth
                .get(y as usize * self.width as usize + x as usize)
                .copied()
        } else {
            None
        }
    }
}
