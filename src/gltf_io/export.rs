//! [`write_scene`]: a scene as glTF 2.0.

use super::cameras::camera_rotation;
use super::export_geometry::GeometryWriter;
use super::precise::{array, scalar, set};
use crate::error::{Error, Result};
use crate::math::Rgb;
use crate::output::Outputs;
use crate::scene::{Camera, Material, Scene};
use gltf_json::camera::{Perspective, Type as CameraType};
use gltf_json::extensions::material::{EmissiveStrength, EmissiveStrengthFactor};
use gltf_json::material::{
    EmissiveFactor, PbrBaseColorFactor, PbrMetallicRoughness, StrengthFactor,
};
use gltf_json::scene::UnitQuaternion;
use gltf_json::validation::{Checked, USize64};
use gltf_json::{Asset, Buffer, Index, Node, Root, Value};
use std::borrow::Cow;
use std::path::Path;

pub(super) const EMISSIVE_STRENGTH: &str = "KHR_materials_emissive_strength";

/// Writes `scene` as glTF 2.0: a `.glb` file if the extension is `glb`, else a
/// `.gltf` file with its one buffer embedded as a base64 data URI.
///
/// - One node and one mesh per [`Object`](crate::scene::Object), both named after
///   it (an object without surfaces becomes a node without a mesh), one primitive
///   per material the object uses. Quads are written as two triangles sharing their
///   diagonal; no vertex is shared between surfaces, so [`load_scene`](super::load_scene)
///   merges exactly those pairs back into the original quads. Loaded again, the
///   surfaces come grouped by object, then by material (in order of first use
///   within the object), otherwise in their original order.
/// - Positions are stored as `f32` (glTF vertex data is single precision): a
///   coordinate comes back with a relative error up to about 6e-8, so areas and
///   normals change in the seventh or eighth digit. Accessors carry the `min`/`max`
///   bounds glTF requires.
/// - Materials, in the scene's order: `baseColorFactor` is the reflectance;
///   the emitted radiance (emission / pi) is split into an `emissiveFactor` with
///   components at most 1 and a `KHR_materials_emissive_strength` that is the
///   largest component rounded up to a power of two, so that the division and the
///   importer's multiplication are exact. These numbers and the camera angles and
///   placements are written with all the digits of an `f64`, so they survive a
///   round trip exactly. `doubleSided` is false: a double-sided scene already holds
///   both faces as surfaces.
/// - Each camera becomes a node with a perspective camera, placed by translation
///   and rotation (glTF cameras look down their local -Z with +Y up).
///
/// # Errors
///
/// [`Error::Output`] for an unknown extension or a scene that glTF cannot hold
/// (a surface referring to a missing object or material, a coordinate beyond the
/// `f32` range); [`Error::Io`] if the file cannot be written. The file is
/// written whole or not at all (see [`crate::output`]): on any error a file
/// already at `path` is left as it was.
pub fn write_scene(scene: &Scene, path: &Path) -> Result<()> {
    let mut outputs = Outputs::new();
    stage_scene(&mut outputs, scene, path)?;
    outputs.commit().map(drop)
}

/// [`write_scene`] into a caller's set of outputs, renamed into place with the
/// rest of the set by [`Outputs::commit`].
///
/// # Errors
///
/// As for [`write_scene`].
pub(crate) fn stage_scene(outputs: &mut Outputs, scene: &Scene, path: &Path) -> Result<()> {
    let binary = is_binary(path)?;
    check_exportable(scene).map_err(|m| output_error(path, m))?;
    let mut root = new_root();
    let mut precise: Vec<(String, Value)> = Vec::new();
    for (i, m) in scene.materials.iter().enumerate() {
        let material = export_material(i, m, &mut precise);
        if material.extensions.is_some() {
            use_extension(&mut root, EMISSIVE_STRENGTH);
        }
        root.materials.push(material);
    }
    let by_object = surfaces_by_object(scene);
    let mut geometry = GeometryWriter { bin: Vec::new() };
    let mut scene_nodes = Vec::new();
    for (o, object) in scene.objects.iter().enumerate() {
        let mesh = geometry
            .object_mesh(&mut root, scene, &object.name, &by_object[o])
            .map(|m| root.push(m));
        scene_nodes.push(root.push(Node {
            name: Some(object.name.clone()),
            mesh,
            ..Node::default()
        }));
    }
    scene_nodes.extend(export_cameras(&mut root, scene, &mut precise));
    finish(
        root,
        scene,
        scene_nodes,
        geometry.bin,
        &precise,
        (outputs, path),
        binary,
    )?;
    Ok(())
}

/// An [`Error::Output`] for the file being written.
pub(super) fn output_error(path: &Path, message: String) -> Error {
    Error::Output {
        path: path.to_path_buf(),
        message,
    }
}

