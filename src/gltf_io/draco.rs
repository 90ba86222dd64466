//! `KHR_draco_mesh_compression`: primitives whose indices and attributes are
//! stored as one Draco stream, decoded at load by the pure-Rust `draco-core`
//! decoder.
//!
//! Each compressed primitive's stream is decoded once; its faces (as 32-bit
//! indices) and every attribute the extension maps (as 32-bit floats) are
//! appended to a buffer of their own, and the primitive's accessors are
//! pointed at them, so that the rest of the importer reads them as any
//! other accessor. Counts are checked against the accessors and the import
//! limits; a corrupt stream is an error naming the mesh and primitive.

use super::accessors::view_bytes;
use super::describe;
use super::document::Document;
use super::limits::ImportLimits;
use draco_core::{DataType, DecodeLimits, DecoderBuffer, Mesh, MeshDecoder};
use gltf_json::accessor::{ComponentType, GenericComponentType, Type};
use gltf_json::validation::{Checked, USize64};
use gltf_json::Index;
use serde_json::Value;

/// The extension's name.
pub(super) const EXTENSION: &str = "KHR_draco_mesh_compression";

/// What a compressed primitive's extension says.
struct Compressed {
    view: usize,
    /// glTF attribute semantic and Draco unique id.
    attributes: Vec<(String, u32)>,
}

fn read(ext: &Value, here: &str) -> Result<Compressed, String> {
    let view = ext
        .get("bufferView")
        .and_then(Value::as_u64)
        .ok_or_else(|| format!("{here}: {EXTENSION}: bufferView is missing or not an index"))?;
    let map = ext
        .get("attributes")
        .and_then(Value::as_object)
        .ok_or_else(|| format!("{here}: {EXTENSION}: attributes is missing or not an object"))?;
    let mut attributes = Vec::with_capacity(map.len());
    for (semantic, id) in map {
        let id = id
            .as_u64()
            .and_then(|i| u32::try_from(i).ok())
            .ok_or_else(|| {
                format!("{here}: {EXTENSION}: attribute {semantic} is not a Draco attribute id")
            })?;
        attributes.push((semantic.clone(), id));
    }
    Ok(Compressed {
        view: usize::try_from(view).map_err(|_| format!("{here}: bufferView out of range"))?,
        attributes,
    })
}

/// Decodes every Draco-compressed primitive of `doc` into a new buffer
/// appended to `buffers`, and points the primitives' accessors at it.
/// Errors name the mesh and primitive and the fault.
pub(super) fn decompress_primitives(
    doc: &mut Document,
    buffers: &mut Vec<Vec<u8>>,
    limits: &ImportLimits,
) -> Result<(), String> {
    let mut decoded_bytes: Vec<u8> = Vec::new();
    let buffer = buffers.len();
    for m in 0..doc.root.meshes.len() {
        for p in 0..doc.root.meshes[m].primitives.len() {
            let pointer = format!("/meshes/{m}/primitives/{p}/extensions/{EXTENSION}");
            let Some(ext) = doc.raw.pointer(&pointer) else {
                continue;
            };
            let mesh = &doc.root.meshes[m];
            let here = format!(
                "{} primitive {p}",
                describe("mesh", m, mesh.name.as_deref())
            );
            let c = read(ext, &here)?;
            let (stream, _) =
                view_bytes(doc, buffers, c.view).map_err(|e| format!("{here}: {e}"))?;
            let decoded =
                decode(stream, limits).map_err(|e| format!("{here}: {EXTENSION}: {e}"))?;
            decoded_bytes.reserve(decoded.num_faces() * 12);
            let prim = &doc.root.meshes[m].primitives[p];
            if !matches!(prim.mode, Checked::Valid(gltf_json::mesh::Mode::Triangles)) {
                return Err(format!(
                    "{here}: {EXTENSION} with mode {:?}: only triangle lists are decoded",
                    prim.mode
                ));
            }
            let mut plan: Vec<(usize, Vec<u8>, ComponentType)> = Vec::new();
            if let Some(indices) = prim.indices {
                let bytes: Vec<u8> = decoded
                    .faces()
                    .iter()
                    .flatten()
                    .flat_map(|v| v.0.to_le_bytes())
                    .collect();
                plan.push((indices.value(), bytes, ComponentType::U32));
            }
            for (semantic, id) in &c.attributes {
                let Some(accessor) = prim.attributes.iter().find_map(|(s, a)| {
                    matches!(s, Checked::Valid(s) if s.to_string() == *semantic)
                        .then_some(a.value())
                }) else {
                    continue;
                };
                let values = attribute_values(doc, &decoded, *id, accessor)
                    .map_err(|e| format!("{here}: {EXTENSION}: attribute {semantic}: {e}"))?;
                plan.push((accessor, values, ComponentType::F32));
            }
            for (accessor, bytes, component) in plan {
                let acc = doc
                    .root
                    .accessors
                    .get_mut(accessor)
                    .ok_or_else(|| format!("{here}: accessor {accessor} does not exist"))?;
                // Both kinds of values written are four bytes each.
                let width = 4 * component_count(acc, accessor)?;
                let count = bytes.len() / width.max(1);
                if count as u64 != acc.count.0 {
                    return Err(format!(
                        "{here}: {EXTENSION}: {} says {} elements, the Draco stream holds {count}",
                        describe("accessor", accessor, acc.name.as_deref()),
                        acc.count.0
                    ));
                }
                let view = doc.root.buffer_views.len();
                doc.root.buffer_views.push(gltf_json::buffer::View {
                    buffer: Index::new(buffer as u32),
                    byte_length: USize64(bytes.len() as u64),
                    byte_offset: Some(USize64(decoded_bytes.len() as u64)),
                    byte_stride: None,
                    name: None,
                    target: None,
                    extensions: None,
                    extras: Default::default(),
                });
                decoded_bytes.extend_from_slice(&bytes);
                acc.buffer_view = Some(Index::new(view as u32));
                acc.byte_offset = None;
                acc.component_type = Checked::Valid(GenericComponentType(component));
                acc.normalized = false;
                acc.sparse = None;
            }
        }
    }
    if !decoded_bytes.is_empty() {
        buffers.push(decoded_bytes);
    }
    Ok(())
}

