//! Geometry for export: one mesh per object, one primitive per material used by the
//! object, positions as `f32` with their bounds, `u32` triangle indices; optional
//! normals and vertex colours (for baked solutions).

use crate::scene::{Scene, Surface};
use gltf_json::accessor::{ComponentType, GenericComponentType, Type};
use gltf_json::buffer::{Target, View};
use gltf_json::mesh::{Mode, Primitive, Semantic};
use gltf_json::validation::{Checked, USize64};
use gltf_json::{Accessor, Index, Mesh, Root};
use std::collections::BTreeMap;

/// Per-vertex data of one primitive: positions, and optionally unit normals,
/// linear RGB colours (`COLOR_0`) and texture coordinates (`TEXCOORD_0`), all
/// of the same length.
pub(super) struct VertexStreams<'a> {
    /// Vertex positions.
    pub positions: &'a [[f32; 3]],
    /// Unit normals (`NORMAL`), if any.
    pub normals: Option<&'a [[f32; 3]]>,
    /// Colours in `[0, 1]` (`COLOR_0`), if any.
    pub colours: Option<&'a [[f32; 3]]>,
    /// Texture coordinates (`TEXCOORD_0`), if any.
    pub texcoords: Option<&'a [[f32; 2]]>,
    /// Application-specific `VEC3` attributes: (name without the leading
    /// underscore, values).
    pub extra: &'a [(String, Vec<[f32; 3]>)],
}

/// The binary buffer being filled, with the views and accessors that describe it.
pub(super) struct GeometryWriter {
    /// Bytes of the single buffer (buffer 0).
    pub bin: Vec<u8>,
}

impl GeometryWriter {
    /// The mesh of object `object` (its surfaces' indices in `surfaces`), or `None`
    /// when it has no surfaces.
    pub(super) fn object_mesh(
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
        self.triangle_primitive(
            root,
            &VertexStreams {
                positions: &positions,
                normals: None,
                colours: None,
                texcoords: None,
                extra: &[],
            },
            &indices,
            material,
        )
    }

    /// A triangle-list primitive from vertex streams and `u32` indices, using
    /// material `material`. Positions get the `min`/`max` bounds glTF requires.
    pub(super) fn triangle_primitive(
        &mut self,
        root: &mut Root,
        streams: &VertexStreams,
        indices: &[u32],
        material: u32,
    ) -> Primitive {
        let mut attributes = BTreeMap::new();
        let positions = self.vec3_accessor(root, streams.positions, true);
        attributes.insert(Checked::Valid(Semantic::Positions), positions);
        if let Some(normals) = streams.normals {
            let a = self.vec3_accessor(root, normals, false);
            attributes.insert(Checked::Valid(Semantic::Normals), a);
        }
        if let Some(colours) = streams.colours {
            let a = self.vec3_accessor(root, colours, false);
            attributes.insert(Checked::Valid(Semantic::Colors(0)), a);
        }
        if let Some(texcoords) = streams.texcoords {
            let bytes: Vec<u8> = texcoords
                .iter()
                .flatten()
                .flat_map(|c| c.to_le_bytes())
                .collect();
            let view = self.view(root, &bytes, Some(Target::ArrayBuffer));
            let a = root.push(accessor(
                view,
                texcoords.len(),
                ComponentType::F32,
                Type::Vec2,
            ));
            attributes.insert(Checked::Valid(Semantic::TexCoords(0)), a);
        }
        for (name, values) in streams.extra {
            let a = self.vec3_accessor(root, values, false);
            attributes.insert(Checked::Valid(Semantic::Extras(name.clone())), a);
        }
        let index_bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let index_view = self.view(root, &index_bytes, Some(Target::ElementArrayBuffer));
        let index_accessor = root.push(accessor(
            index_view,
            indices.len(),
            ComponentType::U32,
            Type::Scalar,
        ));
        Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(index_accessor),
            material: Some(Index::new(material)),
            mode: Checked::Valid(Mode::Triangles),
            targets: None,
        }
    }

    /// A `VEC3` `FLOAT` vertex attribute in its own view, with its bounds when
    /// `bounds` is set.
    fn vec3_accessor(
        &mut self,
        root: &mut Root,
        values: &[[f32; 3]],
        bounds: bool,
    ) -> Index<Accessor> {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in values {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        let view = self.view(root, &bytes, Some(Target::ArrayBuffer));
        let json = |v: [f32; 3]| Some(v.iter().map(|&c| serde_json::Value::from(c)).collect());
        root.push(Accessor {
            min: if bounds { json(lo) } else { None },
            max: if bounds { json(hi) } else { None },
            ..accessor(view, values.len(), ComponentType::F32, Type::Vec3)
        })
    }

    /// Appends `bytes` (an image file) to the buffer as a new view without a
    /// target, padded to a multiple of four bytes.
    pub(super) fn image_view(&mut self, root: &mut Root, bytes: &[u8]) -> Index<View> {
        self.view(root, bytes, None)
    }

    /// Appends `bytes` to the buffer as a new view for `target`, padded to a
    /// multiple of four bytes so that the next view starts aligned.
    fn view(&mut self, root: &mut Root, bytes: &[u8], target: Option<Target>) -> Index<View> {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        root.push(View {
            buffer: Index::new(0),
            byte_length: USize64(bytes.len() as u64),
            byte_offset: Some(USize64(offset as u64)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: target.map(Checked::Valid),
        })
    }
}

/// A tightly packed accessor of `count` elements over `view`, without bounds.
fn accessor(view: Index<View>, count: usize, component: ComponentType, type_: Type) -> Accessor {
    Accessor {
        buffer_view: Some(view),
        byte_offset: None,
        count: USize64(count as u64),
        component_type: Checked::Valid(GenericComponentType(component)),
        extensions: None,
        extras: Default::default(),
        type_: Checked::Valid(type_),
        min: None,
        max: None,
        name: None,
        normalized: false,
        sparse: None,
    }
}
