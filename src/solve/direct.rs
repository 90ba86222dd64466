//! Direct light from punctual lights, the first reflection of sources that
//! lie outside the mesh.
//!
//! A point, spot or directional light has no patch to shoot from and no area
//! a hemi-cube could see, so its light enters the radiosity system one
//! reflection in: each leaf's irradiance `Hd` from the lights is computed
//! exactly (the lights' falloffs, and a shadow ray to each light from each
//! of the element's quadrature points), and its reflection `rho Hd` is added
//! to the leaf's emission. The solvers take that as a source like any
//! emitted light, so what follows, the indirect light, is the radiosity
//! solution as usual: `B_e = E_e + rho_e (Hd_e + sum_j F_ej B_j)`.
//!
//! The element's mean over its Gauss points (the points the exact emitter
//! visibility uses, on the same lifted plane as the hemi-cube's eye) makes a
//! leaf crossed by a shadow's edge take a value between its lit and shadowed
//! neighbours, so that the refinement criterion splits along hard shadows as
//! it does along penumbrae.

use crate::formfactor::{element_samples, eye_lift, FormFactors, Occluders, Sources};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::scene::{Light, Sky, Target};
use crate::solve::sky_light::sky_irradiance;
use crate::solve::system::{scene_is_closed, weight};
use crate::solve::PatchSystem;
use glam::DVec3;
use rayon::prelude::*;
use slotmap::SecondaryMap;

/// Per leaf element, the irradiance from the scene's punctual lights.
#[derive(Clone, Debug, Default)]
pub(crate) struct DirectLight {
    irradiance: SecondaryMap<ElementKey, Rgb>,
    /// Shadow rays cast so far.
    pub shadow_rays: u64,
}

impl DirectLight {
    /// The irradiance from the punctual lights on leaf `k` (0 for a key not
    /// computed).
    #[inline]
    #[must_use]
    pub(crate) fn irradiance(&self, k: ElementKey) -> Rgb {
        self.irradiance.get(k).copied().unwrap_or(Rgb::ZERO)
    }

    /// The reflected direct light of leaf `k`, `rho Hd`: the exitance it adds
    /// to the leaf's emission.
    #[inline]
    #[must_use]
    pub(crate) fn exitance(&self, mesh: &Mesh, k: ElementKey) -> Rgb {
        let rho = mesh.elements[k].reflectance;
        rho * self.irradiance(k)
    }

    /// Computes the irradiance of every leaf of `mesh` that has none yet
    /// (new leaves of a split; every leaf the first time), with shadow rays
    /// through the patch polygons of `sources`. Returns how many leaves it
    /// computed. With a `sky`, its light on each leaf is added (see
    /// `sky_light`). The same bits at any thread count: each leaf's value
    /// depends on that leaf alone.
    pub(crate) fn update(
        &mut self,
        mesh: &Mesh,
        sources: &Sources,
        lights: &[Light],
        sky: Option<&Sky>,
    ) -> usize {
        let keys: Vec<ElementKey> = mesh
            .leaves()
            .into_iter()
            .filter(|k| !self.irradiance.contains_key(*k))
            .collect();
        if keys.is_empty() {
            return 0;
        }
        let occluders = Occluders::new(sources);
        let far = far_distance(sources);
        let results: Vec<(Rgb, u64)> = keys
            .par_iter()
            .map(|&k| {
                let (h, rays) = leaf_irradiance(mesh, sources, &occluders, far, lights, k);
                match sky {
                    Some(sky) => {
                        let e = &mesh.elements[k];
                        let lattice = &mesh.surfaces[e.surface as usize];
                        let samples = element_samples(
                            &lattice.polygon(&e.cell),
                            eye_lift(lattice.normal, e.area),
                        );
                        let (hs, more) = sky_irradiance(
                            sky,
                            sources,
                            &occluders,
                            far,
                            e.surface,
                            lattice.normal,
                            &samples,
                        );
                        (h + hs, rays + more)
                    }
                    None => (h, rays),
                }
            })
            .collect();
        for (&k, (h, rays)) in keys.iter().zip(results) {
            self.irradiance.insert(k, h);
            self.shadow_rays += rays;
        }
        keys.len()
    }

