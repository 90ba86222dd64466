//! Geometry for export: one mesh per object, one primitive per material used by the
//! object, positions as `f32` with their bounds, `u32` triangle indices.

use crate::scene::{Scene, Surface};
use gltf_json::accessor::{ComponentType, GenericComponentType, Type};
use gltf_json::buffer::{Target, View};
use gltf_json::mesh::{Mode, Primitive, Semantic};
use gltf_json::validation::{Checked, USize64};
use gltf_json::{Accessor, Index, Mesh, Root};
use std::collections::BTreeMap;

/// The binary buffer being filled, with the views and accessors that describe it.
pub(super) struct GeometryWriter {
    /// Bytes of the single buffer (buffer 0).
    pub bin: Vec<u8>,
}

impl GeometryWriter {
    /// The mesh of object `object` (its surfaces' indices in `surfaces`), or `None`
    /// when it has no surfaces.
    pub fn object_mesh(
        &mut self,
        root: &mut Root,
        scene: &Scene,
        name: &str,
        surfaces: &[usize],
    ) -> Option<Mesh> {
        if surfaces.is_empty() {
            return None;
        }
        // Materials in order of first use, so that the output is deterministic.
        let mut groups: Vec<(u32, Vec<&Surface>)> = Vec::new();
        for &s in surfaces {
            let surface = &scene.surfaces[s];
            match groups.iter_mut().find(|(m, _)| *m == surface.material) {
                Some((_, list)) => list.push(surface),
                None => groups.push((surface.material, vec![surface])),
            }
        }
        let primitives = groups
            .into_iter()
            .map(|(material, list)| self.primitive(root, material, &list))
            .collect();
        Some(Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(name.to_string()),
            primitives,
            weights: None,
        })
    }

    /// One triangle-list primitive. Every surface gets its own vertices, so that a
    /// quad's two triangles share their diagonal but nothing is shared between
    /// surfaces, and the importer's quad merging restores exactly the quads.
    fn primitive(&mut self, root: &mut Root, material: u32, surfaces: &[&Surface]) -> Primitive {
        let mut positions: Vec<[f32; 3]> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        for s in surfaces {
            let first = positions.len() as u32;
            positions.extend(
                s.vertices
                    .iter()
                    .map(|v| [v.x as f32, v.y as f32, v.z as f32]),
            );
            indices.extend([first, first + 1, first + 2]);
            if s.is_quad() {
                indices.extend([first, first + 2, first + 3]);
            }
        }
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let position_bytes: Vec<u8> = positions
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        let index_bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let position_view = self.view(root, &position_bytes, Target::ArrayBuffer);
        let index_view = self.view(root, &index_bytes, Target::ElementArrayBuffer);
        let position_accessor = root.push(Accessor {
            buffer_view: Some(position_view),
            byte_offset: None,
            count: USize64(positions.len() as u64),
            component_type: Checked::Valid(GenericComponentType(ComponentType::F32)),
            extensions: None,
            extras: Default::default(),
            type_: Checked::Valid(Type::Vec3),
            min: Some(lo.iter().map(|&v| serde_json::Value::from(v)).collect()),
            max: Some(hi.iter().map(|&v| serde_json::Value::from(v)).collect()),
            name: None,
            normalized: false,
            sparse: None,
        });
        let index_accessor = root.push(Accessor {
            buffer_view: Some(index_view),
            byte_offset: None,
            count: USize64(indices.len() as u64),
            component_type: Checked::Valid(GenericComponentType(ComponentType::U32)),
            extensions: None,
            extras: Default::default(),
            type_: Checked::Valid(Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
        });
        Primitive {
            attributes: BTreeMap::from([(Checked::Valid(Semantic::Positions), position_accessor)]),
            extensions: None,
            extras: Default::default(),
            indices: Some(index_accessor),
            material: Some(Index::new(material)),
            mode: Checked::Valid(Mode::Triangles),
            targets: None,
        }
    }

    /// Appends `bytes` (a multiple of four long) to the buffer as a new view.
    fn view(&mut self, root: &mut Root, bytes: &[u8], target: Target) -> Index<View> {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        root.push(View {
            buffer: Index::new(0),
            byte_length: USize64(bytes.len() as u64),
            byte_offset: Some(USize64(offset as u64)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: Some(Checked::Valid(target)),
        })
    }
}
