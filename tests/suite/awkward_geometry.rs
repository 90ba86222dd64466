//! Awkward geometry: slivers, needles, non-planar quads, surfaces nearly or
//! exactly on top of each other, boxes standing on or through a floor, and
//! emitters from 1e-6 to 1e6. Each must give finite, sensible radiosities,
//! checked against closed forms (furnaces), Lambert's exact form factor, or
//! linearity.

use super::common::rel;
use super::stress_scenes::{
    assert_finite_non_negative, downward_quad, energy_errors, leaves, lit_room_with_box,
    quick_settings, room, v,
};
use glam::DVec3;
use radiosity::analytic::lambert;
use radiosity::math::Rgb;
use radiosity::pipeline::{ProgressiveSettings, SolverKind};
use radiosity::scene::{Overlaps, Scene, SceneBuilder};
use radiosity::{GeometryFault, Settings, Solution};

const FURNACE_RHO: f64 = 0.5;

/// A furnace room `2 x 1.6 x 2.4` (every surface reflectance 0.5, exitance 1)
/// with whatever `inside` adds (in the same material, index 0).
fn furnace_with(inside: impl FnOnce(&mut SceneBuilder)) -> Scene {
    let mut b = SceneBuilder::new("furnace");
    let m = b
        .material(
            "furnace",
            Rgb::splat(FURNACE_RHO),
            Rgb::splat(1.0 / std::f64::consts::PI),
        )
        .unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(2.0, 1.6, 2.4), m, m, m);
    inside(&mut b);
    b.build().unwrap()
}

/// In a closed homogeneous furnace every element is at `E / (1 - rho)` = 2,
/// whatever the geometry, as long as every hemi-cube sees only front faces.
fn assert_furnace(sol: &Solution, what: &str) {
    assert_finite_non_negative(sol, what);
    let exact = 1.0 / (1.0 - FURNACE_RHO);
    for e in leaves(sol) {
        assert!(
            rel(e.radiosity[0], exact) < 0.005,
            "{what}: element at {} (area {:.2e}) has {} instead of {exact}",
            e.centroid(),
            e.area(),
            e.radiosity[0]
        );
    }
}

#[test]
fn slivers_of_aspect_1000_in_a_furnace() {
    // A 1 m rod of 1 mm square section: four faces of aspect 1000:1 (two ends
    // of 1 mm square). Its patches are 1 mm wide strips.
    let scene = furnace_with(|b| {
        b.axis_box("rod", 0, v(0.5, 0.8, 1.0), v(1.5, 0.801, 1.001))
            .unwrap();
    });
    let sol = radiosity::solve(&scene, &quick_settings(0.4), &|_| {}).unwrap();
    assert_furnace(&sol, "rod");
}

#[test]
fn needle_triangles_with_a_near_zero_edge_in_a_furnace() {
    // A flat tetrahedron whose edge c-d is 1e-6 m long: faces a-c-d and b-c-d
    // are needles of aspect about 1e6, faces a-b-c and a-b-d meet at a
    // dihedral angle of 1e-6 rad. All four face outwards.
    let (a, bb, c, d) = (
        v(0.6, 0.5, 1.0),
        v(1.4, 0.5, 1.0),
        v(1.0, 0.5, 1.8),
        v(1.0, 0.500001, 1.8),
    );
    let scene = furnace_with(|b| {
        b.object("needle");
        b.triangle(0, a, bb, c).unwrap(); // faces -y
        b.triangle(0, a, d, bb).unwrap(); // faces +y
        b.triangle(0, a, c, d).unwrap();
        b.triangle(0, bb, d, c).unwrap();
    });
    for s in &scene.surfaces[6..] {
        let centre = scene.surfaces[6..]
            .iter()
            .map(|s| s.centroid())
            .sum::<DVec3>()
            / 4.0;
        assert!(
            s.normal.dot(s.centroid() - centre) > 0.0,
            "the test's tetrahedron must face outwards"
        );
    }
    let sol = radiosity::solve(&scene, &quick_settings(0.4), &|_| {}).unwrap();
    assert_furnace(&sol, "needle");
}

