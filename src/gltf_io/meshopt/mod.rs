//! `EXT_meshopt_compression`: buffer views stored compressed, decoded at load
//! into the (often placeholder) buffer their parent view points to, so that
//! accessors read them as any other view.
//!
//! Written from the extension's public specification (the bitstreams of its
//! appendix A, the filters of appendix B): [`attributes`] for mode
//! `ATTRIBUTES`, [`indices`] for `TRIANGLES` and `INDICES`, [`filters`] for
//! the `OCTAHEDRAL`, `QUATERNION` and `EXPONENTIAL` filters. Every read is
//! bounds-checked: a corrupt stream is an error naming the buffer view.

mod attributes;
mod filters;
mod indices;

use super::document::Document;
use serde_json::Value;

/// The extension's name.
pub(super) const EXTENSION: &str = "EXT_meshopt_compression";

/// What one compressed view says.
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: String,
    filter: String,
}

fn extension_of(doc: &Document, view: usize) -> Option<&Value> {
    doc.raw
        .pointer(&format!("/bufferViews/{view}/extensions/{EXTENSION}"))
}

/// True when buffer `buffer` is the target of some compressed view (its bytes
/// may then be a placeholder without data: decoding fills it).
pub(super) fn is_fallback(doc: &Document, buffer: usize) -> bool {
    doc.root
        .buffer_views
        .iter()
        .enumerate()
        .any(|(i, v)| v.buffer.value() == buffer && extension_of(doc, i).is_some())
}

fn read(view: usize, ext: &Value) -> Result<Compressed, String> {
    let uint = |key: &str, default: Option<u64>| {
        ext.get(key)
            .map(|v| {
                v.as_u64()
                    .ok_or(format!("{key} is not a non-negative integer"))
            })
            .unwrap_or(default.ok_or(format!("{key} is missing")))
            .and_then(|n| usize::try_from(n).map_err(|_| format!("{key} is too large")))
    };
    let text = |key: &str, default: Option<&str>| {
        ext.get(key)
            .map(|v| {
                v.as_str()
                    .map(str::to_string)
                    .ok_or(format!("{key} is not a string"))
            })
            .unwrap_or(
                default
                    .map(str::to_string)
                    .ok_or(format!("{key} is missing")),
            )
    };
    let fields = || -> Result<Compressed, String> {
        Ok(Compressed {
            buffer: uint("buffer", None)?,
            offset: uint("byteOffset", Some(0))?,
            length: uint("byteLength", None)?,
            stride: uint("byteStride", None)?,
            count: uint("count", None)?,
            mode: text("mode", None)?,
            filter: text("filter", Some("NONE"))?,
        })
    };
    fields().map_err(|e| format!("buffer view {view}: {EXTENSION}: {e}"))
}

/// Decodes every compressed view of `doc` into its parent view's bytes.
/// Errors name the buffer view and the fault.
pub(super) fn decompress_views(doc: &Document, buffers: &mut [Vec<u8>]) -> Result<(), String> {
    for (i, view) in doc.root.buffer_views.iter().enumerate() {
        let Some(ext) = extension_of(doc, i) else {
            continue;
        };
        let c = read(i, ext)?;
        let fail = |m: String| format!("buffer view {i}: {EXTENSION} ({} mode): {m}", c.mode);
        let source = buffers
            .get(c.buffer)
            .ok_or_else(|| fail(format!("buffer {} does not exist", c.buffer)))?;
        let data = c
            .offset
            .checked_add(c.length)
            .and_then(|end| source.get(c.offset..end))
            .ok_or_else(|| {
                fail(format!(
                    "bytes {} + {} run past the end of buffer {} ({} bytes)",
                    c.offset,
                    c.length,
                    c.buffer,
                    source.len()
                ))
            })?;
        let size = c
            .stride
            .checked_mul(c.count)
            .filter(|n| *n as u64 == view.byte_length.0)
            .ok_or_else(|| {
                fail(format!(
                    "byteStride {} times count {} is not the view's byteLength {}",
                    c.stride, c.count, view.byte_length.0
                ))
            })?;
        let mut decoded = match c.mode.as_str() {
            "ATTRIBUTES" => attributes::decode(data, c.count, c.stride),
            "TRIANGLES" => indices::decode_triangles(data, c.count, c.stride),
            "INDICES" => indices::decode_indices(data, c.count, c.stride),
            other => Err(format!("unknown mode '{other}'")),
        }
        .map_err(fail)?;
        debug_assert_eq!(decoded.len(), size);
        filters::apply(&c.filter, &mut decoded, c.stride, &c.mode).map_err(fail)?;
        let start = view.byte_offset.map_or(0, |o| o.0) as usize;
        let target = buffers
            .get_mut(view.buffer.value())
            .and_then(|b| {
                start
                    .checked_add(size)
                    .and_then(|end| b.get_mut(start..end))
            })
            .ok_or_else(|| fail("the view runs past the end of its buffer".to_string()))?;
        target.copy_from_slice(&decoded);
    }
    Ok(())
}

/// Reads an unsigned LEB128 value (at most 5 bytes) at `*at`.
fn varint(data: &[u8], at: &mut usize, end: usize) -> Result<u32, String> {
    let mut value: u32 = 0;
    for shift in (0..35).step_by(7) {
        if *at >= end {
            return Err("the stream ends inside a variable-length value".to_string());
        }
        let byte = data[*at];
        *at += 1;
        value |= u32::from(byte & 0x7f).wrapping_shl(shift);
        if byte & 0x80 == 0 {
            return Ok(value);
        }
    }
    Err("a variable-length value longer than 5 bytes".to_string())
}

/// Writes `values` as little-endian indices of `size` bytes (2 or 4).
fn index_bytes(values: &[u32], size: usize) -> Vec<u8> {
    let mut out = Vec::with_capacity(values.len() * size);
    for &v in values {
        if size == 2 {
            out.extend_from_slice(&(v as u16).to_le_bytes());
        } else {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests;
