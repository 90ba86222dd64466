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
    check_attribute_indices(path, &root)?;
    validate(path, &root, warnings)?;
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

fn validate(path: &Path, root: &Root, warnings: &mut Vec<String>) -> Result<()> {
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
        if e == ValidationError::Unsupported {
            match required_extension(root, &where_) {
                Some(name) if HANDLED_EXTENSIONS.contains(&name) => continue,
                Some("KHR_draco_mesh_compression") => {
                    fatal.push(format!(
                        "{where_} = \"KHR_draco_mesh_compression\": Draco-compressed meshes \
                         cannot be read here; decompress the file first, for example with \
                         glTF-Transform: `npx @gltf-transform/cli copy in.glb out.glb` \
                         writes it without Draco"
                    ));
                    continue;
                }
                _ => {}
            }
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

/// Extensions a file may require that the importer handles (gltf-json does
/// not know them and reports them as unsupported).
const HANDLED_EXTENSIONS: [&str; 3] = [
    "KHR_mesh_quantization",
    super::meshopt::EXTENSION,
    super::lights::EXTENSION,
];

/// The extension named at `extensionsRequired[i]`, when `where_` is that
/// path (gltf-json spells it `extensionsRequired[i] = "NAME"`).
fn required_extension<'a>(root: &'a Root, where_: &str) -> Option<&'a str> {
    let rest = where_.strip_prefix("extensionsRequired[")?;
    let index: usize = rest[..rest.find(']')?].parse().ok()?;
    root.extensions_required.get(index).map(String::as_str)
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
