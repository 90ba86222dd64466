//! Radiosity at points of a solved scene, interpolated exactly as the renderer
//! shades it.
//!
//! A probe is a point and a normal. It lands on the scene surface whose plane
//! passes through the point (within a distance tolerance), whose front normal
//! agrees with the given normal (within an angle), and whose outline contains
//! the point. The leaf element under the point is found in the surface's
//! lattice, and the value is interpolated barycentrically over that leaf's
//! shading triangles: the fan of [`Mesh::shading_mesh`](crate::mesh::Mesh::shading_mesh)
//! around the leaf's centre through its corners and T-vertices. So a probe
//! reads the same value a camera would see at that point.

use super::Solution;
use crate::error::{Error, Result};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh, VertexRadiosity, MAX_DEPTH};
use glam::DVec3;
use smallvec::SmallVec;

/// How far a probe may stray from a surface and still read it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeTolerance {
    /// Largest distance from a surface's plane, and from its outline within
    /// the plane, as a fraction of the mesh's bounding-box diagonal.
    pub relative_distance: f64,
    /// Largest angle between the probe's normal and the surface's front
    /// normal, in degrees.
    pub normal_degrees: f64,
}

impl Default for ProbeTolerance {
    /// `1e-4` of the scene's diagonal (0.1 mm in a 1 m room) and 5 degrees:
    /// loose enough for hand-typed points on measured, slightly skewed walls.
    fn default() -> Self {
        ProbeTolerance {
            relative_distance: 1e-4,
            normal_degrees: 5.0,
        }
    }
}

impl ProbeTolerance {
    /// Checks the ranges; the error names the setting.
    pub fn validate(&self) -> Result<()> {
        let d = self.relative_distance;
        if !(d.is_finite() && d >= 0.0) {
            return Err(Error::Setting {
                name: "plane_tolerance",
                message: format!("must be a finite fraction >= 0, got {d}"),
            });
        }
        let a = self.normal_degrees;
        if !(a.is_finite() && (0.0..90.0).contains(&a)) {
            return Err(Error::Setting {
                name: "normal_tolerance",
                message: format!("must lie in [0, 90) degrees, got {a}"),
            });
        }
        Ok(())
    }
}

/// Where a probe landed and what it read.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeHit {
    /// Index of the surface (in `Scene::surfaces` and `Mesh::surfaces`).
    pub surface: u32,
    /// The leaf element under the point.
    pub element: ElementKey,
    /// The probe point moved onto the surface's plane.
    pub point: DVec3,
    /// The interpolated radiosity (exitance) there.
    pub radiosity: Rgb,
}

/// Answers many probes against one solution; the vertex radiosities of the
/// shading mesh are built once, when the prober is made.
#[derive(Clone, Debug)]
pub struct SolutionProbe<'a> {
    mesh: &'a Mesh,
    vertices: VertexRadiosity,
    distance: f64,
    min_cosine: f64,
}

impl Solution {
    /// A prober with the default [`ProbeTolerance`].
    #[must_use]
    pub fn probe(&self) -> SolutionProbe<'_> {
        SolutionProbe::build(self, ProbeTolerance::default())
    }

    /// A prober with the given tolerances. Fails if they are out of range.
    pub fn probe_with(&self, tolerance: ProbeTolerance) -> Result<SolutionProbe<'_>> {
        tolerance.validate()?;
        Ok(SolutionProbe::build(self, tolerance))
    }

    /// The radiosity at `point` on the surface facing `normal`, interpolated
    /// as the renderer does, or `None` if no surface holds the point (see the
    /// module docs). Builds the vertex radiosities on every call: for many
    /// points, use [`Solution::probe`] once and ask it.
    #[must_use]
    pub fn radiosity_at(&self, point: DVec3, normal: DVec3) -> Option<Rgb> {
        self.probe().radiosity_at(point, normal)
    }
}

