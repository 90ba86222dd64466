//! [`load_baked`]: a baked solution read back as a mesh to render from any
//! camera, without solving again.

use super::accessors::{read_colours, read_indices, read_positions, read_texcoords};
use super::bake_colour::{radiosity_from, SCALE_KEY};
use super::bake_groups::{read_description, BakedGroupInfo};
use super::buffers::load_buffers;
use super::cameras::import_camera;
use super::container::{read_limited, split};
use super::document::{parse, Document};
use super::limits::ImportLimits;
use super::nodes::{walk, Placed};
use super::precise::{number, numbers};
use super::primitives::{triangle_count, triangle_mode, triangles};
use super::texture_use::texture_use;
use super::textures::{Images, Unusable};
use super::{describe, gltf_error};
use crate::error::{Error, GeometryFault, LimitKind, Result};
use crate::math::Rgb;
use crate::render::{ShadedMesh, Texels};
use crate::scene::{Camera, Material};
use glam::{DMat3, DVec2, DVec3};
use gltf_json::mesh::{Primitive, Semantic};
use gltf_json::validation::Checked;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::Path;
use std::rc::Rc;
use std::sync::Arc;

/// A baked solution as read back by [`load_baked`].
#[derive(Clone, Debug, Default)]
pub struct BakedScene {
    /// The file's stem, used for output file names.
    pub name: String,
    /// Every triangle of the default scene in world space, with the *radiance*
    /// (radiosity / pi) of each vertex, ready for [`crate::render`].
    pub mesh: ShadedMesh,
    /// The file's perspective cameras (the first is the default view).
    pub cameras: Vec<Camera>,
    /// The names of the nodes that carried meshes, in the order they were read.
    pub objects: Vec<String>,
    /// The exposure in stops the file's `COLOR_0` was made with (a bake
    /// with light groups), which `radiosity render` uses unless told.
    pub exposure: Option<f64>,
    /// The file's light groups: their names, attributes and scales (empty for
    /// a bake made before light groups).
    pub groups: Vec<BakedGroupInfo>,
    /// Things skipped or ignored, in words a user can act on.
    pub warnings: Vec<String>,
}

/// How one material turns colours into radiosity.
#[derive(Clone, Debug)]
struct BakedMaterial {
    base_colour: Rgb,
    emission: Rgb,
    unlit: bool,
    /// With a base-colour texture: the material the renderer looks up at
    /// every sample (the texture times the base colour factor, and the
    /// emission unless unlit), the colours then being the light.
    texels: Option<Arc<Material>>,
}

/// The glTF default material: white, lit, not emitting.
const DEFAULT_MATERIAL: BakedMaterial = BakedMaterial {
    base_colour: Rgb::ONE,
    emission: Rgb::ZERO,
    unlit: false,
    texels: None,
};

/// Accessors already decoded, so that a mesh placed by many nodes is read once.
#[derive(Default)]
struct Cache {
    positions: HashMap<usize, Rc<Vec<DVec3>>>,
    colours: HashMap<usize, Rc<Vec<[f64; 3]>>>,
    indices: HashMap<usize, Rc<Vec<u32>>>,
}

