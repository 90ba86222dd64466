//! glTF materials as diffuse materials: reflectance from `baseColorFactor` (times the
//! mean of its texture, if it decodes, which the material also keeps so that
//! each element gets the texture over its own footprint) times `1 - metallic`,
//! emitted radiance from `emissiveFactor` times `KHR_materials_emissive_strength`
//! (times the mean of the emissive texture, if it decodes, likewise kept for
//! each element's footprint). Textures are decoded only for materials that some
//! triangle primitive of the imported scene uses.

use super::alpha_mask::Mask;
use super::document::Document;
use super::gltf_error_at;
use super::nodes::Placed;
use super::options::LoadOptions;
use super::precise::{number, numbers};
use super::primitives::triangle_mode;
use super::texture_use::texture_use;
use super::textures::{Images, Unusable};
use crate::error::{Error, GltfKind, GltfObject, Result};
use crate::math::Rgb;
use crate::scene::Material;
use gltf_json::validation::Checked;
use std::path::Path;
use std::sync::Arc;

/// The reflectance given to primitives without a material.
pub(super) const DEFAULT_GREY: f64 = 0.8;

/// Which materials of the document some triangle primitive of a placed node's
/// mesh uses (index `i` for glTF material `i`).
pub(super) fn used_materials(doc: &Document, placed: &[Placed]) -> Vec<bool> {
    let mut used = vec![false; doc.root.materials.len()];
    let meshes = placed
        .iter()
        .filter_map(|p| doc.root.nodes[p.node].mesh)
        .filter_map(|m| doc.root.meshes.get(m.value()));
    for prim in meshes.flat_map(|m| &m.primitives) {
        let draws_triangles = matches!(prim.mode, Checked::Valid(m) if triangle_mode(m).is_some());
        if let (true, Some(m)) = (draws_triangles, prim.material) {
            if let Some(flag) = used.get_mut(m.value()) {
                *flag = true;
            }
        }
    }
    used
}

