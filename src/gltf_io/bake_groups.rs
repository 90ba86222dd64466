//! Light groups in a bake: each group's values as a vertex attribute
//! `_GROUP_k`, scaled by a power of two per group, and the description in
//! `asset.extras.radiosity` that says how to read them, written and read
//! back.

use super::bake::BakeGroup;
use super::bake_colour::scale_for;
use super::document::Document;
use super::gltf_error;
use crate::error::Result;
use crate::math::Rgb;
use crate::mesh::ShadingMesh;
use crate::render::ToneMap;
use gltf_json::Value;
use std::path::Path;

/// The attribute name of group `k`, without its leading underscore (which
/// glTF's application-specific attributes start with).
fn attribute(k: usize) -> String {
    format!("GROUP_{k}")
}

/// The groups' names and scales, and the bytes their attributes take.
pub(super) struct GroupWriter {
    names: Vec<String>,
    scales: Vec<f64>,
    bytes: usize,
}

impl GroupWriter {
    /// The writer for `groups`, each group's scale the smallest power of two
    /// at least its largest value over every primitive of `baked` (each a
    /// list of values per group).
    pub(super) fn new<'a>(
        groups: &[BakeGroup<'_>],
        baked: impl Iterator<Item = &'a Vec<Vec<Rgb>>>,
    ) -> Self {
        let mut largest = vec![0.0f64; groups.len()];
        for primitive in baked {
            for (max, values) in largest.iter_mut().zip(primitive) {
                *max = values.iter().map(|v| v.max_band()).fold(*max, f64::max);
            }
        }
        GroupWriter {
            names: groups.iter().map(|g| g.name.to_string()).collect(),
            scales: largest.into_iter().map(scale_for).collect(),
            bytes: 0,
        }
    }

    /// One primitive's group attributes: (name without the underscore,
    /// values over the group's scale in single precision).
    pub(super) fn attributes(&mut self, values: &[Vec<Rgb>]) -> Vec<(String, Vec<[f32; 3]>)> {
        values
            .iter()
            .zip(&self.scales)
            .enumerate()
            .map(|(k, (values, scale))| {
                self.bytes += 12 * values.len();
                let scaled = values.iter().map(|v| (*v / *scale).to_f32()).collect();
                (attribute(k), scaled)
            })
            .collect()
    }

    /// Bytes of the attributes written so far.
    pub(super) fn bytes(&self) -> usize {
        self.bytes
    }
}

/// Checks that every group's display mesh has the whole solution's vertices,
/// finite values and, where the whole has texels, texels of its own.
pub(super) fn check_groups(
    shading: &ShadingMesh,
    groups: &[BakeGroup<'_>],
) -> std::result::Result<(), String> {
    let n = shading.positions.len();
    for g in groups {
        let what = format!("the light group '{}'", g.name);
        if g.shading.radiosity.len() != n || g.shading.triangles.len() != shading.triangles.len() {
            return Err(format!(
                "{what} has {} vertices and {} triangles, the solution {n} and {}",
                g.shading.radiosity.len(),
                g.shading.triangles.len(),
                shading.triangles.len()
            ));
        }
        if let Some(v) = g.shading.radiosity.iter().position(|b| !b.is_finite()) {
            return Err(format!("{what} has a non-finite radiosity at vertex {v}"));
        }
        match (&shading.texels, &g.shading.texels) {
            (None, _) => {}
            (Some(_), Some(t)) if t.irradiance.len() == n => {
                if let Some(v) = t.irradiance.iter().position(|h| !h.is_finite()) {
                    return Err(format!("{what} has a non-finite irradiance at vertex {v}"));
                }
            }
            (Some(_), _) => {
                return Err(format!(
                    "{what} has no irradiance under the textures the solution shows"
                ))
            }
        }
    }
    Ok(())
}

/// `asset.extras.radiosity`: how `COLOR_0` was made, and the groups.
pub(super) fn description(writer: &GroupWriter, exposure: f64, tone: ToneMap) -> Value {
    let groups: Vec<Value> = writer
        .names
        .iter()
        .zip(&writer.scales)
        .enumerate()
        .map(|(k, (name, scale))| {
            serde_json::json!({
                "name": name,
                "attribute": format!("_{}", attribute(k)),
                "scale": scale,
            })
        })
        .collect();
    serde_json::json!({
        "version": 2,
        "exposure": exposure,
        "toneMap": tone.name(),
        "groups": groups,
        "formula": "radiosity (lm/m^2) = sum over groups of scale * _GROUP_k, times \
                    baseColorFactor * baseColorTexture on textured materials (where the \
                    groups hold the irradiance); radiance = radiosity / pi; COLOR_0 = \
                    toneMap(2^exposure * radiance), per vertex (on textured materials, of the \
                    mean texel's radiance, over the material's mean reflectance)",
    })
}

/// A light group of a baked file, as `asset.extras.radiosity.groups` lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct BakedGroupInfo {
    /// Its name.
    pub name: String,
    /// The vertex attribute that holds it (`_GROUP_k`).
    pub attribute: String,
    /// Its values are the attribute's times this.
    pub scale: f64,
}

/// The exposure and light groups of `asset.extras.radiosity` (version 2;
/// `None` and none for an older bake or another file).
pub(super) fn read_description(
    path: &Path,
    doc: &Document,
) -> Result<(Option<f64>, Vec<BakedGroupInfo>)> {
    let Some(d) = doc.raw.pointer("/asset/extras/radiosity") else {
        return Ok((None, Vec::new()));
    };
    if d.get("version").and_then(serde_json::Value::as_u64) != Some(2) {
        return Ok((None, Vec::new()));
    }
    let fail = |m: String| gltf_error(path, format!("asset.extras.radiosity: {m}"));
    let exposure = d
        .get("exposure")
        .and_then(serde_json::Value::as_f64)
        .filter(|e| e.is_finite())
        .ok_or_else(|| fail("no finite exposure".to_string()))?;
    let listed = d
        .get("groups")
        .and_then(serde_json::Value::as_array)
        .ok_or_else(|| fail("no list of groups".to_string()))?;
    let mut groups = Vec::with_capacity(listed.len());
    for (k, g) in listed.iter().enumerate() {
        let text = |key: &str| {
            g.get(key)
                .and_then(serde_json::Value::as_str)
                .map(str::to_string)
        };
        let (Some(name), Some(attribute)) = (text("name"), text("attribute")) else {
            return Err(fail(format!("group {k} has no name or attribute")));
        };
        let scale = g
            .get("scale")
            .and_then(serde_json::Value::as_f64)
            .filter(|s| s.is_finite() && *s > 0.0)
            .ok_or_else(|| {
                fail(format!(
                    "the scale of group '{name}' is not a positive number"
                ))
            })?;
        if !attribute.starts_with('_') {
            return Err(fail(format!(
                "the attribute '{attribute}' of group '{name}' does not start with '_'"
            )));
        }
        groups.push(BakedGroupInfo {
            name,
            attribute,
            scale,
        });
    }
    if groups.is_empty() {
        return Err(fail("no light group".to_string()));
    }
    Ok((Some(exposure), groups))
}
