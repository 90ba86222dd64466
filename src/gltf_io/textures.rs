//! Decoding the images that textures show, once per image and file.
//!
//! [`Images`] is the cache: the first texture that asks for an image decodes it
//! into a [`LinearImage`] (linear RGB, `f32`), every later texture showing the
//! same image gets the same decoded pixels, and an image that could not be used
//! is not tried again. The pixels kept from one file are bounded by
//! [`ImportLimits::max_texture_pixels`] in total, not per image, so that a small
//! file cannot have one large image (or many) decoded over and over: an image
//! that would exceed what is left is reduced to fit (with a warning), not
//! dropped. PNG, JPEG, WebP (`EXT_texture_webp`) and KTX2 / Basis Universal
//! (`KHR_texture_basisu`, with the `ktx2` feature) images are decoded; a
//! texture whose image is in none of these is left out with a warning naming
//! it, and its material keeps its factor.

use super::accessors::view_bytes;
use super::container::read_limited;
use super::document::Document;
use super::image_decode::{decode, dimensions};
use super::limits::ImportLimits;
use super::uri::{resolve, Resolved};
use super::{describe, gltf_error};
use crate::error::{Error, GltfKind, GltfObject};
use crate::input::is_not_regular;
use crate::scene::LinearImage;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// Why a texture cannot be used.
#[derive(Debug)]
pub(super) enum Unusable {
    /// The texture is left out with a warning saying why (a broken, unknown or
    /// over-budget image): the material's factor alone is used.
    Ignored(String),
    /// The file is refused: the image names something that must never be read
    /// (a FIFO or device, which would block or never end).
    Refused(Error),
}

/// The outcome of decoding one image, kept so that it is never decoded twice.
#[derive(Clone, Debug)]
enum Outcome {
    Decoded(Arc<LinearImage>, Option<Arc<Alpha>>),
    Ignored(String),
}

/// The alpha channel of a decoded image, texel for texel with its
/// [`LinearImage`]: 0 (transparent) to 255 (opaque).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Alpha {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// Row-major, top row first.
    pub values: Vec<u8>,
}

/// How many times the pixels the file may keep an image may hold at full
/// size, to be decoded and reduced: bounds the decoder's memory.
const DECODE_HEADROOM: u64 = 16;

/// The images of one file, decoded on first use.
pub(super) struct Images<'a> {
    doc: &'a Document,
    buffers: &'a [Vec<u8>],
    /// The scene file, whose folder holds the image files.
    scene: &'a Path,
    limits: &'a ImportLimits,
    by_image: HashMap<usize, Outcome>,
    /// Images decoded (successfully or not) so far; images refused before
    /// decoding (unreadable, over the pixel budget) are not counted.
    pub decodes: usize,
    /// Pixels charged against the file's budget so far.
    pub pixels: u64,
    /// Warnings for images reduced to fit the budget, in decoding order.
    pub reduced: Vec<String>,
}

impl<'a> Images<'a> {
    /// An empty cache for the images of `doc`, read from the scene file
    /// `scene` (image files are relative to its folder).
    pub(super) fn new(
        doc: &'a Document,
        buffers: &'a [Vec<u8>],
        scene: &'a Path,
        limits: &'a ImportLimits,
    ) -> Self {
        Images {
            doc,
            buffers,
            scene,
            limits,
            by_image: HashMap::new(),
            decodes: 0,
            pixels: 0,
            reduced: Vec::new(),
        }
    }

    /// The decoded image that texture `index` shows.
    pub(super) fn for_texture(&mut self, index: usize) -> Result<Arc<LinearImage>, Unusable> {
        self.with_alpha(index).map(|(image, _)| image)
    }

    /// The decoded image that texture `index` shows, and its alpha channel
    /// when it has one.
    pub(super) fn with_alpha(
        &mut self,
        index: usize,
    ) -> Result<(Arc<LinearImage>, Option<Arc<Alpha>>), Unusable> {
        let image = self.source_of(index).map_err(Unusable::Ignored)?;
        let outcome = match self.by_image.get(&image) {
            Some(known) => known.clone(),
            None => {
                let fresh = match self.decode(image) {
                    Ok((decoded, alpha)) => {
                        Outcome::Decoded(Arc::new(decoded), alpha.map(Arc::new))
                    }
                    Err(Unusable::Ignored(why)) => Outcome::Ignored(why),
                    Err(refused) => return Err(refused),
                };
                self.by_image.insert(image, fresh.clone());
                fresh
            }
        };
        match outcome {
            Outcome::Decoded(decoded, alpha) => Ok((decoded, alpha)),
            Outcome::Ignored(why) => Err(Unusable::Ignored(why)),
        }
    }

