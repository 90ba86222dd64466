//! Choosing points on emitters: a surface in proportion to its emitted power
//! (area times the sum of the bands of its mean exitance), then a point
//! uniformly by area on it. The estimator weighs the point by the exitance
//! there (an emissive texture's value), which keeps light sampling unbiased
//! wherever the mean is positive, i.e. wherever a texel can be.

use super::sampling::Cdf;
use crate::math::Rgb;
use crate::scene::rays::SurfaceGeometry;
use glam::DVec3;

/// The emitting surfaces and the probability of choosing each.
#[derive(Clone, Debug)]
pub(crate) struct Emitters {
    /// Indices of the surfaces that emit in some band.
    surfaces: Vec<u32>,
    /// Choice among `surfaces`.
    choice: Cdf,
    /// Per scene surface: probability of choosing it divided by its area, i.e.
    /// the area density of a light sample on it (0 for surfaces that do not emit).
    area_density: Vec<f64>,
}

/// A point chosen on an emitter.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightPoint {
    /// The emitting surface.
    pub(crate) surface: u32,
    /// The point, on the surface's plane.
    pub(crate) position: DVec3,
}

impl Emitters {
    /// The emitters among surfaces with the given geometry and exitance, or
    /// `None` when nothing emits.
    pub(crate) fn new(geometry: &[SurfaceGeometry], emission: &[Rgb]) -> Option<Emitters> {
        let power: Vec<f64> = geometry
            .iter()
            .zip(emission)
            .map(|(g, e)| g.area * (e[0] + e[1] + e[2]))
            .collect();
        let surfaces: Vec<u32> = (0..power.len() as u32)
            .filter(|s| power[*s as usize] > 0.0)
            .collect();
        let weights: Vec<f64> = surfaces.iter().map(|s| power[*s as usize]).collect();
        let choice = Cdf::new(&weights)?;
        let mut area_density = vec![0.0; geometry.len()];
        for (i, s) in surfaces.iter().enumerate() {
            area_density[*s as usize] = choice.probability(i) / geometry[*s as usize].area;
        }
        Some(Emitters {
            surfaces,
            choice,
            area_density,
        })
    }

    /// A point on an emitter from two uniforms in [0, 1).
    pub(crate) fn sample(
        &self,
        geometry: &[SurfaceGeometry],
        u_choice: f64,
        u2: f64,
    ) -> LightPoint {
        let (i, u1) = self.choice.pick(u_choice);
        let surface = self.surfaces[i];
        LightPoint {
            surface,
            position: geometry[surface as usize].sample(u1, u2),
        }
    }

    /// The area density with which [`Emitters::sample`] produces points on
    /// `surface`.
    pub(crate) fn area_density(&self, surface: u32) -> f64 {
        self.area_density[surface as usize]
    }
}
