//! A scene with its light groups' emission scaled: what a mix of the
//! groups stands for, to solve anew and compare.

use super::spec::LightGroups;
use crate::error::{Error, Result};
use crate::math::Rgb;
use crate::scene::Scene;
use std::collections::HashMap;

impl LightGroups {
    /// `scene` with each group's sources scaled per band by its entry of
    /// `factors` (one per group): its surfaces' emission (and emissive
    /// textures), its lights' colour and the sky's radiance. A material shared by surfaces of
    /// different groups is copied for each. A new solve of the result is
    /// what a mix of the groups with those factors stands for.
    ///
    /// # Errors
    ///
    /// [`Error::Setting`] (named `light_groups`) when the groups do not fit
    /// `scene` (see [`Self::validate`]), `factors` has the wrong length, or
    /// a factor is negative or not finite.
    pub fn scaled_scene(&self, scene: &Scene, factors: &[Rgb]) -> Result<Scene> {
        self.validate(scene)?;
        if factors.len() != self.groups.len() {
            return Err(Error::Setting {
                name: "light_groups",
                message: format!(
                    "{} factors for {} light groups",
                    factors.len(),
                    self.groups.len()
                ),
            });
        }
        if let Some((g, f)) = self
            .groups
            .iter()
            .zip(factors)
            .find(|(_, f)| !(f.is_finite() && f.min_band() >= 0.0))
        {
            return Err(Error::Setting {
                name: "light_groups",
                message: format!(
                    "the factor {:?} of the group '{}' is not a finite number of at least 0",
                    f.0, g.name
                ),
            });
        }
        let mut out = scene.clone();
        // (material, group) -> the material's copy for the group.
        let mut copies: HashMap<(u32, usize), u32> = HashMap::new();
        for (g, group) in self.groups.iter().enumerate() {
            let f = factors[g];
            for &s in &group.surfaces {
                let m = scene.surfaces[s as usize].material;
                let copy = *copies.entry((m, g)).or_insert_with(|| {
                    let mut material = scene.materials[m as usize].clone();
                    material.emission = material.emission * f;
                    if let Some(t) = &material.emissive_texture {
                        let mut t = (**t).clone();
                        t.factor = t.factor * f;
                        t.max_value *= f.max_band();
                        material.emissive_texture = Some(std::sync::Arc::new(t));
                    }
                    out.materials.push(material);
                    (out.materials.len() - 1) as u32
                });
                out.surfaces[s as usize].material = copy;
            }
            for &l in &group.lights {
                let light = &mut out.lights[l as usize];
                light.colour = light.colour * f;
            }
            if group.sky {
                if let Some(sky) = &mut out.sky {
                    sky.zenith = sky.zenith * f;
                }
            }
        }
        Ok(out)
    }
}
