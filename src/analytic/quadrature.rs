//! Adaptive quadrature over a planar triangle or quad, robust to kinks.
//!
//! The element is mapped from the unit square of parameters `(u, v)`: a quad
//! bilinearly, a triangle by the collapsed-square (Duffy) map
//! `a + u (b - a) + u v (c - b)`. The unit square is integrated by globally
//! adaptive subdivision: every cell carries a 3 x 3 Gauss-Legendre value on
//! itself and the sum of the same rule on its four quarter cells; their
//! difference is the cell's error estimate and the finer sum its value. The cell
//! with the largest estimate is split until the estimates add up to less than
//! the tolerance. A kink along a curve (a penumbra boundary) therefore draws
//! cells towards the curve only as far as the total error needs, instead of
//! forcing every cell along it to a fixed local tolerance.

use crate::error::{Error, GeometryFault, LimitKind, Result, SolverFault};
use crate::math::{is_convex, newell_normal, planarity_error};
use glam::DVec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Limits of the adaptive quadrature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadratureSettings {
    /// Absolute tolerance on the integral: refinement stops once the summed
    /// error estimates are below it.
    pub tolerance: f64,
    /// Depth to which the unit square is split uniformly before adapting (cells
    /// of side `2^-min_depth`), so that a feature smaller than the element is
    /// not missed by every sample of the first rule.
    pub min_depth: u32,
    /// No cell is split below side `2^-max_depth`.
    pub max_depth: u32,
    /// Most cells (leaves) allowed; reaching it with the tolerance unmet is an
    /// error.
    pub max_cells: usize,
}

impl Default for QuadratureSettings {
    /// Tolerance `1e-9`, uniform depth 2, maximum depth 24, at most 400 000 cells.
    fn default() -> Self {
        QuadratureSettings {
            tolerance: 1e-9,
            min_depth: 2,
            max_depth: 24,
            max_cells: 400_000,
        }
    }
}

impl QuadratureSettings {
    /// The default settings with absolute tolerance `tolerance`.
    #[must_use]
    pub fn with_tolerance(tolerance: f64) -> Self {
        QuadratureSettings {
            tolerance,
            ..QuadratureSettings::default()
        }
    }

    fn validate(&self) -> Result<()> {
        let bad = |name: &'static str, message: String| Err(Error::Setting { name, message });
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return bad(
                "quadrature tolerance",
                format!("must be finite and positive, got {}", self.tolerance),
            );
        }
        if self.max_depth > 40 {
            return bad(
                "quadrature max_depth",
                format!("must be at most 40, got {}", self.max_depth),
            );
        }
        if self.min_depth > self.max_depth || self.min_depth > 10 {
            return bad(
                "quadrature min_depth",
                format!(
                    "must be at most max_depth ({}) and at most 10, got {}",
                    self.max_depth, self.min_depth
                ),
            );
        }
        Ok(())
    }
}

/// The result of an adaptive quadrature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Integral {
    /// The integral.
    pub value: f64,
    /// The sum of the cells' error estimates `|fine - coarse|`. It estimates the
    /// error of the coarser rule while the value comes from the finer, so for
    /// smooth integrands it overstates the error by orders of magnitude; along a
    /// kink it is of the same order as the true error (for `|u - 0.3|` at
    /// tolerance `1e-8`: estimate `9.6e-9`, true error `8.1e-9`).
    pub error_estimate: f64,
    /// How many times the integrand was evaluated.
    pub evaluations: usize,
    /// How many cells the unit square ended in.
    pub cells: usize,
}

/// Integrates `f(u, v)` over the unit square `[0, 1]^2`.
///
/// Fails if the settings are out of range, if `f` returns a non-finite value,
/// or ([`Error::Limit`]) if the tolerance is not met within `max_depth` and
/// `max_cells`.
pub fn integrate_unit_square(
    f: impl FnMut(f64, f64) -> f64,
    settings: &QuadratureSettings,
) -> Result<Integral> {
    settings.validate()?;
    Adaptive::new(f, settings).run()
}

