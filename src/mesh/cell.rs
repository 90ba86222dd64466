//! Lattice cells: the shape of one quadtree node in its surface's integer lattice.
//!
//! Every surface carries an integer lattice fine enough for the deepest element.
//! A quad surface with `nu x nv` patches has lattice coordinates `u in 0..=nu << D`,
//! `v in 0..=nv << D`; a triangle surface uses barycentric lattice coordinates
//! `(a, b)` with `a + b <= L`. Cells are squares (quads) or lattice triangles,
//! "up" `(a,b) (a+s,b) (a,b+s)` or "down" `(a+s,b+s) (a,b+s) (a+s,b)`. Integer
//! coordinates make shared vertices, neighbours and T-vertices exact.

use smallvec::SmallVec;

/// The deepest subdivision below a patch that the lattice can hold.
pub(crate) const MAX_DEPTH: u8 = 12;

/// A point in a surface lattice, at four times the lattice resolution so that
/// probes just beside an edge midpoint are representable.
pub(crate) type Probe = (i64, i64);

/// A probe beside an edge's midpoint (outside the cell), and the edge's two
/// lattice endpoints.
pub(super) type EdgeProbe = (Probe, (u32, u32), (u32, u32));

/// One quadtree node's region in its surface's lattice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Cell {
    /// The square `[u, u+size] x [v, v+size]` of a quad surface.
    Quad {
        /// Lower corner, first axis.
        u: u32,
        /// Lower corner, second axis.
        v: u32,
        /// Side length in lattice units.
        size: u32,
    },
    /// A lattice triangle of a triangle surface, anchored at the lower corner of
    /// its bounding lattice square.
    Tri {
        /// Anchor, first barycentric axis.
        a: u32,
        /// Anchor, second barycentric axis.
        b: u32,
        /// Leg length in lattice units.
        size: u32,
        /// `true` for `(a,b) (a+s,b) (a,b+s)`, `false` for the inverted triangle.
        up: bool,
    },
}

impl Cell {
    /// Side length in lattice units.
    #[must_use]
    pub fn size(&self) -> u32 {
        match *self {
            Cell::Quad { size, .. } | Cell::Tri { size, .. } => size,
        }
    }

    /// The corners in counter-clockwise order (same orientation as the surface).
    #[must_use]
    pub fn corners(&self) -> SmallVec<[(u32, u32); 4]> {
        match *self {
            Cell::Quad { u, v, size: s } => {
                SmallVec::from_slice(&[(u, v), (u + s, v), (u + s, v + s), (u, v + s)])
            }
            Cell::Tri {
                a,
                b,
                size: s,
                up: true,
            } => SmallVec::from_slice(&[(a, b), (a + s, b), (a, b + s)]),
            Cell::Tri {
                a,
                b,
                size: s,
                up: false,
            } => SmallVec::from_slice(&[(a + s, b + s), (a, b + s), (a + s, b)]),
        }
    }

    /// The four children of a split (`size` must be even).
    #[must_use]
    pub fn children(&self) -> [Cell; 4] {
        match *self {
            Cell::Quad { u, v, size } => {
                let h = size / 2;
                let q = |u, v| Cell::Quad { u, v, size: h };
                [q(u, v), q(u + h, v), q(u + h, v + h), q(u, v + h)]
            }
            Cell::Tri { a, b, size, up } => {
                let h = size / 2;
                let t = |a, b, up| Cell::Tri { a, b, size: h, up };
                if up {
                    [
                        t(a, b, true),
                        t(a + h, b, true),
                        t(a, b + h, true),
                        t(a, b, false),
                    ]
                } else {
                    [
                        t(a + h, b + h, false),
                        t(a, b + h, false),
                        t(a + h, b, false),
                        t(a + h, b + h, true),
                    ]
                }
            }
        }
    }

    /// A probe strictly inside the cell. Cells of one quadtree are nested or
    /// disjoint, so a cell no larger than `other` lies inside it exactly when
    /// `other` contains this probe.
    #[must_use]
    pub(crate) fn inner_probe(&self) -> Probe {
        match *self {
            Cell::Quad { u, v, size } => (
                4 * u as i64 + 2 * size as i64,
                4 * v as i64 + 2 * size as i64,
            ),
            Cell::Tri { a, b, size, up } => {
                // A quarter and three quarters along the legs (in probe units,
                // `size` is a quarter of the leg).
                let k = if up { 1 } else { 3 };
                (
                    4 * a as i64 + k * size as i64,
                    4 * b as i64 + k * size as i64,
                )
            }
        }
    }

    /// True when `inner` (a cell of the same quadtree) lies inside this one.
    #[must_use]
    pub fn holds(&self, inner: &Cell) -> bool {
        inner.size() <= self.size() && self.contains(inner.inner_probe())
    }

    /// True when the probe (at four times lattice resolution) lies inside the
    /// cell or on its boundary.
    #[must_use]
    pub fn contains(&self, p: Probe) -> bool {
        let (x, y) = p;
        match *self {
            Cell::Quad { u, v, size } => {
                let (u0, v0, u1, v1) = (
                    4 * u as i64,
                    4 * v as i64,
                    4 * (u + size) as i64,
                    4 * (v + size) as i64,
                );
                x >= u0 && x <= u1 && y >= v0 && y <= v1
            }
            Cell::Tri { a, b, size, up } => {
                let (a0, b0, s) = (4 * a as i64, 4 * b as i64, 4 * size as i64);
                if up {
                    x >= a0 && y >= b0 && x + y <= a0 + b0 + s
                } else {
                    x <= a0 + s && y <= b0 + s && x + y >= a0 + b0 + s
                }
            }
        }
    }