/// Every material of the document, in the document's order, so that glTF material
/// `i` is scene material `i`. Reflectance bands above `options.max_reflectance`
/// (a pure-white `baseColorFactor`, or beyond glTF's range of 0 to 1) are clamped
/// to it, with one warning naming every such material; with
/// `options.double_sided` every material is double-sided. Negative or
/// non-finite values are an error naming the material and the file. The textures of material `i` are decoded (through `images`, once per
/// image) only when `used[i]`: an unused material keeps its factors alone.
/// The second list holds, for each material whose `alphaMode` is `MASK`,
/// what its surfaces are cut by ([`Mask`]); `BLEND` materials are kept
/// opaque, with one warning naming them.
pub(super) fn convert_materials(
    path: &Path,
    doc: &Document,
    used: &[bool],
    images: &mut Images,
    options: &LoadOptions,
    warnings: &mut Vec<String>,
) -> Result<(Vec<Material>, Vec<Option<Mask>>)> {
    let mut out = Vec::with_capacity(doc.root.materials.len());
    let mut masks = Vec::with_capacity(doc.root.materials.len());
    let mut blended: Vec<String> = Vec::new();
    let mut clamped: Vec<String> = Vec::new();
    for (i, m) in doc.root.materials.iter().enumerate() {
        let name = match m.name.as_deref() {
            Some(n) if !n.is_empty() => n.to_string(),
            _ => format!("material {i}"),
        };
        let object = || GltfObject::new(GltfKind::Material, i, m.name.as_deref());
        let base = format!("/materials/{i}");
        let rgba = numbers::<4>(
            &doc.raw,
            &format!("{base}/pbrMetallicRoughness/baseColorFactor"),
        )
        .unwrap_or([1.0; 4]);
        let mut reflectance = Rgb::new(rgba[0], rgba[1], rgba[2]);
        let factor = reflectance;
        let in_use = used.get(i).copied().unwrap_or(false);
        let base_texture = m.pbr_metallic_roughness.base_color_texture.as_ref();
        let mut texture = None;
        let mode = doc
            .raw
            .pointer(&format!("{base}/alphaMode"))
            .and_then(|v| v.as_str());
        let mut mask = (mode == Some("MASK")).then(|| Mask {
            cutoff: number(&doc.raw, &format!("{base}/alphaCutoff")).unwrap_or(0.5),
            alpha: None,
            factor_alpha: rgba[3],
        });
        if mode == Some("BLEND") && in_use {
            blended.push(format!("'{name}' (alpha {:.3})", rgba[3]));
        }
        if let Some(info) = base_texture.filter(|_| in_use) {
            match images.with_alpha(info.index.value()) {
                Ok((image, alpha)) => {
                    if let (Some(m), Some(alpha)) = (&mut mask, alpha) {
                        let pointer = format!("{base}/pbrMetallicRoughness/baseColorTexture");
                        let grey = alpha.values.iter().map(|a| [f32::from(*a) / 255.0; 3]).collect();
                        let grey = Arc::new(crate::scene::LinearImage {
                            width: alpha.width,
                            height: alpha.height,
                            texels: grey,
                        });
                        m.alpha = Some(texture_use(
                            doc,
                            &pointer,
                            info,
                            grey,
                            Rgb::splat(rgba[3]),
                            f64::INFINITY,
                        ));
                    }
                    reflectance = reflectance * image.mean();
                    let pointer = format!("{base}/pbrMetallicRoughness/baseColorTexture");
                    texture = Some(texture_use(
                        doc,
                        &pointer,
                        info,
                        image,
                        factor,
                        options.max_reflectance,
                    ));
                }
                Err(Unusable::Ignored(why)) => warnings.push(format!(
                    "material '{name}': base colour texture ignored ({why}); using baseColorFactor alone"
                )),
                Err(Unusable::Refused(e)) => return Err(e.within(object)),
            }
        }
        if in_use {
            let metallic = metallic(path, doc, i, &name, images, warnings)?;
            if metallic > 0.0 {
                reflectance *= 1.0 - metallic.min(1.0);
                if let Some(t) = &mut texture {
                    t.factor *= 1.0 - metallic.min(1.0);
                }
            }
        }
        let factor = numbers::<3>(&doc.raw, &format!("{base}/emissiveFactor")).unwrap_or([0.0; 3]);
        let strength = number(
            &doc.raw,
            &format!("{base}/extensions/KHR_materials_emissive_strength/emissiveStrength"),
        )
        .unwrap_or(1.0);
        let mut radiance = Rgb(factor) * strength;
        let mut emissive_texture = None;
        if let Some(info) = m.emissive_texture.as_ref().filter(|_| in_use) {
            match images.for_texture(info.index.value()) {
                Ok(image) => {
                    // The texture holds radiance; elements take exitance.
                    let exitance = radiance * std::f64::consts::PI;
                    radiance = radiance * image.mean();
                    let pointer = format!("{base}/emissiveTexture");
                    emissive_texture = (exitance.max_band() > 0.0).then(|| {
                        texture_use(doc, &pointer, info, image, exitance, f64::INFINITY)
                    });
                }
                Err(Unusable::Ignored(why)) => warnings.push(format!(
                    "material '{name}': emissive texture ignored ({why}); using emissiveFactor alone"
                )),
                Err(Unusable::Refused(e)) => return Err(e.within(object)),
            }
        }
        let max = options.max_reflectance;
        if reflectance.is_finite() && reflectance.max_band() > max {
            clamped.push(format!("'{name}' ({})", bands(reflectance)));
            reflectance = Rgb(reflectance.0.map(|r| r.min(max)));
        }
        let mut material = Material::from_radiance(&name, reflectance, radiance)
            .map_err(|e| in_file(path, object(), e))?;
        material.double_sided = m.double_sided || options.double_sided;
        if let (Some(b), Some(e)) = (&texture, &emissive_texture) {
            if b.texcoord != e.texcoord {
                warnings.push(format!(
                    "material '{name}': its emissive texture reads TEXCOORD_{} and its base \
                     colour texture TEXCOORD_{}; one set per surface is kept, so the emission \
                     is the emissive texture's mean",
                    e.texcoord, b.texcoord
                ));
                emissive_texture = None;
            }
        }
        material.base_texture = texture.map(Arc::new);
        material.emissive_texture = emissive_texture.map(Arc::new);
        out.push(material);
        masks.push(mask.filter(|_| in_use));
    }
    if !blended.is_empty() {
        warnings.push(format!(
            "alphaMode BLEND is not simulated: {} materials are opaque with their diffuse \
             base colour: {}",
            blended.len(),
            blended.join(", ")
        ));
    }
    if !clamped.is_empty() {
        warnings.push(format!(
            "reflectance clamped to {} (the most kept, `max_reflectance`; near 1 light \
             bounces almost for ever and the solve slows and loses accuracy) in {} materials: {}",
            options.max_reflectance,
            clamped.len(),
            clamped.join(", ")
        ));
    }
    Ok((out, masks))
}