#[test]
fn a_non_planar_ceiling_is_split_and_stays_closed() {
    // One ceiling corner raised by 0.3 m: the walls stay planar (each lies in an
    // axis plane), the ceiling quad is warped and the builder splits it.
    let mut b = SceneBuilder::new("tent");
    let m = b
        .material(
            "furnace",
            Rgb::splat(FURNACE_RHO),
            Rgb::splat(1.0 / std::f64::consts::PI),
        )
        .unwrap();
    let (x, z) = (2.0, 2.4);
    let h = |px: f64, pz: f64| if px > 0.0 && pz > 0.0 { 1.9 } else { 1.6 };
    let top = |px: f64, pz: f64| v(px, h(px, pz), pz);
    let floor = |px: f64, pz: f64| v(px, 0.0, pz);
    b.quad(m, floor(0., 0.), floor(0., z), floor(x, z), floor(x, 0.))
        .unwrap();
    b.quad(m, top(0., 0.), top(x, 0.), top(x, z), top(0., z))
        .unwrap();
    b.quad(m, floor(0., 0.), floor(x, 0.), top(x, 0.), top(0., 0.))
        .unwrap();
    b.quad(m, floor(0., z), top(0., z), top(x, z), floor(x, z))
        .unwrap();
    b.quad(m, floor(0., 0.), top(0., 0.), top(0., z), floor(0., z))
        .unwrap();
    b.quad(m, floor(x, 0.), floor(x, z), top(x, z), top(x, 0.))
        .unwrap();
    let scene = b.build().unwrap();
    assert_eq!(
        scene.surfaces.len(),
        7,
        "the warped ceiling becomes two triangles"
    );
    let sol = radiosity::solve(&scene, &quick_settings(0.4), &|_| {}).unwrap();
    assert_furnace(&sol, "tent");
}

/// Leaf elements whose polygon lies inside the axis-aligned rectangle
/// `x0..x1, z0..z1` (at any height), strictly or touching its border.
fn elements_within(
    sol: &Solution,
    surface: u32,
    x: (f64, f64),
    z: (f64, f64),
) -> Vec<radiosity::solution::Leaf<'_>> {
    leaves(sol)
        .into_iter()
        .filter(|e| e.surface() == surface)
        .filter(|e| {
            let poly = sol.mesh().surfaces()[e.surface() as usize].polygon(&e.cell());
            poly.iter().all(|p| {
                p.x >= x.0 - 1e-12 && p.x <= x.1 + 1e-12 && p.z >= z.0 - 1e-12 && p.z <= z.1 + 1e-12
            })
        })
        .collect()
}

const LIGHT_X: (f64, f64) = (0.7, 1.3);
const LIGHT_Z: (f64, f64) = (0.9, 1.5);
const LIGHT_RADIANCE: f64 = 10.0;

/// A room with black walls, a grey floor, a ceiling of reflectance
/// `ceiling_rho` and a light facing down `gap` below the ceiling.
fn room_with_light_under_ceiling(gap: f64, ceiling_rho: f64) -> Scene {
    room_with_light_under_ceiling_as(gap, ceiling_rho, Some(Overlaps::Resolve)).unwrap()
}

#[test]
fn a_light_a_ten_thousandth_of_the_scene_below_the_ceiling() {
    // The room's diagonal is 3.5 m; the light hangs 3.5e-4 m below the ceiling.
    let gap = 3.5e-4;

    // Black ceiling: the floor receives the light's direct light only, so an
    // element's radiosity is 0.5 E F(centroid -> light), Lambert's exact form
    // factor. The hybrid rows give the light exactly that, but a row whose sum
    // exceeds 1 is scaled back, and the ceiling patches the light half hides
    // get pixel estimates of their visible fraction: at 64 pixels across a
    // face, that aliasing is a few tenths of a percent of the row.
    let scene = room_with_light_under_ceiling(gap, 0.0);
    let light = &scene.surfaces[6];
    assert_eq!(light.normal, -DVec3::Y, "the light faces down");
    let light_polygon = light.vertices.to_vec();
    let sol = radiosity::solve(&scene, &quick_settings(0.3), &|_| {}).unwrap();
    assert_finite_non_negative(&sol, "gap, black ceiling");
    let exitance = LIGHT_RADIANCE * std::f64::consts::PI;
    let floor: Vec<_> = leaves(&sol)
        .into_iter()
        .filter(|e| e.surface() == 0)
        .collect();
    assert!(floor.len() > 50);
    let mut worst: f64 = 0.0;
    for e in floor {
        let f = lambert::point_to_polygon(e.centroid(), DVec3::Y, &light_polygon).unwrap();
        let direct = 0.5 * exitance * f;
        worst = worst.max(rel(e.radiosity[0], direct));
        assert!(
            rel(e.radiosity[0], direct) < 0.01,
            "floor element at {}: {} instead of {direct}",
            e.centroid(),
            e.radiosity[0]
        );
    }
    eprintln!("light {gap} m below the ceiling: floor within {worst:.1e} of Lambert");

    // Grey ceiling: its elements wholly above the light see only the light's
    // back and get nothing, however close the two surfaces are.
    let sol = radiosity::solve(
        &room_with_light_under_ceiling(gap, 0.5),
        &quick_settings(0.3),
        &|_| {},
    )
    .unwrap();
    assert_finite_non_negative(&sol, "gap, grey ceiling");
    let hidden = elements_within(&sol, 1, LIGHT_X, LIGHT_Z);
    assert!(hidden.len() >= 4);
    for e in hidden {
        assert_eq!(
            e.radiosity[0],
            0.0,
            "ceiling element at {} is lit",
            e.centroid()
        );
    }
    let lit = leaves(&sol)
        .into_iter()
        .filter(|e| e.surface() == 1)
        .map(|e| e.radiosity[0])
        .fold(0.0, f64::max);
    assert!(lit > 0.0, "the rest of the ceiling is lit by the floor");
}

