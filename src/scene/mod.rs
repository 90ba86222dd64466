//! The scene: planar surfaces with diffuse materials, grouped into named objects,
//! punctual lights, and the cameras to view them. Built by the glTF importer or
//! by [`SceneBuilder`]. Units: see [`Light`]'s module notes (emitted radiance in
//! cd/m², point and spot intensity in candela, directional illuminance in lux;
//! radiosity in lm/m²).

mod builder;
mod camera;
mod coincident_lights;
mod extent;
mod facing;
mod framing;
mod light;
pub(crate) mod light_groups;
mod linear_image;
mod material;
mod overlaps;
pub(crate) mod rays;
mod regions;
mod room_view;
mod rooms;
mod sky;
mod surface;
mod texture;

pub use builder::SceneBuilder;
pub use camera::Camera;
pub(crate) use coincident_lights::merge_coincident_lights;
pub use extent::Outliers;
pub(crate) use facing::facing_warnings;
pub use light::{Incident, Light, LightKind, Target};
pub use linear_image::LinearImage;
pub use material::{Material, MAX_CONTRACTION};
pub(crate) use overlaps::check_coplanar_overlaps;
pub use overlaps::{Overlaps, COPLANAR_GAP};
pub(crate) use rooms::Tracer;
pub use sky::{sun, Sky, SkyModel};
pub use surface::{Surface, MAX_COORDINATE};
pub(crate) use texture::uv_transform;
pub use texture::{Texture, Wrap, EMISSION_DEPTH, FOOTPRINT_SAMPLES, SHARP_CONTRAST};

use glam::DVec3;
use serde::Serialize;

/// A named group of surfaces: one glTF node that carries a mesh. Per-object figures
/// (area, mean radiosity) are what the stats report as `surfaces`.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// The node's name, else its mesh's, else its index.
    pub name: String,
}

/// Counts kept by the importer so that nothing it drops goes unreported.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ImportStats {
    /// Triangles read from the file, before merging and skipping.
    pub triangles_read: usize,
    /// Triangles skipped because they have (near) zero area.
    pub degenerate_triangles: usize,
    /// Pairs of coplanar triangles merged into one quad surface.
    pub merged_quads: usize,
    /// Primitives of point or line modes, skipped.
    pub skipped_primitives: usize,
    /// Images read and decoded for textures (each at most once per file).
    pub images_decoded: usize,
    /// `KHR_lights_punctual` lights placed by the scene's nodes (one per
    /// node that refers to a light), as in [`Scene::lights`].
    pub punctual_lights: usize,
    /// Pixels of those images, counted against
    /// [`ImportLimits::max_texture_pixels`](crate::gltf_io::ImportLimits::max_texture_pixels).
    pub texture_pixels: u64,
    /// Pairs of coplanar surfaces that overlapped, facing the same way, and
    /// were resolved (see [`Scene::resolve_overlaps`]), duplicates excluded.
    pub overlapping_pairs: usize,
    /// Surfaces dropped as coincident duplicates of a surface on top of them.
    pub duplicate_surfaces: usize,
    /// Pieces of cut surfaces thinner than the coplanar gap, dropped.
    pub sliver_pieces_dropped: usize,
}

/// A scene ready to mesh: every surface is a planar triangle or convex quad, front
/// face counter-clockwise around its normal.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// A short name, used for output file names.
    pub name: String,
    /// The materials surfaces refer to by index.
    pub materials: Vec<Material>,
    /// The named objects surfaces belong to.
    pub objects: Vec<Object>,
    /// The planar surfaces. A double-sided glTF surface appears twice, back to back.
    pub surfaces: Vec<Surface>,
    /// Punctual lights (point, spot, directional): sources outside the mesh,
    /// whose direct light enters the solution as its first reflection.
    pub lights: Vec<Light>,
    /// A sky over the scene (see [`Sky`]): a source at infinity whose light
    /// each surface receives where nothing hides the sky from it.
    pub sky: Option<Sky>,
    /// Cameras found in the file (the first is the default view).
    pub cameras: Vec<Camera>,
    /// Things the importer skipped or changed, in words a user can act on.
    pub warnings: Vec<String>,
    /// What the importer counted.
    pub import_stats: ImportStats,
}

impl Scene {
    /// The axis-aligned bounds of all surfaces (min, max).
    #[must_use]
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for s in &self.surfaces {
            for v in &s.vertices {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
        }
        (lo, hi)
    }

    /// The length of the bounding box diagonal of every surface. Defaults
    /// that scale with the scene follow [`Scene::extent`] instead, which
    /// leaves out far outliers.
    #[must_use]
    pub fn diameter(&self) -> f64 {
        let (lo, hi) = self.bounds();
        if lo.x <= hi.x {
            (hi - lo).length()
        } else {
            0.0
        }
    }

    /// The material of surface `s`.
    #[must_use]
    pub fn material_of(&self, s: &Surface) -> &Material {
        &self.materials[s.material as usize]
    }

    /// True when something in the scene gives light: a surface whose
    /// material emits, or a punctual light of some intensity.
    #[must_use]
    pub fn has_light(&self) -> bool {
        self.sky.is_some_and(|s| s.zenith.max_band() > 0.0)
            || self.lights.iter().any(Light::shines)
            || self
                .surfaces
                .iter()
                .any(|s| self.material_of(s).is_emitter())
    }

