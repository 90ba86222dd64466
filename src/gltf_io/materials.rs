//! glTF materials as diffuse materials: reflectance from `baseColorFactor` (times the
//! mean of its texture, if it decodes), emitted radiance from `emissiveFactor` times
//! `KHR_materials_emissive_strength` (times the mean of the emissive texture, if it
//! decodes).

use super::document::Document;
use super::gltf_error;
use super::limits::ImportLimits;
use super::precise::{number, numbers};
use super::textures::mean_linear_colour;
use crate::error::{Error, Result};
use crate::math::Rgb;
use crate::scene::Material;
use std::path::Path;

/// The reflectance given to primitives without a material.
pub(super) const DEFAULT_GREY: f64 = 0.8;

/// Every material of the document, in the document's order, so that glTF material
/// `i` is scene material `i`. A material outside the physical range (reflectance
/// above 1, negative or non-finite values) is an error naming the material and the
/// file.
pub(super) fn convert_materials(
    path: &Path,
    doc: &Document,
    buffers: &[Vec<u8>],
    limits: &ImportLimits,
    warnings: &mut Vec<String>,
) -> Result<Vec<Material>> {
    let folder = path.parent().unwrap_or(Path::new("."));
    let mut out = Vec::with_capacity(doc.root.materials.len());
    for (i, m) in doc.root.materials.iter().enumerate() {
        let name = match m.name.as_deref() {
            Some(n) if !n.is_empty() => n.to_string(),
            _ => format!("material {i}"),
        };
        let base = format!("/materials/{i}");
        let rgba = numbers::<4>(
            &doc.raw,
            &format!("{base}/pbrMetallicRoughness/baseColorFactor"),
        )
        .unwrap_or([1.0; 4]);
        let mut reflectance = Rgb::new(rgba[0], rgba[1], rgba[2]);
        if let Some(info) = &m.pbr_metallic_roughness.base_color_texture {
            match mean_linear_colour(doc, buffers, folder, info.index.value(), limits) {
                Ok(mean) => reflectance = reflectance * mean,
                Err(why) => warnings.push(format!(
                    "material '{name}': base colour texture ignored ({why}); using baseColorFactor alone"
                )),
            }
        }
        let factor = numbers::<3>(&doc.raw, &format!("{base}/emissiveFactor")).unwrap_or([0.0; 3]);
        let strength = number(
            &doc.raw,
            &format!("{base}/extensions/KHR_materials_emissive_strength/emissiveStrength"),
        )
        .unwrap_or(1.0);
        let mut radiance = Rgb(factor) * strength;
        if let Some(info) = &m.emissive_texture {
            match mean_linear_colour(doc, buffers, folder, info.index.value(), limits) {
                Ok(mean) => radiance = radiance * mean,
                Err(why) => warnings.push(format!(
                    "material '{name}': emissive texture ignored ({why}); using emissiveFactor alone"
                )),
            }
        }
        let mut material = Material::from_radiance(&name, reflectance, radiance)
            .map_err(|e| in_file(path, i, e))?;
        material.double_sided = m.double_sided;
        out.push(material);
    }
    Ok(out)
}

/// The material used where a primitive names none.
pub(super) fn default_material() -> Material {
    Material {
        name: "default grey".to_string(),
        reflectance: Rgb::splat(DEFAULT_GREY),
        emission: Rgb::ZERO,
        double_sided: false,
    }
}

/// A material error restated as a glTF error, so that it names the file too.
fn in_file(path: &Path, index: usize, e: Error) -> Error {
    match e {
        Error::Material { material, message } => gltf_error(
            path,
            format!("material '{material}' (index {index}): {message}"),
        ),
        other => other,
    }
}
