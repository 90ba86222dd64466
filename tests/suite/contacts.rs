//! Objects standing on surfaces (issue 18): a column stands in the middle of
//! its plinth's top. The elements of the top that the column covers in part
//! must not take their light from a hemi-cube placed inside the column (the
//! whole top went black) or from one in the open (the covered part counted
//! as lit): their row is taken at a visible point and scaled by the visible
//! share. Checked against the path tracer, which knows nothing of elements.

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::pipeline::SolverKind;
use radiosity::reference::{Reference, ReferenceSettings};
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::Settings;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Adds quad `c` of `material`, wound to face along `outward`.
pub(super) fn face(b: &mut SceneBuilder, material: u32, c: [DVec3; 4], outward: DVec3) {
    if (c[1] - c[0]).cross(c[3] - c[0]).dot(outward) > 0.0 {
        b.quad(material, c[0], c[1], c[2], c[3]).unwrap();
    } else {
        b.quad(material, c[3], c[2], c[1], c[0]).unwrap();
    }
}

/// The top and four sides of the box from `lo` to `hi` (no bottom: it stands
/// on something), the top as object `top` and the sides as `sides`.
fn standing_box(b: &mut SceneBuilder, m: u32, lo: DVec3, hi: DVec3, top: &str, sides: &str) {
    b.object(top);
    face(
        b,
        m,
        [
            v(lo.x, hi.y, lo.z),
            v(hi.x, hi.y, lo.z),
            v(hi.x, hi.y, hi.z),
            v(lo.x, hi.y, hi.z),
        ],
        DVec3::Y,
    );
    b.object(sides);
    let (x0, x1, y0, y1, z0, z1) = (lo.x, hi.x, lo.y, hi.y, lo.z, hi.z);
    face(
        b,
        m,
        [v(x0, y0, z0), v(x1, y0, z0), v(x1, y1, z0), v(x0, y1, z0)],
        DVec3::NEG_Z,
    );
    face(
        b,
        m,
        [v(x0, y0, z1), v(x1, y0, z1), v(x1, y1, z1), v(x0, y1, z1)],
        DVec3::Z,
    );
    face(
        b,
        m,
        [v(x0, y0, z0), v(x0, y1, z0), v(x0, y1, z1), v(x0, y0, z1)],
        DVec3::NEG_X,
    );
    face(
        b,
        m,
        [v(x1, y0, z0), v(x1, y1, z0), v(x1, y1, z1), v(x1, y0, z1)],
        DVec3::X,
    );
}

/// A closed 3 m room lit by a lamp under its ceiling; a 0.6 m plinth on the
/// floor, and a 0.36 m square column 1.2 m tall standing in the middle of
/// the plinth's top.
fn plinth_room() -> Scene {
    let (w, h) = (3.0, 2.5);
    let mut b = SceneBuilder::new("plinth");
    let white = b.material("white", Rgb::splat(0.7), Rgb::ZERO).unwrap();
    let stone = b
        .material("stone", Rgb::new(0.7, 0.6, 0.4), Rgb::ZERO)
        .unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(10.0)).unwrap();
    let inward = |b: &mut SceneBuilder, name: &str, c: [DVec3; 4], n: DVec3| {
        b.object(name);
        face(b, white, c, n);
    };
    inward(
        &mut b,
        "floor",
        [v(0., 0., 0.), v(w, 0., 0.), v(w, 0., w), v(0., 0., w)],
        DVec3::Y,
    );
    inward(
        &mut b,
        "ceiling",
        [v(0., h, 0.), v(w, h, 0.), v(w, h, w), v(0., h, w)],
        DVec3::NEG_Y,
    );
    inward(
        &mut b,
        "wall_x0",
        [v(0., 0., 0.), v(0., h, 0.), v(0., h, w), v(0., 0., w)],
        DVec3::X,
    );
    inward(
        &mut b,
        "wall_x1",
        [v(w, 0., 0.), v(w, h, 0.), v(w, h, w), v(w, 0., w)],
        DVec3::NEG_X,
    );
    inward(
        &mut b,
        "wall_z0",
        [v(0., 0., 0.), v(w, 0., 0.), v(w, h, 0.), v(0., h, 0.)],
        DVec3::Z,
    );
    inward(
        &mut b,
        "wall_z1",
        [v(0., 0., w), v(w, 0., w), v(w, h, w), v(0., h, w)],
        DVec3::NEG_Z,
    );
    b.object("lamp");
    let y = h - 0.001;
    face(
        &mut b,
        lamp,
        [
            v(0.6, y, 0.6),
            v(1.2, y, 0.6),
            v(1.2, y, 1.2),
            v(0.6, y, 1.2),
        ],
        DVec3::NEG_Y,
    );
    let c = 1.6;
    standing_box(
        &mut b,
        stone,
        v(c - 0.3, 0.0, c - 0.3),
        v(c + 0.3, 0.3, c + 0.3),
        "plinth_top",
        "plinth_sides",
    );
    standing_box(
        &mut b,
        stone,
        v(c - 0.18, 0.3, c - 0.18),
        v(c + 0.18, 1.5, c + 0.18),
        "column_top",
        "column_sides",
    );
    b.build().unwrap()
}

