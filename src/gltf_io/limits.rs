//! Limits that keep a hostile or absurd file from exhausting memory or time.

/// Bounds checked by [`load_scene`](super::load_scene) before it allocates or
/// recurses. Every count a file claims is compared with these first, so a small
/// file cannot make the importer reserve gigabytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImportLimits {
    /// Most triangles read from the file (counted before merging and before
    /// degenerate triangles are dropped). Exceeding it is an
    /// [`Error::Limit`](crate::Error::Limit).
    pub max_triangles: usize,
    /// Deepest node nesting followed from a scene root.
    pub max_node_depth: usize,
    /// Largest size in bytes of any one file or buffer read (the scene file,
    /// an external buffer, a decoded data URI, an image).
    pub max_file_bytes: u64,
    /// Most pixels decoded from the images of one file, all images together
    /// (each image counts once, however many materials use it). An image that
    /// would exceed it is not decoded: its textures are ignored with a warning
    /// naming the image.
    pub max_texture_pixels: u64,
}

impl Default for ImportLimits {
    /// Generous limits for radiosity scenes, whose cost grows with the square of
    /// the patch count: 2 million triangles, nesting 256 deep, 1 GiB per file,
    /// 16 megapixels of textures per file.
    fn default() -> Self {
        ImportLimits {
            max_triangles: 2_000_000,
            max_node_depth: 256,
            max_file_bytes: 1 << 30,
            max_texture_pixels: 1 << 24,
        }
    }
}
