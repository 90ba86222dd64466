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
    /// Most texels kept from the images of one file, all images together
    /// (each image counts once, however many materials use it). An image that
    /// would exceed what is left is reduced to fit (a KTX2 image to a smaller
    /// mip level, any other by averaging blocks of texels), with a warning
    /// naming it; one more than 16 times this limit is not decoded at all
    /// (its textures are ignored with a warning naming the image).
    /// [`ImportLimits::for_memory`] derives it from a memory budget.
    pub max_texture_pixels: u64,
}

/// The share of the memory budget that decoded textures may take: one part
/// in this many.
const TEXTURE_SHARE: u64 = 16;

/// Bytes a decoded texel takes (linear RGB, `f32`) plus one of alpha.
const TEXEL_BYTES: u64 = 13;

impl ImportLimits {
    /// The default limits, with the texels kept from a file's images bounded
    /// by a sixteenth of `max_memory` bytes (the memory budget of the whole
    /// run, [`Settings::max_memory`](crate::Settings::max_memory)): at 13
    /// bytes a decoded texel, 41 megapixels for 8 GiB.
    #[must_use]
    pub fn for_memory(max_memory: u64) -> Self {
        ImportLimits {
            max_texture_pixels: (max_memory / TEXTURE_SHARE / TEXEL_BYTES).max(1),
            ..ImportLimits::default()
        }
    }
}

impl Default for ImportLimits {
    /// Generous limits for radiosity scenes, whose cost grows with the square of
    /// the patch count: 2 million triangles, nesting 256 deep, 1 GiB per file,
    /// textures as [`ImportLimits::for_memory`] allows for the library's
    /// default memory budget
    /// ([`DEFAULT_MAX_MEMORY`](crate::pipeline::DEFAULT_MAX_MEMORY)).
    fn default() -> Self {
        ImportLimits {
            max_triangles: 2_000_000,
            max_node_depth: 256,
            max_file_bytes: 1 << 30,
            max_texture_pixels: crate::pipeline::DEFAULT_MAX_MEMORY / TEXTURE_SHARE / TEXEL_BYTES,
        }
    }
}
