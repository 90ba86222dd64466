//! [`load_scene`]: the import pipeline, stage by stage.

use super::alpha_mask::{budget_divisions, masked_triangles, Mask, MaskTally, MAX_CUT_TRIANGLES};
use super::buffers::load_buffers;
use super::cameras::import_camera;
use super::container::{read_limited, split};
use super::document::parse;
use super::lights::placed_lights;
use super::limits::ImportLimits;
use super::materials::{convert_materials, used_materials};
use super::meshes::{add_mesh_instance, Decoded, Source};
use super::nodes::walk;
use super::options::LoadOptions;
use super::textures::Images;
use crate::error::{Error, GeometryFault, GltfKind, GltfObject, Result};
use crate::scene::{facing_warnings, Scene};
use std::path::Path;

/// Loads a `.gltf` or `.glb` file as a [`Scene`] named after the file's stem,
/// with the default repairs ([`LoadOptions::default`]); see
/// [`load_scene_with`].
///
/// # Errors
///
/// As [`load_scene_with`].
pub fn load_scene(path: &Path, limits: &ImportLimits) -> Result<Scene> {
    load_scene_with(path, limits, &LoadOptions::default())
}

/// Loads a `.gltf` or `.glb` file as a [`Scene`] named after the file's stem,
/// repaired as `options` say.
///
/// - The default scene (else the first, else every parentless node) is walked with
///   node transforms (matrix or translation/rotation/scale) composed in `f64`.
/// - Each node with a mesh becomes one [`Object`](crate::scene::Object), named after
///   the node, else the mesh, else `node N`. Triangles of every triangle-mode primitive
///   (indexed or not; lists, strips and fans) become surfaces; coplanar pairs that form
///   a strictly convex quad are merged into one quad surface; degenerate triangles are
///   skipped. Points and lines are skipped with a warning. Everything skipped is
///   counted in [`Scene::import_stats`] and explained in [`Scene::warnings`].
/// - Material `i` of the file is scene material `i` (see the [module docs](super)
///   for the conversion); primitives without one get a default grey (0.8) appended
///   last. A `doubleSided` material's surfaces are added twice, back to back.
///   Textures are decoded only for materials some triangle primitive uses, each
///   image once however many textures show it, and keep at most
///   [`ImportLimits::max_texture_pixels`] texels over the whole file (an image
///   over what is left is reduced to fit, with a warning). `alphaMode` `MASK`
///   cuts the triangles where the alpha is below the cutoff; `BLEND` is
///   opaque, with a warning.
/// - Extensions are read whether the file uses or requires them: Draco and
///   meshopt geometry, mesh quantization, texture transforms, KTX2 and WebP
///   images, emission strength and lights in full; one warning per
///   extension honoured only in part (specular, transmission, sheen, ...:
///   the diffuse part is kept); an [`Error::Gltf`] for a required one whose
///   absence would make the result wrong (an unknown one,
///   `EXT_mesh_gpu_instancing`).
/// - Perspective cameras are imported; orthographic ones are skipped with a warning.
/// - Repairs, each with a warning: reflectance bands above
///   [`LoadOptions::max_reflectance`] are clamped to it; with
///   [`LoadOptions::double_sided`] every material is treated as double-sided;
///   objects whose single-sided faces point against their neighbours are
///   named; coplanar surfaces that overlap are resolved or refused as
///   [`LoadOptions::overlaps`] says
///   ([`Scene::resolve_overlaps`](crate::scene::Scene::resolve_overlaps)).
/// - `KHR_lights_punctual` lights become [`Scene::lights`], one per node that
///   places one, at the node's world transform (spots and suns shine down its
///   -Z axis); unknown light types are left out with a warning naming them.
///
/// # Errors
///
/// [`Error::Io`] if the file cannot be read; [`Error::Gltf`] naming the file and
/// the mesh, material, accessor or buffer for anything malformed (not glTF at all,
/// invalid JSON, a buffer URI outside the file's folder, data out of range,
/// non-finite positions, negative or non-finite material values, lights out of
/// range); [`Error::Limit`]
/// when the file exceeds `limits`; [`Error::Geometry`] naming the file when it
/// has no usable surface, or naming the overlapping objects with
/// [`Overlaps::Error`](crate::scene::Overlaps::Error); [`Error::Setting`] for
/// options out of range. Never panics, whatever the input.
pub fn load_scene_with(path: &Path, limits: &ImportLimits, options: &LoadOptions) -> Result<Scene> {
    options.validate()?;
    let bytes = read_limited(path, limits)?;
    let container = split(path, bytes)?;
    let mut scene = Scene {
        name: path
            .file_stem()
            .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned()),
        ..Scene::default()
    };
    #[allow(unused_mut)] // Draco decoding rewrites accessors.
    let mut doc = parse(path, &container.json, &mut scene.warnings)?;
    super::extensions::warn_used(&doc.raw, &mut scene.warnings);
    let mut buffers = load_buffers(path, &doc, container.bin, limits)?;
    super::meshopt::decompress_views(&doc, &mut buffers).map_err(|m| super::gltf_error(path, m))?;
    #[cfg(feature = "draco")]
    super::draco::decompress_primitives(&mut doc, &mut buffers, limits)
        .map_err(|m| super::gltf_error(path, m))?;
    let placed = walk(path, &doc, limits)?;
    let mut images = Images::new(&doc, &buffers, path, limits);
    let (materials, masks) = convert_materials(
        path,
        &doc,
        &used_materials(&doc, &placed),
        &mut images,
        options,
        &mut scene.warnings,
    )?;
    scene.materials = materials;
    scene.lights = placed_lights(path, &doc, &placed, &mut scene.warnings)?;
    scene.import_stats.punctual_lights = scene.lights.len();
    scene.import_stats.images_decoded = images.decodes;
    scene.import_stats.texture_pixels = images.pixels;
    scene.warnings.append(&mut images.reduced);
    let source = Source {
        path,
        doc: &doc,
        buffers: &buffers,
        limits,
        masks: &masks,
        mask_divisions: budget_divisions(masked_triangles(&doc, &placed, &masks)),
    };
    let mut default_material = None;
    let mut decoded = Decoded::default();
    for placed in placed {
        let node = &doc.root.nodes[placed.node];
        if let Some(camera) = node.camera {
            match import_camera(&doc, camera.value(), placed.node, &placed.world) {
                Ok(c) => scene.cameras.push(c),
                Err(warning) => scene.warnings.push(warning),
            }
        }
        if let Some(mesh) = node.mesh {
            add_mesh_instance(
                &source,
                &placed,
                mesh.value(),
                &mut scene,
                &mut default_material,
                &mut decoded,
            )
            .map_err(|e| {
                e.within(|| {
                    let name = doc
                        .root
                        .meshes
                        .get(mesh.value())
                        .and_then(|m| m.name.as_deref());
                    GltfObject::new(GltfKind::Mesh, mesh.value(), name)
                })
            })?;
        }
    }
    for (material, tally) in &decoded.masked {
        let name = &scene.materials[*material as usize].name;
        scene
            .warnings
            .push(mask_warning(name, &masks[*material as usize], tally));
    }
    if scene.surfaces.is_empty() {
        return Err(Error::geometry(
            GeometryFault::NoSurfaces,
            format!(
                "{}: the scene has no surfaces (no usable triangles in any mesh of the scene's nodes)",
                path.display()
            ),
        ));
    }
    let facing = facing_warnings(&scene);
    scene.warnings.extend(facing);
    scene
        .resolve_overlaps(options.overlaps)
        .map_err(|e| match e {
            Error::Geometry { message, .. } => super::gltf_error(path, message),
            other => other,
        })?;
    let far = scene.outlier_warning();
    scene.warnings.extend(far);
    options.add_daylight(&mut scene);
    // A mesh placed by several nodes warns of its faults once per node, in
    // the same words: each is said once.
    let mut said = std::collections::HashSet::new();
    scene.warnings.retain(|w| said.insert(w.clone()));
    Ok(scene)
}

/// What `alphaMode` `MASK` did to the surfaces of material `name`.
fn mask_warning(name: &str, mask: &Option<Mask>, t: &MaskTally) -> String {
    let cutoff = mask.as_ref().map_or(0.5, |m| m.cutoff);
    format!(
        "material '{name}': alphaMode MASK (cutoff {cutoff}): the surfaces are cut where \
         the alpha is below the cutoff, so light passes through the holes: {} triangles kept \
         whole, {} dropped as transparent, {} cut into {} pieces (at most {} pieces in all \
         for the file; finer detail of the alpha is not followed)",
        t.whole, t.dropped, t.cut, t.pieces, MAX_CUT_TRIANGLES
    )
}
