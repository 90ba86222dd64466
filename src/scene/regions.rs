//! Regions of a scene cut by a grid, for measuring error where objects are
//! few and large.
//!
//! A real mesh is often one object (a whole building in one glTF mesh), so
//! per-object means say little about where a solution errs. Cut into the
//! cells of a grid, by where each surface's centroid falls, the same mesh
//! gives one mean per cell: a solution and a reference grouped the same way
//! can be compared cell by cell.

use super::{Object, Scene};
use crate::error::{Error, Result};
use std::collections::BTreeMap;

impl Scene {
    /// This scene with its objects replaced by the cells of a grid `cell`
    /// metres wide, aligned with the world origin: each surface joins the
    /// cell its area centroid falls in, and each non-empty cell is an object
    /// named `cell I,J,K` (its integer grid coordinates), in increasing
    /// order of those. Geometry, materials and lights are unchanged.
    ///
    /// Fails on a cell size that is not a positive finite length, or one so
    /// small that a coordinate's cell index would not fit in 32 bits.
    pub fn regions_by_grid(&self, cell: f64) -> Result<Scene> {
        if !(cell.is_finite() && cell > 0.0) {
            return Err(Error::Setting {
                name: "regions",
                message: format!("the grid's cell must be a positive length, got {cell}"),
            });
        }
        let mut index_of = Vec::with_capacity(self.surfaces.len());
        for s in &self.surfaces {
            let c = s.centroid() / cell;
            let ijk = c.floor().to_array();
            if ijk.iter().any(|v| v.abs() > f64::from(i32::MAX)) {
                return Err(Error::Setting {
                    name: "regions",
                    message: format!(
                        "a grid of {cell} m cells has more than 2^31 cells across the scene"
                    ),
                });
            }
            index_of.push(ijk.map(|v| v as i32));
        }
        let mut cells: BTreeMap<[i32; 3], u32> = index_of.iter().map(|&ijk| (ijk, 0)).collect();
        for (n, slot) in cells.values_mut().enumerate() {
            *slot = n as u32;
        }
        let mut regions = self.clone();
        regions.objects = cells
            .keys()
            .map(|[i, j, k]| Object {
                name: format!("cell {i},{j},{k}"),
            })
            .collect();
        for (s, ijk) in regions.surfaces.iter_mut().zip(&index_of) {
            s.object = cells[ijk];
        }
        Ok(regions)
    }
}

#[cfg(test)]
mod tests {
    use crate::math::Rgb;
    use crate::scene::{Scene, SceneBuilder};
    use glam::DVec3;

    fn two_floors() -> Scene {
        let mut b = SceneBuilder::new("floors");
        let white = b.material("white", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        // One object spanning two cells of a 1 m grid along x.
        b.object("floor");
        for x in [0.0, 1.0] {
            b.quad(
                white,
                DVec3::new(x + 0.1, 0.0, 0.1),
                DVec3::new(x + 0.1, 0.0, 0.9),
                DVec3::new(x + 0.9, 0.0, 0.9),
                DVec3::new(x + 0.9, 0.0, 0.1),
            )
            .unwrap();
        }
        b.build().unwrap()
    }

    #[test]
    fn surfaces_join_the_cell_their_centroid_falls_in() {
        let scene = two_floors();
        let regions = scene.regions_by_grid(1.0).unwrap();
        let names: Vec<&str> = regions.objects.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["cell 0,0,0", "cell 1,0,0"]);
        assert_eq!(regions.surfaces[0].object, 0);
        assert_eq!(regions.surfaces[1].object, 1);
        // A grid coarser than the scene holds it in one cell.
        assert_eq!(scene.regions_by_grid(10.0).unwrap().objects.len(), 1);
    }

    #[test]
    fn a_cell_that_is_not_a_positive_length_is_refused() {
        let scene = two_floors();
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-300] {
            assert!(scene.regions_by_grid(bad).is_err(), "{bad}");
        }
    }
}
