//! The exact discrete solution of the unit cube made of six patches.
//!
//! Each face is one constant-radiosity patch. Its form factors are closed forms:
//! `0.199825...` to the opposite face (Howell C-11) and `0.200044...` to each
//! adjacent face (Howell C-14); every row sums to one. The 6 x 6 system
//! `(I - diag(rho) F) B = E` is solved by Gaussian elimination, so a hemi-cube
//! solver run on the same six patches must converge to these values as its
//! resolution grows.

use super::rectangles::{parallel_ratios, perpendicular_ratios};
use crate::error::{Error, Result, SolverFault};
use glam::DVec3;

/// The six faces of the unit cube `[0, 1]^3` (Y up), in the order used by every
/// array in this module.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CubeFace {
    /// `y = 0`, facing up.
    Floor,
    /// `y = 1`, facing down.
    Ceiling,
    /// `x = 0`, facing `+x`.
    WallXMin,
    /// `x = 1`, facing `-x`.
    WallXMax,
    /// `z = 0`, facing `+z`.
    WallZMin,
    /// `z = 1`, facing `-z`.
    WallZMax,
}

impl CubeFace {
    /// All faces, in array order.
    pub const ALL: [CubeFace; 6] = [
        CubeFace::Floor,
        CubeFace::Ceiling,
        CubeFace::WallXMin,
        CubeFace::WallXMax,
        CubeFace::WallZMin,
        CubeFace::WallZMax,
    ];

    /// The face's position in the arrays of this module.
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }

    /// The face across the cube.
    #[must_use]
    pub fn opposite(self) -> CubeFace {
        match self {
            CubeFace::Floor => CubeFace::Ceiling,
            CubeFace::Ceiling => CubeFace::Floor,
            CubeFace::WallXMin => CubeFace::WallXMax,
            CubeFace::WallXMax => CubeFace::WallXMin,
            CubeFace::WallZMin => CubeFace::WallZMax,
            CubeFace::WallZMax => CubeFace::WallZMin,
        }
    }

    /// The face as a quad, counter-clockwise seen from inside the cube (so its
    /// front faces the interior).
    #[must_use]
    pub fn polygon(self) -> [DVec3; 4] {
        let p = DVec3::new;
        match self {
            CubeFace::Floor => [p(0., 0., 0.), p(0., 0., 1.), p(1., 0., 1.), p(1., 0., 0.)],
            CubeFace::Ceiling => [p(0., 1., 0.), p(1., 1., 0.), p(1., 1., 1.), p(0., 1., 1.)],
            CubeFace::WallXMin => [p(0., 0., 0.), p(0., 1., 0.), p(0., 1., 1.), p(0., 0., 1.)],
            CubeFace::WallXMax => [p(1., 0., 0.), p(1., 0., 1.), p(1., 1., 1.), p(1., 1., 0.)],
            CubeFace::WallZMin => [p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)],
            CubeFace::WallZMax => [p(0., 0., 1.), p(0., 1., 1.), p(1., 1., 1.), p(1., 0., 1.)],
        }
    }
}

/// The exact face-to-face form factors of the unit cube, `F[i][j]` from face `i`
/// to face `j` in [`CubeFace::ALL`] order.
#[must_use]
pub fn unit_cube_form_factors() -> [[f64; 6]; 6] {
    let opposite = parallel_ratios(1.0, 1.0);
    let adjacent = perpendicular_ratios(1.0, 1.0);
    let mut f = [[0.0; 6]; 6];
    for i in CubeFace::ALL {
        for j in CubeFace::ALL {
            f[i.index()][j.index()] = if i == j {
                0.0
            } else if i.opposite() == j {
                opposite
            } else {
                adjacent
            };
        }
    }
    f
}

