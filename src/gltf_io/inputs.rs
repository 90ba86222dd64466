//! The files a glTF asset is made of: the file itself and the buffers and
//! images its URIs name, so that a command can refuse to write over any of
//! them.

use super::container::{read_limited, split};
use super::gltf_error;
use super::limits::ImportLimits;
use super::uri::{resolve, Resolved};
use crate::error::Result;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// `path` and every file its buffers and images name by a relative URI
/// (`data:` URIs and URIs the importer would refuse are left out: they name
/// no file it reads), in the order the document lists them.
///
/// # Errors
///
/// As for reading the file: [`crate::Error::Io`], [`crate::Error::Limit`],
/// and [`crate::Error::Gltf`] when it is not a glTF file or its JSON does not
/// parse.
pub fn input_files(path: &Path, limits: &ImportLimits) -> Result<Vec<PathBuf>> {
    let container = split(path, read_limited(path, limits)?)?;
    let doc: Value = serde_json::from_slice(&container.json)
        .map_err(|e| gltf_error(path, format!("the JSON does not parse: {e}")))?;
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut files = vec![path.to_path_buf()];
    for list in ["buffers", "images"] {
        let entries = doc.get(list).and_then(Value::as_array);
        for entry in entries.into_iter().flatten() {
            let Some(uri) = entry.get("uri").and_then(Value::as_str) else {
                continue;
            };
            if let Ok(Resolved::File(file)) = resolve(uri, folder, limits) {
                files.push(file);
            }
        }
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffers_and_images_named_by_relative_uris_are_inputs() {
        let dir = std::env::temp_dir().join(format!("radiosity_inputs_{}", std::process::id()));
        std::fs::create_dir_all(dir.join("tex")).unwrap();
        let scene = dir.join("s.gltf");
        let doc = serde_json::json!({
            "asset": {"version": "2.0"},
            "buffers": [{"uri": "s.bin", "byteLength": 4},
                        {"uri": "data:application/octet-stream;base64,AAAA", "byteLength": 3}],
            "images": [{"uri": "tex/wood%20grain.png"}, {"uri": "../outside.png"}]
        });
        std::fs::write(&scene, doc.to_string()).unwrap();
        let files = input_files(&scene, &ImportLimits::default()).unwrap();
        assert_eq!(
            files,
            [
                scene.clone(),
                dir.join("s.bin"),
                dir.join("tex").join("wood grain.png")
            ]
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
