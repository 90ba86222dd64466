//! Coverage of screen triangles at sample centres, in exact integer arithmetic.
//!
//! Vertices are snapped to 1/256 of a sample and edge functions are evaluated
//! in `i64`, so the inside test is exact: two triangles sharing an edge agree on
//! every sample, and the top-left rule gives each sample on a shared edge or
//! vertex to exactly one of them (no cracks, no double coverage).
//!
//! Range: the guard band keeps coordinates within 2^21 samples, i.e. 2^29 in
//! fixed point; coordinate differences stay below 2^30 and an edge function
//! (a difference of two products) below 2^61.

use glam::DVec2;
use std::ops::Range;

/// Fractional bits of the fixed-point sample coordinates.
const SUBPIXEL_BITS: u32 = 8;
/// One sample in fixed point.
const ONE: i64 = 1 << SUBPIXEL_BITS;
/// Half a sample: sample centres sit at `i * ONE + HALF`.
const HALF: i64 = ONE / 2;

/// A point in fixed-point sample coordinates.
pub(crate) type FixedPoint = [i64; 2];

/// `p` (in samples) snapped to the fixed-point grid.
#[inline]
pub(crate) fn to_fixed(p: DVec2) -> FixedPoint {
    let s = ONE as f64;
    [(p.x * s).round() as i64, (p.y * s).round() as i64]
}

/// The inclusive range of sample indices whose centres lie in `[lo, hi]`
/// (fixed point), clamped to `0..count`; `None` if empty.
#[inline]
pub(crate) fn sample_range(lo: i64, hi: i64, count: u32) -> Option<(u32, u32)> {
    // First i with i*ONE + HALF >= lo, last i with i*ONE + HALF <= hi.
    let first = -((HALF - lo).div_euclid(ONE));
    let last = (hi - HALF).div_euclid(ONE);
    let first = first.max(0);
    let last = last.min(i64::from(count) - 1);
    (first <= last).then_some((first as u32, last as u32))
}

/// One edge `a -> b` of a triangle whose inside has positive edge values.
#[derive(Clone, Copy)]
struct Edge {
    a: FixedPoint,
    dx: i64,
    dy: i64,
    /// 0 if samples exactly on the edge belong to this triangle, else 1.
    bias: i64,
}

impl Edge {
    #[inline]
    fn new(a: FixedPoint, b: FixedPoint) -> Edge {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        // The edge function grows along (-dy, dx), into the triangle. Top-left
        // rule (y down): keep samples on a left edge (inside to its right,
        // -dy > 0) or a top edge (horizontal, inside below, dx > 0).
        let owns = -dy > 0 || (dy == 0 && dx > 0);
        Edge {
            a,
            dx,
            dy,
            bias: i64::from(!owns),
        }
    }

    /// The biased edge function at `p`: `>= 0` means inside this edge.
    #[inline]
    fn at(&self, p: FixedPoint) -> i64 {
        self.dx * (p[1] - self.a[1]) - self.dy * (p[0] - self.a[0]) - self.bias
    }
}

