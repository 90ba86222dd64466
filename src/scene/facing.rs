//! Single-sided faces that point the other way from their neighbours (half a
//! floor facing down, a closed mesh with some faces turned inwards): they
//! reflect and emit from the side nobody sees, and their lit side is dark.
//!
//! Two faces of one object that share an edge (the same two end points, bit
//! for bit, in world space) agree when they run along it in opposite
//! directions, as the triangles of a consistently wound mesh do; they
//! disagree when they run along it the same way, so that one of them faces
//! the other side. Faces are grouped into connected parts through the edges
//! exactly two faces share, and each face's side is propagated through them;
//! the faces on the smaller side of their part are the ones counted as facing
//! the wrong way. Edges of one face, or of more than two (fins, non-manifold
//! seams), say nothing. Double-sided materials are left out: both their sides
//! reflect. A closed mesh turned wholly inwards is consistent (a room's walls
//! face inwards) and is not reported.

use crate::scene::Scene;
use glam::DVec3;
use std::collections::{BTreeMap, HashMap};

/// An object with faces pointing the other way from their neighbours.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Inconsistent {
    /// Index into `Scene::objects`.
    pub object: u32,
    /// Single-sided faces of the object.
    pub faces: usize,
    /// Faces on the smaller side of their connected part.
    pub against: usize,
}

type Point = [u64; 3];

fn point(p: DVec3) -> Point {
    // Adding 0.0 turns -0.0 into 0.0, so both weld.
    [
        (p.x + 0.0).to_bits(),
        (p.y + 0.0).to_bits(),
        (p.z + 0.0).to_bits(),
    ]
}

/// Every object of `scene` with single-sided faces that point against their
/// neighbours, in object order.
pub(crate) fn inconsistent_objects(scene: &Scene) -> Vec<Inconsistent> {
    // Faces per object, single-sided only.
    let mut by_object: HashMap<u32, Vec<usize>> = HashMap::new();
    for (i, s) in scene.surfaces.iter().enumerate() {
        if !scene.material_of(s).double_sided {
            by_object.entry(s.object).or_default().push(i);
        }
    }
    let mut out: Vec<Inconsistent> = by_object
        .into_iter()
        .filter_map(|(object, faces)| {
            let against = faces_against(scene, &faces);
            (against > 0).then_some(Inconsistent {
                object,
                faces: faces.len(),
                against,
            })
        })
        .collect();
    out.sort_by_key(|o| o.object);
    out
}

/// The number of `faces` on the smaller side of their connected parts.
fn faces_against(scene: &Scene, faces: &[usize]) -> usize {
    // Undirected edge -> (local face, runs from the smaller end point). In
    // a fixed order: where the windings contradict each other (a Moebius
    // strip, a non-manifold fan), which join is ignored decides the count.
    let mut edges: BTreeMap<(Point, Point), Vec<(usize, bool)>> = BTreeMap::new();
    for (local, &i) in faces.iter().enumerate() {
        let v = &scene.surfaces[i].vertices;
        for k in 0..v.len() {
            let (a, b) = (point(v[k]), point(v[(k + 1) % v.len()]));
            if a == b {
                continue;
            }
            let key = if a < b { (a, b) } else { (b, a) };
            edges.entry(key).or_default().push((local, a < b));
        }
    }
    let mut sides = Sides::new(faces.len());
    for shared in edges.values() {
        if let [(f, fa), (g, ga)] = shared[..] {
            // Running the edge the same way: opposite sides.
            sides.join(f, g, fa == ga);
        }
    }
    sides.smaller_sides()
}

/// Union-find with parity: which faces are connected, and whether each faces
/// the same side as its part's root.
struct Sides {
    parent: Vec<usize>,
    /// Parity to the parent: true when the face is turned against it.
    flip: Vec<bool>,
}

impl Sides {
    fn new(n: usize) -> Self {
        Sides {
            parent: (0..n).collect(),
            flip: vec![false; n],
        }
    }

    /// The root of `x` and whether `x` is turned against it (iterative, with
    /// path compression).
    fn find(&mut self, x: usize) -> (usize, bool) {
        let mut path = Vec::new();
        let mut r = x;
        while self.parent[r] != r {
            path.push(r);
            r = self.parent[r];
        }
        // Parities to the root, from the node nearest the root down.
        let mut parity = false;
        for &node in path.iter().rev() {
            parity ^= self.flip[node];
            self.flip[node] = parity;
            self.parent[node] = r;
        }
        (r, self.flip[x] && x != r)
    }

    /// Records that `a` and `b` face opposite sides (`opposite`) or the same.
    /// A contradiction (a face that would be turned against itself, as on a
    /// Moebius strip) is ignored.
    fn join(&mut self, a: usize, b: usize, opposite: bool) {
        let (ra, pa) = self.find(a);
        let (rb, pb) = self.find(b);
        if ra != rb {
            self.parent[rb] = ra;
            self.flip[rb] = pa ^ pb ^ opposite;
        }
    }

