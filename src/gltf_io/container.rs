//! Reading a scene file and telling `.glb` from `.gltf`: the binary container's
//! header and chunks are parsed here, with every length checked against the bytes
//! actually present (the `gltf` crate's own parser trusts the header's length).

use super::gltf_error;
use super::limits::ImportLimits;
use crate::error::{Error, LimitKind, Result};
use crate::input::open_regular;
use std::io::Read;
use std::path::Path;

/// The JSON text of a glTF asset and, for `.glb`, its binary chunk.
#[derive(Debug)]
pub(super) struct Container {
    /// The JSON document.
    pub json: Vec<u8>,
    /// The GLB `BIN` chunk, which backs the first buffer when that has no URI.
    pub bin: Option<Vec<u8>>,
}

const GLB_MAGIC: &[u8; 4] = b"glTF";
const GLB_HEADER_LEN: usize = 12;
const CHUNK_HEADER_LEN: usize = 8;
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// Reads a whole file after checking its size against the limit. `Error::Io`
/// when it cannot be opened or read, or is not a regular file (a FIFO would
/// block the read for ever; see [`open_regular`]).
pub(super) fn read_limited(path: &Path, limits: &ImportLimits) -> Result<Vec<u8>> {
    let file = open_regular(path)?;
    let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
    if len > limits.max_file_bytes {
        return Err(Error::limit(
            LimitKind::FileBytes,
            format!(
                "{}: the file has {len} bytes, more than the limit of {}",
                path.display(),
                limits.max_file_bytes
            ),
        ));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    // `take` guards against a file that grows while it is read.
    file.take(limits.max_file_bytes)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    Ok(bytes)
}

/// Splits a file's bytes into JSON and binary chunk. Anything that is neither a
/// GLB container nor a JSON object is rejected with a message that says so.
pub(super) fn split(path: &Path, bytes: Vec<u8>) -> Result<Container> {
    if bytes.starts_with(GLB_MAGIC) {
        return split_glb(path, &bytes);
    }
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes);
    match text.iter().find(|b| !b.is_ascii_whitespace()) {
        Some(b'{') => Ok(Container {
            json: text.to_vec(),
            bin: None,
        }),
        _ => Err(gltf_error(path, not_gltf_message(&bytes))),
    }
}

fn not_gltf_message(bytes: &[u8]) -> String {
    let kind = if bytes.is_empty() {
        "the file is empty"
    } else if bytes.starts_with(b"\x89PNG") {
        "this is a PNG image"
    } else if bytes.starts_with(b"\xFF\xD8\xFF") {
        "this is a JPEG image"
    } else {
        "it starts neither with the GLB magic 'glTF' nor with a JSON object"
    };
    format!("not a glTF file: {kind}")
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

fn split_glb(path: &Path, bytes: &[u8]) -> Result<Container> {
    let err = |m: String| gltf_error(path, format!("GLB container: {m}"));
    if bytes.len() < GLB_HEADER_LEN {
        return Err(err(format!(
            "truncated: the header needs {GLB_HEADER_LEN} bytes, the file has {}",
            bytes.len()
        )));
    }
    let version = read_u32(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(err(format!(
            "version {version} is not supported (only glTF 2)"
        )));
    }
    let declared = read_u32(bytes, 8).unwrap_or(0) as usize;
    if declared < GLB_HEADER_LEN {
        return Err(err(format!(
            "the header's total length {declared} is shorter than the header"
        )));
    }
    if declared > bytes.len() {
        return Err(err(format!(
            "truncated: the header says {declared} bytes, the file has {}",
            bytes.len()
        )));
    }
    let body = &bytes[..declared];
    let mut at = GLB_HEADER_LEN;
    let mut json: Option<Vec<u8>> = None;
    let mut bin: Option<Vec<u8>> = None;
    while at < body.len() {
        let (Some(len), Some(kind)) = (read_u32(body, at), read_u32(body, at + 4)) else {
            return Err(err(format!(
                "truncated: a chunk header at byte {at} runs past the end ({declared} bytes)"
            )));
        };
        let start = at + CHUNK_HEADER_LEN;
        let end = start
            .checked_add(len as usize)
            .filter(|&e| e <= body.len())
            .ok_or_else(|| {
                err(format!(
                    "truncated: a chunk of {len} bytes at byte {start} runs past the end ({declared} bytes)"
                ))
            })?;
        let data = &body[start..end];
        match kind {
            CHUNK_JSON if json.is_none() && at == GLB_HEADER_LEN => json = Some(data.to_vec()),
            CHUNK_BIN if json.is_some() && bin.is_none() => bin = Some(data.to_vec()),
            CHUNK_JSON | CHUNK_BIN => {
                return Err(err(format!(
                    "unexpected chunk at byte {at} (the JSON chunk must come first, then at most one BIN chunk)"
                )))
            }
            // The GLB format asks readers to skip chunk types they do not know.
            _ => {}
        }
        // A chunk's length includes its padding, so the next chunk starts at `end`.
        at = end;
    }
    let Some(mut json) = json else {
        return Err(err("it has no JSON chunk".to_string()));
    };
    // The JSON chunk is padded with spaces; some writers pad with zeros instead.
    while json
        .last()
        .is_some_and(|b| *b == 0 || b.is_ascii_whitespace())
    {
        json.pop();
    }
    Ok(Container { json, bin })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        let mut chunk = |kind: u32, data: &[u8], pad: u8| {
            let padded = (data.len() + 3) & !3;
            out.extend_from_slice(&(padded as u32).to_le_bytes());
            out.extend_from_slice(&kind.to_le_bytes());
            out.extend_from_slice(data);
            out.resize(out.len() + padded - data.len(), pad);
        };
        chunk(CHUNK_JSON, json, b' ');
        if let Some(b) = bin {
            chunk(CHUNK_BIN, b, 0);
        }
        let total = out.len() as u32;
        out[8..12].copy_from_slice(&total.to_le_bytes());
        out
    }

    #[test]
    fn glb_chunks_are_split_and_padding_removed() {
        let bytes = glb(b"{\"a\":1}", Some(&[1, 2, 3, 4, 5]));
        let c = split(Path::new("x.glb"), bytes).unwrap();
        assert_eq!(c.json, b"{\"a\":1}");
        assert_eq!(c.bin.as_deref(), Some(&[1, 2, 3, 4, 5, 0, 0, 0][..]));
    }

    #[test]
    fn every_truncation_of_a_glb_is_an_error() {
        let bytes = glb(b"{\"asset\":{}}", Some(&[9; 16]));
        for cut in 0..bytes.len() {
            let r = split(Path::new("t.glb"), bytes[..cut].to_vec());
            assert!(r.is_err(), "cut at {cut} was accepted");
        }
    }

    #[test]
    fn non_gltf_bytes_are_named() {
        let e = split(Path::new("p.gltf"), b"\x89PNG\r\n\x1a\n....".to_vec()).unwrap_err();
        assert!(e.to_string().contains("PNG"), "{e}");
        let e = split(Path::new("r.gltf"), vec![7, 200, 13, 0]).unwrap_err();
        assert!(e.to_string().contains("not a glTF file"), "{e}");
    }
}