/// The metallic part of material `i` (`metallicFactor`, glTF's default 1,
/// times the mean of the blue channel of its `metallicRoughnessTexture` when
/// it decodes), with one warning for a material that has any: a metal's
/// reflection is specular, which radiosity does not simulate, so only the
/// diffuse part `1 - metallic` of the base colour is kept.
fn metallic(
    path: &Path,
    doc: &Document,
    i: usize,
    name: &str,
    images: &mut Images,
    warnings: &mut Vec<String>,
) -> Result<f64> {
    let object = || GltfObject::new(GltfKind::Material, i, doc.root.materials[i].name.as_deref());
    let pointer = format!("/materials/{i}/pbrMetallicRoughness/metallicFactor");
    let factor = number(&doc.raw, &pointer);
    let mut metallic = factor.unwrap_or(1.0);
    let mut from = match factor {
        Some(_) => format!("metallicFactor {metallic}"),
        None => "no metallicFactor: glTF's default is 1, a metal".to_string(),
    };
    let texture = doc.root.materials[i]
        .pbr_metallic_roughness
        .metallic_roughness_texture
        .as_ref();
    if let (Some(info), true) = (texture, metallic > 0.0) {
        match images.for_texture(info.index.value()) {
            Ok(image) => {
                let mean = image.mean().0[2];
                metallic *= mean;
                from.push_str(&format!(" times the metallic texture's mean {mean:.3}"));
            }
            Err(Unusable::Ignored(why)) => warnings.push(format!(
                "material '{name}': metallic-roughness texture ignored ({why}); using \
                 metallicFactor alone"
            )),
            Err(Unusable::Refused(e)) => return Err(e.within(object)),
        }
    }
    if !metallic.is_finite() || metallic < 0.0 {
        return Err(gltf_error_at(
            path,
            object(),
            format!("material '{name}' (index {i}): metallic {metallic} is not from 0 to 1"),
        ));
    }
    if metallic > 0.0 {
        warnings.push(format!(
            "material '{name}': metallic {:.3} ({from}); its reflectance is the base colour \
             times {:.3}, the diffuse part; its specular (metal) reflection is not simulated",
            metallic.min(1.0),
            1.0 - metallic.min(1.0)
        ));
    }
    Ok(metallic)
}

/// Reflectance bands for a message, to three decimals.
fn bands(r: Rgb) -> String {
    let [a, b, c] = r.0;
    format!("{a:.3}, {b:.3}, {c:.3}")
}

/// The material used where a primitive names none.
pub(super) fn default_material() -> Material {
    Material {
        name: "default grey".to_string(),
        reflectance: Rgb::splat(DEFAULT_GREY),
        base_texture: None,
        emission: Rgb::ZERO,
        emissive_texture: None,
        double_sided: false,
    }
}

/// A material error restated as a glTF error, so that it names the file too.
fn in_file(path: &Path, object: GltfObject, e: Error) -> Error {
    match e {
        Error::Material { material, message } => {
            let index = object.index;
            gltf_error_at(
                path,
                object,
                format!("material '{material}' (index {index}): {message}"),
            )
        }
        other => other,
    }
}