/// Loads a baked solution (a `.gltf` or `.glb` file with per-vertex radiosity in
/// `COLOR_0`, as [`write_baked`](super::write_baked) writes it).
///
/// - The default scene (else the first, else every parentless node) is walked
///   with node transforms, as [`load_scene`](super::load_scene) does; every
///   triangle-mode primitive (lists, strips, fans; indexed or not) must carry
///   `COLOR_0`. Point and line primitives are skipped with a warning.
/// - The radiosity of a vertex is `radiosityScale * baseColorFactor * COLOR_0`
///   (the scale from the primitive's `extras`, 1 if absent), plus, unless the
///   material is unlit (`KHR_materials_unlit`), its emitted exitance
///   `pi * emissiveFactor * emissiveStrength`. That gives back the solution's
///   radiosity. The mesh holds radiance, radiosity / pi.
/// - A base-colour texture (read through its texture coordinate set, sampler
///   and `KHR_texture_transform`) multiplies `baseColorFactor` at every
///   sample: such primitives carry the light `radiosityScale * COLOR_0 / pi`
///   per vertex and their material in [`ShadedMesh::texels`]. A texture that
///   cannot be used, or a primitive without its coordinates, is ignored with
///   a warning, as are emissive textures.
/// - Perspective cameras are read as the scene importer reads them.
///
/// # Errors
///
/// [`Error::Io`] if the file cannot be read; [`Error::Gltf`] naming the file and
/// the mesh, material or accessor for anything malformed, including a triangle
/// primitive without `COLOR_0` (the file is not a baked solution), a colour
/// count that differs from the position count, a scale that is not a positive
/// number, or non-finite values; [`Error::Limit`] when the file exceeds
/// `limits`; [`Error::Geometry`] when the scene has no triangles. Never panics.
pub fn load_baked(path: &Path, limits: &ImportLimits) -> Result<BakedScene> {
    let bytes = read_limited(path, limits)?;
    let container = split(path, bytes)?;
    let mut out = BakedScene {
        mesh: ShadedMesh {
            cull_back_faces: true,
            ..ShadedMesh::default()
        },
        name: path
            .file_stem()
            .map_or_else(|| "baked".to_string(), |s| s.to_string_lossy().into_owned()),
        ..BakedScene::default()
    };
    let doc = parse(path, &container.json, &mut out.warnings)?;
    (out.exposure, out.groups) = read_description(path, &doc)?;
    let buffers = load_buffers(path, &doc, container.bin, limits)?;
    let mut images = Images::new(&doc, &buffers, path, limits);
    let materials = read_materials(path, &doc, &mut images, &mut out.warnings)?;
    let mut reader = Reader {
        path,
        doc: &doc,
        buffers: &buffers,
        limits,
        materials: &materials,
        cache: Cache::default(),
        triangles_read: 0,
        groups: &out.groups.clone(),
    };
    for placed in walk(path, &doc, limits)? {
        let node = &doc.root.nodes[placed.node];
        if let Some(camera) = node.camera {
            match import_camera(&doc, camera.value(), placed.node, &placed.world) {
                Ok(c) => out.cameras.push(c),
                Err(warning) => out.warnings.push(warning),
            }
        }
        if let Some(mesh) = node.mesh {
            reader.add_mesh(&placed, mesh.value(), &mut out)?;
        }
    }
    if out.mesh.triangles.is_empty() {
        return Err(Error::geometry(
            GeometryFault::NoSurfaces,
            format!(
                "{}: the baked file has no triangles in any mesh of the scene's nodes",
                path.display()
            ),
        ));
    }
    if let Err(e) = out.mesh.validate() {
        return Err(gltf_error(path, e.to_string()));
    }
    Ok(out)
}

/// Every material's base colour, emission, unlit flag and base-colour
/// texture, in the file's order.
fn read_materials(
    path: &Path,
    doc: &Document,
    images: &mut Images,
    warnings: &mut Vec<String>,
) -> Result<Vec<BakedMaterial>> {
    let mut out = Vec::with_capacity(doc.root.materials.len());
    for (i, m) in doc.root.materials.iter().enumerate() {
        let what = describe("material", i, m.name.as_deref());
        let base = format!("/materials/{i}");
        let rgba = numbers::<4>(
            &doc.raw,
            &format!("{base}/pbrMetallicRoughness/baseColorFactor"),
        )
        .unwrap_or([1.0; 4]);
        let factor = numbers::<3>(&doc.raw, &format!("{base}/emissiveFactor")).unwrap_or([0.0; 3]);
        let strength = number(
            &doc.raw,
            &format!("{base}/extensions/KHR_materials_emissive_strength/emissiveStrength"),
        )
        .unwrap_or(1.0);
        let mut material = BakedMaterial {
            base_colour: Rgb::new(rgba[0], rgba[1], rgba[2]),
            emission: Rgb(factor) * strength * PI,
            unlit: doc
                .raw
                .pointer(&format!("{base}/extensions/KHR_materials_unlit"))
                .is_some(),
            texels: None,
        };
        let usable = |c: Rgb| c.is_finite() && c.min_band() >= 0.0;
        if !usable(material.base_colour) || !usable(material.emission) {
            return Err(gltf_error(
                path,
                format!(
                    "{what}: base colour {:?} or emission {:?} is negative or not finite",
                    material.base_colour.0, material.emission.0
                ),
            ));
        }
        if let Some(info) = &m.pbr_metallic_roughness.base_color_texture {
            match images.for_texture(info.index.value()) {
                Ok(image) => {
                    let pointer = format!("{base}/pbrMetallicRoughness/baseColorTexture");
                    let texture = texture_use(
                        doc,
                        &pointer,
                        info,
                        image,
                        material.base_colour,
                        f64::INFINITY,
                    );
                    material.texels = Some(Arc::new(Material {
                        name: what.clone(),
                        reflectance: material.base_colour,
                        base_texture: Some(Arc::new(texture)),
                        emission: if material.unlit {
                            Rgb::ZERO
                        } else {
                            material.emission
                        },
                        emissive_texture: None,
                        double_sided: false,
                    }));
                }
                Err(Unusable::Ignored(why)) => warnings.push(format!(
                    "{what}: base colour texture ignored ({why}); the vertex colours and \
                     factors alone give the radiosity"
                )),
                Err(Unusable::Refused(e)) => return Err(e),
            }
        }
        if m.emissive_texture.is_some() {
            warnings.push(format!(
                "{what}: emissive texture ignored; emissiveFactor alone gives the emission"
            ));
        }
        out.push(material);
    }
    Ok(out)
}

