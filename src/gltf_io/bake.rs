//! [`write_baked`]: a solution as glTF 2.0 that any viewer shows as
//! `radiosity render` does, with each light group's radiosity kept apart.

use super::bake_display::{cameras_to_write, clip_planes, default_exposure, Display};
use super::bake_groups::{check_groups, description, GroupWriter};
use super::bake_texture::{
    drop_clipped_textures, kept_textures, TextureWriter, FAR_CLIPPED, MAX_CLIPPED_SHARE,
};
use super::export::{
    check_exportable, export_camera, finish, is_binary, new_root, output_error, use_extension,
};
use super::export_geometry::{GeometryWriter, VertexStreams};
use super::precise::array;
use crate::error::Result;
use crate::math::Rgb;
use crate::mesh::ShadingMesh;
use crate::output::Outputs;
use crate::render::ToneMap;
use crate::scene::{Material, Scene, Texture};
use gltf_json::material::{
    EmissiveFactor, PbrBaseColorFactor, PbrMetallicRoughness, StrengthFactor,
};
use gltf_json::{Mesh, Node};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

const UNLIT: &str = "KHR_materials_unlit";

/// One light group's share of a bake: its name and its display mesh (see
/// [`Solution::group_shading_meshes`](crate::Solution::group_shading_meshes)),
/// the same vertices and triangles as the whole solution's.
#[derive(Clone, Copy, Debug)]
pub struct BakeGroup<'a> {
    /// The group's name, shown by viewers.
    pub name: &'a str,
    /// Its display mesh.
    pub shading: &'a ShadingMesh,
}

/// How [`write_baked`] shows the solution to stock viewers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BakeOptions {
    /// The exposure of `COLOR_0` in stops; `None` takes what `render`'s
    /// automatic exposure gives the file's first camera.
    pub exposure: Option<f64>,
    /// The tone map of `COLOR_0`.
    pub tone: ToneMap,
}

/// What [`write_baked`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct BakeSummary {
    /// Vertices over all primitives.
    pub vertices: usize,
    /// Triangles over all primitives.
    pub triangles: usize,
    /// Size of the file in bytes.
    pub bytes: usize,
    /// The exposure of `COLOR_0` in stops.
    pub exposure: f64,
    /// Light groups written, each a vertex attribute.
    pub groups: usize,
    /// Bytes of the buffer the groups' attributes take.
    pub group_bytes: usize,
    /// Simplifications made, in words a user can act on.
    pub warnings: Vec<String>,
}

/// The triangles of one primitive: one object's triangles on one material.
struct Group {
    material: u32,
    triangles: Vec<usize>,
}

/// Per material, the vertices of its primitives in `baked` clipped by more
/// than [`FAR_CLIPPED`], and all its vertices.
fn clipping_textures(
    materials: usize,
    primitives: &[Vec<Group>],
    baked: &[Vec<Baked>],
) -> Vec<(usize, usize)> {
    let mut out = vec![(0, 0); materials];
    for (g, b) in primitives.iter().flatten().zip(baked.iter().flatten()) {
        let m = &mut out[g.material as usize];
        m.0 += b.far_clipped;
        m.1 += b.positions.len();
    }
    out
}

/// One primitive's vertex data.
struct Baked {
    positions: Vec<[f32; 3]>,
    /// `COLOR_0`: the display value.
    colours: Vec<[f32; 3]>,
    /// Per light group, its unscaled value per vertex: radiosity, or on a
    /// kept texture the irradiance.
    groups: Vec<Vec<Rgb>>,
    /// `TEXCOORD_0` (transformed) when the material's texture is kept.
    texcoords: Option<Vec<[f32; 2]>>,
    indices: Vec<u32>,
    /// Vertices whose display colour was clipped to 1.
    clipped: usize,
    /// Vertices clipped by more than [`FAR_CLIPPED`].
    far_clipped: usize,
}

