//! glTF 2.0 import and export.
//!
//! - [`load_scene`] reads a `.gltf` file (buffers embedded as base64 data URIs or in
//!   external `.bin` files beside it) or a `.glb` file into a [`Scene`](crate::scene::Scene):
//!   every triangle of every mesh instance in the default scene, with node transforms
//!   applied in double precision, coplanar triangle pairs merged back into quads,
//!   materials turned into diffuse reflectance and emission, and perspective cameras.
//!   Hostile or broken files give a typed [`Error`] naming the file and
//!   the mesh, material, accessor or buffer at fault; counts are checked against
//!   [`ImportLimits`] before anything is allocated.
//! - [`write_scene`] writes a scene back as glTF 2.0 so that loading the file again
//!   gives the same surfaces (within single precision), materials, objects and cameras.
//! - [`write_baked`] writes a solution: the refined display mesh with each
//!   vertex's display colour in `COLOR_0` (what `radiosity render` shows, for
//!   stock viewers) and each light group's radiosity in an attribute of its
//!   own, one node per object; [`load_baked`] reads such a file back as a
//!   [`ShadedMesh`](crate::render::ShadedMesh) to render from new cameras
//!   without solving again.
//!
//! Conventions (see the project's design notes): glTF units are metres; the emitted
//! radiance is `emissiveFactor * KHR_materials_emissive_strength`, the emitted exitance
//! is pi times that; the reflectance is `baseColorFactor` (times the mean colour of a
//! base colour texture, when it can be decoded) times `1 - metallic`;
//! `KHR_lights_punctual` lights are placed by their nodes (see
//! [`Light`](crate::scene::Light) for the units).

mod accessors;
mod alpha_mask;
mod bake;
mod bake_colour;
mod bake_display;
mod bake_groups;
mod bake_texture;
mod baked;
mod buffers;
mod cameras;
mod container;
mod document;
#[cfg(feature = "draco")]
mod draco;
mod export;
mod export_geometry;
mod extensions;
mod image_decode;
mod import;
mod inputs;
mod lights;
mod limits;
mod materials;
mod meshes;
mod meshopt;
mod nodes;
mod options;
mod precise;
mod primitives;
mod quad_merge;
mod texture_use;
mod textures;
mod uri;

pub use crate::scene::LinearImage;
pub use bake::{write_baked, BakeGroup, BakeOptions, BakeSummary};
pub use bake_groups::BakedGroupInfo;
pub use baked::{load_baked, BakedScene};
pub use export::write_scene;
pub use import::{load_scene, load_scene_with};
pub use inputs::input_files;
pub use limits::ImportLimits;
pub use options::{LoadOptions, DEFAULT_MAX_REFLECTANCE};

use crate::error::{Error, GltfObject};
use std::path::Path;

/// An [`Error::Gltf`] for the scene file `path`.
fn gltf_error(path: &Path, message: impl Into<String>) -> Error {
    Error::Gltf {
        path: path.to_path_buf(),
        object: None,
        message: message.into(),
    }
}

/// An [`Error::Gltf`] for the scene file `path` that names `object`.
fn gltf_error_at(path: &Path, object: GltfObject, message: impl Into<String>) -> Error {
    Error::Gltf {
        path: path.to_path_buf(),
        object: Some(object),
        message: message.into(),
    }
}

/// How a glTF object is named in messages: `kind index ('name')`, or without the
/// name when it has none.
fn describe(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(n) if !n.is_empty() => format!("{kind} {index} ('{n}')"),
        _ => format!("{kind} {index}"),
    }
}