    /// The power the lights deliver to the leaves' fronts, `sum A_e Hd_e`
    /// per band.
    #[must_use]
    pub(crate) fn incident_power(&self, mesh: &Mesh) -> Rgb {
        mesh.leaves()
            .into_iter()
            .map(|k| self.irradiance(k) * mesh.elements[k].area)
            .fold(Rgb::ZERO, |a, b| a + b)
    }

    /// Per patch, the reflected direct light as a source: the mean of its
    /// leaves' `rho Hd` weighted as the patch system weighs them (exposure in
    /// a closed scene, area where a leaf sees anything), the area mean where
    /// no leaf has weight; `form_factors` holds the leaves' rows.
    #[must_use]
    pub(crate) fn patch_exitance(&self, mesh: &Mesh, form_factors: &FormFactors) -> Vec<Rgb> {
        let leaves = mesh.leaves();
        let closed = scene_is_closed(mesh, form_factors, &leaves);
        (0..mesh.patches.len() as u32)
            .map(|p| {
                let (mut sum, mut total, mut area_sum) = (Rgb::ZERO, 0.0, Rgb::ZERO);
                for k in mesh.patch_leaves(p) {
                    let d = self.exitance(mesh, k);
                    let w = weight(mesh, form_factors, k, closed);
                    sum += d * w;
                    total += w;
                    area_sum += d * mesh.elements[k].area;
                }
                if total > 0.0 {
                    sum / total
                } else {
                    area_sum / mesh.patches[p as usize].area
                }
            })
            .collect()
    }

    /// Per patch, the area mean of its leaves' `rho Hd` (before any row).
    #[must_use]
    pub(crate) fn patch_area_means(&self, mesh: &Mesh) -> Vec<Rgb> {
        (0..mesh.patches.len() as u32)
            .map(|p| {
                let sum = mesh
                    .patch_leaves(p)
                    .into_iter()
                    .map(|k| self.exitance(mesh, k) * mesh.elements[k].area)
                    .fold(Rgb::ZERO, |a, b| a + b);
                sum / mesh.patches[p as usize].area
            })
            .collect()
    }

    /// Adds each patch's reflected direct light to the emission of
    /// `system` (assembled from `form_factors`'s rows): the patch system then
    /// solves for the indirect light that follows it.
    pub(crate) fn add_to_system(
        &self,
        system: &mut PatchSystem,
        mesh: &Mesh,
        form_factors: &FormFactors,
    ) {
        for (p, d) in self
            .patch_exitance(mesh, form_factors)
            .into_iter()
            .enumerate()
        {
            system.emission[p] = mesh.patch_emission(p as u32) + d;
        }
    }
}

/// A distance that takes a shadow ray from anywhere in the scene out of it:
/// the diagonal of the polygons' bounds, doubled.
fn far_distance(sources: &Sources) -> f64 {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for p in &sources.polygons {
        for v in &p.vertices[..p.count as usize] {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
    }
    2.0 * (hi - lo).length().max(f64::MIN_POSITIVE)
}

/// The mean irradiance over leaf `k`'s quadrature points from every light,
/// each point lit by a light only where a shadow ray reaches it; and the
/// number of shadow rays cast.
fn leaf_irradiance(
    mesh: &Mesh,
    sources: &Sources,
    occluders: &Occluders,
    far: f64,
    lights: &[Light],
    k: ElementKey,
) -> (Rgb, u64) {
    let e = &mesh.elements[k];
    let lattice = &mesh.surfaces[e.surface as usize];
    let normal = lattice.normal;
    let polygon = lattice.polygon(&e.cell);
    let samples = element_samples(&polygon, eye_lift(normal, e.area));
    let skip = [e.surface, e.surface];
    let (mut sum, mut rays) = (Rgb::ZERO, 0u64);
    for light in lights {
        for &(point, w) in &samples {
            let Some(incident) = light.incident(point) else {
                continue;
            };
            let h = incident.on(normal);
            if h == Rgb::ZERO {
                continue;
            }
            let target = match incident.target {
                Target::Point(p) => p,
                // Out of the scene: receiving points lie within the
                // polygons' bounds, so twice their diagonal is beyond
                // everything along the ray.
                Target::Infinity(dir) => point + dir * far,
            };
            rays += 1;
            if occluders.clear(sources, point, target, skip) {
                sum += h * w;
            }
        }
    }
    (sum, rays)
}
