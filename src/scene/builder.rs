//! Building scenes in code: materials, objects, quads, triangles and boxes.

use super::{Camera, Light, Material, Object, Overlaps, Scene, Surface};
use crate::error::{Error, GeometryFault, Result};
use crate::math::{planarity_error, Rgb};
use glam::DVec3;

/// Assembles a [`Scene`] from materials, named objects and polygons. Quads that are
/// not planar are split into two triangles (so that measured data such as the
/// Cornell box's slightly warped wall is usable as published). Coplanar
/// overlaps are resolved when the scene is built (see [`SceneBuilder::overlaps`]).
#[derive(Debug)]
pub struct SceneBuilder {
    scene: Scene,
    current_object: Option<u32>,
    overlaps: Option<Overlaps>,
}

impl Default for SceneBuilder {
    fn default() -> Self {
        SceneBuilder::new("scene")
    }
}

impl SceneBuilder {
    /// An empty scene called `name`.
    #[must_use]
    pub fn new(name: &str) -> Self {
        SceneBuilder {
            scene: Scene {
                name: name.to_string(),
                ..Scene::default()
            },
            current_object: None,
            overlaps: Some(Overlaps::Resolve),
        }
    }

    /// What [`build`](Self::build) does with coplanar surfaces that overlap,
    /// facing the same way ([`Scene::resolve_overlaps`]): resolve them (the
    /// default), refuse them, or with `None` leave the surfaces as they were
    /// added (the solve still refuses pairs whose materials differ).
    pub fn overlaps(&mut self, policy: Option<Overlaps>) -> &mut Self {
        self.overlaps = policy;
        self
    }

    /// Adds a material from reflectance and emitted radiance (glTF's convention);
    /// returns its index.
    pub fn material(&mut self, name: &str, reflectance: Rgb, radiance: Rgb) -> Result<u32> {
        let m = Material::from_radiance(name, reflectance, radiance)?;
        self.scene.materials.push(m);
        Ok(self.scene.materials.len() as u32 - 1)
    }

    /// Starts a new named object; later polygons belong to it.
    pub fn object(&mut self, name: &str) -> u32 {
        self.scene.objects.push(Object {
            name: name.to_string(),
        });
        let id = self.scene.objects.len() as u32 - 1;
        self.current_object = Some(id);
        id
    }

    fn object_id(&mut self) -> u32 {
        match self.current_object {
            Some(o) => o,
            None => self.object("object"),
        }
    }

    /// Adds a planar polygon of 3 or 4 vertices, counter-clockwise seen from the
    /// front. A non-planar quad becomes two triangles split along its shorter
    /// diagonal.
    pub fn polygon(&mut self, material: u32, vertices: &[DVec3]) -> Result<()> {
        if material as usize >= self.scene.materials.len() {
            return Err(Error::geometry(
                GeometryFault::Mismatch,
                format!(
                    "polygon refers to material {material}, but the scene has {}",
                    self.scene.materials.len()
                ),
            ));
        }
        let object = self.object_id();
        if vertices.len() == 4 && planarity_error(vertices) > super::surface::PLANARITY_TOLERANCE {
            let v = vertices;
            let (t1, t2) = if (v[0] - v[2]).length() <= (v[1] - v[3]).length() {
                ([v[0], v[1], v[2]], [v[0], v[2], v[3]])
            } else {
                ([v[0], v[1], v[3]], [v[1], v[2], v[3]])
            };
            self.scene
                .surfaces
                .push(Surface::new(&t1, material, object)?);
            self.scene
                .surfaces
                .push(Surface::new(&t2, material, object)?);
            return Ok(());
        }
        self.scene
            .surfaces
            .push(Surface::new(vertices, material, object)?);
        Ok(())
    }

    /// Adds a quad `a b c d` (counter-clockwise seen from the front).
    pub fn quad(&mut self, material: u32, a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Result<()> {
        self.polygon(material, &[a, b, c, d])
    }

    /// Adds a triangle `a b c` (counter-clockwise seen from the front).
    pub fn triangle(&mut self, material: u32, a: DVec3, b: DVec3, c: DVec3) -> Result<()> {
        self.polygon(material, &[a, b, c])
    }

    /// Adds the six outward-facing faces of an axis-aligned box as one object.
    pub fn axis_box(&mut self, name: &str, material: u32, lo: DVec3, hi: DVec3) -> Result<()> {
        self.object(name);
        let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let (a, b) = (lo, hi);
        // -x, +x, -y, +y, -z, +z faces, each counter-clockwise seen from outside.
        self.quad(
            material,
            p(a.x, a.y, a.z),
            p(a.x, a.y, b.z),
            p(a.x, b.y, b.z),
            p(a.x, b.y, a.z),
        )?;
        self.quad(
            material,
            p(b.x, a.y, a.z),
            p(b.x, b.y, a.z),
            p(b.x, b.y, b.z),
            p(b.x, a.y, b.z),
        )?;
        self.quad(
            material,
            p(a.x, a.y, a.z),
            p(b.x, a.y, a.z),
            p(b.x, a.y, b.z),
            p(a.x, a.y, b.z),
        )?;
        self.quad(
            material,
            p(a.x, b.y, a.z),
            p(a.x, b.y, b.z),
            p(b.x, b.y, b.z),
            p(b.x, b.y, a.z),
        )?;
        self.quad(
            material,
            p(a.x, a.y, a.z),
            p(a.x, b.y, a.z),
            p(b.x, b.y, a.z),
            p(b.x, a.y, a.z),
        )?;
        self.quad(
            material,
            p(a.x, a.y, b.z),
            p(b.x, a.y, b.z),
            p(b.x, b.y, b.z),
            p(a.x, b.y, b.z),
        )?;
        Ok(())
    }

    /// Adds a camera.
    pub fn camera(&mut self, camera: Camera) {
        self.scene.cameras.push(camera);
    }

    /// Adds a warning to the scene.
    pub fn warn(&mut self, message: String) {
        self.scene.warnings.push(message);
    }

    /// Adds a punctual light (see [`Light`]), checked first: an error names
    /// the light and the value out of range.
    pub fn light(&mut self, light: Light) -> Result<()> {
        light.validate()?;
        self.scene.lights.push(light);
        Ok(())
    }

    /// Finishes the scene, resolving or refusing coplanar overlaps as
    /// [`overlaps`](Self::overlaps) says; fails if it has no surfaces.
    pub fn build(self) -> Result<Scene> {
        let mut scene = self.scene;
        if scene.surfaces.is_empty() {
            return Err(Error::geometry(
                GeometryFault::NoSurfaces,
                format!("scene '{}' has no surfaces", scene.name),
            ));
        }
        if let Some(policy) = self.overlaps {
            scene.resolve_overlaps(policy)?;
        }
        let far = scene.outlier_warning();
        scene.warnings.extend(far);
        Ok(scene)
    }
}
