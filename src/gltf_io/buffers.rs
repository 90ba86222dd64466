//! Loading the bytes of every buffer: the GLB binary chunk, data URIs or external
//! files, each checked against the `byteLength` the document declares.

use super::container::read_limited;
use super::document::Document;
use super::limits::ImportLimits;
use super::uri::{resolve, Resolved};
use super::{describe, gltf_error};
use crate::error::{Error, LimitKind, Result};
use std::path::Path;

/// Padding a buffer may carry beyond its declared length (GLB chunks are padded to
/// four bytes).
const MAX_PADDING: u64 = 3;

/// The bytes of every buffer of `doc`, in order, each exactly `byteLength` long.
pub(super) fn load_buffers(
    path: &Path,
    doc: &Document,
    mut glb_bin: Option<Vec<u8>>,
    limits: &ImportLimits,
) -> Result<Vec<Vec<u8>>> {
    let folder = path.parent().unwrap_or(Path::new("."));
    let mut out = Vec::with_capacity(doc.root.buffers.len());
    for (i, buffer) in doc.root.buffers.iter().enumerate() {
        let what = describe("buffer", i, buffer.name.as_deref());
        let declared = buffer.byte_length.0;
        if declared > limits.max_file_bytes {
            return Err(Error::limit(
                LimitKind::FileBytes,
                format!(
                    "{}: {what} declares {declared} bytes, more than the limit of {}",
                    path.display(),
                    limits.max_file_bytes
                ),
            ));
        }
        let mut bytes = match &buffer.uri {
            None => match (i, glb_bin.take()) {
                (0, Some(bin)) => bin,
                // A placeholder that compressed views decode into.
                (_, bin) if super::meshopt::is_fallback(doc, i) => {
                    glb_bin = bin;
                    vec![0; declared as usize]
                }
                _ => {
                    return Err(gltf_error(
                        path,
                        format!("{what} has no URI and is not the binary chunk of a .glb file"),
                    ))
                }
            },
            Some(uri) => match resolve(uri, folder, limits) {
                Ok(Resolved::Data(bytes)) => bytes,
                Ok(Resolved::File(file)) => read_limited(&file, limits).map_err(|e| {
                    gltf_error(
                        path,
                        format!("{what}: cannot read '{uri}': {}", io_reason(&e)),
                    )
                })?,
                Err(why) => return Err(gltf_error(path, format!("{what}: {why}"))),
            },
        };
        let actual = bytes.len() as u64;
        if actual < declared || actual > declared + MAX_PADDING {
            return Err(gltf_error(
                path,
                format!("{what} holds {actual} bytes, but its byteLength says {declared}"),
            ));
        }
        bytes.truncate(declared as usize);
        out.push(bytes);
    }
    Ok(out)
}

/// The operating system's reason without repeating the path.
fn io_reason(e: &Error) -> String {
    match e {
        Error::Io { error, .. } => error.to_string(),
        other => other.to_string(),
    }
}
