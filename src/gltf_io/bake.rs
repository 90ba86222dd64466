//! [`write_baked`]: a solution as glTF 2.0 with per-vertex radiosity.

use super::bake_colour::{scale_for, BakeColour, SCALE_KEY};
use super::bake_texture::{kept_textures, TextureWriter};
use super::export::{
    check_exportable, export_cameras, export_material, finish, is_binary, new_root, output_error,
    use_extension, EMISSIVE_STRENGTH,
};
use super::export_geometry::{GeometryWriter, VertexStreams};
use super::precise::{array, scalar};
use crate::error::Result;
use crate::math::Rgb;
use crate::mesh::ShadingMesh;
use crate::output::Outputs;
use crate::scene::{Material, Scene, Texture};
use gltf_json::material::{
    EmissiveFactor, PbrBaseColorFactor, PbrMetallicRoughness, StrengthFactor,
};
use gltf_json::{Mesh, Node, Value};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

const UNLIT: &str = "KHR_materials_unlit";

/// What [`write_baked`] wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BakeSummary {
    /// Vertices over all primitives.
    pub vertices: usize,
    /// Triangles over all primitives.
    pub triangles: usize,
    /// Size of the file in bytes.
    pub bytes: usize,
}

/// The triangles of one primitive: one object's triangles on one material.
struct Group {
    material: u32,
    triangles: Vec<usize>,
}

/// One primitive's vertex data, before scaling.
struct Baked {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    colours: Vec<Rgb>,
    /// `TEXCOORD_0` (transformed) when the material's texture is kept.
    texcoords: Option<Vec<[f32; 2]>>,
    indices: Vec<u32>,
    max: f64,
}

/// Writes a solved scene as glTF 2.0 with the radiosity of every vertex of the
/// crack-free display mesh `shading` (from
/// [`Solution::shading_mesh`](crate::Solution::shading_mesh) of a solve of
/// `scene`) in `COLOR_0`: a `.glb` file if the extension is `glb`, else a
/// `.gltf` file with its buffer embedded.
///
/// - One node and one mesh per scene object, both named after it, with one
///   triangle-list primitive per material the object uses (in order of first
///   use); within a primitive the triangles keep the order of `shading`, and
///   vertices are shared only within a surface, where the radiosity is
///   continuous. The scene's cameras come along as camera nodes.
/// - `colour` chooses what `COLOR_0` means (see [`BakeColour`]). Vertex colours
///   must lie in `[0, 1]`, so every primitive stores its values divided by a power
///   of two kept in the primitive's `extras` as `radiosityScale`: the value is
///   `radiosityScale * COLOR_0` exactly, up to the `f32` rounding of `COLOR_0`.
///   With [`BakeColour::Radiosity`] every non-emitting primitive shares one scale
///   (so a viewer shows their radiosities in proportion, the brightest at
///   least half white) and each emitting primitive has its own (so emitters show
///   near white rather than darkening everything else). With
///   [`BakeColour::Light`] all primitives share one scale and the materials are
///   the scene's own, exactly as [`write_scene`](super::write_scene) writes them,
///   plus `NORMAL`s for lit viewers.
/// - Textured surfaces (see [`ShadingMesh::texels`]): a material's base-colour
///   texture is kept (image, sampler, `TEXCOORD_0` per vertex with the
///   texture transform applied; see `bake_texture.rs`) and `COLOR_0` holds
///   the irradiance `H` interpolated smoothly, so that `baseColorTexture *
///   baseColorFactor * COLOR_0 * radiosityScale` is the drawn radiosity
///   `rho(texel) H` in both modes ([`BakeColour::Radiosity`] writes the
///   texture's factor as `baseColorFactor` of the unlit material). Emission
///   cannot be added to that product by an unlit material: a textured
///   material that emits is baked in [`BakeColour::Radiosity`] as an
///   untextured one (radiosity per vertex, the texture dropped); in
///   [`BakeColour::Light`] its emission stays on the material as the mean
///   `emissiveFactor`, as for untextured ones. Emissive textures are not
///   kept: their detail is lost, their mean remains.
/// - `asset.extras.radiosity` records the colour mode and the formula.
///
/// [`load_baked`](super::load_baked) reads such a file back into a
/// [`ShadedMesh`](crate::render::ShadedMesh).
///
/// # Errors
///
/// [`Error::Output`](crate::Error::Output) for an unknown extension, a scene
/// glTF cannot hold, or a display mesh that does not belong to `scene` (a
/// surface or vertex index out of range, a non-finite radiosity);
/// [`Error::Io`](crate::Error::Io) if the file cannot be written. The file is
/// written whole or not at all (see [`crate::output`]): on any error a file
/// already at `path` (even the scene that was solved) is left as it was.
pub fn write_baked(
    scene: &Scene,
    shading: &ShadingMesh,
    colour: BakeColour,
    path: &Path,
) -> Result<BakeSummary> {
    let mut outputs = Outputs::new();
    let summary = stage_baked(&mut outputs, scene, shading, colour, path)?;
    outputs.commit()?;
    Ok(summary)
}