/// What reading the meshes needs, and the triangle count so far.
struct Reader<'a> {
    path: &'a Path,
    doc: &'a Document,
    buffers: &'a [Vec<u8>],
    limits: &'a ImportLimits,
    materials: &'a [BakedMaterial],
    cache: Cache,
    triangles_read: usize,
    /// The light groups whose sum is each vertex's value (empty: a version 1
    /// bake, whose `COLOR_0` times the primitive's scale is).
    groups: &'a [BakedGroupInfo],
}

impl Reader<'_> {
    /// Adds every triangle primitive of mesh `mesh_index`, placed by `placed`.
    fn add_mesh(&mut self, placed: &Placed, mesh_index: usize, out: &mut BakedScene) -> Result<()> {
        let doc = self.doc;
        let node = &doc.root.nodes[placed.node];
        let mesh =
            doc.root.meshes.get(mesh_index).ok_or_else(|| {
                gltf_error(self.path, format!("mesh {mesh_index} does not exist"))
            })?;
        let mesh_name = describe("mesh", mesh_index, mesh.name.as_deref());
        out.objects.push(
            [node.name.as_deref(), mesh.name.as_deref()]
                .into_iter()
                .flatten()
                .find(|n| !n.is_empty())
                .map_or_else(|| format!("node {}", placed.node), str::to_string),
        );
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let here = format!("{mesh_name} primitive {p}");
            self.add_primitive(placed, mesh_index, p, prim, &here, out)?;
        }
        Ok(())
    }

    fn add_primitive(
        &mut self,
        placed: &Placed,
        mesh_index: usize,
        p: usize,
        prim: &Primitive,
        here: &str,
        out: &mut BakedScene,
    ) -> Result<()> {
        let path = self.path;
        let fail = |m: String| gltf_error(path, format!("{here}: {m}"));
        let mode = match prim.mode {
            Checked::Valid(m) => m,
            Checked::Invalid => return Err(fail("invalid mode".to_string())),
        };
        let Some(mode) = triangle_mode(mode) else {
            out.warnings
                .push(format!("{here} draws {mode:?}, not triangles: skipped"));
            return Ok(());
        };
        let attribute = |semantic: Semantic| {
            prim.attributes
                .get(&Checked::Valid(semantic))
                .map(|a| a.value())
        };
        let position_accessor =
            attribute(Semantic::Positions).ok_or_else(|| fail("no POSITION attribute".into()))?;
        let colour_accessor = attribute(Semantic::Colors(0)).ok_or_else(|| {
            fail("no COLOR_0 attribute: this is not a baked solution (one written by `radiosity bake`)".into())
        })?;
        // Count the triangles from the declared sizes before decoding anything.
        let declared = |a: usize| self.doc.root.accessors.get(a).map_or(0, |a| a.count.0);
        let stream_len = prim
            .indices
            .map_or(declared(position_accessor), |i| declared(i.value()));
        let count = triangle_count(mode, usize::try_from(stream_len).unwrap_or(usize::MAX));
        let total = self.triangles_read.saturating_add(count);
        if total > self.limits.max_triangles {
            return Err(Error::limit(
                LimitKind::Triangles,
                format!(
                    "{}: {here} brings the triangle count to {total}, more than the limit of {}",
                    self.path.display(),
                    self.limits.max_triangles
                ),
            ));
        }
        self.triangles_read = total;

        let positions = self.positions(position_accessor).map_err(&fail)?;
        let colours = self.colours(colour_accessor).map_err(&fail)?;
        if colours.len() != positions.len() {
            return Err(fail(format!(
                "COLOR_0 has {} values for {} positions",
                colours.len(),
                positions.len()
            )));
        }
        // A bake with light groups: each vertex's value is their sum.
        let colours = if self.groups.is_empty() {
            colours
        } else {
            Rc::new(self.group_sum(prim, positions.len()).map_err(&fail)?)
        };
        let indices = match prim.indices {
            Some(acc) => Some(self.indices(acc.value()).map_err(&fail)?),
            None => None,
        };
        let stream_len = indices.as_ref().map_or(positions.len(), |ix| ix.len());
        if let Some(ix) = &indices {
            if let Some(k) = ix.iter().position(|&v| v as usize >= positions.len()) {
                return Err(fail(format!(
                    "index {} (at position {k} of the index list) is out of range: the primitive has {} vertices",
                    ix[k],
                    positions.len()
                )));
            }
        }
        let material = match prim.material {
            Some(m) => self
                .materials
                .get(m.value())
                .ok_or_else(|| fail(format!("material {} does not exist", m.value())))?
                .clone(),
            None => DEFAULT_MATERIAL,
        };
        let texels = match &material.texels {
            Some(m) => self.texels(prim, m, positions.len(), here, out)?,
            None => None,
        };
        let scale_at = format!("/meshes/{mesh_index}/primitives/{p}/extras/{SCALE_KEY}");
        let scale = match self.doc.raw.pointer(&scale_at) {
            _ if !self.groups.is_empty() => 1.0,
            None => 1.0,
            Some(v) => v
                .as_f64()
                .filter(|s| s.is_finite() && *s > 0.0)
                .ok_or_else(|| fail(format!("extras.{SCALE_KEY} {v} is not a positive number")))?,
        };

        // Only vertices that triangles use are kept: bounded by the triangle
        // limit, however large the accessors they come from.
        let world = &placed.world;
        let mut number: HashMap<usize, u32> = HashMap::new();
        let mut vertex = |i: usize, out: &mut BakedScene| -> Result<u32> {
            let v = indices.as_ref().map_or(i, |ix| ix[i] as usize);
            if let Some(&n) = number.get(&v) {
                return Ok(n);
            }
            let position = world.transform_point3(positions[v]);
            // On a textured primitive the value is the light, which the
            // texture (times the factor) multiplies at every sample.
            let b = match &texels {
                Some(_) => Rgb(colours[v]) * scale,
                None => radiosity_from(
                    Rgb(colours[v]),
                    scale,
                    material.base_colour,
                    material.emission,
                    material.unlit,
                ),
            };
            if !position.is_finite() || !b.is_finite() {
                return Err(fail(format!(
                    "vertex {v} has a non-finite position or radiosity in world space"
                )));
            }
            let n = u32::try_from(out.mesh.positions.len())
                .map_err(|_| fail("more vertices than 32-bit indices can number".to_string()))?;
            out.mesh.positions.push(position);
            out.mesh.values.push(b / PI);
            if let Some(t) = &mut out.mesh.texels {
                t.uv.push(texels.as_ref().map_or(DVec2::ZERO, |(uv, _)| uv[v]));
            }
            number.insert(v, n);
            Ok(n)
        };
        // A mirroring transform turns counter-clockwise triangles clockwise.
        let mirrored = DMat3::from_mat4(*world).determinant() < 0.0;
        for t in triangles(mode, stream_len) {
            let v = [vertex(t[0], out)?, vertex(t[1], out)?, vertex(t[2], out)?];
            out.mesh
                .triangles
                .push(if mirrored { [v[0], v[2], v[1]] } else { v });
            if let Some(t) = &mut out.mesh.texels {
                t.materials
                    .push(texels.as_ref().map(|(_, m)| Arc::clone(m)));
            }
        }
        Ok(())
    }

    /// The texture coordinates of a primitive whose material `material` has a
    /// base-colour texture, and the material, starting the mesh's texels if
    /// this is the first; `None` (with a warning) when the primitive lacks the
    /// coordinate set or has fewer coordinates than positions.
    fn texels(
        &self,
        prim: &Primitive,
        material: &Arc<Material>,
        count: usize,
        here: &str,
        out: &mut BakedScene,
    ) -> Result<Option<(Vec<DVec2>, Arc<Material>)>> {
        let set = material.base_texture.as_ref().map_or(0, |t| t.texcoord);
        let accessor = prim
            .attributes
            .get(&Checked::Valid(Semantic::TexCoords(set)))
            .map(|a| a.value());
        let uv = match accessor.map(|a| read_texcoords(self.doc, self.buffers, a, self.limits)) {
            Some(Ok(uv)) if uv.len() == count && uv.iter().all(|t| t.is_finite()) => uv,
            Some(Err(m)) => return Err(gltf_error(self.path, format!("{here}: {m}"))),
            _ => {
                out.warnings.push(format!(
                    "{here}: no usable TEXCOORD_{set} for its material's texture: drawn \
                     without the texture"
                ));
                return Ok(None);
            }
        };
        if out.mesh.texels.is_none() {
            out.mesh.texels = Some(Texels {
                uv: vec![DVec2::ZERO; out.mesh.positions.len()],
                materials: vec![None; out.mesh.triangles.len()],
            });
        }
        Ok(Some((uv, Arc::clone(material))))
    }

    /// Per vertex of `prim` (`count` of them), the sum of its light groups'
    /// attributes times their scales.
    fn group_sum(
        &mut self,
        prim: &Primitive,
        count: usize,
    ) -> std::result::Result<Vec<[f64; 3]>, String> {
        let mut sum = vec![[0.0; 3]; count];
        for g in self.groups {
            let name = g.attribute.strip_prefix('_').unwrap_or(&g.attribute);
            let accessor = prim
                .attributes
                .get(&Checked::Valid(Semantic::Extras(name.to_string())))
                .map(|a| a.value())
                .ok_or_else(|| {
                    format!(
                        "no {} attribute for the light group '{}'",
                        g.attribute, g.name
                    )
                })?;
            let values = self.colours(accessor)?;
            if values.len() != count {
                return Err(format!(
                    "{} has {} values for {count} positions",
                    g.attribute,
                    values.len()
                ));
            }
            for (s, v) in sum.iter_mut().zip(values.iter()) {
                for k in 0..3 {
                    s[k] += v[k] * g.scale;
                }
            }
        }
        Ok(sum)
    }

    fn positions(&mut self, a: usize) -> std::result::Result<Rc<Vec<DVec3>>, String> {
        if let Some(p) = self.cache.positions.get(&a) {
            return Ok(Rc::clone(p));
        }
        let p = Rc::new(read_positions(self.doc, self.buffers, a, self.limits)?);
        self.cache.positions.insert(a, Rc::clone(&p));
        Ok(p)
    }

    fn colours(&mut self, a: usize) -> std::result::Result<Rc<Vec<[f64; 3]>>, String> {
        if let Some(c) = self.cache.colours.get(&a) {
            return Ok(Rc::clone(c));
        }
        let c = Rc::new(read_colours(self.doc, self.buffers, a, self.limits)?);
        self.cache.colours.insert(a, Rc::clone(&c));
        Ok(c)
    }

    fn indices(&mut self, a: usize) -> std::result::Result<Rc<Vec<u32>>, String> {
        if let Some(ix) = self.cache.indices.get(&a) {
            return Ok(Rc::clone(ix));
        }
        let ix = Rc::new(read_indices(self.doc, self.buffers, a, self.limits)?);
        self.cache.indices.insert(a, Rc::clone(&ix));
        Ok(ix)
    }
}
