//! Parsing the JSON document and checking it before anything reads from it.
//!
//! The document is parsed twice: into `gltf_json::Root` for its structure, and into a
//! plain `serde_json::Value` from which numbers that matter (material factors, node
//! transforms, camera angles) are read in double precision (the typed structures keep
//! them as `f32`).

use super::{describe, gltf_error};
use crate::error::Result;
use gltf_json::validation::{Error as ValidationError, Validate};
use gltf_json::{Path as JsonPath, Root};
use serde_json::Value;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// A parsed and validated glTF document.
#[derive(Debug)]
pub(super) struct Document {
    /// The typed structure.
    pub root: Root,
    /// The same JSON as an untyped value, for full-precision numbers.
    pub raw: Value,
}

/// How many validation problems are spelled out in one error message.
const PROBLEMS_SHOWN: usize = 5;

/// Parses and validates the JSON text of a glTF asset.
pub(super) fn parse(path: &Path, json: &[u8], warnings: &mut Vec<String>) -> Result<Document> {
    let raw: Value = serde_json::from_slice(json)
        .map_err(|e| gltf_error(path, format!("not valid JSON: {e}")))?;
    if !raw.is_object() {
        return Err(gltf_error(
            path,
            "not a glTF document: the JSON is not an object",
        ));
    }
    let root: Root = Root::from_slice(json)
        .map_err(|e| gltf_error(path, format!("JSON is not a glTF document: {e}")))?;
    let version = root.asset.version.as_str();
    if version.split('.').next() != Some("2") {
        return Err(gltf_error(
            path,
            format!("glTF version '{version}' is not supported (only 2.x)"),
        ));
    }
    super::extensions::check_required(&raw).map_err(|why| gltf_error(path, why))?;
    check_attribute_indices(path, &root)?;
    validate(path, &root, &raw, warnings)?;
    Ok(Document { root, raw })
}

/// The `gltf-json` validator indexes `accessors` with a primitive's `POSITION`
/// directly, so an index out of range would panic inside it: check those first.
fn check_attribute_indices(path: &Path, root: &Root) -> Result<()> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &prim.attributes {
                if accessor.value() >= root.accessors.len() {
                    return Err(gltf_error(
                        path,
                        format!(
                            "{} primitive {p}: attribute {} refers to accessor {}, but the file has {} accessors",
                            describe("mesh", m, mesh.name.as_deref()),
                            semantic.to_string(),
                            accessor.value(),
                            root.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

fn validate(path: &Path, root: &Root, raw: &Value, warnings: &mut Vec<String>) -> Result<()> {
    let mut problems: Vec<(String, ValidationError)> = Vec::new();
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        root.validate(
            root,
            JsonPath::new,
            &mut |where_: &dyn Fn() -> JsonPath, e| {
                problems.push((where_().to_string(), e));
            },
        );
    }));
    if outcome.is_err() {
        return Err(gltf_error(
            path,
            "the glTF validator failed on this file (it is malformed in a way the gltf-json crate does not report)",
        ));
    }
    let mut fatal = Vec::new();
    for (where_, e) in problems {
        // Required extensions were checked against the importer's own table
        // (`extensions::check`); gltf-json knows only a few of them.
        if e == ValidationError::Unsupported && where_.starts_with("extensionsRequired[") {
            continue;
        }
        // A texture whose image comes through an extension (KTX2, WebP) may
        // leave the core `source` out.
        if e == ValidationError::Missing && extension_source(raw, &where_) {
            continue;
        }
        // POSITION min/max are required by the specification but this importer does
        // not need them, so their absence is only reported. gltf-json spells the
        // path `attributes["POSITION"].min`.
        let bounds = [
            "POSITION.min",
            "POSITION.max",
            "\"POSITION\"].min",
            "\"POSITION\"].max",
        ]
        .iter()
        .any(|end| where_.ends_with(end));
        // glTF 2.0 allows an accessor without a buffer view (it reads as zeros);
        // gltf-json reports it as missing.
        let zeros = where_.starts_with("accessors[") && where_.ends_with("].bufferView");
        if zeros && e == ValidationError::Missing {
            continue;
        }
        if bounds && e == ValidationError::Missing {
            warnings.push(format!(
                "{where_} is missing (required by glTF, not needed here)"
            ));
        } else {
            fatal.push(format!("{where_}: {}", problem_words(e)));
        }
    }
    if fatal.is_empty() {
        return Ok(());
    }
    let more = fatal.len().saturating_sub(PROBLEMS_SHOWN);
    let mut message = format!(
        "invalid glTF: {}",
        fatal[..fatal.len().min(PROBLEMS_SHOWN)].join("; ")
    );
    if more > 0 {
        message.push_str(&format!(" (and {more} more)"));
    }
    Err(gltf_error(path, message))
}

/// True when `where_` is `textures[i].source` and texture `i` names its
/// image through an extension.
fn extension_source(raw: &Value, where_: &str) -> bool {
    let Some(rest) = where_.strip_prefix("textures[") else {
        return false;
    };
    let Some(index) = rest
        .strip_suffix("].source")
        .and_then(|i| i.parse::<usize>().ok())
    else {
        return false;
    };
    raw.pointer(&format!("/textures/{index}/extensions"))
        .and_then(Value::as_object)
        .is_some_and(|e| {
            e.values()
                .any(|v| v.get("source").is_some_and(Value::is_u64))
        })
}

fn problem_words(e: ValidationError) -> &'static str {
    match e {
        ValidationError::IndexOutOfBounds => "index out of range",
        ValidationError::Invalid => "invalid value",
        ValidationError::Missing => "required value missing",
        ValidationError::Oversize => "size beyond what this machine can address",
        ValidationError::Unsupported => "extension required by the file is not supported",
    }
}
