//! One mesh instance (a node carrying a mesh) into surfaces of one scene object:
//! positions moved to world space, triangles assembled per primitive mode,
//! degenerate triangles dropped, coplanar pairs merged into quads.

use super::accessors::{read_indices, read_positions, read_texcoords};
use super::alpha_mask::{Cut, Mask, MaskTally};
use super::document::Document;
use super::limits::ImportLimits;
use super::materials::default_material;
use super::nodes::Placed;
use super::primitives::{triangle_count, triangle_mode, triangles};
use super::quad_merge::{merge_into_quads, Polygon, Triangle};
use super::{describe, gltf_error};
use crate::error::{Error, LimitKind, Result};
use crate::scene::{Object, Scene, Surface, MAX_COORDINATE};
use glam::{DMat3, DVec2, DVec3};
use gltf_json::mesh::{Mode, Semantic};
use gltf_json::validation::Checked;
use smallvec::SmallVec;
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

/// A triangle whose area is below this fraction of its longest edge squared (a
/// height under twice this fraction of that edge) is degenerate and skipped. Far
/// above rounding noise of exactly collinear `f32` input, far below any triangle a
/// radiosity mesh can use.
pub(super) const DEGENERATE_RATIO: f64 = 1e-8;

/// What the mesh importer reads from.
pub(super) struct Source<'a> {
    /// The scene file, for messages.
    pub path: &'a Path,
    /// The parsed document.
    pub doc: &'a Document,
    /// Every buffer's bytes.
    pub buffers: &'a [Vec<u8>],
    /// The import limits.
    pub limits: &'a ImportLimits,
    /// What each material's `alphaMode` `MASK` cuts by (by material index).
    pub masks: &'a [Option<Mask>],
    /// The lattice division each masked triangle may be cut at most.
    pub mask_divisions: usize,
}

/// Accessors already decoded, by index, so that a mesh placed by many nodes or an
/// accessor shared by many primitives is read once (a small file could otherwise
/// make the importer decode one large accessor over and over).
#[derive(Debug, Default)]
pub(super) struct Decoded {
    positions: HashMap<usize, Rc<Vec<DVec3>>>,
    indices: HashMap<usize, Rc<Vec<u32>>>,
    /// What the masks did, by material index.
    pub masked: std::collections::BTreeMap<u32, MaskTally>,
}

impl Decoded {
    fn positions(
        &mut self,
        src: &Source,
        accessor: usize,
    ) -> std::result::Result<Rc<Vec<DVec3>>, String> {
        if let Some(p) = self.positions.get(&accessor) {
            return Ok(Rc::clone(p));
        }
        let p = Rc::new(read_positions(src.doc, src.buffers, accessor, src.limits)?);
        self.positions.insert(accessor, Rc::clone(&p));
        Ok(p)
    }

    fn indices(
        &mut self,
        src: &Source,
        accessor: usize,
    ) -> std::result::Result<Rc<Vec<u32>>, String> {
        if let Some(ix) = self.indices.get(&accessor) {
            return Ok(Rc::clone(ix));
        }
        let ix = Rc::new(read_indices(src.doc, src.buffers, accessor, src.limits)?);
        self.indices.insert(accessor, Rc::clone(&ix));
        Ok(ix)
    }
}