/// Writes a solved scene as glTF 2.0: the crack-free display mesh `shading`
/// (from [`Solution::shading_mesh`](crate::Solution::shading_mesh) of a
/// solve of `scene`) with each light group of `groups` (see
/// [`crate::light_groups`]; none: the whole solution is one group, `all`)
/// as a vertex attribute: a `.glb` file if the extension is `glb`, else a
/// `.gltf` file with its buffer embedded.
///
/// - One node and one mesh per scene object, both named after it, with one
///   triangle-list primitive per material the object uses (in order of first
///   use); vertices are shared only within a surface, where the radiosity is
///   continuous. Materials are unlit (`KHR_materials_unlit`) and white, or
///   keep their base-colour texture and factor.
/// - `COLOR_0` is what a viewer that draws vertex colours on unlit materials
///   with no tone mapping of its own (three.js's default) must show to match
///   `radiosity render`: each vertex's radiance (radiosity / pi) times
///   `2^exposure`, tone mapped (`options`), one exposure for the whole file.
///   On a kept texture the colour is the display value of the mean texel's
///   radiance over the mean reflectance, so that texel times colour shows
///   the texture's detail around it (where that would exceed 1 it is
///   clipped, counted in a warning). Textured materials that emit are baked
///   untextured, as are those that would be clipped by more than a stop at
///   more than a tenth of their vertices (with a warning naming them).
/// - Light group `k` is the attribute `_GROUP_k`: its radiosity per vertex
///   (its irradiance on kept textures) divided by its scale, a power of two;
///   `asset.extras.radiosity` lists the groups' names, attributes and scales,
///   the exposure and tone map, and the formula. The groups add up to the
///   whole solution: a viewer that mixes them relights the model.
/// - The scene's cameras, or when it has none the default view
///   ([`Camera::framing`](crate::scene::Camera::framing)), with near and far
///   planes that hold the scene and keep depth resolution.
///
/// [`load_baked`](super::load_baked) reads such a file back.
///
/// # Errors
///
/// [`Error::Output`](crate::Error::Output) for an unknown extension, a scene
/// glTF cannot hold, or a display mesh (or group) that does not belong to
/// `scene`; [`Error::Io`](crate::Error::Io) if the file cannot be written.
/// The file is written whole or not at all (see [`crate::output`]).
pub fn write_baked(
    scene: &Scene,
    shading: &ShadingMesh,
    groups: &[BakeGroup<'_>],
    options: &BakeOptions,
    path: &Path,
) -> Result<BakeSummary> {
    let mut outputs = Outputs::new();
    let summary = stage_baked(&mut outputs, scene, shading, groups, options, path)?;
    outputs.commit()?;
    Ok(summary)
}

/// [`write_baked`] into a caller's set of outputs, renamed into place with the
/// rest of the set by [`Outputs::commit`].
///
/// # Errors
///
/// As for [`write_baked`].
pub(crate) fn stage_baked(
    outputs: &mut Outputs,
    scene: &Scene,
    shading: &ShadingMesh,
    groups: &[BakeGroup<'_>],
    options: &BakeOptions,
    path: &Path,
) -> Result<BakeSummary> {
    let binary = is_binary(path)?;
    check_exportable(scene).map_err(|m| output_error(path, m))?;
    check_shading(scene, shading).map_err(|m| output_error(path, m))?;
    let whole = [BakeGroup {
        name: "all",
        shading,
    }];
    let groups = if groups.is_empty() {
        &whole[..]
    } else {
        groups
    };
    check_groups(shading, groups).map_err(|m| output_error(path, m))?;

    let cameras = cameras_to_write(scene);
    let exposure = options
        .exposure
        .unwrap_or_else(|| default_exposure(shading, &cameras[0], options.tone));
    let display = Display {
        gain: exposure.exp2(),
        tone: options.tone,
    };
    let mut kept = kept_textures(scene, shading);
    let primitives = group_triangles(scene, shading);
    let bake_all = |kept: &[Option<Arc<Texture>>]| -> Vec<Vec<Baked>> {
        primitives
            .iter()
            .map(|object| {
                object
                    .iter()
                    .map(|g| {
                        let texture = kept[g.material as usize].as_ref();
                        bake_primitive(scene, shading, groups, display, g, texture)
                    })
                    .collect()
            })
            .collect()
    };
    let mut baked = bake_all(&kept);
    let clipped_far = clipping_textures(scene.materials.len(), &primitives, &baked);
    let dropped = drop_clipped_textures(scene, &clipped_far, &mut kept);
    if !dropped.is_empty() {
        baked = bake_all(&kept);
    }
    let mut group_writer = GroupWriter::new(groups, baked.iter().flatten().map(|b| &b.groups));

    let mut root = new_root();
    let mut precise = Vec::new();
    let mut geometry = GeometryWriter { bin: Vec::new() };
    let mut textures = TextureWriter::default();
    use_extension(&mut root, UNLIT);
    for (i, m) in scene.materials.iter().enumerate() {
        let mut material = unlit_white(m);
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
        root.materials.push(material);
    }

    let mut nodes = Vec::new();
    let mut summary = BakeSummary {
        vertices: 0,
        triangles: 0,
        bytes: 0,
        exposure,
        groups: groups.len(),
        group_bytes: 0,
        warnings: Vec::new(),
    };
    let mut clipped = 0;
    for (o, object) in scene.objects.iter().enumerate() {
        let mut meshes = Vec::new();
        for (g, b) in primitives[o].iter().zip(&baked[o]) {
            let extra = group_writer.attributes(&b.groups);
            let streams = VertexStreams {
                positions: &b.positions,
                normals: None,
                colours: Some(&b.colours),
                texcoords: b.texcoords.as_deref(),
                extra: &extra,
            };
            meshes.push(geometry.triangle_primitive(&mut root, &streams, &b.indices, g.material));
            summary.vertices += b.positions.len();
            summary.triangles += b.indices.len() / 3;
            clipped += b.clipped;
        }
        let mesh = (!meshes.is_empty()).then(|| {
            root.push(Mesh {
                extensions: None,
                extras: Default::default(),
                name: Some(object.name.clone()),
                primitives: meshes,
                weights: None,
            })
        });
        nodes.push(root.push(Node {
            name: Some(object.name.clone()),
            mesh,
            ..Node::default()
        }));
    }
    for camera in &cameras {
        let clip = clip_planes(camera, &shading.positions, &shading.triangles);
        nodes.push(export_camera(
            &mut root,
            camera,
            (clip.0, Some(clip.1)),
            &mut precise,
        ));
    }
    summary.group_bytes = group_writer.bytes();
    precise.push((
        "/asset/extras/radiosity".to_string(),
        description(&group_writer, exposure, options.tone),
    ));
    if !dropped.is_empty() {
        summary.warnings.push(format!(
            "{} textured materials are lit brighter than their textures can show in \
             COLOR_0 at exposure {exposure:.2} (a viewer draws texel times colour, each at \
             most 1), by more than a stop at more than {}% of their vertices: baked \
             without their textures, \
             each element in its own colour: {}",
            dropped.len(),
            100.0 * MAX_CLIPPED_SHARE,
            dropped.join(", ")
        ));
    }
    if clipped > 0 {
        summary.warnings.push(format!(
            "{clipped} vertices on textured materials are brighter than their texture can \
             show in COLOR_0 at exposure {exposure:.2}: clipped there (their light groups \
             keep the whole value)"
        ));
    }
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

/// The vertices of one primitive, numbered in order of first use, with their
/// display colours and each group's value; with the material's `texture`
/// kept, the values are the light and the texture coordinates come along.
fn bake_primitive(
    scene: &Scene,
    shading: &ShadingMesh,
    groups: &[BakeGroup<'_>],
    display: Display,
    g: &Group,
    texture: Option<&Arc<Texture>>,
) -> Baked {
    let material: &Material = &scene.materials[g.material as usize];
    let mut number: HashMap<u32, u32> = HashMap::new();
    // `kept_textures` keeps a texture only where the display mesh has texels.
    let texels = texture.and_then(|t| Some((t, shading.texels.as_ref()?)));
    let mut out = Baked {
        positions: Vec::new(),
        colours: Vec::new(),
        groups: vec![Vec::new(); groups.len()],
        texcoords: texels.map(|_| Vec::new()),
        indices: Vec::with_capacity(3 * g.triangles.len()),
        clipped: 0,
        far_clipped: 0,
    };
    for &t in &g.triangles {
        for v in shading.triangles[t] {
            let k = *number.entry(v).or_insert_with(|| {
                let i = v as usize;
                let p = shading.positions[i];
                let colour = match (texels, &mut out.texcoords) {
                    (Some((t, x)), Some(texcoords)) => {
                        let uv = t.transform.transform_point2(x.uv[i]);
                        texcoords.push([uv.x as f32, uv.y as f32]);
                        for (values, group) in out.groups.iter_mut().zip(groups) {
                            let light = group.shading.texels.as_ref().map(|t| t.irradiance[i]);
                            values.push(light.unwrap_or(Rgb::ZERO).max(Rgb::ZERO));
                        }
                        let (c, largest) =
                            display.of_irradiance(x.irradiance[i], material.reflectance);
                        out.clipped += usize::from(largest > 1.0);
                        out.far_clipped += usize::from(largest > FAR_CLIPPED);
                        c
                    }
                    _ => {
                        for (values, group) in out.groups.iter_mut().zip(groups) {
                            values.push(group.shading.radiosity[i].max(Rgb::ZERO));
                        }
                        display.of_radiosity(shading.radiosity[i])
                    }
                };
                out.positions.push([p.x as f32, p.y as f32, p.z as f32]);
                out.colours.push(colour.to_f32());
                (out.positions.len() - 1) as u32
            });
            out.indices.push(k);
        }
    }
    out
}

/// The stand-in for `m` in a bake: unlit white, no emission (the vertex
/// colours hold it), named after `m`.
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