/// Components per element of an accessor's type.
fn component_count(acc: &gltf_json::Accessor, index: usize) -> Result<usize, String> {
    match acc.type_ {
        Checked::Valid(t) => Ok(t.multiplicity()),
        Checked::Invalid => Err(format!(
            "{}: invalid type",
            describe("accessor", index, acc.name.as_deref())
        )),
    }
}

/// Decodes one Draco stream, within the import limits.
fn decode(stream: &[u8], limits: &ImportLimits) -> Result<Mesh, String> {
    let bounds = DecodeLimits::default()
        .with_max_faces(limits.max_triangles as u64)
        .with_max_points(3 * limits.max_triangles as u64)
        .with_max_decoded_bytes(limits.max_file_bytes);
    let mut buffer = DecoderBuffer::new(stream).with_limits(bounds);
    let mut mesh = Mesh::new();
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        MeshDecoder::new().decode(&mut buffer, &mut mesh)
    }));
    match outcome {
        Ok(Ok(())) => Ok(mesh),
        Ok(Err(e)) => Err(format!("the Draco stream does not decode: {e}")),
        Err(_) => Err("the Draco decoder failed on this stream".to_string()),
    }
}

/// The values of Draco attribute `id` as little-endian `f32`s, as many
/// components a point as accessor `accessor`'s type has; integers of a
/// normalized accessor are brought to 0..1 (or -1..1) as glTF specifies.
fn attribute_values(
    doc: &Document,
    mesh: &Mesh,
    id: u32,
    accessor: usize,
) -> Result<Vec<u8>, String> {
    let acc = doc
        .root
        .accessors
        .get(accessor)
        .ok_or_else(|| format!("accessor {accessor} does not exist"))?;
    let components = match acc.type_ {
        Checked::Valid(Type::Mat2 | Type::Mat3 | Type::Mat4) | Checked::Invalid => {
            return Err("a matrix or invalid accessor type".to_string())
        }
        Checked::Valid(t) => t.multiplicity(),
    };
    let attribute = mesh
        .attribute_by_unique_id(id)
        .ok_or_else(|| format!("the Draco stream has no attribute with id {id}"))?;
    let (scale, signed) = match (acc.normalized, attribute.data_type()) {
        (true, DataType::Uint8) => (1.0 / 255.0, false),
        (true, DataType::Int8) => (1.0 / 127.0, true),
        (true, DataType::Uint16) => (1.0 / 65535.0, false),
        (true, DataType::Int16) => (1.0 / 32767.0, true),
        _ => (1.0, false),
    };
    let values = attribute.read_f32s(mesh.num_points(), components);
    Ok(values
        .into_iter()
        .map(|v| {
            if signed {
                (v * scale).max(-1.0)
            } else {
                v * scale
            }
        })
        .flat_map(f32::to_le_bytes)
        .collect())
}