    /// The image texture `index` shows: a KTX2 image of `KHR_texture_basisu`
    /// (when this build decodes KTX2), a WebP image of `EXT_texture_webp`,
    /// else the core `source` (a fallback PNG or JPEG, when the file has one).
    fn source_of(&self, index: usize) -> Result<usize, String> {
        let texture = self
            .doc
            .root
            .textures
            .get(index)
            .ok_or_else(|| format!("texture {index} does not exist"))?;
        let extension_source = |name: &str| {
            self.doc
                .raw
                .pointer(&format!("/textures/{index}/extensions/{name}/source"))
                .and_then(serde_json::Value::as_u64)
                .map(|s| s as usize)
        };
        let basisu = extension_source("KHR_texture_basisu");
        let preferred = [
            basisu.filter(|_| cfg!(feature = "ktx2")),
            extension_source("EXT_texture_webp"),
        ];
        if let Some(image) = preferred.into_iter().flatten().next() {
            return Ok(image);
        }
        let core = texture.source.value();
        if core != u32::MAX as usize {
            return Ok(core);
        }
        let what = describe("texture", index, texture.name.as_deref());
        Err(match basisu {
            Some(_) => format!(
                "{what}: its only image is KTX2 (KHR_texture_basisu), which this build \
                 cannot decode (the crate's `ktx2` feature is off)"
            ),
            None => format!("{what}: it names no image this importer can read"),
        })
    }

    /// Reads and decodes image `index`, charging its pixels to the budget; an
    /// image larger than what is left of the budget is reduced to fit, with
    /// a warning in [`Images::reduced`].
    fn decode(&mut self, index: usize) -> Result<(LinearImage, Option<Alpha>), Unusable> {
        let image = self
            .doc
            .root
            .images
            .get(index)
            .ok_or_else(|| Unusable::Ignored(format!("image {index} does not exist")))?;
        let what = describe("image", index, image.name.as_deref());
        let ignored = |why: String| Unusable::Ignored(format!("{what}: {why}"));
        let bytes: Vec<u8> = match (&image.buffer_view, &image.uri) {
            (Some(view), _) => view_bytes(self.doc, self.buffers, view.value())
                .map_err(ignored)?
                .0
                .to_vec(),
            (None, Some(uri)) => {
                let folder = self.scene.parent().unwrap_or(Path::new("."));
                match resolve(uri, folder, self.limits).map_err(ignored)? {
                    Resolved::Data(b) => b,
                    Resolved::File(f) => read_image_file(self.scene, &f, uri, self.limits, &what)
                        .map_err(|u| match u {
                        Unusable::Ignored(why) => ignored(why),
                        Unusable::Refused(e) => Unusable::Refused(e.within(|| {
                            GltfObject::new(GltfKind::Image, index, image.name.as_deref())
                        })),
                    })?,
                }
            }
            (None, None) => return Err(ignored("it has neither a URI nor a buffer view".into())),
        };
        let (w, h) = dimensions(&bytes).map_err(ignored)?;
        let pixels = u64::from(w) * u64::from(h);
        let budget = self.limits.max_texture_pixels;
        let left = budget.saturating_sub(self.pixels);
        let headroom = budget.saturating_mul(DECODE_HEADROOM);
        if pixels == 0 || left == 0 || pixels > headroom {
            return Err(ignored(format!(
                "{w} x {h} pixels: {}",
                if pixels == 0 {
                    "an empty image".to_string()
                } else if left == 0 {
                    format!(
                        "the {budget} pixels this file may keep in textures (the limit) are spent"
                    )
                } else {
                    format!(
                        "more than {DECODE_HEADROOM} times the limit of {budget} pixels this \
                         file may keep in textures, too large to decode and reduce"
                    )
                }
            )));
        }
        self.decodes += 1;
        let decoded = decode(&bytes, left, headroom).map_err(ignored)?;
        let kept = u64::from(decoded.image.width) * u64::from(decoded.image.height);
        self.pixels += kept;
        if (decoded.image.width, decoded.image.height) != decoded.full {
            self.reduced.push(format!(
                "{what}: reduced from {w} x {h} to {} x {} texels to keep the textures of \
                 this file within the limit of {budget} pixels (which follows the memory \
                 limit); its finest detail is averaged",
                decoded.image.width, decoded.image.height
            ));
        }
        let alpha = decoded.alpha.map(|values| Alpha {
            width: decoded.image.width,
            height: decoded.image.height,
            values,
        });
        Ok((decoded.image, alpha))
    }
}

/// The bytes of an image file named by `uri`. A file that cannot be read is
/// ignored like any broken image, but one that is not a regular file refuses
/// the whole scene: a FIFO or a device in a scene's folder is no texture.
fn read_image_file(
    scene: &Path,
    file: &Path,
    uri: &str,
    limits: &ImportLimits,
    what: &str,
) -> Result<Vec<u8>, Unusable> {
    read_limited(file, limits).map_err(|e| {
        if !is_not_regular(&e) {
            return Unusable::Ignored(format!("cannot read '{uri}': {e}"));
        }
        let reason = match &e {
            Error::Io { error, .. } => error.to_string(),
            other => other.to_string(),
        };
        Unusable::Refused(gltf_error(
            scene,
            format!("{what}: its URI '{uri}' is {reason}"),
        ))
    })
}