/// Integrates `f` over a planar triangle or convex quad (`∫ f dA`, in the
/// polygon's units of area).
///
/// Fails if the polygon does not have 3 or 4 finite vertices, has zero area, or
/// is a non-planar or non-convex quad; otherwise as [`integrate_unit_square`].
pub fn integrate_over_polygon(
    polygon: &[DVec3],
    mut f: impl FnMut(DVec3) -> f64,
    settings: &QuadratureSettings,
) -> Result<Integral> {
    let map = ElementMap::new(polygon)?;
    integrate_unit_square(
        |u, v| {
            let (point, jacobian) = map.point_and_jacobian(u, v);
            f(point) * jacobian
        },
        settings,
    )
}

/// The map from the unit square onto an element.
enum ElementMap {
    /// Collapsed square: `a + u (b - a) + u v (c - b)`.
    Triangle([DVec3; 3]),
    /// Bilinear: corners `a b c d` at `(0,0) (1,0) (1,1) (0,1)`.
    Quad([DVec3; 4]),
}

impl ElementMap {
    fn new(polygon: &[DVec3]) -> Result<Self> {
        if !(3..=4).contains(&polygon.len()) {
            let fault = if polygon.len() < 3 {
                GeometryFault::Degenerate
            } else {
                GeometryFault::Unsupported
            };
            return Err(Error::geometry(
                fault,
                format!(
                    "quadrature needs a triangle or a quad, got {} vertices",
                    polygon.len()
                ),
            ));
        }
        if let Some(v) = polygon.iter().find(|v| !v.is_finite()) {
            return Err(Error::geometry(
                GeometryFault::NonFinite,
                format!("quadrature element has a non-finite vertex {v}"),
            ));
        }
        let normal = newell_normal(polygon);
        let diameter2 = polygon
            .iter()
            .flat_map(|a| polygon.iter().map(move |b| (*a - *b).length_squared()))
            .fold(0.0, f64::max);
        if normal.length() <= 1e-12 * diameter2 {
            return Err(Error::geometry(
                GeometryFault::Degenerate,
                format!("quadrature element {polygon:?} has zero area"),
            ));
        }
        if polygon.len() == 3 {
            return Ok(ElementMap::Triangle([polygon[0], polygon[1], polygon[2]]));
        }
        let fault = if planarity_error(polygon) > 1e-6 {
            Some(GeometryFault::NonPlanar)
        } else if !is_convex(polygon, normal) {
            Some(GeometryFault::NonConvex)
        } else {
            None
        };
        if let Some(fault) = fault {
            return Err(Error::geometry(
                fault,
                format!("quadrature element {polygon:?} is not a planar convex quad"),
            ));
        }
        Ok(ElementMap::Quad([
            polygon[0], polygon[1], polygon[2], polygon[3],
        ]))
    }

    /// The point at `(u, v)` and the area Jacobian there.
    fn point_and_jacobian(&self, u: f64, v: f64) -> (DVec3, f64) {
        match self {
            ElementMap::Triangle([a, b, c]) => {
                let point = *a + (*b - *a) * u + (*c - *b) * (u * v);
                let d_du = (*b - *a) + (*c - *b) * v;
                let d_dv = (*c - *b) * u;
                (point, d_du.cross(d_dv).length())
            }
            ElementMap::Quad([a, b, c, d]) => {
                let point = *a * ((1.0 - u) * (1.0 - v))
                    + *b * (u * (1.0 - v))
                    + *c * (u * v)
                    + *d * ((1.0 - u) * v);
                let d_du = (*b - *a) * (1.0 - v) + (*c - *d) * v;
                let d_dv = (*d - *a) * (1.0 - u) + (*c - *b) * u;
                (point, d_du.cross(d_dv).length())
            }
        }
    }
}

/// 3-point Gauss-Legendre nodes and weights on `[0, 1]`.
const GAUSS_NODES: [f64; 3] = [
    0.5 - 0.387_298_334_620_741_7,
    0.5,
    0.5 + 0.387_298_334_620_741_7,
];
const GAUSS_WEIGHTS: [f64; 3] = [5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0];

