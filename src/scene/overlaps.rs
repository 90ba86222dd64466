//! Surfaces that lie on top of each other, facing the same way, with different
//! materials (a light flush with the ceiling it hangs from). The hemi-cube's
//! depth test cannot order them: whichever is drawn first wins every pixel, so
//! the other is hidden from the whole scene (a flush light leaves the room
//! black). The solve refuses such a scene with a message naming both objects.

use crate::error::{Error, Result};
use crate::scene::{Scene, Surface};
use glam::{DVec2, DVec3};

/// Planes closer than this fraction of the scene's diameter count as one. The
/// item buffer keeps 1/depth in single precision, stepped along each span, so
/// it can misorder surfaces whose depths differ by less than about
/// `n * 1.2e-7` relative at a resolution of `n` (1.5e-5 at 128): such a gap
/// is as good as none for a receiver across the scene.
pub const COPLANAR_GAP: f64 = 1e-5;

/// Fails with a [`Error::Geometry`] naming the first pair of objects that overlap
/// in one plane, facing the same way, with materials that differ.
pub(crate) fn check_coplanar_overlaps(scene: &Scene) -> Result<()> {
    let gap = COPLANAR_GAP * scene.diameter();
    let touch = 1e-9 * scene.diameter();
    let key = |s: &Surface| {
        let q = (s.normal * 1e3).round();
        (q.x as i64, q.y as i64, q.z as i64)
    };
    let offset = |s: &Surface| s.normal.dot(s.vertices[0]);
    let mut order: Vec<usize> = (0..scene.surfaces.len()).collect();
    order.sort_by(|&a, &b| {
        let (sa, sb) = (&scene.surfaces[a], &scene.surfaces[b]);
        key(sa)
            .cmp(&key(sb))
            .then(offset(sa).total_cmp(&offset(sb)))
    });
    // Runs of surfaces with the same rounded normal whose offsets chain within
    // `gap`: the only candidates for overlapping.
    let mut start = 0;
    while start < order.len() {
        let first = &scene.surfaces[order[start]];
        let mut end = start + 1;
        while end < order.len() {
            let (prev, next) = (&scene.surfaces[order[end - 1]], &scene.surfaces[order[end]]);
            if key(next) != key(first) || offset(next) - offset(prev) > gap {
                break;
            }
            end += 1;
        }
        if end - start > 1 {
            check_run(scene, &order[start..end], first.normal, gap, touch)?;
        }
        start = end;
    }
    Ok(())
}

/// Sweep and prune along one in-plane axis, then the exact test on pairs whose
/// bounds overlap.
fn check_run(scene: &Scene, run: &[usize], normal: DVec3, gap: f64, touch: f64) -> Result<()> {
    let u_axis = normal.any_orthonormal_vector();
    let w_axis = normal.cross(u_axis);
    let flat: Vec<(usize, Vec<DVec2>)> = run
        .iter()
        .map(|&i| {
            let v = &scene.surfaces[i].vertices;
            (
                i,
                v.iter()
                    .map(|p| DVec2::new(p.dot(u_axis), p.dot(w_axis)))
                    .collect(),
            )
        })
        .collect();
    let bounds = |p: &[DVec2]| {
        p.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), q| (lo.min(*q), hi.max(*q)),
        )
    };
    let mut by_u: Vec<(DVec2, DVec2, usize)> = flat
        .iter()
        .enumerate()
        .map(|(k, (_, p))| {
            let (lo, hi) = bounds(p);
            (lo, hi, k)
        })
        .collect();
    by_u.sort_by(|a, b| a.0.x.total_cmp(&b.0.x));
    let mut active: Vec<(DVec2, DVec2, usize)> = Vec::new();
    for &(lo, hi, k) in &by_u {
        active.retain(|a| a.1.x > lo.x + touch);
        for &(alo, ahi, j) in &active {
            if alo.y + touch >= hi.y || lo.y + touch >= ahi.y {
                continue;
            }
            let (a, b) = (flat[j].0, flat[k].0);
            let (sa, sb) = (&scene.surfaces[a], &scene.surfaces[b]);
            if scene.materials[sa.material as usize].reflectance
                == scene.materials[sb.material as usize].reflectance
                && scene.materials[sa.material as usize].emission
                    == scene.materials[sb.material as usize].emission
            {
                continue; // duplicates look the same whichever wins
            }
            if same_plane(sa, sb, gap) && overlap(&flat[j].1, &flat[k].1, touch) {
                return Err(overlap_error(scene, a, b));
            }
        }
        active.push((lo, hi, k));
    }
    Ok(())
}