    /// For each edge (corner i to corner i+1): a probe a quarter lattice unit
    /// outside the edge's midpoint, and the edge's two lattice endpoints.
    #[must_use]
    pub(crate) fn edge_probes(&self) -> SmallVec<[EdgeProbe; 4]> {
        let c = self.corners();
        let m = c.len();
        let centre = {
            let (sx, sy) = c
                .iter()
                .fold((0i64, 0i64), |(x, y), p| (x + p.0 as i64, y + p.1 as i64));
            (4 * sx / m as i64, 4 * sy / m as i64)
        };
        let mut out = SmallVec::new();
        for i in 0..m {
            let p0 = c[i];
            let p1 = c[(i + 1) % m];
            // Midpoint at 4x resolution: 2 * (p0 + p1).
            let mx = 2 * (p0.0 as i64 + p1.0 as i64);
            let my = 2 * (p0.1 as i64 + p1.1 as i64);
            // Outward direction: away from the cell centre, one unit per axis
            // that the edge is not parallel to.
            let dx = if p0.0 == p1.0 {
                (mx - centre.0).signum()
            } else {
                0
            };
            let dy = if p0.1 == p1.1 {
                (my - centre.1).signum()
            } else {
                0
            };
            let (dx, dy) = if dx == 0 && dy == 0 {
                // Diagonal edge of a lattice triangle: outward is (+1,+1) for an
                // up triangle and (-1,-1) for a down one.
                let sgn = (mx + my - centre.0 - centre.1).signum();
                (sgn, sgn)
            } else {
                (dx, dy)
            };
            out.push(((mx + dx, my + dy), p0, p1));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cell_holds_its_descendants_and_nothing_else() {
        for root in [
            Cell::Quad {
                u: 8,
                v: 4,
                size: 8,
            },
            Cell::Tri {
                a: 0,
                b: 8,
                size: 8,
                up: true,
            },
            Cell::Tri {
                a: 8,
                b: 0,
                size: 8,
                up: false,
            },
        ] {
            let children = root.children();
            let grandchildren: Vec<Cell> = children.iter().flat_map(Cell::children).collect();
            for (i, c) in children.iter().enumerate() {
                assert!(root.holds(c));
                assert!(!c.holds(&root), "a child does not hold its parent");
                for (j, d) in children.iter().enumerate() {
                    assert_eq!(c.holds(d), i == j, "{c:?} {d:?}");
                }
                for g in &grandchildren {
                    let mine = c.children().contains(g);
                    assert_eq!(c.holds(g), mine, "{c:?} {g:?}");
                }
            }
        }
    }

    #[test]
    fn children_tile_the_parent() {
        for parent in [
            Cell::Quad {
                u: 8,
                v: 4,
                size: 4,
            },
            Cell::Tri {
                a: 0,
                b: 0,
                size: 4,
                up: true,
            },
            Cell::Tri {
                a: 4,
                b: 0,
                size: 4,
                up: false,
            },
        ] {
            let area = |c: &Cell| {
                let k = c.corners();
                let mut s = 0i64;
                for i in 0..k.len() {
                    let (x0, y0) = (k[i].0 as i64, k[i].1 as i64);
                    let (x1, y1) = (k[(i + 1) % k.len()].0 as i64, k[(i + 1) % k.len()].1 as i64);
                    s += x0 * y1 - x1 * y0;
                }
                s
            };
            let pa = area(&parent);
            assert!(pa > 0, "parent {parent:?} must be counter-clockwise");
            let sum: i64 = parent
                .children()
                .iter()
                .map(|c| {
                    let a = area(c);
                    assert!(a > 0, "child {c:?} must be counter-clockwise");
                    for k in c.corners() {
                        assert!(parent.contains((4 * k.0 as i64, 4 * k.1 as i64)));
                    }
                    a
                })
                .sum();
            assert_eq!(sum, pa);
        }
    }

    #[test]
    fn edge_probes_lie_outside_and_beside_the_edge() {
        for cell in [
            Cell::Quad {
                u: 8,
                v: 4,
                size: 4,
            },
            Cell::Tri {
                a: 4,
                b: 4,
                size: 4,
                up: true,
            },
            Cell::Tri {
                a: 4,
                b: 4,
                size: 4,
                up: false,
            },
        ] {
            for (probe, _, _) in cell.edge_probes() {
                assert!(!cell.contains(probe), "{cell:?} {probe:?}");
            }
        }
        // The up triangle's diagonal probe lands in the down triangle of the same square.
        let up = Cell::Tri {
            a: 4,
            b: 4,
            size: 4,
            up: true,
        };
        let down = Cell::Tri {
            a: 4,
            b: 4,
            size: 4,
            up: false,
        };
        let diag = up.edge_probes()[1].0;
        assert!(down.contains(diag));
    }
}