/// A leaf of the subdivision.
#[derive(Clone, Copy, Debug)]
struct Cell {
    u0: f64,
    v0: f64,
    depth: u32,
    /// The sum of the rule over the four quarter cells: the cell's value.
    fine: f64,
    /// The rule on each quarter cell, which become the children's coarse values.
    quarters: [f64; 4],
    /// `|fine - coarse|`.
    error: f64,
    /// False once the cell has been split.
    live: bool,
}

/// A cell in the priority queue: largest error first, then oldest cell, so the
/// order (and thus the result's bits) never depends on anything but the input.
struct Queued {
    error: f64,
    index: usize,
}

impl PartialEq for Queued {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Queued {}
impl PartialOrd for Queued {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Queued {
    fn cmp(&self, o: &Self) -> Ordering {
        self.error
            .total_cmp(&o.error)
            .then_with(|| o.index.cmp(&self.index))
    }
}

/// The state of one adaptive integration.
struct Adaptive<'s, F> {
    f: F,
    settings: &'s QuadratureSettings,
    cells: Vec<Cell>,
    queue: BinaryHeap<Queued>,
    evaluations: usize,
    leaves: usize,
    total_error: f64,
}

impl<'s, F: FnMut(f64, f64) -> f64> Adaptive<'s, F> {
    fn new(f: F, settings: &'s QuadratureSettings) -> Self {
        Adaptive {
            f,
            settings,
            cells: Vec::new(),
            queue: BinaryHeap::new(),
            evaluations: 0,
            leaves: 0,
            total_error: 0.0,
        }
    }

    fn run(mut self) -> Result<Integral> {
        let depth = self.settings.min_depth;
        let n = 1u32 << depth;
        let side = 1.0 / f64::from(n);
        for j in 0..n {
            for i in 0..n {
                let (u0, v0) = (f64::from(i) * side, f64::from(j) * side);
                let coarse = self.rule(u0, v0, side)?;
                self.add_cell(u0, v0, depth, coarse)?;
            }
        }
        while self.total_error > self.settings.tolerance {
            if self.leaves + 3 > self.settings.max_cells {
                break;
            }
            let Some(Queued { index, .. }) = self.queue.pop() else {
                break;
            };
            self.split(index)?;
        }
        let (value, error_estimate) = self
            .cells
            .iter()
            .filter(|c| c.live)
            .fold((0.0, 0.0), |(v, e), c| (v + c.fine, e + c.error));
        if error_estimate > self.settings.tolerance {
            return Err(Error::limit(
                LimitKind::QuadratureCells,
                format!(
                    "adaptive quadrature reached an error estimate of {error_estimate:.3e}, \
                 above the tolerance {:.3e}, with {} cells (max_depth {}, max_cells {})",
                    self.settings.tolerance,
                    self.leaves,
                    self.settings.max_depth,
                    self.settings.max_cells
                ),
            ));
        }
        Ok(Integral {
            value,
            error_estimate,
            evaluations: self.evaluations,
            cells: self.leaves,
        })
    }

    /// Replaces cell `index` by its four quarters.
    fn split(&mut self, index: usize) -> Result<()> {
        let parent = self.cells[index];
        self.cells[index].live = false;
        self.leaves -= 1;
        self.total_error -= parent.error;
        let half = side_of(parent.depth + 1);
        for (k, coarse) in parent.quarters.into_iter().enumerate() {
            let u0 = parent.u0 + half * (k % 2) as f64;
            let v0 = parent.v0 + half * (k / 2) as f64;
            self.add_cell(u0, v0, parent.depth + 1, coarse)?;
        }
        Ok(())
    }