/// The exact patch radiosities of the unit cube for per-face reflectance and
/// emitted exitance (one colour band), in [`CubeFace::ALL`] order.
///
/// Fails if a reflectance is outside `[0, 1]` or an emission is negative or not
/// finite ([`Error::Material`]), or if the system is singular, which happens
/// when every face reflects everything ([`Error::Solver`]).
pub fn unit_cube_radiosity(reflectance: [f64; 6], emission: [f64; 6]) -> Result<[f64; 6]> {
    for face in CubeFace::ALL {
        let (rho, e) = (reflectance[face.index()], emission[face.index()]);
        let fault = if !(0.0..=1.0).contains(&rho) {
            Some(format!("reflectance {rho} is outside [0, 1]"))
        } else if !(e.is_finite() && e >= 0.0) {
            Some(format!("emission {e} is negative or not finite"))
        } else {
            None
        };
        if let Some(message) = fault {
            return Err(Error::Material {
                material: format!("unit cube {face:?}"),
                message,
            });
        }
    }
    let f = unit_cube_form_factors();
    let mut system = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            let identity = if i == j { 1.0 } else { 0.0 };
            system[i][j] = identity - reflectance[i] * f[i][j];
        }
    }
    solve_dense(system, emission)
}

/// The unit cube with uniform reflectance `rho` and only the ceiling emitting,
/// with exitance 1: the brief's check case (`rho = 0.5` gives floor `0.181746`,
/// ceiling `1.090909`, walls `0.181836`).
pub fn unit_cube_ceiling_lit(rho: f64) -> Result<[f64; 6]> {
    let mut emission = [0.0; 6];
    emission[CubeFace::Ceiling.index()] = 1.0;
    unit_cube_radiosity([rho; 6], emission)
}

/// Solves `a x = b` by Gaussian elimination with partial pivoting.
fn solve_dense<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> Result<[f64; N]> {
    let scale = a
        .iter()
        .flatten()
        .fold(0.0, |m: f64, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    for col in 0..N {
        let pivot_row = (col..N)
            .max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs()))
            .unwrap_or(col);
        let pivot = a[pivot_row][col];
        if pivot.is_nan() || pivot.abs() <= 1e-13 * scale {
            return Err(Error::solver(
                SolverFault::Singular,
                format!(
                    "the {N} x {N} system is singular (pivot {:.3e} in column {col}); \
                 a closed scene whose reflectance is 1 everywhere has no finite solution",
                    pivot
                ),
            ));
        }
        a.swap(col, pivot_row);
        b.swap(col, pivot_row);
        for row in col + 1..N {
            let factor = a[row][col] / a[col][col];
            let pivot_equation = a[col];
            for (target, source) in a[row][col..].iter_mut().zip(&pivot_equation[col..]) {
                *target -= factor * source;
            }
            b[row] -= factor * b[col];
        }
    }
    let mut x = [0.0; N];
    for row in (0..N).rev() {
        let known: f64 = (row + 1..N).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - known) / a[row][row];
    }
    Ok(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{newell_normal, polygon_centroid};

    #[test]
    fn faces_face_the_inside() {
        let centre = DVec3::splat(0.5);
        for face in CubeFace::ALL {
            let q = face.polygon();
            let n = newell_normal(&q).normalize();
            let to_centre = (centre - polygon_centroid(&q)).normalize();
            assert!((n - to_centre).length() < 1e-15, "{face:?}");
        }
    }

    #[test]
    fn every_row_sums_to_one() {
        for row in unit_cube_form_factors() {
            assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn elimination_solves_a_permuted_system() {
        // Needs a row swap: the first pivot is zero.
        let a = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]];
        let x_true = [1.0, -2.0, 0.5];
        let b: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| a[i][j] * x_true[j]).sum());
        let x = solve_dense(a, b).unwrap();
        for k in 0..3 {
            assert!((x[k] - x_true[k]).abs() < 1e-15);
        }
    }

    #[test]
    fn reflectance_one_everywhere_is_singular() {
        assert!(matches!(
            unit_cube_ceiling_lit(1.0),
            Err(Error::Solver {
                fault: SolverFault::Singular,
                ..
            })
        ));
        assert!(matches!(
            unit_cube_ceiling_lit(1.2),
            Err(Error::Material { .. })
        ));
    }
}
