//! The renderer's input: triangles carrying one radiance per vertex.

use crate::math::Rgb;
use crate::mesh::ShadingMesh;
use crate::{Error, Result};
use glam::DVec3;
use std::f64::consts::PI;

/// A triangle mesh with one linear RGB value per vertex, ready to render.
///
/// Triangles are counter-clockwise seen from their front. A triangle seen from
/// behind renders black but still hides what lies behind it: surfaces are
/// single-sided, and their back neither emits nor reflects.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadedMesh {
    /// Vertex positions in world space.
    pub positions: Vec<DVec3>,
    /// Radiance per vertex (radiosity B / pi), linear RGB.
    pub values: Vec<Rgb>,
    /// Vertex indices, three per triangle.
    pub triangles: Vec<[u32; 3]>,
}

impl ShadedMesh {
    /// The radiance of a display mesh's vertex radiosities: radiosity / pi,
    /// what a camera sees on a diffuse surface.
    #[must_use]
    pub fn radiance_of(shading: ShadingMesh) -> ShadedMesh {
        ShadedMesh {
            positions: shading.positions,
            values: shading.radiosity.iter().map(|b| *b / PI).collect(),
            triangles: shading.triangles,
        }
    }

    /// Checks that there is one value per position, that every index is in
    /// range, and that positions and values are finite. The error names the
    /// first offending vertex or triangle.
    pub fn validate(&self) -> Result<()> {
        if self.values.len() != self.positions.len() {
            return Err(Error::Geometry(format!(
                "shaded mesh has {} positions but {} values",
                self.positions.len(),
                self.values.len()
            )));
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::Geometry(format!(
                "shaded mesh vertex {i} has a non-finite position {}",
                self.positions[i]
            )));
        }
        if let Some(i) = self.values.iter().position(|v| !v.is_finite()) {
            return Err(Error::Geometry(format!(
                "shaded mesh vertex {i} has a non-finite value {:?}",
                self.values[i].0
            )));
        }
        let n = self.positions.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&bad) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(Error::Geometry(format!(
                    "shaded mesh triangle {t} refers to vertex {bad}, but there are only {n}"
                )));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_triangle() -> ShadedMesh {
        ShadedMesh {
            positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
            values: vec![Rgb::ONE; 3],
            triangles: vec![[0, 1, 2]],
        }
    }

    #[test]
    fn accepts_a_sound_mesh() {
        assert!(one_triangle().validate().is_ok());
    }

    #[test]
    fn rejects_out_of_range_index() {
        let mut m = one_triangle();
        m.triangles.push([0, 1, 3]);
        let e = m.validate().unwrap_err().to_string();
        assert!(e.contains("triangle 1") && e.contains("vertex 3"), "{e}");
    }

    #[test]
    fn rejects_non_finite_values_and_positions() {
        let mut m = one_triangle();
        m.values[2] = Rgb::new(0.0, f64::NAN, 0.0);
        assert!(m.validate().unwrap_err().to_string().contains("vertex 2"));
        let mut m = one_triangle();
        m.positions[1].x = f64::INFINITY;
        assert!(m.validate().unwrap_err().to_string().contains("vertex 1"));
    }

    #[test]
    fn rejects_mismatched_lengths() {
        let mut m = one_triangle();
        m.values.pop();
        assert!(m.validate().is_err());
    }
}