#[test]
fn a_plinth_top_under_a_column_keeps_the_light_of_its_visible_part() {
    let scene = plinth_room();
    let reference = Reference::new(&scene)
        .unwrap()
        .object_means(&ReferenceSettings {
            paths: 200_000,
            seed: 5,
            ..ReferenceSettings::default()
        })
        .unwrap();
    let top = scene
        .objects
        .iter()
        .position(|o| o.name == "plinth_top")
        .unwrap();
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        // Patches of 1 m: the plinth's top is one patch, and the centres of
        // its four initial elements all lie under the column.
        let settings = Settings {
            patch_size: Some(1.0),
            solver_kind: kind,
            ..Settings::default()
        };
        let sol = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
        let objects = sol.object_radiosity(&scene);
        let mut worst = 0.0f64;
        for (o, r) in objects.iter().zip(&reference) {
            if o.name == "lamp" {
                continue;
            }
            for band in 0..3 {
                let e = o.radiosity.0[band] / r.radiosity.0[band] - 1.0;
                let sigma = r.std_error.0[band] / r.radiosity.0[band];
                eprintln!(
                    "{kind:?} {} band {band}: {e:+.4} (sigma {sigma:.4})",
                    o.name
                );
                worst = worst.max(e.abs() - 3.0 * sigma);
            }
        }
        let e = objects[top].radiosity.0[1] / reference[top].radiosity.0[1] - 1.0;
        assert!(e.abs() < 0.05, "{kind:?}: plinth top {e:+.4}");
        assert!(worst < 0.03, "{kind:?}: worst {worst:.4}");
        let energy = sol.stats().energy.relative_difference;
        assert!(energy.abs() < 2e-3, "{kind:?}: energy {energy}");
    }
}

/// Points on the plinth's top beside the column, on leaves that the column
/// covers in part: such a leaf's radiosity is the mean of its whole area,
/// dark where covered. What pictures and probes show there must be the
/// light of the visible part, as the path tracer finds it, not that diluted
/// mean.
#[test]
fn a_partly_covered_element_shows_the_light_of_its_visible_part() {
    let scene = plinth_room();
    let settings = Settings {
        patch_size: Some(1.0),
        ..Settings::default()
    };
    let sol = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
    let top = scene
        .objects
        .iter()
        .position(|o| o.name == "plinth_top")
        .unwrap() as u32;
    // The column's footprint on the plinth's top.
    let (lo, hi) = (1.6 - 0.18, 1.6 + 0.18);
    let outside =
        |p: DVec3| p.x < lo - 1e-3 || p.x > hi + 1e-3 || p.z < lo - 1e-3 || p.z > hi + 1e-3;
    // On each partly covered leaf of the top, a grid of points over its
    // visible part.
    let mut leaves = Vec::new();
    for leaf in sol.leaves() {
        let surface = leaf.surface();
        if scene.surfaces[surface as usize].object != top || !(0.05..0.95).contains(&leaf.visible())
        {
            continue;
        }
        let corners = sol.mesh().surfaces()[surface as usize].polygon(&leaf.cell());
        let mut spots = Vec::new();
        for i in 0..6 {
            for j in 0..6 {
                let (s, t) = ((i as f64 + 0.5) / 6.0, (j as f64 + 0.5) / 6.0);
                let p = corners[0]
                    .lerp(corners[1], s)
                    .lerp(corners[3].lerp(corners[2], s), t);
                if outside(p) {
                    spots.push(p);
                }
            }
        }
        leaves.push((leaf, spots));
    }
    assert!(
        leaves.len() >= 8,
        "only {} partly covered leaves",
        leaves.len()
    );
    let step = leaves.len() / 8;
    let leaves: Vec<_> = leaves.into_iter().step_by(step).take(8).collect();
    let prober = sol.probe();
    let reference = Reference::new(&scene).unwrap();
    let band = 1;
    let mut shown_close = 0;
    for (leaf, spots) in &leaves {
        let points: Vec<_> = spots
            .iter()
            .map(|p| reference.locate(*p, DVec3::Y).expect("on the plinth top"))
            .collect();
        let traced = reference
            .radiosity_at(
                &points,
                &ReferenceSettings {
                    paths: 4_000,
                    seed: 3,
                    ..ReferenceSettings::default()
                },
            )
            .unwrap();
        let n = spots.len() as f64;
        let truth = traced.iter().map(|t| t.radiosity.0[band]).sum::<f64>() / n;
        let sigma = traced
            .iter()
            .map(|t| t.std_error.0[band].powi(2))
            .sum::<f64>()
            .sqrt()
            / n;
        let shown = spots
            .iter()
            .map(|p| prober.hit(*p, DVec3::Y).expect("on the top").radiosity.0[band])
            .sum::<f64>()
            / n;
        let visible = leaf.visible_radiosity().0[band];
        let mean = leaf.radiosity.0[band];
        eprintln!(
            "leaf at {}: visible share {:.3}, traced {truth:.4} +- {sigma:.4}, visible part {visible:.4}, shown {shown:.4}, leaf mean {mean:.4}",
            leaf.centroid(),
            leaf.visible()
        );
        // Measured: the visible parts within 11% (the row is taken at one
        // visible point, beside a contact shadow), the whole-area means 4 to
        // 5 times too dark.
        let tolerance = 0.15 + 3.0 * sigma / truth;
        assert!(
            (visible / truth - 1.0).abs() < tolerance,
            "visible part {visible} against traced {truth}"
        );
        assert!(mean < 0.5 * truth, "leaf mean {mean} not diluted");
        // Shading interpolates between leaves across the contact shadow's
        // steep edge: nearer the truth than the diluted mean always, within
        // the tolerance on most leaves (measured: 7 of 8; the one off, +50%,
        // is a leaf at the column's corner).
        assert!(
            (shown - truth).abs() < (mean - truth).abs(),
            "shown {shown} against traced {truth}, leaf mean {mean}"
        );
        shown_close += usize::from((shown / truth - 1.0).abs() < tolerance);
    }
    assert!(
        shown_close >= 6,
        "shown within tolerance on {shown_close} of 8 leaves"
    );
}