    /// Adds a leaf whose own rule gave `coarse`, computing its quarters.
    fn add_cell(&mut self, u0: f64, v0: f64, depth: u32, coarse: f64) -> Result<()> {
        let half = side_of(depth + 1);
        let mut quarters = [0.0; 4];
        for (k, q) in quarters.iter_mut().enumerate() {
            *q = self.rule(u0 + half * (k % 2) as f64, v0 + half * (k / 2) as f64, half)?;
        }
        let fine = quarters.iter().sum::<f64>();
        let error = (fine - coarse).abs();
        let index = self.cells.len();
        self.cells.push(Cell {
            u0,
            v0,
            depth,
            fine,
            quarters,
            error,
            live: true,
        });
        self.leaves += 1;
        self.total_error += error;
        if depth < self.settings.max_depth {
            self.queue.push(Queued { error, index });
        }
        Ok(())
    }

    /// The tensor Gauss rule on the cell `[u0, u0 + side] x [v0, v0 + side]`.
    fn rule(&mut self, u0: f64, v0: f64, side: f64) -> Result<f64> {
        let mut sum = 0.0;
        for (wu, nu) in GAUSS_WEIGHTS.iter().zip(GAUSS_NODES) {
            for (wv, nv) in GAUSS_WEIGHTS.iter().zip(GAUSS_NODES) {
                let (u, v) = (u0 + side * nu, v0 + side * nv);
                let value = (self.f)(u, v);
                if !value.is_finite() {
                    return Err(Error::solver(
                        SolverFault::NotANumber,
                        format!("quadrature integrand is {value} at parameters ({u}, {v})"),
                    ));
                }
                sum += wu * wv * value;
            }
        }
        self.evaluations += 9;
        Ok(sum * side * side)
    }
}

/// The side of a cell at `depth`.
fn side_of(depth: u32) -> f64 {
    0.5f64.powi(depth as i32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomials_of_degree_five_are_exact_at_once() {
        let f = |u: f64, v: f64| u.powi(5) * v.powi(4) + 3.0 * u * v;
        let r = integrate_unit_square(f, &QuadratureSettings::default()).unwrap();
        let exact = 1.0 / 30.0 + 0.75;
        assert!((r.value - exact).abs() < 1e-15, "{}", r.value);
        assert_eq!(r.cells, 16, "uniform start only");
    }

    #[test]
    fn areas_of_a_triangle_and_a_trapezoid() {
        let tri = [
            DVec3::ZERO,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 2.0),
        ];
        let r = integrate_over_polygon(&tri, |_| 1.0, &QuadratureSettings::default()).unwrap();
        assert!((r.value - 3.0).abs() < 1e-14);
        let trap = [
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(3.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
        ];
        let r = integrate_over_polygon(&trap, |_| 1.0, &QuadratureSettings::default()).unwrap();
        assert!((r.value - 3.0).abs() < 1e-14);
    }

    #[test]
    fn a_linear_function_over_a_triangle() {
        // The mean of a linear function over a triangle is its value at the centroid.
        let tri = [
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 4.0),
        ];
        let f = |p: DVec3| 2.0 * p.x - p.z + 0.5;
        let r = integrate_over_polygon(&tri, f, &QuadratureSettings::default()).unwrap();
        let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
        assert!((r.value - 4.0 * f(centroid)).abs() < 1e-13);
    }

    #[test]
    fn unmet_tolerance_is_an_error() {
        let s = QuadratureSettings {
            tolerance: 1e-14,
            min_depth: 0,
            max_depth: 3,
            max_cells: 1000,
        };
        let r = integrate_unit_square(|u, _| (u - 0.3).abs(), &s);
        assert!(matches!(r, Err(Error::Limit { .. })));
    }

    #[test]
    fn bad_settings_and_integrands_are_refused() {
        let s = QuadratureSettings::with_tolerance(0.0);
        assert!(integrate_unit_square(|_, _| 1.0, &s).is_err());
        let s = QuadratureSettings::default();
        assert!(integrate_unit_square(|u, _| 1.0 / (u - u), &s).is_err());
        let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        assert!(integrate_over_polygon(&line, |_| 1.0, &s).is_err());
    }
}
