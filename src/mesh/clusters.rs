//! Face clusters: small adjacent surfaces of one object and material whose
//! normals agree, grouped so that they act as one patch.
//!
//! A tessellated curved surface (a column, an arch, a draped cloth) is made
//! of thousands of facets, each far smaller than the patch size. As patches of
//! their own, every facet would be a source of the coarse system: rows would
//! hold an entry per facet seen and the patch system would grow with the
//! triangle count, not with the scene's size. Grouped into clusters about a
//! patch across (after Willmott, Heckbert and Garland's face clusters), the
//! sources follow the patch size again; each facet stays an element of its
//! own, a receiver with its own hemi-cube.
//!
//! The rules, so that a cluster is a fair constant-radiosity source:
//!
//! - only surfaces that the lattice would leave as a single patch, and whose
//!   longest edge is below half the patch size, join clusters (larger ones
//!   are patches of their own already);
//! - members share an edge with the cluster (the same two vertices, traversed
//!   in opposite directions, so that both face the same side), the object and
//!   the material;
//! - every member's normal lies within [`MAX_CLUSTER_ANGLE_DEGREES`] of the
//!   seed's;
//! - the cluster's bounding box diagonal stays at most the patch size;
//! - on an emissive texture, only surfaces whose emission is even join, and
//!   only with neighbours of like emission (see `emission_grid`);
//! - members are lit alike before the solve: the same punctual lights in
//!   view and about the same share of the sky (see `light_signature`).
//!
//! Clusters grow breadth first from the lowest-numbered surface not yet in
//! one, so the result depends on the scene alone.

use super::emission_grid::{emissive_texture, is_even, EVEN_EMISSION};
use super::light_signature::light_signatures;
use crate::math::Rgb;
use crate::scene::{Scene, EMISSION_DEPTH};
use glam::DVec3;
use std::collections::{HashMap, VecDeque};

/// The widest angle between a member's normal and its cluster's seed normal.
/// A cluster this curved seen from a receiver differs from the sum of its
/// facets' form factors only where some facets face away, and its facets'
/// radiosities stay close enough for one source value.
pub const MAX_CLUSTER_ANGLE_DEGREES: f64 = 30.0;

/// A surface joins clusters only if its longest edge is below this fraction
/// of the patch size.
const SMALL: f64 = 0.5;

/// The clusters of two or more surfaces of `scene` at `patch_size`, each
/// listing its surfaces in increasing order, in the order of their first
/// surfaces. Surfaces in no cluster are patches (or lattices of patches) of
/// their own.
pub(crate) fn face_clusters(scene: &Scene, patch_size: f64) -> Vec<Vec<u32>> {
    // A surface whose emission varies within it is cut finer on its own;
    // the rest of a textured emitter joins only neighbours of like emission.
    let emission: Vec<Option<Rgb>> = scene
        .surfaces
        .iter()
        .map(|s| emissive_texture(scene, s).map(|t| t.mean_over_refined(&s.uv, EMISSION_DEPTH)))
        .collect();
    let small: Vec<bool> = scene
        .surfaces
        .iter()
        .map(|s| {
            longest_edge(&s.vertices) < SMALL * patch_size
                && emissive_texture(scene, s).is_none_or(|t| is_even(s, t, patch_size))
        })
        .collect();
    let edges = directed_edges(scene, &small);
    let lit = light_signatures(scene, &small);
    let lit_alike = |a: usize, b: usize| {
        lit.as_ref().is_none_or(|lit| match (&lit[a], &lit[b]) {
            (Some(a), Some(b)) => a.alike(b),
            _ => true,
        })
    };
    let min_cos = MAX_CLUSTER_ANGLE_DEGREES.to_radians().cos();
    let mut taken = vec![false; scene.surfaces.len()];
    let mut clusters = Vec::new();
    let mut queue = VecDeque::new();
    for seed in 0..scene.surfaces.len() {
        if !small[seed] || taken[seed] {
            continue;
        }
        taken[seed] = true;
        let first = &scene.surfaces[seed];
        let (mut lo, mut hi) = bounds(&first.vertices);
        let mut members = vec![seed as u32];
        queue.clear();
        queue.push_back(seed);
        while let Some(s) = queue.pop_front() {
            let v = &scene.surfaces[s].vertices;
            for k in 0..v.len() {
                let (a, b) = (key(v[k]), key(v[(k + 1) % v.len()]));
                // The neighbour across this edge runs it the other way.
                let Some(across) = edges.get(&(b, a)) else {
                    continue;
                };
                for &t in across {
                    let t = t as usize;
                    if taken[t] {
                        continue;
                    }
                    let other = &scene.surfaces[t];
                    if other.material != first.material
                        || other.object != first.object
                        || other.normal.dot(first.normal) < min_cos
                        || !like_emission(emission[seed], emission[t])
                        || !lit_alike(seed, t)
                    {
                        continue;
                    }
                    let (olo, ohi) = bounds(&other.vertices);
                    let (nlo, nhi) = (lo.min(olo), hi.max(ohi));
                    if (nhi - nlo).length() > patch_size {
                        continue;
                    }
                    (lo, hi) = (nlo, nhi);
                    taken[t] = true;
                    members.push(t as u32);
                    queue.push_back(t);
                }
            }
        }
        if members.len() > 1 {
            members.sort_unstable();
            clusters.push(members);
        }
    }
    clusters
}

