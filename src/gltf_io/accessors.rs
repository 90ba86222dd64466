//! Reading accessors (vertex positions, indices and colours) with every offset, stride and
//! count checked against the bytes the buffer really holds, so that out-of-range
//! views or accessors become errors instead of panics. Sparse accessors are
//! supported; an accessor without a buffer view reads as zeros, as glTF specifies.

use super::describe;
use super::document::Document;
use super::limits::ImportLimits;
use glam::DVec3;
use gltf_json::accessor::{Accessor, ComponentType, Type};
use gltf_json::validation::Checked;

/// An error message naming the accessor, buffer view or buffer at fault.
type Message = String;

/// The positions of a `VEC3` accessor of `FLOAT`, or of (normalized or not)
/// signed or unsigned bytes or shorts as `KHR_mesh_quantization` allows:
/// integers read as their values, normalized ones as glTF specifies (`c /
/// 255` or `c / 65535` unsigned, `max(c / 127, -1)` or `max(c / 32767, -1)`
/// signed); the node's transform scales them back to metres.
pub(super) fn read_positions(
    doc: &Document,
    buffers: &[Vec<u8>],
    index: usize,
    limits: &ImportLimits,
) -> Result<Vec<DVec3>, Message> {
    let acc = accessor(doc, index)?;
    let name = describe("accessor", index, acc.name.as_deref());
    let component = component_type(acc);
    let size = match component {
        Some(ComponentType::F32) if !acc.normalized => 4,
        Some(ComponentType::I8 | ComponentType::U8) => 1,
        Some(ComponentType::I16 | ComponentType::U16) => 2,
        _ => 0,
    };
    if type_of(acc) != Some(Type::Vec3) || size == 0 {
        return Err(format!(
            "{name} holds positions as {:?} of {:?}{}; positions must be VEC3 of FLOAT, or of \
             bytes or shorts (KHR_mesh_quantization)",
            type_of(acc),
            component,
            if acc.normalized { " (normalized)" } else { "" }
        ));
    }
    let normalized = acc.normalized;
    let read = move |b: &[u8]| -> f64 {
        match component {
            Some(ComponentType::I8) => {
                let c = f64::from(b[0] as i8);
                if normalized {
                    (c / 127.0).max(-1.0)
                } else {
                    c
                }
            }
            Some(ComponentType::U8) => {
                let c = f64::from(b[0]);
                if normalized {
                    c / 255.0
                } else {
                    c
                }
            }
            Some(ComponentType::I16) => {
                let c = f64::from(i16::from_le_bytes([b[0], b[1]]));
                if normalized {
                    (c / 32767.0).max(-1.0)
                } else {
                    c
                }
            }
            Some(ComponentType::U16) => {
                let c = f64::from(u16::from_le_bytes([b[0], b[1]]));
                if normalized {
                    c / 65535.0
                } else {
                    c
                }
            }
            _ => f64::from(f32_at(b, 0)),
        }
    };
    read_elements(doc, buffers, acc, &name, 3 * size, limits, |b| {
        DVec3::new(read(b), read(&b[size..]), read(&b[2 * size..]))
    })
}

/// The vertex indices of a `SCALAR` accessor of unsigned bytes, shorts or ints.
pub(super) fn read_indices(
    doc: &Document,
    buffers: &[Vec<u8>],
    index: usize,
    limits: &ImportLimits,
) -> Result<Vec<u32>, Message> {
    let acc = accessor(doc, index)?;
    let name = describe("accessor", index, acc.name.as_deref());
    let component = component_type(acc);
    let size = match component {
        Some(ComponentType::U8) => 1,
        Some(ComponentType::U16) => 2,
        Some(ComponentType::U32) => 4,
        _ => 0,
    };
    if type_of(acc) != Some(Type::Scalar) || size == 0 {
        return Err(format!(
            "{name} holds indices as {:?} of {:?}; indices must be SCALAR unsigned bytes, shorts or ints",
            type_of(acc),
            component
        ));
    }
    read_elements(doc, buffers, acc, &name, size, limits, |b| uint_at(b, size))
}