    /// Fails with [`Error::NoLight`](crate::Error::NoLight) when nothing in
    /// the scene gives light: the solution would be black everywhere. The
    /// message says what would give light, and names punctual lights of no
    /// intensity when the scene has some.
    pub fn check_light(&self) -> crate::Result<()> {
        if self.has_light() {
            return Ok(());
        }
        let mut message = format!(
            "scene '{}' has no light: no material emits (every emissiveFactor is zero or \
             absent) and no punctual light shines, so every surface would be black",
            self.name
        );
        match self.lights.len() {
            0 => message.push_str(
                "; give a lamp, window or sky surface a material with an emissiveFactor \
                 (and KHR_materials_emissive_strength for more than 1), or add a \
                 KHR_lights_punctual light",
            ),
            _ => {
                let names: Vec<String> = self
                    .lights
                    .iter()
                    .take(5)
                    .map(|l| format!("'{}'", l.name))
                    .collect();
                message.push_str(&format!(
                    "; its {} punctual lights ({}) have intensity or colour 0",
                    self.lights.len(),
                    names.join(", ")
                ));
            }
        }
        // A model exported before anyone lit it (common in architecture)
        // is lit by daylight instead.
        message.push_str("; or light it with daylight (`sky`, `sun`)");
        let dark_lights = self
            .lights
            .iter()
            .filter(|l| !l.shines())
            .map(|l| l.name.clone())
            .collect();
        Err(crate::Error::NoLight {
            scene: self.name.clone(),
            dark_lights,
            message,
        })
    }

    /// Checks every punctual light ([`Light::validate`]).
    pub(crate) fn check_lights(&self) -> crate::Result<()> {
        if let Some(sky) = &self.sky {
            sky.validate()?;
        }
        self.lights.iter().try_for_each(Light::validate)
    }

    /// Fails with [`Error::Material`](crate::Error::Material) naming the first
    /// material in use whose reflectance exceeds
    /// [`MAX_CONTRACTION`]: the solver would
    /// refuse it only after the form factors (the glTF importer clamps such
    /// materials; a scene built in code keeps the values it was given).
    pub(crate) fn check_reflectance(&self) -> crate::Result<()> {
        let limit = MAX_CONTRACTION;
        let mut used = vec![false; self.materials.len()];
        for s in &self.surfaces {
            used[s.material as usize] = true;
        }
        let too_bright = self
            .materials
            .iter()
            .zip(used)
            .find(|(m, used)| *used && m.reflectance.max_band() > limit);
        match too_bright {
            None => Ok(()),
            Some((m, _)) => Err(crate::Error::Material {
                material: m.name.clone(),
                message: format!(
                    "reflectance {:?} is above {limit}, the most the solver takes: light \
                     would bounce for ever in any closed part of the scene; lower it (0.95 \
                     is as white as paint gets)",
                    m.reflectance.0
                ),
            }),
        }
    }

    /// Runs [`Material::validate`] on every material a surface uses: a
    /// material built field by field skips the check
    /// [`Material::from_radiance`] makes (a subnormal emission, for one,
    /// would stall the solve).
    pub(crate) fn check_materials(&self) -> crate::Result<()> {
        let mut used = vec![false; self.materials.len()];
        for s in &self.surfaces {
            used[s.material as usize] = true;
        }
        self.materials
            .iter()
            .zip(used)
            .filter(|(_, used)| *used)
            .try_for_each(|(m, _)| m.validate())
    }

    /// Treats every surface as two-sided: each surface of a material not yet
    /// double-sided gets a copy facing the other way, right after it (as the
    /// importer adds `doubleSided` surfaces), and every material is marked
    /// double-sided.
    pub fn make_double_sided(&mut self) {
        let surfaces = std::mem::take(&mut self.surfaces);
        for s in surfaces {
            let back = (!self.material_of(&s).double_sided).then(|| s.flipped());
            self.surfaces.push(s);
            self.surfaces.extend(back);
        }
        for m in &mut self.materials {
            m.double_sided = true;
        }
    }

    /// Total area of every surface.
    #[must_use]
    pub fn total_area(&self) -> f64 {
        self.surfaces.iter().map(|s| s.area).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::{Light, SceneBuilder};
    use crate::math::Rgb;
    use crate::Error;
    use glam::DVec3;

    #[test]
    fn a_dark_punctual_light_is_named_in_no_light() {
        let mut b = SceneBuilder::new("dark room");
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("floor");
        b.quad(
            m,
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 0.0),
        )
        .unwrap();
        b.light(Light::point(
            "off lamp",
            DVec3::new(0.5, 1.0, 0.5),
            Rgb::splat(1.0),
            0.0,
        ))
        .unwrap();
        let scene = b.build().unwrap();
        let e = scene.check_light().unwrap_err();
        let Error::NoLight {
            scene: name,
            dark_lights,
            message,
        } = &e
        else {
            panic!("expected NoLight, got {e}");
        };
        assert_eq!(name, "dark room");
        assert_eq!(dark_lights, &["off lamp".to_string()]);
        assert_eq!(e.to_string(), *message);
        assert!(message.contains("'off lamp'"), "{message}");
    }
}