/// True when two surfaces' emissions (from an emissive texture, else
/// `None`) are close enough for one patch.
fn like_emission(a: Option<Rgb>, b: Option<Rgb>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => {
            (a - b).abs().max_band() <= EVEN_EMISSION * a.max_band().max(b.max_band())
        }
        _ => true,
    }
}

/// A vertex as exact bits: facets of one tessellated mesh share their
/// vertices exactly.
type VertexKey = [u64; 3];

fn key(v: DVec3) -> VertexKey {
    // +0.0 and -0.0 are one point.
    [v.x + 0.0, v.y + 0.0, v.z + 0.0].map(f64::to_bits)
}

/// Every directed edge (from, to) of the small surfaces, with the surfaces
/// that run it in that direction.
fn directed_edges(scene: &Scene, small: &[bool]) -> HashMap<(VertexKey, VertexKey), Vec<u32>> {
    let mut edges: HashMap<(VertexKey, VertexKey), Vec<u32>> = HashMap::new();
    for (s, surface) in scene.surfaces.iter().enumerate() {
        if !small[s] {
            continue;
        }
        let v = &surface.vertices;
        for k in 0..v.len() {
            edges
                .entry((key(v[k]), key(v[(k + 1) % v.len()])))
                .or_default()
                .push(s as u32);
        }
    }
    edges
}

fn longest_edge(v: &[DVec3]) -> f64 {
    (0..v.len())
        .map(|k| (v[(k + 1) % v.len()] - v[k]).length())
        .fold(0.0, f64::max)
}