/// The colours of a `COLOR_n` accessor: `VEC3` or `VEC4` (alpha dropped) of
/// `FLOAT`, or of normalized unsigned bytes or shorts, as linear RGB.
pub(super) fn read_colours(
    doc: &Document,
    buffers: &[Vec<u8>],
    index: usize,
    limits: &ImportLimits,
) -> Result<Vec<[f64; 3]>, Message> {
    let acc = accessor(doc, index)?;
    let name = describe("accessor", index, acc.name.as_deref());
    let component = component_type(acc);
    let components = match type_of(acc) {
        Some(Type::Vec3) => 3,
        Some(Type::Vec4) => 4,
        _ => 0,
    };
    let (size, unit) = match component {
        Some(ComponentType::F32) if !acc.normalized => (4, None),
        Some(ComponentType::U8) if acc.normalized => (1, Some(255.0)),
        Some(ComponentType::U16) if acc.normalized => (2, Some(65535.0)),
        _ => (0, None),
    };
    if components == 0 || size == 0 {
        return Err(format!(
            "{name} holds colours as {:?} of {:?}{}; colours must be VEC3 or VEC4 of FLOAT, \
             or of normalized unsigned bytes or shorts",
            type_of(acc),
            component,
            if acc.normalized { " (normalized)" } else { "" }
        ));
    }
    read_elements(doc, buffers, acc, &name, components * size, limits, |b| {
        [0, 1, 2].map(|k| match unit {
            None => f64::from(f32_at(b, 4 * k)),
            Some(max) => f64::from(uint_at(&b[k * size..], size)) / max,
        })
    })
}

fn accessor(doc: &Document, index: usize) -> Result<&Accessor, Message> {
    doc.root.accessors.get(index).ok_or_else(|| {
        format!(
            "accessor {index} does not exist (the file has {})",
            doc.root.accessors.len()
        )
    })
}

fn type_of(acc: &Accessor) -> Option<Type> {
    match acc.type_ {
        Checked::Valid(t) => Some(t),
        Checked::Invalid => None,
    }
}

fn component_type(acc: &Accessor) -> Option<ComponentType> {
    match &acc.component_type {
        Checked::Valid(c) => Some(c.0),
        Checked::Invalid => None,
    }
}

fn f32_at(b: &[u8], at: usize) -> f32 {
    b.get(at..at + 4)
        .map(|s| f32::from_le_bytes([s[0], s[1], s[2], s[3]]))
        .unwrap_or(f32::NAN)
}