/// [`write_baked`] into a caller's set of outputs, renamed into place with the
/// rest of the set by [`Outputs::commit`].
///
/// # Errors
///
/// As for [`write_baked`].
pub fn stage_baked(
    outputs: &mut Outputs,
    scene: &Scene,
    shading: &ShadingMesh,
    colour: BakeColour,
    path: &Path,
) -> Result<BakeSummary> {
    let binary = is_binary(path)?;
    check_exportable(scene).map_err(|m| output_error(path, m))?;
    check_shading(scene, shading).map_err(|m| output_error(path, m))?;

    let kept = kept_textures(scene, shading, colour);
    let groups = group_triangles(scene, shading);
    let baked: Vec<Vec<Baked>> = groups
        .iter()
        .map(|object| {
            object
                .iter()
                .map(|g| {
                    bake_group(
                        scene,
                        shading,
                        colour,
                        g,
                        kept[g.material as usize].as_ref(),
                    )
                })
                .collect()
        })
        .collect();
    let emits = |g: &Group| scene.materials[g.material as usize].is_emitter();
    let shared_max = groups
        .iter()
        .flatten()
        .zip(baked.iter().flatten())
        .filter(|(g, _)| colour == BakeColour::Light || !emits(g))
        .map(|(_, b)| b.max)
        .fold(0.0, f64::max);
    let shared_scale = scale_for(shared_max);

    let mut root = new_root();
    let mut precise: Vec<(String, Value)> = Vec::new();
    let mut geometry = GeometryWriter { bin: Vec::new() };
    let mut textures = TextureWriter::default();
    for (i, m) in scene.materials.iter().enumerate() {
        let mut material = match colour {
            BakeColour::Light => export_material(i, m, &mut precise),
            BakeColour::Radiosity => unlit_white(m),
        };
        if let Some(t) = &kept[i] {
            let pbr = &mut material.pbr_metallic_roughness;
            pbr.base_color_texture = Some(
                textures
                    .reference(&mut root, &mut geometry, t)
                    .map_err(|m| output_error(path, m))?,
            );
            let f = t.factor.0;
            pbr.base_color_factor =
                PbrBaseColorFactor([f[0] as f32, f[1] as f32, f[2] as f32, 1.0]);
            precise.push((
                format!("/materials/{i}/pbrMetallicRoughness/baseColorFactor"),
                array(&[f[0], f[1], f[2], 1.0]),
            ));
        }
        if material
            .extensions
            .as_ref()
            .is_some_and(|e| e.emissive_strength.is_some())
        {
            use_extension(&mut root, EMISSIVE_STRENGTH);
        }
        if colour == BakeColour::Radiosity {
            use_extension(&mut root, UNLIT);
        }
        root.materials.push(material);
    }

    let mut nodes = Vec::new();
    let mut summary = BakeSummary {
        vertices: 0,
        triangles: 0,
        bytes: 0,
    };
    for (o, object) in scene.objects.iter().enumerate() {
        let mut primitives = Vec::new();
        let mut scales = Vec::new();
        for (g, b) in groups[o].iter().zip(&baked[o]) {
            let scale = if colour == BakeColour::Radiosity && emits(g) {
                scale_for(b.max)
            } else {
                shared_scale
            };
            let colours: Vec<[f32; 3]> = b.colours.iter().map(|c| (*c / scale).to_f32()).collect();
            let streams = VertexStreams {
                positions: &b.positions,
                normals: (colour == BakeColour::Light).then_some(&b.normals[..]),
                colours: Some(&colours),
                texcoords: b.texcoords.as_deref(),
            };
            primitives
                .push(geometry.triangle_primitive(&mut root, &streams, &b.indices, g.material));
            scales.push(scale);
            summary.vertices += b.positions.len();
            summary.triangles += b.indices.len() / 3;
        }
        let mesh = (!primitives.is_empty()).then(|| {
            root.push(Mesh {
                extensions: None,
                extras: Default::default(),
                name: Some(object.name.clone()),
                primitives,
                weights: None,
            })
        });
        if let Some(m) = mesh {
            for (p, scale) in scales.iter().enumerate() {
                precise.push((
                    format!("/meshes/{}/primitives/{p}/extras/{SCALE_KEY}", m.value()),
                    scalar(*scale),
                ));
            }
        }
        nodes.push(root.push(Node {
            name: Some(object.name.clone()),
            mesh,
            ..Node::default()
        }));
    }
    nodes.extend(export_cameras(&mut root, scene, &mut precise));
    precise.push(("/asset/extras/radiosity".to_string(), description(colour)));
    summary.bytes = finish(
        root,
        scene,
        nodes,
        geometry.bin,
        &precise,
        (outputs, path),
        binary,
    )?;
    Ok(summary)
}

