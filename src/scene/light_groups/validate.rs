//! Checking that light groups partition a scene's sources.

use super::spec::LightGroups;
use super::spec::{describe, sources, Source};
use crate::error::{Error, Result};
use crate::scene::Scene;

impl LightGroups {
    /// Checks that the groups partition the sources of `scene`: every
    /// emitting surface, every punctual light and the sky in exactly one group, no
    /// index out of range, no group empty, names unique and not empty.
    ///
    /// # Errors
    ///
    /// [`Error::Setting`] (named `light_groups`) naming the group and the
    /// surface or light at fault.
    pub fn validate(&self, scene: &Scene) -> Result<()> {
        let bad = |message: String| {
            Err(Error::Setting {
                name: "light_groups",
                message,
            })
        };
        let mut surface_group: Vec<Option<usize>> = vec![None; scene.surfaces.len()];
        let mut light_group: Vec<Option<usize>> = vec![None; scene.lights.len()];
        let mut sky_group: Option<usize> = None;
        for (i, g) in self.groups.iter().enumerate() {
            if g.name.trim().is_empty() {
                return bad(format!("group {} has no name", i + 1));
            }
            if self.groups[..i].iter().any(|h| h.name == g.name) {
                return bad(format!("two groups are named '{}'", g.name));
            }
            if g.is_empty() {
                return bad(format!("the group '{}' holds no source", g.name));
            }
            for &s in &g.surfaces {
                let Some(slot) = surface_group.get_mut(s as usize) else {
                    return bad(format!(
                        "the group '{}' holds surface {s}, but scene '{}' has {}",
                        g.name,
                        scene.name,
                        scene.surfaces.len()
                    ));
                };
                let surface = &scene.surfaces[s as usize];
                let material = scene.material_of(surface);
                if !material.is_emitter() {
                    return bad(format!(
                        "the group '{}' holds surface {s} of object '{}', whose material '{}' \
                         emits nothing",
                        g.name, scene.objects[surface.object as usize].name, material.name
                    ));
                }
                if let Some(other) = slot.replace(i) {
                    return bad(format!(
                        "surface {s} (material '{}') is in both '{}' and '{}'",
                        material.name, self.groups[other].name, g.name
                    ));
                }
            }
            for &l in &g.lights {
                let Some(slot) = light_group.get_mut(l as usize) else {
                    return bad(format!(
                        "the group '{}' holds light {l}, but scene '{}' has {}",
                        g.name,
                        scene.name,
                        scene.lights.len()
                    ));
                };
                if let Some(other) = slot.replace(i) {
                    return bad(format!(
                        "the light {} is in both '{}' and '{}'",
                        scene.lights[l as usize].name, self.groups[other].name, g.name
                    ));
                }
            }
            if g.sky {
                if scene.sky.is_none() {
                    return bad(format!(
                        "the group '{}' holds the sky, but scene '{}' has none",
                        g.name, scene.name
                    ));
                }
                if let Some(other) = sky_group.replace(i) {
                    return bad(format!(
                        "the sky is in both '{}' and '{}'",
                        self.groups[other].name, g.name
                    ));
                }
            }
        }
        for source in sources(scene) {
            let missing = match source {
                Source::Surface(s) => surface_group[s as usize].is_none(),
                Source::Light(l) => light_group[l as usize].is_none(),
                Source::Sky => sky_group.is_none(),
            };
            if missing {
                return bad(format!(
                    "the {} is in no group: the groups would not add up to the whole light",
                    describe(scene, source)
                ));
            }
        }
        Ok(())
    }
}