/// Whether `path` asks for a `.glb` file (else a `.gltf`); an error for any
/// other extension.
pub(super) fn is_binary(path: &Path) -> Result<bool> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
    {
        Some(e) if e == "glb" => Ok(true),
        Some(e) if e == "gltf" => Ok(false),
        _ => Err(output_error(
            path,
            "the file name must end in .gltf or .glb".to_string(),
        )),
    }
}

/// An empty glTF 2.0 document naming this program as its generator.
pub(super) fn new_root() -> Root {
    Root {
        asset: Asset {
            copyright: None,
            extensions: None,
            extras: Default::default(),
            generator: Some(format!("radiosity {}", env!("CARGO_PKG_VERSION"))),
            min_version: None,
            version: "2.0".to_string(),
        },
        ..Root::default()
    }
}

/// Lists `extension` in `extensionsUsed`, once.
pub(super) fn use_extension(root: &mut Root, extension: &str) {
    if !root.extensions_used.iter().any(|e| e == extension) {
        root.extensions_used.push(extension.to_string());
    }
}

/// The indices of each object's surfaces, object by object.
pub(super) fn surfaces_by_object(scene: &Scene) -> Vec<Vec<usize>> {
    let mut by_object: Vec<Vec<usize>> = vec![Vec::new(); scene.objects.len()];
    for (s, surface) in scene.surfaces.iter().enumerate() {
        by_object[surface.object as usize].push(s);
    }
    by_object
}

/// A camera node for each of the scene's cameras.
pub(super) fn export_cameras(
    root: &mut Root,
    scene: &Scene,
    precise: &mut Vec<(String, Value)>,
) -> Vec<Index<Node>> {
    let znear = (scene.extent() * 1e-4).max(1e-6);
    scene
        .cameras
        .iter()
        .map(|camera| export_camera(root, camera, (znear, None), precise))
        .collect()
}

/// Adds the scene (named after `scene`, holding `nodes`) and the buffer `bin`,
/// writes the numbers of `precise` at full precision over the JSON, and writes
/// the file as `.glb` or `.gltf` (buffer embedded as a base64 data URI) into
/// the set of outputs. Returns the number of bytes written.
pub(super) fn finish(
    mut root: Root,
    scene: &Scene,
    nodes: Vec<Index<Node>>,
    bin: Vec<u8>,
    precise: &[(String, Value)],
    (outputs, path): (&mut Outputs, &Path),
    binary: bool,
) -> Result<usize> {
    root.scene = Some(root.push(gltf_json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some(scene.name.clone()),
        nodes,
    }));
    if !bin.is_empty() {
        root.push(Buffer {
            byte_length: USize64(bin.len() as u64),
            extensions: None,
            extras: Default::default(),
            name: None,
            uri: (!binary).then(|| {
                format!(
                    "data:application/octet-stream;base64,{}",
                    base64::encode(&bin)
                )
            }),
        });
    }
    let fail = |e: &dyn std::fmt::Display| output_error(path, e.to_string());
    let mut json = root.to_value().map_err(|e| fail(&e))?;
    for (pointer, value) in precise {
        set(&mut json, pointer, value.clone());
    }
    let bytes = if binary {
        let text = serde_json::to_vec(&json).map_err(|e| fail(&e))?;
        let glb = gltf::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                length: 0, // computed by the writer
            },
            json: Cow::Owned(text),
            bin: (!bin.is_empty()).then_some(Cow::Owned(bin)),
        };
        glb.to_vec().map_err(|e| fail(&e))?
    } else {
        let mut text = serde_json::to_vec_pretty(&json).map_err(|e| fail(&e))?;
        text.push(b'\n');
        text
    };
    outputs.stage_bytes(path, &bytes)?;
    Ok(bytes.len())
}

/// Refuses what glTF cannot hold, before anything is built.
pub(super) fn check_exportable(scene: &Scene) -> std::result::Result<(), String> {
    for (k, s) in scene.surfaces.iter().enumerate() {
        if s.object as usize >= scene.objects.len() {
            return Err(format!(
                "surface {k} refers to object {}, but the scene has {}",
                s.object,
                scene.objects.len()
            ));
        }
        if s.material as usize >= scene.materials.len() {
            return Err(format!(
                "surface {k} refers to material {}, but the scene has {}",
                s.material,
                scene.materials.len()
            ));
        }
        let in_f32 = |v: f64| v.is_finite() && (v as f32).is_finite();
        if s.vertices
            .iter()
            .any(|v| !(in_f32(v.x) && in_f32(v.y) && in_f32(v.z)))
        {
            return Err(format!(
                "surface {k} has a coordinate beyond single precision"
            ));
        }
    }
    for m in &scene.materials {
        m.validate().map_err(|e| e.to_string())?;
    }
    for c in &scene.cameras {
        let frame_ok = c.position.is_finite()
            && c.forward.is_finite()
            && c.up.is_finite()
            && c.forward.cross(c.up).length_squared() > 0.0;
        let lens_ok = c.yfov > 0.0
            && c.yfov < std::f64::consts::PI
            && !matches!(c.aspect, Some(a) if !(a.is_finite() && a > 0.0));
        if !(frame_ok && lens_ok) {
            return Err(format!(
                "camera '{}' has no usable position, orientation or field of view",
                c.name
            ));
        }
    }
    Ok(())
}

