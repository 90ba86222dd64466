//! `KHR_lights_punctual`: the file's lights, placed by the nodes that refer
//! to them.
//!
//! The extension defines lights once, at the top level, and a node places
//! one with its world transform: the light sits at the node's origin, and
//! spots and suns shine down the node's -Z axis (scale does not change a
//! light's intensity). A light type the extension does not define is left
//! out with a warning naming it; lights no node places are counted in a
//! warning too, so that nothing is dropped silently.

use super::document::Document;
use super::nodes::Placed;
use super::{describe, gltf_error, gltf_error_at};
use crate::error::{Error, GltfKind, GltfObject, Result};
use crate::math::Rgb;
use crate::scene::{merge_coincident_lights, Light, LightKind};
use glam::DVec3;
use serde_json::Value;
use std::f64::consts::FRAC_PI_4;
use std::path::Path;

/// The extension's name.
pub(super) const EXTENSION: &str = "KHR_lights_punctual";

/// More distinct lights than this are named in a warning at load, before
/// the work: each costs a shadow ray per sample point.
const MANY_LIGHTS: usize = 256;

/// Every light placed by a node of `placed`, in the walk's order. Values out
/// of range are an error naming the file, the light and its node; unknown
/// light types and lights no node places are warnings.
pub(super) fn placed_lights(
    path: &Path,
    doc: &Document,
    placed: &[Placed],
    warnings: &mut Vec<String>,
) -> Result<Vec<Light>> {
    let defined: &[Value] = doc
        .raw
        .pointer(&format!("/extensions/{EXTENSION}/lights"))
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice);
    let mut used = vec![false; defined.len()];
    let mut unknown: Vec<String> = Vec::new();
    let mut out = Vec::new();
    for p in placed {
        let pointer = format!("/nodes/{}/extensions/{EXTENSION}/light", p.node);
        let Some(index) = doc.raw.pointer(&pointer) else {
            continue;
        };
        let node_name = doc.root.nodes[p.node].name.as_deref();
        let node = describe("node", p.node, node_name);
        let Some(i) = index
            .as_u64()
            .map(|i| i as usize)
            .filter(|i| *i < defined.len())
        else {
            return Err(gltf_error_at(
                path,
                GltfObject::new(GltfKind::Node, p.node, node_name),
                format!(
                    "{node}: {EXTENSION} light {index} does not exist (the file defines {})",
                    defined.len()
                ),
            ));
        };
        used[i] = true;
        let light_name = defined[i].get("name").and_then(Value::as_str);
        let what = format!("{} of {node}", describe("light", i, light_name));
        let object = || GltfObject::new(GltfKind::Light, i, light_name);
        let field = |name: &'static str| Field {
            path,
            object: object(),
            what: &what,
            value: defined[i].pointer(name),
            name,
        };
        let kind = match defined[i].get("type") {
            Some(Value::String(t)) if t == "point" => LightKind::Point,
            Some(Value::String(t)) if t == "directional" => LightKind::Directional,
            Some(Value::String(t)) if t == "spot" => LightKind::Spot {
                inner_cone: field("/spot/innerConeAngle").number()?.unwrap_or(0.0),
                outer_cone: field("/spot/outerConeAngle").number()?.unwrap_or(FRAC_PI_4),
            },
            Some(Value::String(t)) => {
                unknown.push(format!("{what}: type '{t}'"));
                continue;
            }
            Some(other) => {
                return Err(gltf_error_at(
                    path,
                    object(),
                    format!("{what}: \"type\" must be a string, got {other}"),
                ))
            }
            None => {
                unknown.push(format!("{what}: type missing"));
                continue;
            }
        };
        let colour = field("/color").numbers::<3>()?.unwrap_or([1.0; 3]);
        let light = Light {
            name: what.clone(),
            kind,
            colour: Rgb(colour),
            intensity: field("/intensity").number()?.unwrap_or(1.0),
            range: field("/range").number()?,
            position: p.world.transform_point3(DVec3::ZERO),
            direction: p.world.transform_vector3(DVec3::NEG_Z).normalize_or_zero(),
        };
        light.validate().map_err(|e| match e {
            Error::Light { message, .. } => {
                gltf_error_at(path, object(), format!("{what}: {message}"))
            }
            other => other,
        })?;
        out.push(light);
    }
    let (out, merged) = merge_coincident_lights(out);
    if merged > 0 {
        for light in &out {
            // Summed, a group can pass what each light kept to.
            light
                .validate()
                .map_err(|e| gltf_error(path, e.to_string()))?;
        }
        warnings.push(format!(
            "{merged} {EXTENSION} lights lie exactly where another of the same kind, \
             direction, range and cones does, and were merged into it: their power adds, \
             so the light is the same and its cost {:.0} times less",
            (merged + out.len()) as f64 / out.len() as f64
        ));
    }
    if out.len() > MANY_LIGHTS {
        warnings.push(format!(
            "{} distinct {EXTENSION} lights: the direct light casts a shadow ray from every \
             sample point of every element to each of them, so it costs {} times what one \
             light does (an emissive surface of the same total power is solved by the \
             hemi-cubes instead)",
            out.len(),
            out.len()
        ));
    }
    if !unknown.is_empty() {
        warnings.push(format!(
            "{} {EXTENSION} lights of a type this tool does not know left out (only point, \
             spot and directional are simulated): {}",
            unknown.len(),
            unknown.join("; ")
        ));
    }
    let unplaced: Vec<String> = used
        .iter()
        .enumerate()
        .filter(|(_, u)| !**u)
        .map(|(i, _)| describe("light", i, defined[i].get("name").and_then(Value::as_str)))
        .collect();
    if !unplaced.is_empty() {
        warnings.push(format!(
            "{} {EXTENSION} lights are placed by no node of the scene and give no light: {}",
            unplaced.len(),
            unplaced.join(", ")
        ));
    }
    Ok(out)
}

/// One field of a light definition, read strictly: absent is the
/// extension's default, but a value of the wrong type (`"intensity":
/// "1000"`, `"color": "red"`) is an error naming the light and the field,
/// never quietly the default.
struct Field<'a> {
    path: &'a Path,
    /// The light it belongs to.
    object: GltfObject,
    what: &'a str,
    value: Option<&'a Value>,
    name: &'a str,
}

impl Field<'_> {
    /// The field's name as the file spells it (`spot.innerConeAngle`).
    fn shown(&self) -> String {
        self.name.trim_start_matches('/').replace('/', ".")
    }

    fn wrong(&self, expected: &str) -> Error {
        let got = self.value.map_or_else(String::new, Value::to_string);
        gltf_error_at(
            self.path,
            self.object.clone(),
            format!(
                "{}: \"{}\" must be {expected}, got {got}",
                self.what,
                self.shown()
            ),
        )
    }

    /// A number, or `None` when the field is absent.
    fn number(&self) -> Result<Option<f64>> {
        match self.value {
            None => Ok(None),
            Some(v) => v.as_f64().map(Some).ok_or_else(|| self.wrong("a number")),
        }
    }

    /// An array of exactly `N` numbers, or `None` when the field is absent.
    fn numbers<const N: usize>(&self) -> Result<Option<[f64; N]>> {
        let Some(v) = self.value else {
            return Ok(None);
        };
        let expected = format!("an array of {N} numbers");
        let items = v.as_array().filter(|a| a.len() == N);
        let items = items.ok_or_else(|| self.wrong(&expected))?;
        let mut out = [0.0; N];
        for (slot, item) in out.iter_mut().zip(items) {
            *slot = item.as_f64().ok_or_else(|| self.wrong(&expected))?;
        }
        Ok(Some(out))
    }
}