    fn smaller_sides(&mut self) -> usize {
        let mut count: HashMap<usize, [usize; 2]> = HashMap::new();
        for x in 0..self.parent.len() {
            let (r, p) = self.find(x);
            count.entry(r).or_default()[usize::from(p)] += 1;
        }
        count.values().map(|c| c[0].min(c[1])).sum()
    }
}

/// One warning per object of `scene` whose faces point against their
/// neighbours, naming it.
pub(crate) fn facing_warnings(scene: &Scene) -> Vec<String> {
    inconsistent_objects(scene)
        .into_iter()
        .map(|o| {
            let name = scene
                .objects
                .get(o.object as usize)
                .map_or_else(|| format!("{}", o.object), |x| x.name.clone());
            format!(
                "object '{name}': {} of its {} single-sided faces point the other way from \
                 their neighbours (they share an edge with a face that runs along it the same \
                 way); those faces reflect light from the side that faces away. Fix the \
                 winding in the modelling tool, or treat every surface as two-sided \
                 (`double_sided`)",
                o.against, o.faces
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::SceneBuilder;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    /// A 2 x 2 floor of triangles (8 faces) whose faces listed in `down` are
    /// wound to face down, in one object, and a consistent box in another.
    fn floor_with(down: &[usize]) -> Scene {
        let mut b = SceneBuilder::new("floor");
        b.overlaps(None);
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("floor");
        let mut k = 0;
        for i in 0..2 {
            for j in 0..2 {
                let (x, z) = (f64::from(i), f64::from(j));
                let tris = [
                    [v(x, 0.0, z), v(x, 0.0, z + 1.0), v(x + 1.0, 0.0, z + 1.0)],
                    [v(x, 0.0, z), v(x + 1.0, 0.0, z + 1.0), v(x + 1.0, 0.0, z)],
                ];
                for t in tris {
                    if down.contains(&k) {
                        b.triangle(m, t[0], t[2], t[1]).unwrap();
                    } else {
                        b.triangle(m, t[0], t[1], t[2]).unwrap();
                    }
                    k += 1;
                }
            }
        }
        b.axis_box("box", m, v(0.2, 0.0, 0.2), v(0.6, 0.4, 0.6))
            .unwrap();
        b.build().unwrap()
    }

    #[test]
    fn faces_wound_against_their_neighbours_are_counted_per_object() {
        assert!(inconsistent_objects(&floor_with(&[])).is_empty());
        let found = inconsistent_objects(&floor_with(&[3]));
        assert_eq!(
            found,
            vec![Inconsistent {
                object: 0,
                faces: 8,
                against: 1
            }]
        );
        // Half the floor turned: the smaller side is half.
        assert_eq!(
            inconsistent_objects(&floor_with(&[0, 1, 2, 3]))[0].against,
            4
        );
        // Every face turned: consistent again (the floor faces down).
        assert!(inconsistent_objects(&floor_with(&[0, 1, 2, 3, 4, 5, 6, 7])).is_empty());
    }

    #[test]
    fn a_moebius_strip_gives_the_same_count_every_time() {
        // A band of 24 quads (48 triangles) with a half twist: no winding
        // agrees with every neighbour, so one join is always ignored, and
        // which one it is must not depend on a hash map's random order.
        let mut b = SceneBuilder::new("band");
        b.overlaps(None);
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("band");
        let n = 24;
        let at = |k: usize, side: f64| {
            // Once round, the band comes back on its other side.
            let (k, side) = if k == n { (0, -side) } else { (k, side) };
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            let r = 2.0 + side * 0.5 * (t / 2.0).cos();
            v(r * t.cos(), r * t.sin(), side * 0.5 * (t / 2.0).sin())
        };
        for k in 0..n {
            let (a, b0, c, d) = (at(k, -1.0), at(k, 1.0), at(k + 1, 1.0), at(k + 1, -1.0));
            b.triangle(m, a, b0, c).unwrap();
            b.triangle(m, a, c, d).unwrap();
        }
        let scene = b.build().unwrap();
        let first = inconsistent_objects(&scene);
        assert_eq!(first.len(), 1, "{first:?}");
        for _ in 0..20 {
            assert_eq!(inconsistent_objects(&scene), first);
        }
    }

    #[test]
    fn a_box_with_one_face_turned_inwards_is_found_and_a_double_sided_one_is_not() {
        let build = |double_sided: bool| {
            let mut b = SceneBuilder::new("box");
            let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
            b.axis_box("box", m, v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0))
                .unwrap();
            let mut scene = b.build().unwrap();
            scene.surfaces[2] = scene.surfaces[2].flipped();
            scene.materials[0].double_sided = double_sided;
            scene
        };
        let found = inconsistent_objects(&build(false));
        assert_eq!(found.len(), 1);
        assert_eq!((found[0].faces, found[0].against), (6, 1));
        assert!(inconsistent_objects(&build(true)).is_empty());
    }
}
