//! What the importer does with each glTF extension a file uses or requires.
//!
//! A diffuse radiosity solver can honour some extensions in full (geometry
//! compression, texture containers, texture transforms, emission strength,
//! lights) and only the diffuse part of others (specular, transmission,
//! sheen, clearcoat: the rest of the light transport is not simulated). The
//! table [`support`] says which; [`check_required`] refuses a file only when
//! it requires an extension whose absence would make the result wrong (an
//! unknown one, or instancing), and [`warn_used`] warns once per extension
//! otherwise, saying what is kept (for scenes; a baked file read back uses
//! `KHR_materials_unlit` on purpose).

use serde_json::Value;
use std::collections::BTreeSet;

/// How the importer treats one extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Support {
    /// Read and applied in full: no warning.
    Honoured,
    /// Only part of what it describes is kept (the words say what); a
    /// warning, once per file, whether used or required.
    Partial(&'static str),
    /// Not applied, and a file that requires it would come out wrong: used,
    /// a warning; required, the file is refused (the words say why).
    Refused(&'static str),
}

/// Draco geometry, when the crate is built with its decoder.
#[cfg(feature = "draco")]
const DRACO: Support = Support::Honoured;
#[cfg(not(feature = "draco"))]
const DRACO: Support = Support::Refused(
    "Draco-compressed meshes need the `draco` feature of this crate, which this build left out",
);

/// KTX2 / Basis Universal textures, when the crate is built with the transcoder.
#[cfg(feature = "ktx2")]
const BASISU: Support = Support::Honoured;
#[cfg(not(feature = "ktx2"))]
const BASISU: Support = Support::Partial(
    "KTX2 textures need the `ktx2` feature of this crate, which this build left out; \
     their materials take their factors alone",
);

/// The importer's treatment of extension `name`, or `None` for one it does
/// not know.
pub(super) fn support(name: &str) -> Option<Support> {
    use Support::{Honoured, Partial, Refused};
    Some(match name {
        "KHR_texture_transform"
        | "KHR_mesh_quantization"
        | "EXT_meshopt_compression"
        | "KHR_materials_emissive_strength"
        | "KHR_lights_punctual"
        | "EXT_texture_webp" => Honoured,
        "KHR_draco_mesh_compression" => DRACO,
        "KHR_texture_basisu" => BASISU,
        "KHR_materials_specular" => Partial("the specular layer is not simulated; the diffuse base colour is kept"),
        "KHR_materials_transmission" => Partial(
            "light through the surface is not simulated; the surface is opaque with its diffuse base colour",
        ),
        "KHR_materials_diffuse_transmission" => Partial(
            "light through the surface is not simulated; the surface is opaque with its diffuse base colour",
        ),
        "KHR_materials_volume" => Partial("the volume is not simulated; the surface is opaque with its diffuse base colour"),
        "KHR_materials_ior" => Partial("the index of refraction only shapes specular light, which is not simulated"),
        "KHR_materials_sheen" => Partial("the sheen layer is not simulated; the diffuse base colour is kept"),
        "KHR_materials_clearcoat" => Partial("the clear coat is not simulated; the diffuse base colour under it is kept"),
        "KHR_materials_iridescence" => Partial("iridescence is not simulated; the diffuse base colour is kept"),
        "KHR_materials_anisotropy" => Partial("anisotropic specular light is not simulated; the diffuse base colour is kept"),
        "KHR_materials_dispersion" => Partial("dispersion is not simulated; the diffuse base colour is kept"),
        "KHR_materials_unlit" => Partial("unlit materials are lit like any other, with their base colour as reflectance"),
        "KHR_materials_pbrSpecularGlossiness" => Partial(
            "the specular-glossiness model is not read; the metallic-roughness base colour (white when absent) is used",
        ),
        "KHR_materials_variants" => Partial("each primitive keeps its default material; the variants are not read"),
        "KHR_animation_pointer" => Partial("animations are not played; the scene is taken in its rest pose"),
        "KHR_xmp_json_ld" | "KHR_xmp" => Partial("the metadata is not read"),
        "MSFT_lod" => Partial("the most detailed level of each node is used"),
        "MSFT_texture_dds" => Partial("DDS images are not read; the texture's fallback image (if any) is used"),
        "EXT_lights_image_based" => Partial("image-based lights are not simulated"),
        "EXT_mesh_gpu_instancing" => Refused(
            "instanced meshes are not placed (only each node's own transform is used), so instances would be missing",
        ),
        _ => return None,
    })
}

/// The extensions the document `raw` lists in `extensionsRequired`, and
/// those it lists in `extensionsUsed` or uses in its objects without
/// listing them (required ones included).
fn listed(raw: &Value) -> (BTreeSet<String>, BTreeSet<String>) {
    let names = |key: &str| -> BTreeSet<String> {
        raw.get(key)
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(Value::as_str)
                    .map(str::to_string)
                    .collect()
            })
            .unwrap_or_default()
    };
    let required = names("extensionsRequired");
    let mut used = names("extensionsUsed");
    collect_extension_keys(raw, &mut used);
    used.extend(required.iter().cloned());
    (required, used)
}

/// Every key of every `extensions` object inside `value` (application data
/// under `extras` is not looked into).
fn collect_extension_keys(value: &Value, out: &mut BTreeSet<String>) {
    match value {
        Value::Object(map) => {
            for (key, v) in map.iter().filter(|(k, _)| *k != "extras") {
                if key == "extensions" {
                    if let Value::Object(ext) = v {
                        out.extend(ext.keys().cloned());
                    }
                }
                collect_extension_keys(v, out);
            }
        }
        Value::Array(items) => items.iter().for_each(|v| collect_extension_keys(v, out)),
        _ => {}
    }
}

/// `Err` with the reason when the document `raw` requires an extension the
/// importer cannot do without (an unknown one, or [`Support::Refused`]).
pub(super) fn check_required(raw: &Value) -> Result<(), String> {
    let (required, _) = listed(raw);
    let mut refused = Vec::new();
    for name in &required {
        match support(name) {
            None => refused.push(format!(
                "it requires the extension {name}, which this importer does not know"
            )),
            Some(Support::Refused(why)) => {
                refused.push(format!("it requires the extension {name}: {why}"));
            }
            Some(_) => {}
        }
    }
    if refused.is_empty() {
        Ok(())
    } else {
        Err(refused.join("; "))
    }
}

/// One warning per extension the document `raw` uses or requires that is
/// not honoured in full, saying what is kept.
pub(super) fn warn_used(raw: &Value, warnings: &mut Vec<String>) {
    let (_, used) = listed(raw);
    for name in &used {
        match support(name) {
            Some(Support::Honoured) => {}
            Some(Support::Partial(kept) | Support::Refused(kept)) => {
                warnings.push(format!("extension {name}: {kept}"));
            }
            None => warnings.push(format!("extension {name} is not known here and is ignored")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extension_keys_are_found_at_any_depth() {
        let v: Value = serde_json::json!({
            "materials": [{"extensions": {"KHR_materials_sheen": {}}}],
            "textures": [{"extensions": {"KHR_texture_basisu": {"source": 0}}}],
            "extensions": {"KHR_lights_punctual": {"lights": []}}
        });
        let mut out = BTreeSet::new();
        collect_extension_keys(&v, &mut out);
        let names: Vec<&str> = out.iter().map(String::as_str).collect();
        assert_eq!(
            names,
            [
                "KHR_lights_punctual",
                "KHR_materials_sheen",
                "KHR_texture_basisu"
            ]
        );
    }
}