fn uint_at(b: &[u8], size: usize) -> u32 {
    match size {
        1 => u32::from(b[0]),
        2 => u32::from(u16::from_le_bytes([b[0], b[1]])),
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

/// The bytes of buffer view `view`, checked to lie inside its buffer.
pub(super) fn view_bytes<'a>(
    doc: &Document,
    buffers: &'a [Vec<u8>],
    view: usize,
) -> Result<(&'a [u8], Option<usize>), Message> {
    let v = doc
        .root
        .buffer_views
        .get(view)
        .ok_or_else(|| format!("buffer view {view} does not exist"))?;
    let vname = describe("buffer view", view, v.name.as_deref());
    let buffer = buffers.get(v.buffer.value()).ok_or_else(|| {
        format!(
            "{vname} refers to buffer {}, which does not exist",
            v.buffer.value()
        )
    })?;
    let start = v.byte_offset.map_or(0, |o| o.0);
    let end = start.checked_add(v.byte_length.0);
    match end {
        Some(end) if end <= buffer.len() as u64 => Ok((
            &buffer[start as usize..end as usize],
            v.byte_stride.map(|s| s.0),
        )),
        _ => Err(format!(
            "{vname} (bytes {start} + {}) runs past the end of buffer {} ({} bytes)",
            v.byte_length.0,
            v.buffer.value(),
            buffer.len()
        )),
    }
}

/// Checks that `count` elements of `size` bytes, `stride` apart, starting at
/// `offset`, fit in `len` bytes.
fn fits(offset: u64, stride: u64, size: u64, count: u64, len: usize) -> bool {
    if count == 0 {
        return offset <= len as u64;
    }
    stride
        .checked_mul(count - 1)
        .and_then(|s| s.checked_add(offset))
        .and_then(|s| s.checked_add(size))
        .is_some_and(|end| end <= len as u64)
}

#[allow(clippy::too_many_arguments)]
fn read_elements<T: Copy + Default>(
    doc: &Document,
    buffers: &[Vec<u8>],
    acc: &Accessor,
    name: &str,
    size: usize,
    limits: &ImportLimits,
    decode: impl Fn(&[u8]) -> T,
) -> Result<Vec<T>, Message> {
    let count = acc.count.0;
    // An accessor without a buffer view claims its count for free; and no primitive
    // within the triangle limit needs more than three vertices per triangle.
    let max_elements = (limits.max_triangles as u64)
        .saturating_mul(3)
        .saturating_add(2);
    if count > max_elements || count.saturating_mul(size as u64) > limits.max_file_bytes {
        return Err(format!(
            "{name} claims {count} elements, more than the import limits allow \
             (3 per triangle of max_triangles = {}, at most {} bytes)",
            limits.max_triangles, limits.max_file_bytes
        ));
    }
    let count = count as usize;
    let mut out = match acc.buffer_view {
        None => {
            // Zeros cost memory the file never paid for: a 250-byte file
            // claiming 6 million of them held 511 MiB. Allow no more elements
            // than the file's buffers hold bytes; a sparse accessor sets a few
            // of them from those buffers, and the zeros left all coincide
            // anyway (degenerate triangles).
            let data: usize = buffers.iter().map(Vec::len).sum();
            if count > data {
                return Err(format!(
                    "{name} has no buffer view and claims {count} elements of zeros, more \
                     than the {data} bytes of buffer data in the file: out of proportion to \
                     the file"
                ));
            }
            vec![T::default(); count]
        }
        Some(view) => {
            let (bytes, stride) = view_bytes(doc, buffers, view.value())?;
            let stride = stride.unwrap_or(size);
            if stride < size {
                return Err(format!(
                    "{name}: byte stride {stride} is smaller than one element ({size} bytes)"
                ));
            }
            let offset = acc.byte_offset.map_or(0, |o| o.0);
            if !fits(
                offset,
                stride as u64,
                size as u64,
                count as u64,
                bytes.len(),
            ) {
                return Err(format!(
                    "{name} ({count} elements from byte {offset}) runs past the end of buffer view {} ({} bytes)",
                    view.value(),
                    bytes.len()
                ));
            }
            let offset = offset as usize;
            (0..count)
                .map(|k| {
                    let at = offset + k * stride;
                    decode(&bytes[at..at + size])
                })
                .collect()
        }
    };
    if let Some(sparse) = &acc.sparse {
        apply_sparse(doc, buffers, sparse, name, size, &mut out, &decode)?;
    }
    Ok(out)
}

fn apply_sparse<T>(
    doc: &Document,
    buffers: &[Vec<u8>],
    sparse: &gltf_json::accessor::sparse::Sparse,
    name: &str,
    size: usize,
    out: &mut [T],
    decode: &impl Fn(&[u8]) -> T,
) -> Result<(), Message> {
    let n = sparse.count.0;
    if n > out.len() as u64 {
        return Err(format!(
            "{name}: {n} sparse values for {} elements",
            out.len()
        ));
    }
    let index_size = match &sparse.indices.component_type {
        Checked::Valid(c) => c.0.size(),
        Checked::Invalid => return Err(format!("{name}: invalid sparse index type")),
    };
    let (ib, _) = view_bytes(doc, buffers, sparse.indices.buffer_view.value())?;
    let (vb, _) = view_bytes(doc, buffers, sparse.values.buffer_view.value())?;
    let io = sparse.indices.byte_offset.0;
    let vo = sparse.values.byte_offset.0;
    if !fits(io, index_size as u64, index_size as u64, n, ib.len())
        || !fits(vo, size as u64, size as u64, n, vb.len())
    {
        return Err(format!(
            "{name}: sparse indices or values run past the end of their buffer views"
        ));
    }
    let (io, vo) = (io as usize, vo as usize);
    let len = out.len();
    for j in 0..n as usize {
        let at = io + j * index_size;
        let target = uint_at(&ib[at..at + index_size], index_size) as usize;
        let slot = out.get_mut(target).ok_or_else(|| {
            format!("{name}: sparse index {target} is out of range (count {len})")
        })?;
        let at = vo + j * size;
        *slot = decode(&vb[at..at + size]);
    }
    Ok(())
}

/// The texture coordinates of a `TEXCOORD_n` accessor: `VEC2` of `FLOAT`, or
/// of normalized unsigned bytes or shorts, as glTF allows.
pub(super) fn read_texcoords(
    doc: &Document,
    buffers: &[Vec<u8>],
    index: usize,
    limits: &ImportLimits,
) -> Result<Vec<glam::DVec2>, Message> {
    let acc = accessor(doc, index)?;
    let name = describe("accessor", index, acc.name.as_deref());
    let (size, unit) = match component_type(acc) {
        Some(ComponentType::F32) if !acc.normalized => (4, None),
        Some(ComponentType::U8) if acc.normalized => (1, Some(255.0)),
        Some(ComponentType::U16) if acc.normalized => (2, Some(65535.0)),
        _ => (0, None),
    };
    if type_of(acc) != Some(Type::Vec2) || size == 0 {
        return Err(format!(
            "{name} holds texture coordinates as {:?} of {:?}; they must be VEC2 of FLOAT, \
             or of normalized unsigned bytes or shorts",
            type_of(acc),
            component_type(acc)
        ));
    }
    read_elements(doc, buffers, acc, &name, 2 * size, limits, |b| {
        let [u, v] = [0, 1].map(|k| match unit {
            None => f64::from(f32_at(b, 4 * k)),
            Some(max) => f64::from(uint_at(&b[k * size..], size)) / max,
        });
        glam::DVec2::new(u, v)
    })
}