/// Twice the signed area of `a, b, c` in fixed point (positive when clockwise on
/// screen, i.e. counter-clockwise with y up).
#[inline]
fn doubled_area(a: FixedPoint, b: FixedPoint, c: FixedPoint) -> i64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Calls `visit(x, y)` for every sample in `rows` and `0..width` whose centre the
/// triangle covers, row by row, left to right. Either winding is accepted; a
/// triangle of zero area covers nothing.
#[inline]
pub(crate) fn for_each_covered(
    tri: [FixedPoint; 3],
    width: u32,
    rows: Range<u32>,
    mut visit: impl FnMut(u32, u32),
) {
    let [a, mut b, mut c] = tri;
    let area = doubled_area(a, b, c);
    if area == 0 {
        return;
    }
    if area < 0 {
        std::mem::swap(&mut b, &mut c);
    }
    let Some((x0, x1)) = sample_range(a[0].min(b[0]).min(c[0]), a[0].max(b[0]).max(c[0]), width)
    else {
        return;
    };
    let Some((y0, y1)) = sample_range(a[1].min(b[1]).min(c[1]), a[1].max(b[1]).max(c[1]), u32::MAX)
    else {
        return;
    };
    let (y0, y1) = (y0.max(rows.start), y1.min(rows.end.saturating_sub(1)));
    if y0 > y1 || rows.is_empty() {
        return;
    }
    let edges = [Edge::new(a, b), Edge::new(b, c), Edge::new(c, a)];
    let steps = edges.map(|e| -e.dy * ONE);
    let left = i64::from(x0) * ONE + HALF;
    for y in y0..=y1 {
        let p = [left, i64::from(y) * ONE + HALF];
        let mut e = edges.map(|edge| edge.at(p));
        for x in x0..=x1 {
            if (e[0] | e[1] | e[2]) >= 0 {
                visit(x, y);
            }
            for k in 0..3 {
                e[k] += steps[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: u32 = 40;

    fn fixed(x: f64, y: f64) -> FixedPoint {
        to_fixed(DVec2::new(x, y))
    }

    fn coverage(tris: &[[FixedPoint; 3]]) -> Vec<u32> {
        let mut count = vec![0u32; (N * N) as usize];
        for &t in tris {
            for_each_covered(t, N, 0..N, |x, y| count[(y * N + x) as usize] += 1);
        }
        count
    }

    #[test]
    fn sample_range_follows_sample_centres() {
        // Centres at 0.5, 1.5, ...: [0.5, 2.5] holds samples 0..=2 exactly.
        assert_eq!(sample_range(HALF, 2 * ONE + HALF, 10), Some((0, 2)));
        assert_eq!(sample_range(HALF + 1, 2 * ONE + HALF - 1, 10), Some((1, 1)));
        assert_eq!(sample_range(ONE + HALF + 1, 2 * ONE + HALF - 1, 10), None);
        assert_eq!(sample_range(-5 * ONE, 50 * ONE, 10), Some((0, 9)));
        assert_eq!(sample_range(-5 * ONE, -ONE, 10), None);
    }

    #[test]
    fn top_left_rule_on_an_axis_aligned_rectangle_through_sample_centres() {
        // Rectangle with corners on sample centres (3.5, 5.5) and (12.5, 20.5),
        // split along either diagonal, either winding: the left and top sides
        // are kept, the right and bottom sides are not.
        let (l, t, r, b) = (3.5, 5.5, 12.5, 20.5);
        let splits = [
            [
                [fixed(l, t), fixed(r, t), fixed(r, b)],
                [fixed(l, t), fixed(r, b), fixed(l, b)],
            ],
            [
                [fixed(l, t), fixed(l, b), fixed(r, b)],
                [fixed(r, t), fixed(l, t), fixed(r, b)],
            ],
            [
                [fixed(l, t), fixed(r, t), fixed(l, b)],
                [fixed(r, t), fixed(r, b), fixed(l, b)],
            ],
        ];
        for tris in splits {
            let count = coverage(&tris);
            for y in 0..N {
                for x in 0..N {
                    let expected = u32::from((3..12).contains(&x) && (5..20).contains(&y));
                    assert_eq!(count[(y * N + x) as usize], expected, "sample ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn fan_with_edges_through_sample_centres_covers_each_sample_once() {
        // A fan around the sample centre (20.5, 20.5); every spoke runs through
        // sample centres. The ring is a convex octagon whose sides also run
        // through sample centres.
        let c = (20.5, 20.5);
        let ring = [
            (8.0, 0.0),
            (6.0, 6.0),
            (0.0, 8.0),
            (-6.0, 6.0),
            (-8.0, 0.0),
            (-6.0, -6.0),
            (0.0, -8.0),
            (6.0, -6.0),
        ];
        let p = |(dx, dy): (f64, f64)| fixed(c.0 + dx, c.1 + dy);
        let tris: Vec<_> = (0..ring.len())
            .map(|i| [p((0.0, 0.0)), p(ring[i]), p(ring[(i + 1) % ring.len()])])
            .collect();
        let count = coverage(&tris);
        let mut inside = 0;
        for y in 0..N {
            for x in 0..N {
                let n = count[(y * N + x) as usize];
                assert!(n <= 1, "sample ({x}, {y}) covered {n} times");
                // Independent inside test: strictly inside the octagon in the
                // sample's offset from the centre.
                let (dx, dy) = (f64::from(x) + 0.5 - c.0, f64::from(y) + 0.5 - c.1);
                let strictly_inside =
                    3.0 * dx.abs() + dy.abs() < 24.0 && dx.abs() + 3.0 * dy.abs() < 24.0;
                if strictly_inside {
                    assert_eq!(n, 1, "sample ({x}, {y}) left uncovered");
                    inside += 1;
                }
            }
        }
        assert!(inside > 150);
    }

    #[test]
    fn jittered_grid_mesh_partitions_its_rectangle() {
        // A 6x6 grid of cells over [2.25, 38.25]^2 with interior
        // vertices jittered by up to 0.2 cells (every cell stays convex), each
        // cell split along a pseudo-randomly chosen diagonal.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rand = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let cells = 6;
        let h = 6.0;
        let mut grid = vec![[0i64; 2]; (cells + 1) * (cells + 1)];
        for j in 0..=cells {
            for i in 0..=cells {
                let interior = i > 0 && j > 0 && i < cells && j < cells;
                let jitter = |r: f64| if interior { (r - 0.5) * 0.4 * h } else { 0.0 };
                let x = 2.25 + i as f64 * h + jitter(rand());
                let y = 2.25 + j as f64 * h + jitter(rand());
                grid[j * (cells + 1) + i] = fixed(x, y);
            }
        }
        let mut tris = Vec::new();
        for j in 0..cells {
            for i in 0..cells {
                let v = |di: usize, dj: usize| grid[(j + dj) * (cells + 1) + i + di];
                if rand() < 0.5 {
                    tris.push([v(0, 0), v(1, 0), v(1, 1)]);
                    tris.push([v(0, 0), v(1, 1), v(0, 1)]);
                } else {
                    tris.push([v(0, 0), v(1, 0), v(0, 1)]);
                    tris.push([v(1, 0), v(1, 1), v(0, 1)]);
                }
            }
        }
        let count = coverage(&tris);
        for y in 0..N {
            for x in 0..N {
                // Centres x + 0.5 in (2.25, 38.25): x in 2..=37.
                let expected = u32::from((2..38).contains(&x) && (2..38).contains(&y));
                assert_eq!(count[(y * N + x) as usize], expected, "sample ({x}, {y})");
            }
        }
    }

    #[test]
    fn degenerate_triangle_covers_nothing() {
        let t = [fixed(1.5, 1.5), fixed(5.5, 5.5), fixed(9.5, 9.5)];
        assert!(coverage(&[t]).iter().all(|&n| n == 0));
    }
}
