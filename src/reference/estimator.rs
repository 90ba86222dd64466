//! One path: an unbiased single-sample estimate of the radiosity at a point.
//!
//! For a diffuse point x,
//! `B(x) = E(x) + rho(x) H(x)` with the irradiance `H(x) = integral L_in cos dw`,
//! and a front hit y carries `L = B(y)/pi = E(y)/pi + rho(y) H(y)/pi`. So
//!
//! `H(x) = integral (E(y)/pi) cos dw  +  integral (rho(y) H(y)/pi) cos dw`.
//!
//! Reflectance and exitance are taken at each point (a textured surface's
//! texel there, see the `textures` source), both where a path starts or
//! lands and at the point a light sample picks on an emitter.
//!
//! The first (direct) integral is estimated with both a light sample and a
//! cosine-distributed direction, combined by multiple importance sampling with the
//! balance heuristic (Veach & Guibas 1995). Each weighted term is then at most E(y),
//! so per-path values stay bounded even at concave corners, where a light sample
//! alone has unbounded variance. The second integral uses the same cosine
//! direction: its estimate is `rho(y) H(y)`, continued recursively from y. A ray
//! that meets a back face, or nothing, carries no light and ends the path.

use super::rng::Rng;
use super::sampling::cosine_direction;
use super::{Reference, ReferenceSettings};
use crate::math::Rgb;
use crate::scene::Target;
use glam::DVec3;
use std::f64::consts::PI;

impl Reference {
    /// One path's estimate of B at `position` on surface `surface`.
    pub(crate) fn trace_path(
        &self,
        surface: u32,
        position: DVec3,
        settings: &ReferenceSettings,
        rng: &mut Rng,
    ) -> Rgb {
        // The weight that H at the current vertex carries in B(x) starts as
        // the reflectance there.
        let (mut value, mut weight) = self.shades[surface as usize].at(position);
        let mut surface = surface;
        let mut position = position;
        let mut bounce = 0u32;
        while weight.max_band() > 0.0 {
            let normal = self.geometry[surface as usize].normal;
            let origin = position + normal * self.tolerances.offset;
            value += weight * self.light_sample_term(surface, origin, normal, rng);
            value += weight * self.punctual_term(surface, origin, normal);
            let dir = cosine_direction(normal, rng.uniform(), rng.uniform());
            let Some(hit) = self.accel.nearest(&self.geometry, origin, dir, surface) else {
                // Out of the scene: the sky, if any, is what it meets. A
                // cosine-distributed direction estimates the irradiance
                // `integral L cos dw` as `pi L(dir)`.
                if let Some(sky) = &self.sky {
                    value += weight * sky.radiance(dir) * PI;
                }
                break;
            };
            if !hit.front {
                break;
            }
            let hit_position = origin + dir * hit.t;
            let (emission, reflectance) = self.shades[hit.surface as usize].at(hit_position);
            value += weight * self.direction_sample_term(hit.surface, emission, dir, normal, hit.t);
            if bounce >= settings.max_bounces {
                break;
            }
            bounce += 1;
            weight = weight * reflectance;
            if bounce > settings.min_bounces_before_roulette {
                // Continue with probability q and divide by it: unbiased.
                let q = weight.max_band().min(1.0);
                if rng.uniform() >= q {
                    break;
                }
                weight *= 1.0 / q;
            }
            surface = hit.surface;
            position = hit_position;
        }
        value
    }

    /// The light-sampling half of the direct term at `origin` (on `surface`).
    fn light_sample_term(&self, surface: u32, origin: DVec3, normal: DVec3, rng: &mut Rng) -> Rgb {
        let Some(emitters) = &self.emitters else {
            return Rgb::ZERO;
        };
        let light = emitters.sample(&self.geometry, rng.uniform(), rng.uniform());
        if light.surface == surface {
            // A planar surface cannot see itself.
            return Rgb::ZERO;
        }
        let span = light.position - origin;
        let distance_squared = span.length_squared();
        let dir = span / distance_squared.sqrt();
        let cos_here = dir.dot(normal);
        let cos_there = -dir.dot(self.geometry[light.surface as usize].normal);
        if !(cos_here > 0.0 && cos_there > 0.0) {
            return Rgb::ZERO;
        }
        if !self
            .accel
            .unblocked(&self.geometry, origin, light.position, surface)
        {
            return Rgb::ZERO;
        }
        let light_density = emitters.area_density(light.surface) * distance_squared / cos_there;
        let cosine_density = cos_here / PI;
        let emission = self.shades[light.surface as usize].emission_at(light.position);
        emission * (cos_here / PI / (light_density + cosine_density))
    }

    /// The irradiance at `origin` (on `surface`, facing `normal`) from every
    /// punctual light a shadow ray reaches: a delta light has a single
    /// direction, so this next-event estimate is exact, and no cosine
    /// direction can hit the light (nothing to combine with MIS).
    pub(super) fn punctual_term(&self, surface: u32, origin: DVec3, normal: DVec3) -> Rgb {
        let mut sum = Rgb::ZERO;
        for light in &self.lights {
            let Some(incident) = light.incident(origin) else {
                continue;
            };
            let h = incident.on(normal);
            if h == Rgb::ZERO {
                continue;
            }
            let target = match incident.target {
                Target::Point(p) => p,
                // Twice the scene's diameter from a point on it is outside.
                Target::Infinity(dir) => {
                    origin + dir * (2.0 * self.diameter.max(f64::MIN_POSITIVE))
                }
            };
            if self
                .accel
                .unblocked(&self.geometry, origin, target, surface)
            {
                sum += h;
            }
        }
        sum
    }

    /// The cosine-direction half of the direct term, for a ray along `dir` from a
    /// point with normal `normal` that meets the front of `hit_surface` at `t`,
    /// where the exitance is `emission`.
    fn direction_sample_term(
        &self,
        hit_surface: u32,
        emission: Rgb,
        dir: DVec3,
        normal: DVec3,
        t: f64,
    ) -> Rgb {
        let Some(emitters) = &self.emitters else {
            return Rgb::ZERO;
        };
        let density = emitters.area_density(hit_surface);
        if density == 0.0 {
            return Rgb::ZERO;
        }
        let cos_here = dir.dot(normal);
        let cos_there = -dir.dot(self.geometry[hit_surface as usize].normal);
        let light_density = density * t * t / cos_there;
        let cosine_density = cos_here / PI;
        emission * (cos_here / PI / (light_density + cosine_density))
    }
}