/// Adds the mesh of `placed` as one object. The object is named after the node,
/// else the mesh, else `node N`; it is left out (with a warning) if none of its
/// triangles is usable.
pub(super) fn add_mesh_instance(
    src: &Source,
    placed: &Placed,
    mesh_index: usize,
    scene: &mut Scene,
    default_material_index: &mut Option<u32>,
    decoded: &mut Decoded,
) -> Result<()> {
    let node = &src.doc.root.nodes[placed.node];
    let mesh = src
        .doc
        .root
        .meshes
        .get(mesh_index)
        .ok_or_else(|| gltf_error(src.path, format!("mesh {mesh_index} does not exist")))?;
    let mesh_name = describe("mesh", mesh_index, mesh.name.as_deref());
    let node_name = describe("node", placed.node, node.name.as_deref());
    let object_name = [node.name.as_deref(), mesh.name.as_deref()]
        .into_iter()
        .flatten()
        .find(|n| !n.is_empty())
        .map_or_else(|| format!("node {}", placed.node), str::to_string);
    if node.skin.is_some() {
        scene.warnings.push(format!(
            "object '{object_name}': the skin is ignored; the mesh is placed by its node's transform"
        ));
    }
    scene.objects.push(Object {
        name: object_name.clone(),
    });
    let object = (scene.objects.len() - 1) as u32;
    let surfaces_before = scene.surfaces.len();
    // A mirroring transform turns counter-clockwise triangles clockwise.
    let mirrored = DMat3::from_mat4(placed.world).determinant() < 0.0;
    for (p, prim) in mesh.primitives.iter().enumerate() {
        let here = format!("{mesh_name} primitive {p}");
        let mode = match prim.mode {
            Checked::Valid(m) => m,
            Checked::Invalid => return Err(gltf_error(src.path, format!("{here}: invalid mode"))),
        };
        let Some(mode) = triangle_mode(mode) else {
            scene.import_stats.skipped_primitives += 1;
            scene
                .warnings
                .push(format!("{here} draws {mode:?}, not triangles: skipped"));
            continue;
        };
        if prim.targets.is_some() {
            scene
                .warnings
                .push(format!("{here}: morph targets ignored"));
        }
        let material = match prim.material {
            Some(m) => m.value() as u32,
            None => {
                scene.warnings.push(format!(
                    "{here} has no material: using a default grey of reflectance {}",
                    super::materials::DEFAULT_GREY
                ));
                *default_material_index.get_or_insert_with(|| {
                    scene.materials.push(default_material());
                    (scene.materials.len() - 1) as u32
                })
            }
        };
        let tris = primitive_triangles(
            src,
            decoded,
            prim,
            mode,
            &here,
            &placed.world,
            &node_name,
            mirrored,
            scene,
        )?;
        let (tris, corners) = tris;
        let read = tris.len();
        let (kept, corners): (Vec<Triangle>, Vec<[usize; 3]>) = tris
            .into_iter()
            .zip(corners)
            .filter(|(t, _)| !is_degenerate(&t.points))
            .unzip();
        scene.import_stats.degenerate_triangles += read - kept.len();
        let uvs = texture_coordinates(src, prim, material, &here, scene)?;
        if let Some(uv) = &uvs {
            if corners.iter().flatten().any(|&i| i >= uv.len()) {
                return Err(gltf_error(
                    src.path,
                    format!("{here}: its texture coordinates are fewer than its vertices"),
                ));
            }
        }
        // A textured primitive keeps its triangles: texture coordinates are
        // affine over a triangle, and a merged quad's bilinear map would bend
        // them.
        let mask = src.masks.get(material as usize).and_then(Option::as_ref);
        let (polygons, uv_of): (Vec<Polygon>, Vec<SmallVec<[DVec2; 4]>>) = match &uvs {
            Some(uv) => {
                let mut polygons = Vec::with_capacity(kept.len());
                let mut uv_of = Vec::with_capacity(kept.len());
                let mut tally = MaskTally::default();
                for (t, c) in kept.iter().zip(&corners) {
                    let tuv = c.map(|i| uv[i]);
                    let cut = match mask {
                        Some(m) => m.cut(&t.points, &tuv, src.mask_divisions),
                        None => Cut::Whole,
                    };
                    match cut {
                        Cut::Whole => {
                            tally.whole += 1;
                            polygons.push(t.points.iter().copied().collect());
                            uv_of.push(tuv.iter().copied().collect());
                        }
                        Cut::Dropped => tally.dropped += 1,
                        Cut::Pieces(pieces) => {
                            tally.cut += 1;
                            tally.pieces += pieces.len();
                            for (p, q) in &pieces {
                                polygons.push(p.iter().copied().collect());
                                uv_of.push(q.iter().copied().collect());
                            }
                        }
                    }
                }
                if mask.is_some() {
                    decoded.masked.entry(material).or_default().add(&tally);
                }
                (polygons, uv_of)
            }
            None => {
                let kept = match mask {
                    // Without coordinates only the factor's alpha can decide.
                    Some(m) if m.is_uniform() && !m.uniform_passes() => {
                        decoded.masked.entry(material).or_default().dropped += kept.len();
                        Vec::new()
                    }
                    _ => kept,
                };
                let (polygons, merged) = merge_into_quads(&kept);
                scene.import_stats.merged_quads += merged;
                let n = polygons.len();
                (polygons, vec![SmallVec::new(); n])
            }
        };
        let double_sided = scene
            .materials
            .get(material as usize)
            .is_some_and(|m| m.double_sided);
        for (poly, uv) in polygons.into_iter().zip(uv_of) {
            match Surface::new(&poly, material, object) {
                Ok(s) => {
                    let s = s.with_uv(&uv);
                    if double_sided {
                        let back = s.flipped();
                        scene.surfaces.push(s);
                        scene.surfaces.push(back);
                    } else {
                        scene.surfaces.push(s);
                    }
                }
                // Only a triangle the degeneracy test let through can fail here.
                Err(_) => scene.import_stats.degenerate_triangles += poly.len() - 2,
            }
        }
    }
    if scene.surfaces.len() == surfaces_before {
        scene.objects.pop();
        scene.warnings.push(format!(
            "object '{object_name}' ({mesh_name}) has no usable triangles: left out"
        ));
    }
    Ok(())
}