/// The emissive factor (components at most 1) and strength whose product is
/// exactly `radiance`: the strength is 1, or the largest component rounded up to a
/// power of two (dividing by a power of two loses nothing).
pub(super) fn emissive_split(radiance: Rgb) -> (Rgb, f64) {
    let max = radiance.max_band();
    let needs_strength = max.is_finite() && max > 1.0;
    if !needs_strength {
        return (radiance, 1.0);
    }
    let mut strength = 1.0_f64;
    while strength < max {
        strength *= 2.0;
    }
    (radiance / strength, strength)
}

/// Material `i` as glTF: reflectance as `baseColorFactor`, emitted radiance as
/// `emissiveFactor` times `KHR_materials_emissive_strength` (see [`write_scene`]).
pub(super) fn export_material(
    i: usize,
    m: &Material,
    precise: &mut Vec<(String, Value)>,
) -> gltf_json::Material {
    let radiance = m.emission / std::f64::consts::PI;
    let (factor, strength) = emissive_split(radiance);
    let base = format!("/materials/{i}");
    let rho = m.reflectance.0;
    precise.push((
        format!("{base}/pbrMetallicRoughness/baseColorFactor"),
        array(&[rho[0], rho[1], rho[2], 1.0]),
    ));
    precise.push((format!("{base}/emissiveFactor"), array(&factor.0)));
    let extensions = (strength != 1.0).then(|| {
        precise.push((
            format!("{base}/extensions/{EMISSIVE_STRENGTH}/emissiveStrength"),
            scalar(strength),
        ));
        gltf_json::extensions::material::Material {
            emissive_strength: Some(EmissiveStrength {
                emissive_strength: EmissiveStrengthFactor(strength as f32),
            }),
            ..Default::default()
        }
    });
    gltf_json::Material {
        name: Some(m.name.clone()),
        pbr_metallic_roughness: PbrMetallicRoughness {
            base_color_factor: PbrBaseColorFactor([
                rho[0] as f32,
                rho[1] as f32,
                rho[2] as f32,
                1.0,
            ]),
            // A rough dielectric: the closest glTF has to a Lambertian surface.
            metallic_factor: StrengthFactor(0.0),
            roughness_factor: StrengthFactor(1.0),
            ..Default::default()
        },
        emissive_factor: EmissiveFactor(factor.to_f32()),
        double_sided: false,
        extensions,
        ..Default::default()
    }
}

/// A node carrying a perspective camera placed as `camera`, with near and
/// (if given) far clip distances `clip`.
pub(super) fn export_camera(
    root: &mut Root,
    camera: &Camera,
    (znear, zfar): (f64, Option<f64>),
    precise: &mut Vec<(String, Value)>,
) -> Index<Node> {
    let index = root.push(gltf_json::Camera {
        name: Some(camera.name.clone()),
        orthographic: None,
        perspective: Some(Perspective {
            aspect_ratio: camera.aspect.map(|a| a as f32),
            yfov: camera.yfov as f32,
            zfar: zfar.map(|f| f as f32),
            znear: znear as f32,
            extensions: None,
            extras: Default::default(),
        }),
        type_: Checked::Valid(CameraType::Perspective),
        extensions: None,
        extras: Default::default(),
    });
    let c = index.value();
    precise.push((
        format!("/cameras/{c}/perspective/yfov"),
        scalar(camera.yfov),
    ));
    if let Some(a) = camera.aspect {
        precise.push((format!("/cameras/{c}/perspective/aspectRatio"), scalar(a)));
    }
    let rotation = camera_rotation(camera);
    let p = camera.position;
    let node = root.push(Node {
        name: Some(camera.name.clone()),
        camera: Some(index),
        translation: Some([p.x as f32, p.y as f32, p.z as f32]),
        rotation: Some(UnitQuaternion(rotation.as_quat().to_array())),
        ..Node::default()
    });
    let n = node.value();
    precise.push((format!("/nodes/{n}/translation"), array(&p.to_array())));
    precise.push((format!("/nodes/{n}/rotation"), array(&rotation.to_array())));
    node
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn emissive_split_is_exact_and_bounded() {
        for r in [
            Rgb::new(17.0, 12.0, 4.0),
            Rgb::new(0.3, 0.7, 1.0),
            Rgb::new(1.0 / 3.0, 100.0 / 7.0, 0.0),
            Rgb::new(1e6 / 49.0, 2.5, 1e-9),
        ] {
            let (f, s) = emissive_split(r);
            assert!(f.max_band() <= 1.0 && f.min_band() >= 0.0, "{f:?}");
            assert_eq!((f * s).0, r.0);
        }
    }
}
