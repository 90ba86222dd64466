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
use super::precise::{number, numbers};
use super::{describe, gltf_error};
use crate::error::{Error, Result};
use crate::math::Rgb;
use crate::scene::{Light, LightKind};
use glam::DVec3;
use serde_json::Value;
use std::f64::consts::FRAC_PI_4;
use std::path::Path;

/// The extension's name.
pub(super) const EXTENSION: &str = "KHR_lights_punctual";

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
            return Err(gltf_error(
                path,
                format!(
                    "{node}: {EXTENSION} light {index} does not exist (the file defines {})",
                    defined.len()
                ),
            ));
        };
        used[i] = true;
        let base = format!("/extensions/{EXTENSION}/lights/{i}");
        let light_name = defined[i].get("name").and_then(Value::as_str);
        let what = format!("{} of {node}", describe("light", i, light_name));
        let kind = match defined[i].get("type").and_then(Value::as_str) {
            Some("point") => LightKind::Point,
            Some("directional") => LightKind::Directional,
            Some("spot") => LightKind::Spot {
                inner_cone: number(&doc.raw, &format!("{base}/spot/innerConeAngle")).unwrap_or(0.0),
                outer_cone: number(&doc.raw, &format!("{base}/spot/outerConeAngle"))
                    .unwrap_or(FRAC_PI_4),
            },
            other => {
                unknown.push(format!(
                    "{what}: type {}",
                    other.map_or_else(|| "missing".to_string(), |t| format!("'{t}'"))
                ));
                continue;
            }
        };
        let colour = numbers::<3>(&doc.raw, &format!("{base}/color")).unwrap_or([1.0; 3]);
        let light = Light {
            name: what.clone(),
            kind,
            colour: Rgb(colour),
            intensity: number(&doc.raw, &format!("{base}/intensity")).unwrap_or(1.0),
            range: number(&doc.raw, &format!("{base}/range")),
            position: p.world.transform_point3(DVec3::ZERO),
            direction: p.world.transform_vector3(DVec3::NEG_Z).normalize_or_zero(),
        };
        light.validate().map_err(|e| match e {
            Error::Light { message, .. } => gltf_error(path, format!("{what}: {message}")),
            other => other,
        })?;
        out.push(light);
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