impl<'a> SolutionProbe<'a> {
    fn build(solution: &'a Solution, tolerance: ProbeTolerance) -> Self {
        let mesh = &solution.mesh;
        let (lo, hi) = mesh
            .surfaces
            .iter()
            .flat_map(|s| s.vertices.iter())
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(*v), hi.max(*v))
            });
        let diagonal = if lo.is_finite() {
            (hi - lo).length()
        } else {
            0.0
        };
        SolutionProbe {
            mesh,
            vertices: solution.vertex_radiosity(),
            distance: tolerance.relative_distance * diagonal,
            min_cosine: tolerance.normal_degrees.to_radians().cos(),
        }
    }

    /// The radiosity at `point` on the surface facing `normal`, or `None` if
    /// no surface holds the point, the normal is zero or anything is not
    /// finite.
    #[must_use]
    pub fn radiosity_at(&self, point: DVec3, normal: DVec3) -> Option<Rgb> {
        self.hit(point, normal).map(|h| h.radiosity)
    }

    /// Where the probe lands and what it reads (see the module docs). Among
    /// several surfaces that qualify, the one whose plane is nearest wins
    /// (the first in scene order on a tie).
    #[must_use]
    pub fn hit(&self, point: DVec3, normal: DVec3) -> Option<ProbeHit> {
        let n = normal.try_normalize()?;
        if !point.is_finite() {
            return None;
        }
        let mut best: Option<(f64, u32, DVec3)> = None;
        for (index, lattice) in self.mesh.surfaces.iter().enumerate() {
            if lattice.normal.dot(n) < self.min_cosine {
                continue;
            }
            let height = lattice.normal.dot(point - lattice.vertices[0]);
            if height.abs() > self.distance {
                continue;
            }
            let on_plane = point - lattice.normal * height;
            if lattice.outside_distance(on_plane) > self.distance {
                continue;
            }
            if best.is_none_or(|(h, _, _)| height.abs() < h) {
                best = Some((height.abs(), index as u32, on_plane));
            }
        }
        let (_, surface, on_plane) = best?;
        self.hit_on(surface, on_plane)
    }

    /// Where a point already known to lie on surface `surface` (an index into
    /// `Scene::surfaces`) lands and what it reads; the point is moved onto
    /// the surface's plane. Unlike [`SolutionProbe::hit`] it does not search
    /// the surfaces, so it suits many queries (a ray caster's hits). `None`
    /// when the surface does not exist, the point is not finite, or no
    /// element of the surface holds it.
    #[must_use]
    pub fn hit_on(&self, surface: u32, point: DVec3) -> Option<ProbeHit> {
        let lattice = self.mesh.surfaces.get(surface as usize)?;
        if !point.is_finite() {
            return None;
        }
        let height = lattice.normal.dot(point - lattice.vertices[0]);
        let on_plane = point - lattice.normal * height;
        let element = self
            .mesh
            .locate(surface, lattice.probe_at(on_plane), MAX_DEPTH)?;
        let radiosity = self.interpolate(element, on_plane);
        Some(ProbeHit {
            surface,
            element,
            point: on_plane,
            radiosity,
        })
    }

    /// Barycentric interpolation over the leaf's shading fan, built as
    /// `Mesh::shading_mesh` builds it.
    fn interpolate(&self, key: ElementKey, point: DVec3) -> Rgb {
        let e = &self.mesh.elements[key];
        let lattice = &self.mesh.surfaces[e.surface as usize];
        let vertex = |c: (u32, u32)| {
            let value = self
                .vertices
                .values
                .get(&(e.surface, c.0, c.1))
                .copied()
                .unwrap_or(Rgb::ZERO);
            (lattice.position(c), value)
        };
        let corners = e.cell.corners();
        let t_vertices = self.vertices.t_vertices.get(&key);
        let mut triangles: SmallVec<[[(DVec3, Rgb); 3]; 8]> = SmallVec::new();
        if t_vertices.is_none() && corners.len() == 3 {
            triangles.push([vertex(corners[0]), vertex(corners[1]), vertex(corners[2])]);
        } else {
            let mut ring: SmallVec<[(DVec3, Rgb); 8]> = SmallVec::new();
            for (i, c) in corners.iter().enumerate() {
                ring.push(vertex(*c));
                if let Some(t) = t_vertices {
                    ring.extend(t[i].iter().map(|m| vertex(*m)));
                }
            }
            let k = corners.len() as f64;
            let centre = (
                corners.iter().map(|c| lattice.position(*c)).sum::<DVec3>() / k,
                corners
                    .iter()
                    .map(|c| vertex(*c).1)
                    .fold(Rgb::ZERO, |a, b| a + b)
                    / k,
            );
            for i in 0..ring.len() {
                triangles.push([centre, ring[i], ring[(i + 1) % ring.len()]]);
            }
        }
        // The triangle that holds the point has no negative weight; take the
        // one whose smallest weight is largest, which also settles points on
        // shared edges and the last bits of rounding.
        let mut best = (f64::NEG_INFINITY, Rgb::ZERO);
        for tri in &triangles {
            let w = barycentric(tri.map(|v| v.0), point, lattice.normal);
            let smallest = w[0].min(w[1]).min(w[2]);
            if smallest > best.0 {
                best = (
                    smallest,
                    tri[0].1 * w[0] + tri[1].1 * w[1] + tri[2].1 * w[2],
                );
            }
        }
        best.1
    }
}

/// Barycentric weights of `p` in the triangle `t`, measured in the plane with
/// normal `n`.
fn barycentric(t: [DVec3; 3], p: DVec3, n: DVec3) -> [f64; 3] {
    let twice_area = n.dot((t[1] - t[0]).cross(t[2] - t[0]));
    if twice_area == 0.0 {
        return [f64::NEG_INFINITY; 3];
    }
    let w0 = n.dot((t[1] - p).cross(t[2] - p)) / twice_area;
    let w1 = n.dot((t[2] - p).cross(t[0] - p)) / twice_area;
    [w0, w1, 1.0 - w0 - w1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentric_weights_sum_to_one_and_vanish_on_the_far_edge() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Z * -1.0];
        // The triangle (0,0,0) (1,0,0) (0,0,-1) is counter-clockwise about +y.
        let w = barycentric(t, DVec3::new(0.25, 0.0, -0.25), DVec3::Y);
        assert!((w[0] - 0.5).abs() < 1e-15 && (w[1] - 0.25).abs() < 1e-15);
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        let on_edge = barycentric(t, DVec3::new(0.5, 0.0, -0.5), DVec3::Y);
        assert!(on_edge[0].abs() < 1e-15);
    }
}