/// [`room_with_light_under_ceiling`] with the builder's overlap policy.
fn room_with_light_under_ceiling_as(
    gap: f64,
    ceiling_rho: f64,
    policy: Option<Overlaps>,
) -> radiosity::Result<Scene> {
    let mut b = SceneBuilder::new("gap");
    b.overlaps(policy);
    let black = b.material("black", Rgb::ZERO, Rgb::ZERO).unwrap();
    let floor = b.material("floor", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let ceiling = b
        .material("ceiling", Rgb::splat(ceiling_rho), Rgb::ZERO)
        .unwrap();
    let light = b
        .material("light", Rgb::ZERO, Rgb::splat(LIGHT_RADIANCE))
        .unwrap();
    room(
        &mut b,
        v(0.0, 0.0, 0.0),
        v(2.0, 1.6, 2.4),
        floor,
        ceiling,
        black,
    );
    b.object("light");
    downward_quad(&mut b, light, 1.6 - gap, LIGHT_X, LIGHT_Z);
    b.build()
}

#[test]
fn a_light_flush_with_the_ceiling_is_refused_by_name_when_overlaps_are_errors() {
    // Exactly in the ceiling's plane the item buffer cannot order the two, the
    // ceiling (drawn first) hides the light everywhere and the room would be
    // black. With Overlaps::Error the builder refuses it, naming both; a scene
    // left unresolved is refused by the solve, whichever solver runs (both go
    // through the same checks).
    for gap in [0.0, 1e-9, 1e-6] {
        let e = room_with_light_under_ceiling_as(gap, 0.5, Some(Overlaps::Error)).unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(
                e,
                radiosity::Error::Geometry {
                    fault: GeometryFault::Overlap,
                    ..
                }
            ),
            "{text}"
        );
        assert!(
            text.contains("'ceiling'") && text.contains("'light'") && text.contains("one plane"),
            "{text}"
        );
        for solver_kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
            let settings = Settings {
                solver_kind,
                ..quick_settings(0.3)
            };
            let scene = room_with_light_under_ceiling_as(gap, 0.5, None).unwrap();
            let e = radiosity::solve(&scene, &settings, &|_| {}).unwrap_err();
            let text = e.to_string();
            assert!(
                matches!(
                    e,
                    radiosity::Error::Geometry {
                        fault: GeometryFault::Overlap,
                        ..
                    }
                ),
                "{text}"
            );
            assert!(
                text.contains("'ceiling'") && text.contains("'light'"),
                "{text}"
            );
        }
    }
    // Identical duplicates z-fight harmlessly (both look the same): accepted.
    let mut b = SceneBuilder::new("duplicates");
    b.overlaps(None);
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let light = b.material("light", Rgb::ZERO, Rgb::ONE).unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(2.0, 1.6, 2.4), grey, grey, grey);
    b.object("light");
    downward_quad(&mut b, light, 1.5, (0.7, 1.3), (0.9, 1.5));
    b.object("floor again");
    b.quad(
        grey,
        v(0.0, 0.0, 0.0),
        v(0.0, 0.0, 2.4),
        v(2.0, 0.0, 2.4),
        v(2.0, 0.0, 0.0),
    )
    .unwrap();
    radiosity::solve(&b.build().unwrap(), &quick_settings(0.6), &|_| {}).unwrap();
}