/// The texture coordinates per vertex of a primitive whose material has a
/// base-colour or emissive texture (the set it reads), or `None`: no texture, or
/// no such set (a warning: the material's mean reflectance is used).
fn texture_coordinates(
    src: &Source,
    prim: &gltf_json::mesh::Primitive,
    material: u32,
    here: &str,
    scene: &mut Scene,
) -> Result<Option<Vec<DVec2>>> {
    // The importer keeps an emissive texture only when it reads the same set
    // as the base colour's, so either names the set the surface carries.
    let Some(texture) = scene
        .materials
        .get(material as usize)
        .and_then(|m| m.base_texture.as_ref().or(m.emissive_texture.as_ref()))
    else {
        return Ok(None);
    };
    let set = texture.texcoord;
    let Some(accessor) = prim
        .attributes
        .get(&Checked::Valid(Semantic::TexCoords(set)))
    else {
        // One warning per material: a file whose textured material covers
        // many primitives without coordinates would otherwise repeat it.
        let name = &scene.materials[material as usize].name;
        let warning = format!(
            "material '{name}': its textures read TEXCOORD_{set}, which some of its \
             primitives (first {here}) lack; they take the textures' means"
        );
        let prefix = format!("material '{name}': its textures read");
        if !scene.warnings.iter().any(|w| w.starts_with(&prefix)) {
            scene.warnings.push(warning);
        }
        return Ok(None);
    };
    let uv = read_texcoords(src.doc, src.buffers, accessor.value(), src.limits)
        .map_err(|m| gltf_error(src.path, format!("{here}: {m}")))?;
    Ok(Some(uv))
}

/// True when the triangle's area is negligible next to its size.
fn is_degenerate(p: &[DVec3; 3]) -> bool {
    let twice_area = (p[1] - p[0]).cross(p[2] - p[0]).length();
    let longest2 = (p[1] - p[0])
        .length_squared()
        .max((p[2] - p[1]).length_squared())
        .max((p[0] - p[2]).length_squared());
    let significant = 0.5 * twice_area > DEGENERATE_RATIO * longest2;
    !significant
}

