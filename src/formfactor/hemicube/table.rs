//! Delta form factors of hemi-cube pixels, normalised to sum to exactly 1.

/// The delta form factor of every pixel of a hemi-cube of resolution `n` (pixels
/// across the full top face). Side faces are `n x n/2`.
#[derive(Clone, Debug)]
pub struct DeltaTable {
    /// Pixels across the top face (even).
    pub n: usize,
    /// Top face, row-major `n x n`.
    pub top: Vec<f64>,
    /// One side face, row-major `n` wide and `n/2` high, row 0 at the horizon.
    pub side: Vec<f64>,
    /// Running sums of `top` along each row: `n + 1` entries a row, so that the
    /// delta form factors of a span of pixels cost one subtraction.
    pub top_prefix: Vec<f64>,
    /// Running sums of `side` along each row.
    pub side_prefix: Vec<f64>,
}

impl DeltaTable {
    /// Builds the table for resolution `n` (must be even and at least 2).
    ///
    /// Top pixel at centre `(x, y)`: `dA / (pi (x^2 + y^2 + 1)^2)`; side pixel at
    /// `(x, z)`: `z dA / (pi (x^2 + z^2 + 1)^2)`, with `dA = (2/n)^2`. The raw sum
    /// exceeds 1 slightly (1.000033 at n = 128); the table is scaled so that it
    /// is exactly 1, since a row sum above 1 creates energy and, near rho = 1,
    /// can make the iteration diverge.
    #[must_use]
    pub fn new(n: usize) -> Self {
        assert!(
            n >= 2 && n.is_multiple_of(2),
            "hemi-cube resolution must be even"
        );
        let h = 2.0 / n as f64;
        let da = h * h;
        let centre = |i: usize| -1.0 + (i as f64 + 0.5) * h;
        let mut top = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (centre(i), centre(j));
                let d = x * x + y * y + 1.0;
                top[j * n + i] = da / (std::f64::consts::PI * d * d);
            }
        }
        let mut side = vec![0.0; n * n / 2];
        for j in 0..n / 2 {
            for i in 0..n {
                let (x, z) = (centre(i), (j as f64 + 0.5) * h);
                let d = x * x + z * z + 1.0;
                side[j * n + i] = z * da / (std::f64::consts::PI * d * d);
            }
        }
        let total: f64 = top.iter().sum::<f64>() + 4.0 * side.iter().sum::<f64>();
        for v in top.iter_mut().chain(side.iter_mut()) {
            *v /= total;
        }
        let prefix = |t: &[f64]| {
            let mut out = Vec::with_capacity(t.len() + t.len() / n);
            for row in t.chunks(n) {
                let mut acc = 0.0;
                out.push(0.0);
                for v in row {
                    acc += v;
                    out.push(acc);
                }
            }
            out
        };
        let (top_prefix, side_prefix) = (prefix(&top), prefix(&side));
        DeltaTable {
            n,
            top,
            side,
            top_prefix,
            side_prefix,
        }
    }

    /// The sum of all five faces (1 up to rounding).
    #[must_use]
    pub fn total(&self) -> f64 {
        self.top.iter().sum::<f64>() + 4.0 * self.side.iter().sum::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_sums_match_the_research_brief_and_normalise_to_one() {
        // Raw sums from the research brief (algorithms.md 2.1): n = 8 -> 1.008569,
        // n = 128 -> 1.000033. Recompute them without normalisation here.
        for (n, expected) in [(8usize, 1.008569), (32, 1.000530), (128, 1.000033)] {
            let h = 2.0 / n as f64;
            let c = |i: usize| -1.0 + (i as f64 + 0.5) * h;
            let mut raw = 0.0;
            for j in 0..n {
                for i in 0..n {
                    let d = c(i).powi(2) + c(j).powi(2) + 1.0;
                    raw += h * h / (std::f64::consts::PI * d * d);
                }
            }
            for j in 0..n / 2 {
                for i in 0..n {
                    let z = (j as f64 + 0.5) * h;
                    let d = c(i).powi(2) + z * z + 1.0;
                    raw += 4.0 * z * h * h / (std::f64::consts::PI * d * d);
                }
            }
            assert!((raw - expected).abs() < 2e-6, "n={n}: {raw}");
            assert!((DeltaTable::new(n).total() - 1.0).abs() < 1e-12);
        }
    }
}