/// Area-weighted mean radiosity (band 0) and area of the object `name`.
fn object_mean(scene: &Scene, sol: &Solution, name: &str) -> (f64, f64) {
    let o = sol
        .object_radiosity(scene)
        .into_iter()
        .find(|o| o.name == name)
        .unwrap();
    (o.radiosity[0], o.area)
}

#[test]
fn a_light_flush_with_the_ceiling_lights_the_room_as_one_just_below_it() {
    // Resolved (the default), the flush light covers its footprint of the
    // ceiling, which is cut away. With a black ceiling the floor then gets the
    // light's direct light alone: Lambert's exact form factor, as for a light
    // hanging clear of the ceiling. Light 1e-6 m below the ceiling (within the
    // coplanar gap) is resolved the same way.
    let exitance = LIGHT_RADIANCE * std::f64::consts::PI;
    for gap in [0.0, 1e-6] {
        let scene = room_with_light_under_ceiling_as(gap, 0.0, Some(Overlaps::Resolve)).unwrap();
        assert_eq!(scene.import_stats.overlapping_pairs, 1);
        let w = scene.warnings.join("\n");
        assert!(w.contains("'light' over 'ceiling'"), "{w}");
        let ceiling_area: f64 = scene
            .surfaces
            .iter()
            .filter(|s| s.object == 1)
            .map(|s| s.area)
            .sum();
        assert!(rel(ceiling_area, 2.0 * 2.4 - 0.36) < 1e-9, "{ceiling_area}");
        let light_polygon: Vec<DVec3> = scene
            .surfaces
            .iter()
            .find(|s| scene.material_of(s).is_emitter())
            .unwrap()
            .vertices
            .to_vec();
        let sol = radiosity::solve(&scene, &quick_settings(0.3), &|_| {}).unwrap();
        assert_finite_non_negative(&sol, "flush, black ceiling");
        let floor: Vec<_> = leaves(&sol)
            .into_iter()
            .filter(|e| scene.surfaces[e.surface() as usize].object == 0)
            .collect();
        assert!(floor.len() > 50);
        for e in floor {
            let f = lambert::point_to_polygon(e.centroid(), DVec3::Y, &light_polygon).unwrap();
            let direct = 0.5 * exitance * f;
            assert!(
                rel(e.radiosity[0], direct) < 0.01,
                "gap {gap}: floor element at {}: {} instead of {direct}",
                e.centroid(),
                e.radiosity[0]
            );
        }
    }
    // Grey ceiling: the room as lit by the same light hanging 3.5e-4 m below
    // a whole ceiling (clear of the gap, not an overlap): the ceiling's part
    // above that light sees only the light's back and stays dark, so the
    // floor's mean and the ceiling's power must agree with the cut ceiling's.
    let clear = room_with_light_under_ceiling_as(3.5e-4, 0.5, Some(Overlaps::Resolve)).unwrap();
    assert_eq!(clear.import_stats.overlapping_pairs, 0);
    let clear_sol = radiosity::solve(&clear, &quick_settings(0.3), &|_| {}).unwrap();
    let (floor_clear, _) = object_mean(&clear, &clear_sol, "floor");
    let (ceiling_clear, ceiling_area_clear) = object_mean(&clear, &clear_sol, "ceiling");
    for gap in [0.0, 1e-6] {
        let scene = room_with_light_under_ceiling_as(gap, 0.5, Some(Overlaps::Resolve)).unwrap();
        let sol = radiosity::solve(&scene, &quick_settings(0.3), &|_| {}).unwrap();
        let (floor, _) = object_mean(&scene, &sol, "floor");
        let (ceiling, ceiling_area) = object_mean(&scene, &sol, "ceiling");
        assert!(floor > 0.0);
        assert!(
            rel(floor, floor_clear) < 0.01,
            "gap {gap}: floor {floor} against {floor_clear} below a whole ceiling"
        );
        let (power, power_clear) = (ceiling * ceiling_area, ceiling_clear * ceiling_area_clear);
        assert!(
            rel(power, power_clear) < 0.02,
            "gap {gap}: ceiling power {power} against {power_clear}"
        );
    }
}

const BOX_X: (f64, f64) = (0.6, 1.2);
const BOX_Z: (f64, f64) = (0.8, 1.4);