/// Checks that `shading` belongs to `scene` and holds finite values.
fn check_shading(scene: &Scene, shading: &ShadingMesh) -> std::result::Result<(), String> {
    let n = shading.positions.len();
    if shading.radiosity.len() != n || shading.triangle_surface.len() != shading.triangles.len() {
        return Err(format!(
            "the display mesh is inconsistent: {n} positions, {} radiosities, {} triangles, \
             {} triangle surfaces",
            shading.radiosity.len(),
            shading.triangles.len(),
            shading.triangle_surface.len()
        ));
    }
    if let Some(t) = shading
        .triangle_surface
        .iter()
        .position(|&s| s as usize >= scene.surfaces.len())
    {
        return Err(format!(
            "display triangle {t} lies on surface {}, but the scene has {} surfaces",
            shading.triangle_surface[t],
            scene.surfaces.len()
        ));
    }
    if let Some(t) = shading
        .triangles
        .iter()
        .position(|tri| tri.iter().any(|&v| v as usize >= n))
    {
        return Err(format!(
            "display triangle {t} refers to a vertex beyond the {n} there are"
        ));
    }
    let in_f32 = |v: f64| v.is_finite() && (v as f32).is_finite();
    if let Some(v) = shading
        .positions
        .iter()
        .position(|p| !(in_f32(p.x) && in_f32(p.y) && in_f32(p.z)))
    {
        return Err(format!(
            "display vertex {v} has a position beyond single precision"
        ));
    }
    if let Some(v) = shading.radiosity.iter().position(|b| !b.is_finite()) {
        return Err(format!(
            "display vertex {v} has a non-finite radiosity {:?}",
            shading.radiosity[v].0
        ));
    }
    if let Some(t) = &shading.texels {
        if t.irradiance.len() != n || t.uv.len() != n {
            return Err(format!(
                "the display mesh is inconsistent: {n} positions, {} irradiances, {} texture \
                 coordinates",
                t.irradiance.len(),
                t.uv.len()
            ));
        }
        let bad = |v: usize| !(t.irradiance[v].is_finite() && t.uv[v].is_finite());
        if let Some(v) = (0..n).find(|&v| bad(v)) {
            return Err(format!(
                "display vertex {v} has a non-finite irradiance or texture coordinates"
            ));
        }
    }
    Ok(())
}