/// Both face the same way and every vertex of each lies within `gap` of the
/// other's plane.
fn same_plane(a: &Surface, b: &Surface, gap: f64) -> bool {
    let near = |s: &Surface, t: &Surface| {
        t.vertices
            .iter()
            .all(|p| s.normal.dot(*p - s.vertices[0]).abs() <= gap)
    };
    a.normal.dot(b.normal) > 0.0 && near(a, b) && near(b, a)
}

/// Convex polygons overlapping by more than `touch` (separating axes: the edge
/// normals of both).
fn overlap(a: &[DVec2], b: &[DVec2], touch: f64) -> bool {
    let project = |p: &[DVec2], axis: DVec2| {
        p.iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| {
                let x = q.dot(axis);
                (lo.min(x), hi.max(x))
            })
    };
    for poly in [a, b] {
        for i in 0..poly.len() {
            let e = poly[(i + 1) % poly.len()] - poly[i];
            let axis = DVec2::new(-e.y, e.x).normalize_or_zero();
            if axis == DVec2::ZERO {
                continue;
            }
            let (a0, a1) = project(a, axis);
            let (b0, b1) = project(b, axis);
            if a1 <= b0 + touch || b1 <= a0 + touch {
                return false;
            }
        }
    }
    true
}

fn overlap_error(scene: &Scene, a: usize, b: usize) -> Error {
    let name = |s: usize| {
        let surface = &scene.surfaces[s];
        let object = scene.objects.get(surface.object as usize);
        (
            object.map_or_else(|| format!("{}", surface.object), |o| o.name.clone()),
            scene.materials[surface.material as usize].name.clone(),
        )
    };
    let ((oa, ma), (ob, mb)) = (name(a), name(b));
    Error::Geometry(format!(
        "surfaces {a} (object '{oa}', material '{ma}') and {b} (object '{ob}', material \
         '{mb}') overlap in one plane, facing the same way: the hemi-cube cannot tell which is \
         in front, so one would hide the other from the whole scene; move one off the other by \
         at least {:.3e} m (1e-4 of the scene's size) or cut a hole for it",
        1e-4 * scene.diameter()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::SceneBuilder;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn the_cornell_box_light_hangs_far_enough_below_its_ceiling() {
        check_coplanar_overlaps(&crate::scenes::cornell_box()).unwrap();
    }

    #[test]
    fn overlapping_touching_and_separate_squares() {
        let square = |b: &mut SceneBuilder, m: u32, x0: f64, y: f64| {
            b.quad(
                m,
                v(x0, y, 0.0),
                v(x0 + 1.0, y, 0.0),
                v(x0 + 1.0, y, 1.0),
                v(x0, y, 1.0),
            )
            .unwrap();
        };
        let scene = |second_x: f64, second_y: f64| {
            let mut b = SceneBuilder::new("squares");
            let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
            let red = b
                .material("red", Rgb::new(0.5, 0.0, 0.0), Rgb::ZERO)
                .unwrap();
            b.object("a");
            square(&mut b, grey, 0.0, 0.0);
            b.object("b");
            square(&mut b, red, second_x, second_y);
            b.build().unwrap()
        };
        // Half overlapping in one plane: refused.
        let e = check_coplanar_overlaps(&scene(0.5, 0.0)).unwrap_err();
        assert!(e.to_string().contains("object 'b'"), "{e}");
        // Sharing an edge, apart, or lifted clear of the plane: accepted.
        check_coplanar_overlaps(&scene(1.0, 0.0)).unwrap();
        check_coplanar_overlaps(&scene(3.0, 0.0)).unwrap();
        check_coplanar_overlaps(&scene(0.5, 1e-3)).unwrap();
    }
}