/// The lit grey room with a box over `BOX_X x BOX_Z` from height `bottom` to
/// 0.5 m (standing on the floor for `bottom = 0`, through it below).
fn room_with_box_from(bottom: f64) -> Scene {
    let mut b = SceneBuilder::new("box_on_floor");
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let white = b.material("white", Rgb::splat(0.7), Rgb::ZERO).unwrap();
    let light = b.material("light", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
    room(
        &mut b,
        v(0.0, 0.0, 0.0),
        v(2.0, 1.6, 2.4),
        grey,
        white,
        grey,
    );
    b.object("light");
    downward_quad(&mut b, light, 1.59, (0.7, 1.3), (0.9, 1.5));
    b.axis_box(
        "box",
        grey,
        v(BOX_X.0, bottom, BOX_Z.0),
        v(BOX_X.1, 0.5, BOX_Z.1),
    )
    .unwrap();
    b.build().unwrap()
}

fn inside_footprint(p: DVec3) -> bool {
    p.x > BOX_X.0 && p.x < BOX_X.1 && p.z > BOX_Z.0 && p.z < BOX_Z.1
}

/// Checks that no light reaches the floor under the box, and returns the area
/// of floor under the box that elements straddling its outline show as lit.
fn assert_no_light_under_the_box(sol: &Solution, what: &str) -> f64 {
    // A floor element's hemi-cube sits a hair above its centroid. If the
    // centroid is under the box, the eye is inside a closed box and sees only
    // back faces: exactly zero. That covers every element wholly under the box.
    // An element the box's outline crosses takes its row at a visible point,
    // scaled by its visible share (`covered` in its row's view): it is lit at
    // most by that share, wherever its centroid lies. So "near zero" under
    // the box means: zero for every element whose centroid is under it but
    // for those, and light at most one straddling element deep, which
    // refinement along the contact line keeps narrow.
    let mut under = 0;
    let mut leaked_area = 0.0;
    for e in leaves(sol).into_iter().filter(|e| e.surface() == 0) {
        let covered = e.row.view().map_or(0.0, |v| v.covered);
        if covered > 0.0 {
            assert!(covered < 1.0, "{what}: {covered}");
            continue;
        }
        if inside_footprint(e.centroid()) {
            under += 1;
            assert_eq!(
                e.radiosity.max_band(),
                0.0,
                "{what}: floor element at {} under the box is lit",
                e.centroid()
            );
        } else if e.radiosity.max_band() > 0.0 {
            let poly = sol.mesh().surfaces()[0].polygon(&e.cell());
            let (lo, hi) = poly.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            let dx = (hi.x.min(BOX_X.1) - lo.x.max(BOX_X.0)).max(0.0);
            let dz = (hi.z.min(BOX_Z.1) - lo.z.max(BOX_Z.0)).max(0.0);
            leaked_area += dx * dz;
        }
    }
    assert!(under >= 16, "{what}: only {under} elements under the box");
    leaked_area
}

#[test]
fn no_light_leaks_under_a_box_standing_on_the_floor() {
    let scene = room_with_box_from(0.0);
    let sol = radiosity::solve(&scene, &quick_settings(0.3), &|_| {}).unwrap();
    assert_finite_non_negative(&sol, "box on floor");
    let leaked = assert_no_light_under_the_box(&sol, "box on floor");
    let footprint = (BOX_X.1 - BOX_X.0) * (BOX_Z.1 - BOX_Z.0);
    eprintln!(
        "box on floor: {} elements; straddling elements show {:.2}% of the footprint lit",
        sol.stats().elements,
        100.0 * leaked / footprint
    );
    // The box's bottom face lies on the floor facing down: it sees nothing.
    for e in leaves(&sol) {
        let s = &scene.surfaces[e.surface() as usize];
        if s.normal == -DVec3::Y && e.centroid().y == 0.0 {
            assert_eq!(
                e.radiosity.max_band(),
                0.0,
                "box bottom at {}",
                e.centroid()
            );
        }
    }
    let energy = energy_errors(&sol);
    assert!(energy.iter().all(|x| x.abs() < 0.01), "{energy:?}");
}

#[test]
fn a_box_through_the_floor_neither_leaks_nor_lights_what_is_below() {
    let scene = room_with_box_from(-0.2);
    let sol = radiosity::solve(&scene, &quick_settings(0.3), &|_| {}).unwrap();
    assert_finite_non_negative(&sol, "box through floor");
    assert_no_light_under_the_box(&sol, "box through floor");
    // Box elements below the floor see only the floor's back.
    let mut below = 0;
    for e in leaves(&sol) {
        if e.surface() >= 7 && e.centroid().y < 0.0 {
            below += 1;
            assert_eq!(
                e.radiosity.max_band(),
                0.0,
                "box below floor at {}",
                e.centroid()
            );
        }
    }
    assert!(below > 0);
}

#[test]
fn emitters_from_1e_minus_6_to_1e6_scale_the_solution_linearly() {
    // The equations are linear in the emission and every tolerance is relative
    // to the brightest value, so the mesh, the sweeps and the radiosities (over
    // the emission) must not change.
    let settings = quick_settings(0.4);
    let reference =
        radiosity::solve(&lit_room_with_box(1.0, 1.0, 1e-3), &settings, &|_| {}).unwrap();
    for radiance in [1e-6, 1e6] {
        let sol =
            radiosity::solve(&lit_room_with_box(1.0, radiance, 1e-3), &settings, &|_| {}).unwrap();
        assert_finite_non_negative(&sol, "scaled emitter");
        let (a, b) = (leaves(&sol), leaves(&reference));
        assert_eq!(a.len(), b.len(), "radiance {radiance}: a different mesh");
        for (x, y) in a.iter().zip(&b) {
            for band in 0..3 {
                let scaled = x.radiosity[band] / radiance;
                assert!(
                    (scaled - y.radiosity[band]).abs() <= 1e-9 * y.radiosity.max_band().max(1e-300),
                    "radiance {radiance}: element at {}: {scaled} vs {}",
                    x.centroid(),
                    y.radiosity[band]
                );
            }
        }
    }
}

#[test]
fn emitters_1e12_apart_in_one_scene() {
    let mut b = SceneBuilder::new("dynamic_range");
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let bright = b.material("bright", Rgb::ZERO, Rgb::splat(1e6)).unwrap();
    let dim = b.material("dim", Rgb::ZERO, Rgb::splat(1e-6)).unwrap();
    room(&mut b, v(0.0, 0.0, 0.0), v(2.0, 1.6, 2.4), grey, grey, grey);
    b.object("bright");
    downward_quad(&mut b, bright, 1.59, (0.2, 0.6), (0.2, 0.6));
    b.object("dim");
    downward_quad(&mut b, dim, 1.59, (1.4, 1.8), (1.8, 2.2));
    let scene = b.build().unwrap();
    let sol = radiosity::solve(&scene, &quick_settings(0.4), &|_| {}).unwrap();
    assert_finite_non_negative(&sol, "dynamic range");
    let energy = energy_errors(&sol);
    assert!(energy.iter().all(|x| x.abs() < 0.01), "{energy:?}");
    // The dim light keeps its own exitance.
    let objects = sol.object_radiosity(&scene);
    let dim = objects.iter().find(|o| o.name == "dim").unwrap();
    assert!(dim.radiosity[0] >= 1e-6 * std::f64::consts::PI);
}

#[test]
fn the_progressive_solver_keeps_the_furnace_and_the_box_dark_beneath() {
    // The same awkward scenes through the shooting solver: a furnace holding
    // a rod of aspect 1000 stays uniform, and no light reaches the floor under
    // a box standing on it, nor the part of a box pushed through the floor.
    let shooting = |patch: f64| Settings {
        solver_kind: SolverKind::Progressive,
        progressive: ProgressiveSettings {
            tolerance: 1e-6,
            ..ProgressiveSettings::default()
        },
        ..quick_settings(patch)
    };
    let rod = furnace_with(|b| {
        b.axis_box("rod", 0, v(0.5, 0.8, 1.0), v(1.5, 0.801, 1.001))
            .unwrap();
    });
    let sol = radiosity::solve(&rod, &shooting(0.4), &|_| {}).unwrap();
    assert_furnace(&sol, "rod, progressive");
    for bottom in [0.0, -0.2] {
        let scene = room_with_box_from(bottom);
        let sol = radiosity::solve(&scene, &shooting(0.3), &|_| {}).unwrap();
        assert_finite_non_negative(&sol, "box, progressive");
        assert_no_light_under_the_box(&sol, "box, progressive");
        for e in leaves(&sol) {
            if e.surface() >= 7 && e.centroid().y < 0.0 {
                assert_eq!(
                    e.radiosity.max_band(),
                    0.0,
                    "box below floor at {}",
                    e.centroid()
                );
            }
        }
    }
}