/// The display triangles of each object, split by material in order of first
/// use, each list in the display mesh's order.
fn group_triangles(scene: &Scene, shading: &ShadingMesh) -> Vec<Vec<Group>> {
    let mut groups: Vec<Vec<Group>> = scene.objects.iter().map(|_| Vec::new()).collect();
    for (t, &s) in shading.triangle_surface.iter().enumerate() {
        let surface = &scene.surfaces[s as usize];
        let object = &mut groups[surface.object as usize];
        match object.iter_mut().find(|g| g.material == surface.material) {
            Some(g) => g.triangles.push(t),
            None => object.push(Group {
                material: surface.material,
                triangles: vec![t],
            }),
        }
    }
    groups
}

/// The vertices of one group, numbered in order of first use, with their
/// unscaled colours and their surface's normal; with the material's `texture`
/// kept, the colour is the irradiance and the texture coordinates come along.
fn bake_group(
    scene: &Scene,
    shading: &ShadingMesh,
    colour: BakeColour,
    g: &Group,
    texture: Option<&Arc<Texture>>,
) -> Baked {
    let material: &Material = &scene.materials[g.material as usize];
    let mut number: HashMap<u32, u32> = HashMap::new();
    // `kept_textures` keeps a texture only where the display mesh has texels.
    let texels = texture.and_then(|t| Some((t, shading.texels.as_ref()?)));
    let mut out = Baked {
        positions: Vec::new(),
        normals: Vec::new(),
        colours: Vec::new(),
        texcoords: texels.map(|_| Vec::new()),
        indices: Vec::with_capacity(3 * g.triangles.len()),
        max: 0.0,
    };
    for &t in &g.triangles {
        let normal = scene.surfaces[shading.triangle_surface[t] as usize].normal;
        for v in shading.triangles[t] {
            let k = *number.entry(v).or_insert_with(|| {
                let p = shading.positions[v as usize];
                let c = match (texels, &mut out.texcoords) {
                    (Some((t, x)), Some(texcoords)) => {
                        let uv = t.transform.transform_point2(x.uv[v as usize]);
                        texcoords.push([uv.x as f32, uv.y as f32]);
                        x.irradiance[v as usize]
                    }
                    _ => colour.colour_of(shading.radiosity[v as usize], material),
                };
                out.positions.push([p.x as f32, p.y as f32, p.z as f32]);
                out.normals.push(normal.as_vec3().normalize().to_array());
                out.max = out.max.max(c.max_band());
                out.colours.push(c);
                (out.positions.len() - 1) as u32
            });
            out.indices.push(k);
        }
    }
    out
}

/// The stand-in for `m` in a radiosity bake: unlit white, no emission (the
/// vertex colours hold it), named after `m`.
fn unlit_white(m: &Material) -> gltf_json::Material {
    gltf_json::Material {
        name: Some(m.name.clone()),
        pbr_metallic_roughness: PbrMetallicRoughness {
            base_color_factor: PbrBaseColorFactor([1.0; 4]),
            metallic_factor: StrengthFactor(0.0),
            roughness_factor: StrengthFactor(1.0),
            ..Default::default()
        },
        emissive_factor: EmissiveFactor([0.0; 3]),
        double_sided: false,
        extensions: Some(gltf_json::extensions::material::Material {
            unlit: Some(gltf_json::extensions::material::Unlit {}),
            ..Default::default()
        }),
        ..Default::default()
    }
}

/// `asset.extras.radiosity`: the colour mode and how to read the colours.
fn description(colour: BakeColour) -> Value {
    let formula = match colour {
        BakeColour::Light => {
            "COLOR_0 * radiosityScale is the irradiance (W/m^2) per band, 0 where the \
             base colour is 0; radiosity = baseColorFactor (times baseColorTexture where \
             there is one) * COLOR_0 * radiosityScale + pi * emitted radiance \
             (emissiveFactor * emissiveStrength)"
        }
        BakeColour::Radiosity => {
            "radiosity (exitance, W/m^2) = COLOR_0 * radiosityScale, times baseColorFactor \
             * baseColorTexture on materials with a texture (COLOR_0 then holds the \
             irradiance); radiance = radiosity / pi"
        }
    };
    serde_json::json!({
        "colour": colour.name(),
        "scaleKey": format!("meshes[].primitives[].extras.{SCALE_KEY}"),
        "formula": formula,
    })
}