fn bounds(v: &[DVec3]) -> (DVec3, DVec3) {
    v.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneBuilder, Texture, Wrap};
    use glam::DVec2;
    use std::f64::consts::TAU;

    /// A cylinder of `sides` facets and `rings` rings, radius 1, height 2,
    /// facing out, as one object of one material (quads).
    fn cylinder(sides: usize, rings: usize) -> Scene {
        let mut b = SceneBuilder::new("cylinder");
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("column");
        let at = |i: usize, j: usize| {
            let a = TAU * i as f64 / sides as f64;
            DVec3::new(a.cos(), 2.0 * j as f64 / rings as f64, a.sin())
        };
        for j in 0..rings {
            for i in 0..sides {
                // Counter-clockwise seen from outside.
                b.polygon(m, &[at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)])
                    .unwrap();
            }
        }
        b.build().unwrap()
    }

    /// A strip of `n` 0.1 m quads along x facing up, its texture coordinates
    /// `u = x / (0.1 n)`, under an emissive texture dark on the left half
    /// and bright on the right (two texels, nearest).
    fn glowing_strip(n: usize) -> Scene {
        let mut b = SceneBuilder::new("strip");
        let m = b.material("glow", Rgb::ZERO, Rgb::splat(1.0)).unwrap();
        b.object("strip");
        let at = |i: usize, z: f64| DVec3::new(0.1 * i as f64, 0.0, z);
        for i in 0..n {
            b.polygon(m, &[at(i, 0.0), at(i, 0.1), at(i + 1, 0.1), at(i + 1, 0.0)])
                .unwrap();
        }
        let mut scene = b.build().unwrap();
        scene.materials[m as usize].emissive_texture = Some(std::sync::Arc::new(Texture {
            wrap: [Wrap::ClampToEdge; 2],
            max_value: f64::INFINITY,
            ..Texture::nearest(2, 1, vec![[0.0; 3], [4.0; 3]])
        }));
        let u = |i: usize| i as f64 / n as f64;
        for (i, surface) in scene.surfaces.iter_mut().enumerate() {
            let uv = [(u(i), 0.0), (u(i), 1.0), (u(i + 1), 1.0), (u(i + 1), 0.0)]
                .map(|(a, b)| DVec2::new(a, b));
            *surface = surface.clone().with_uv(&uv);
        }
        scene
    }

    #[test]
    fn clusters_on_an_emissive_texture_keep_bright_and_dark_apart() {
        // Ten quads: 0-4 dark, 5-9 bright; at 2 m patches the whole strip
        // would fit in one cluster.
        let scene = glowing_strip(10);
        let clusters = face_clusters(&scene, 2.0);
        assert_eq!(
            clusters,
            vec![(0..5).collect::<Vec<u32>>(), (5..10).collect()]
        );
        // Nine quads: the middle one straddles the texel edge, so it emits
        // unevenly and stays a patch of its own.
        let scene = glowing_strip(9);
        let clusters = face_clusters(&scene, 2.0);
        assert_eq!(
            clusters,
            vec![(0..4).collect::<Vec<u32>>(), (5..9).collect()]
        );
    }

    #[test]
    fn clusters_do_not_join_facets_in_the_sky_and_under_a_roof() {
        // A strip of ten 0.1 m quads along x facing up, the last five under
        // a roof a centimetre above them, under an even sky: at 2 m patches
        // the strip would be one cluster; lit so differently it is two.
        let mut b = SceneBuilder::new("porch");
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("strip");
        let at = |i: usize, z: f64| DVec3::new(0.1 * i as f64, 0.0, z);
        for i in 0..10 {
            b.polygon(m, &[at(i, 0.0), at(i, 0.1), at(i + 1, 0.1), at(i + 1, 0.0)])
                .unwrap();
        }
        b.object("roof");
        let roof = |x: f64, z: f64| DVec3::new(x, 0.01, z);
        b.polygon(
            m,
            &[
                roof(0.5, -1.0),
                roof(3.0, -1.0),
                roof(3.0, 1.0),
                roof(0.5, 1.0),
            ],
        )
        .unwrap();
        let mut scene = b.build().unwrap();
        let split = vec![(0..5).collect::<Vec<u32>>(), (5..10).collect()];
        // Without a sky nothing tells the facets apart.
        assert_eq!(
            face_clusters(&scene, 2.0),
            vec![(0..10).collect::<Vec<u32>>()]
        );
        scene.sky = Some(crate::scene::Sky::with_horizontal_illuminance(
            crate::scene::SkyModel::Uniform,
            1000.0,
        ));
        assert_eq!(face_clusters(&scene, 2.0), split);
    }

    #[test]
    fn clusters_respect_angle_size_and_adjacency() {
        let scene = cylinder(24, 8); // 15 degrees per facet, 0.26 x 0.25 m
        let patch_size = 1.0;
        let clusters = face_clusters(&scene, patch_size);
        assert!(!clusters.is_empty());
        let min_cos = MAX_CLUSTER_ANGLE_DEGREES.to_radians().cos();
        let mut seen = vec![false; scene.surfaces.len()];
        for c in &clusters {
            assert!(c.len() >= 2);
            assert!(c.windows(2).all(|w| w[0] < w[1]));
            let seed = &scene.surfaces[c[0] as usize];
            let (mut lo, mut hi) = bounds(&seed.vertices);
            for &s in c {
                assert!(!seen[s as usize], "surface {s} in two clusters");
                seen[s as usize] = true;
                let t = &scene.surfaces[s as usize];
                assert!(t.normal.dot(seed.normal) >= min_cos - 1e-12);
                let (a, b) = bounds(&t.vertices);
                lo = lo.min(a);
                hi = hi.max(b);
            }
            assert!((hi - lo).length() <= patch_size + 1e-12);
        }
        // 15-degree facets: at most three across (0, 15, 30 degrees) fit the
        // angle, so no cluster spans more than three facets around.
        assert!(clusters.iter().all(|c| c.len() <= 3 * 8));
        // Most facets are clustered.
        let clustered = seen.iter().filter(|s| **s).count();
        assert!(clustered > scene.surfaces.len() / 2, "{clustered}");
    }

    #[test]
    fn large_surfaces_and_mismatched_neighbours_stay_alone() {
        // Large facets (longer than half the patch size) never cluster.
        let scene = cylinder(24, 8);
        assert!(face_clusters(&scene, 0.4).is_empty());
        // Two coplanar triangles sharing an edge but of different materials,
        // then of different facing, never cluster.
        let mut b = SceneBuilder::new("pair");
        let m1 = b.material("a", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let m2 = b.material("b", Rgb::splat(0.4), Rgb::ZERO).unwrap();
        let p = DVec3::new;
        b.polygon(m1, &[p(0., 0., 0.), p(0.1, 0., 0.), p(0., 0.1, 0.)])
            .unwrap();
        b.polygon(m2, &[p(0.1, 0., 0.), p(0.1, 0.1, 0.), p(0., 0.1, 0.)])
            .unwrap();
        assert!(face_clusters(&b.build().unwrap(), 1.0).is_empty());
        let mut b = SceneBuilder::new("flipped");
        let m = b.material("a", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.polygon(m, &[p(0., 0., 0.), p(0.1, 0., 0.), p(0., 0.1, 0.)])
            .unwrap();
        // Same edge (0.1,0,0)-(0,0.1,0) run in the same direction: faces the
        // other way.
        b.polygon(m, &[p(0.1, 0., 0.), p(0., 0.1, 0.), p(0.1, 0.1, 0.)])
            .unwrap();
        assert!(face_clusters(&b.build().unwrap(), 1.0).is_empty());
        // The same pair facing one way clusters.
        let mut b = SceneBuilder::new("same");
        let m = b.material("a", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.polygon(m, &[p(0., 0., 0.), p(0.1, 0., 0.), p(0., 0.1, 0.)])
            .unwrap();
        b.polygon(m, &[p(0.1, 0., 0.), p(0.1, 0.1, 0.), p(0., 0.1, 0.)])
            .unwrap();
        assert_eq!(face_clusters(&b.build().unwrap(), 1.0), vec![vec![0, 1]]);
    }
}