/// The triangles of one primitive in world space, with vertex keys for merging,
/// counted in the import stats (degenerate ones included: they are counted and
/// dropped by the caller).
#[allow(clippy::too_many_arguments)]
fn primitive_triangles(
    src: &Source,
    decoded: &mut Decoded,
    prim: &gltf_json::mesh::Primitive,
    mode: Mode,
    here: &str,
    world: &glam::DMat4,
    node_name: &str,
    mirrored: bool,
    scene: &mut Scene,
) -> Result<(Vec<Triangle>, Vec<[usize; 3]>)> {
    let fail = |m: String| gltf_error(src.path, format!("{here}: {m}"));
    let position_accessor = prim
        .attributes
        .get(&Checked::Valid(Semantic::Positions))
        .ok_or_else(|| fail("no POSITION attribute".to_string()))?;
    let positions = decoded
        .positions(src, position_accessor.value())
        .map_err(fail)?;
    if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
        return Err(fail(format!(
            "vertex {k} has a non-finite position {:?}",
            positions[k]
        )));
    }
    let indices = match prim.indices {
        Some(acc) => Some(decoded.indices(src, acc.value()).map_err(fail)?),
        None => None,
    };
    let stream_len = indices.as_ref().map_or(positions.len(), |ix| ix.len());
    let count = triangle_count(mode, stream_len);
    let total = scene.import_stats.triangles_read.saturating_add(count);
    if total > src.limits.max_triangles {
        return Err(Error::limit(
            LimitKind::Triangles,
            format!(
                "{}: {here} brings the triangle count to {total}, more than the limit of {}",
                src.path.display(),
                src.limits.max_triangles
            ),
        ));
    }
    scene.import_stats.triangles_read = total;
    if mode == Mode::Triangles && stream_len % 3 != 0 {
        scene.warnings.push(format!(
            "{here}: {} vertices left over after the last whole triangle",
            stream_len % 3
        ));
    }
    if let Some(ix) = &indices {
        if let Some(k) = ix.iter().position(|&v| v as usize >= positions.len()) {
            return Err(fail(format!(
                "index {} (at position {k} of the index list) is out of range: the primitive has {} vertices",
                ix[k],
                positions.len()
            )));
        }
    }
    // The vertex at position `i` of the stream.
    let vertex_of = |i: usize| indices.as_ref().map_or(i, |ix| ix[i] as usize);
    let keys = vertex_keys(&positions, indices.is_some());
    let world_positions: Vec<DVec3> = positions
        .iter()
        .map(|p| world.transform_point3(*p))
        .collect();
    if let Some(k) = world_positions.iter().position(|p| !p.is_finite()) {
        return Err(fail(format!(
            "vertex {k} leaves the range of double precision when transformed to world space"
        )));
    }
    if let Some(k) = world_positions
        .iter()
        .position(|p| p.abs().max_element() > MAX_COORDINATE)
    {
        return Err(fail(format!(
            "placed by {node_name}, vertex {k} lies at {:?} in world space, beyond +-{MAX_COORDINATE:e} m, \
             the largest coordinate the solver represents (its ray casting is single precision)",
            world_positions[k].to_array()
        )));
    }
    Ok(triangles(mode, stream_len)
        .into_iter()
        .map(|t| {
            let v = t.map(vertex_of);
            let v = if mirrored { [v[0], v[2], v[1]] } else { v };
            let tri = Triangle {
                keys: v.map(|i| keys[i]),
                points: v.map(|i| world_positions[i]),
            };
            (tri, v)
        })
        .unzip())
}

/// Vertex identities for merging. Indexed primitives share vertices through their
/// indices, and only those count as shared (so that separately stored quads do not
/// merge across their common edges). Non-indexed primitives repeat positions, so
/// identical positions are taken as one vertex.
fn vertex_keys(positions: &[DVec3], indexed: bool) -> Vec<u32> {
    if indexed {
        return (0..positions.len() as u32).collect();
    }
    let mut seen: HashMap<[u64; 3], u32> = HashMap::new();
    positions
        .iter()
        .map(|p| {
            let next = seen.len() as u32;
            *seen
                // Adding 0.0 turns -0.0 into 0.0, so both weld.
                .entry([
                    (p.x + 0.0).to_bits(),
                    (p.y + 0.0).to_bits(),
                    (p.z + 0.0).to_bits(),
                ])
                .or_insert(next)
        })
        .collect()
}
