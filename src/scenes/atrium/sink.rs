//! Where the generator's polygons go: into a [`SceneBuilder`], or into a
//! [`Counter`] that only counts them. The size search counts many candidate
//! scenes without building them, and the count of the scene it then builds
//! is the same by construction (one generator for both).

use crate::error::Result;
use crate::math::Rgb;
use crate::scene::SceneBuilder;
use glam::DVec3;

/// Receives materials, objects and planar polygons (3 or 4 vertices,
/// counter-clockwise seen from the front).
pub(super) trait Sink {
    /// Registers a material (reflectance, emitted radiance); returns its index.
    fn material(&mut self, name: &str, reflectance: Rgb, radiance: Rgb) -> Result<u32>;
    /// Starts the object `name`; later polygons belong to it.
    fn object(&mut self, name: &str);
    /// Adds a triangle or a convex planar quad.
    fn polygon(&mut self, material: u32, vertices: &[DVec3]) -> Result<()>;
}

impl Sink for SceneBuilder {
    fn material(&mut self, name: &str, reflectance: Rgb, radiance: Rgb) -> Result<u32> {
        SceneBuilder::material(self, name, reflectance, radiance)
    }

    fn object(&mut self, name: &str) {
        SceneBuilder::object(self, name);
    }

    fn polygon(&mut self, material: u32, vertices: &[DVec3]) -> Result<()> {
        SceneBuilder::polygon(self, material, vertices)
    }
}

/// Counts what a generator would build: triangles (a quad counts as two),
/// objects and materials.
#[derive(Debug, Default)]
pub(super) struct Counter {
    /// Triangles, quads counted twice.
    pub triangles: usize,
    /// Objects started.
    pub objects: usize,
    materials: u32,
}

impl Sink for Counter {
    fn material(&mut self, _name: &str, _reflectance: Rgb, _radiance: Rgb) -> Result<u32> {
        self.materials += 1;
        Ok(self.materials - 1)
    }

    fn object(&mut self, _name: &str) {
        self.objects += 1;
    }

    fn polygon(&mut self, _material: u32, vertices: &[DVec3]) -> Result<()> {
        self.triangles += vertices.len() - 2;
        Ok(())
    }
}

/// Numbers the objects of each kind in the order they are made: `column_0`,
/// `column_1`, ...
#[derive(Debug, Default)]
pub(super) struct Names {
    counts: Vec<(&'static str, usize)>,
}

impl Names {
    /// The next name of `kind`.
    pub(super) fn next(&mut self, kind: &'static str) -> String {
        let slot = match self.counts.iter().position(|(k, _)| *k == kind) {
            Some(i) => i,
            None => {
                self.counts.push((kind, 0));
                self.counts.len() - 1
            }
        };
        let n = self.counts[slot].1;
        self.counts[slot].1 += 1;
        format!("{kind}_{n}")
    }
}
