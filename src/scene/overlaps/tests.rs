use super::*;
use crate::math::{polygon_area, Rgb};
use crate::scene::{SceneBuilder, Surface};
use glam::DVec3;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A square in the plane y = `y`, facing +y, from `(x0, z0)` with side `side`.
fn square(b: &mut SceneBuilder, m: u32, x0: f64, z0: f64, side: f64, y: f64) {
    b.quad(
        m,
        v(x0, y, z0),
        v(x0, y, z0 + side),
        v(x0 + side, y, z0 + side),
        v(x0 + side, y, z0),
    )
    .unwrap();
}

/// Object "wall" (a 4 m square of grey) and object "decal" (a square of red
/// placed by `decal`), not resolved.
fn wall_and_decal(decal: impl FnOnce(&mut SceneBuilder, u32)) -> Scene {
    let mut b = SceneBuilder::new("decal");
    b.overlaps(None);
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let red = b
        .material("red", Rgb::new(0.5, 0.0, 0.0), Rgb::ZERO)
        .unwrap();
    b.object("wall");
    square(&mut b, grey, 0.0, 0.0, 4.0, 0.0);
    b.object("decal");
    decal(&mut b, red);
    b.build().unwrap()
}

fn object_area(scene: &Scene, name: &str) -> f64 {
    let o = scene.objects.iter().position(|o| o.name == name).unwrap() as u32;
    scene
        .surfaces
        .iter()
        .filter(|s| s.object == o)
        .map(|s| s.area)
        .sum()
}

#[test]
fn the_cornell_box_light_hangs_far_enough_below_its_ceiling() {
    check_coplanar_overlaps(&crate::scenes::cornell_box()).unwrap();
}

#[test]
fn overlapping_touching_and_separate_squares_are_refused_or_accepted() {
    let scene = |x: f64, y: f64| wall_and_decal(|b, m| square(b, m, x, 1.0, 4.0, y));
    // Half overlapping in one plane: refused, naming both.
    let e = check_coplanar_overlaps(&scene(2.0, 0.0)).unwrap_err();
    assert!(e.to_string().contains("'decal' and 'wall'"), "{e}");
    // Sharing an edge, apart, or lifted clear of the plane: accepted.
    check_coplanar_overlaps(&scene(4.0, 0.0)).unwrap();
    check_coplanar_overlaps(&scene(9.0, 0.0)).unwrap();
    check_coplanar_overlaps(&scene(2.0, 1e-3)).unwrap();
}

#[test]
fn a_decal_inside_a_wall_cuts_its_footprint_out_of_it() {
    // A 1 m decal inside the 4 m wall, 1e-7 m in front of it (within the gap).
    let mut scene = wall_and_decal(|b, m| square(b, m, 1.0, 2.0, 1.0, 1e-7));
    scene.resolve_overlaps(Overlaps::Resolve).unwrap();
    // The wall keeps 16 - 1 m^2 in pieces of its own plane, the decal all of it.
    assert!((object_area(&scene, "wall") - 15.0).abs() < 1e-9);
    assert!((object_area(&scene, "decal") - 1.0).abs() < 1e-12);
    for s in scene.surfaces.iter().filter(|s| s.object == 0) {
        assert!(s.vertices.iter().all(|p| p.y == 0.0), "{s:?}");
        assert_eq!(s.normal, DVec3::Y);
        assert_eq!(s.material, 0);
        // No piece reaches into the decal's footprint.
        let c = s.centroid();
        assert!(!(c.x > 1.0 && c.x < 2.0 && c.z > 2.0 && c.z < 3.0), "{c}");
    }
    // Nothing overlaps any more, whatever the materials.
    assert!(pairs::find_overlaps(&scene, pairs::Scope::All).is_empty());
    assert_eq!(scene.import_stats.overlapping_pairs, 1);
    let w = scene.warnings.join("\n");
    assert!(
        w.contains("1 pairs") && w.contains("'decal' over 'wall'"),
        "{w}"
    );
}

#[test]
fn a_decal_over_the_edge_of_a_wall_cuts_only_what_it_covers() {
    // A 2 m decal half off the wall's corner: it covers 1 m^2 of the wall.
    let mut scene = wall_and_decal(|b, m| square(b, m, 3.0, 3.0, 2.0, 0.0));
    scene.resolve_overlaps(Overlaps::Resolve).unwrap();
    assert!((object_area(&scene, "wall") - 15.0).abs() < 1e-9);
    assert!((object_area(&scene, "decal") - 4.0).abs() < 1e-12);
}

#[test]
fn the_smaller_object_lies_on_top_whatever_the_order() {
    // The big square comes second: it is still the one cut.
    let mut b = SceneBuilder::new("order");
    b.overlaps(None);
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let red = b
        .material("red", Rgb::new(0.5, 0.0, 0.0), Rgb::ZERO)
        .unwrap();
    b.object("small");
    square(&mut b, red, 1.0, 1.0, 1.0, 0.0);
    b.object("big");
    square(&mut b, grey, 0.0, 0.0, 4.0, 0.0);
    let mut scene = b.build().unwrap();
    scene.resolve_overlaps(Overlaps::Resolve).unwrap();
    assert!((object_area(&scene, "small") - 1.0).abs() < 1e-12);
    assert!((object_area(&scene, "big") - 15.0).abs() < 1e-9);
}

#[test]
fn stacked_layers_leave_each_visible_part_once() {
    // Three nested squares of sides 4, 2 and 1 in three objects: each covers
    // the larger ones. Visible: 16 - 4, 4 - 1, 1.
    let mut b = SceneBuilder::new("logo");
    b.overlaps(None);
    let mats: Vec<u32> = (0..3)
        .map(|k| {
            b.material(
                &format!("m{k}"),
                Rgb::splat(0.2 + 0.2 * k as f64),
                Rgb::ZERO,
            )
            .unwrap()
        })
        .collect();
    for (k, side) in [4.0, 2.0, 1.0].into_iter().enumerate() {
        b.object(&format!("layer{k}"));
        square(
            &mut b,
            mats[k],
            0.5 * (4.0 - side),
            0.5 * (4.0 - side),
            side,
            0.0,
        );
    }
    let mut scene = b.build().unwrap();
    let total_before: f64 = 16.0;
    scene.resolve_overlaps(Overlaps::Resolve).unwrap();
    assert!((object_area(&scene, "layer0") - 12.0).abs() < 1e-9);
    assert!((object_area(&scene, "layer1") - 3.0).abs() < 1e-9);
    assert!((object_area(&scene, "layer2") - 1.0).abs() < 1e-12);
    assert!((scene.total_area() - total_before).abs() < 1e-9);
    assert_eq!(scene.import_stats.overlapping_pairs, 3);
    assert!(pairs::find_overlaps(&scene, pairs::Scope::All).is_empty());
}

#[test]
fn coincident_duplicates_count_once_even_by_the_thousand() {
    // 5 000 copies of one square in one object and one more in another
    // material on top of a floor: one square is left, the others are
    // duplicates, and the floor is cut once.
    let mut b = SceneBuilder::new("copies");
    b.overlaps(None);
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let red = b
        .material("red", Rgb::new(0.5, 0.0, 0.0), Rgb::ZERO)
        .unwrap();
    b.object("floor");
    square(&mut b, grey, 0.0, 0.0, 4.0, 0.0);
    b.object("copies");
    for _ in 0..5000 {
        square(&mut b, grey, 1.0, 1.0, 1.0, 0.0);
    }
    b.object("red copy");
    square(&mut b, red, 1.0, 1.0, 1.0, 0.0);
    let mut scene = b.build().unwrap();
    scene.resolve_overlaps(Overlaps::Resolve).unwrap();
    assert_eq!(scene.import_stats.duplicate_surfaces, 5000);
    let squares: Vec<&Surface> = scene.surfaces.iter().filter(|s| s.object > 0).collect();
    assert_eq!(squares.len(), 1);
    // Equal object areas and sizes: the later, red, copy is kept.
    assert_eq!(squares[0].material, red);
    assert!((object_area(&scene, "floor") - 15.0).abs() < 1e-9);
    // Refusing looks at different materials only: the grey copies pass,
    // the red one does not.
    let e = check_coplanar_overlaps(&{
        let mut b = SceneBuilder::new("grey copies");
        b.overlaps(None);
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        for _ in 0..3 {
            square(&mut b, grey, 1.0, 1.0, 1.0, 0.0);
        }
        b.build().unwrap()
    });
    assert!(e.is_ok());
}

#[test]
fn cut_pieces_are_convex_surfaces_of_the_lower_material_and_plane() {
    // A triangle decal rotated inside a quad: the pieces are triangles or
    // strictly convex quads, front facing, and fill the quad minus the
    // triangle exactly.
    let mut scene = wall_and_decal(|b, m| {
        b.triangle(m, v(1.0, 0.0, 1.0), v(1.5, 0.0, 3.0), v(3.2, 0.0, 1.7))
            .unwrap();
    });
    let decal_area = polygon_area(&[v(1.0, 0.0, 1.0), v(1.5, 0.0, 3.0), v(3.2, 0.0, 1.7)]);
    scene.resolve_overlaps(Overlaps::Resolve).unwrap();
    assert!((object_area(&scene, "wall") - (16.0 - decal_area)).abs() < 1e-9);
    for s in &scene.surfaces {
        assert!(s.vertices.len() == 3 || s.vertices.len() == 4);
        assert!(s.normal.dot(DVec3::Y) > 0.999_999);
    }
}

#[test]
fn policies_parse_from_their_command_line_names() {
    assert_eq!("resolve".parse::<Overlaps>(), Ok(Overlaps::Resolve));
    assert_eq!("error".parse::<Overlaps>(), Ok(Overlaps::Error));
    assert!("ignore".parse::<Overlaps>().is_err());
}

#[test]
fn a_stack_of_forty_shifted_layers_is_cut_into_few_pieces() {
    // Forty 1 m squares of four tiles each in one plane, each 1 cm right of
    // the last, of one object each: every layer is cut by all those on top. The covered
    // strips leave each layer one visible piece (or none), so the pieces
    // stay few, and together they cover the union of the squares exactly.
    let mut b = SceneBuilder::new("stack");
    b.overlaps(None);
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    for i in 0..40 {
        b.object(&format!("layer{i}"));
        for (x, z) in [(0.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.5, 0.5)] {
            square(&mut b, grey, x + i as f64 * 0.01, z, 0.5, 0.0);
        }
    }
    let mut scene = b.build().unwrap();
    scene.resolve_overlaps(Overlaps::Resolve).unwrap();
    assert!(
        scene.surfaces.len() <= 2 * 40,
        "{} pieces",
        scene.surfaces.len()
    );
    let area: f64 = scene.surfaces.iter().map(|s| s.area).sum();
    assert!((area - 1.39).abs() < 1e-9, "area {area}");
}

#[test]
fn many_decals_each_cut_out_once_leave_the_wall_its_exact_area() {
    // 900 decals in a 30 x 30 grid, some rotated by 45 degrees, some
    // overlapping their neighbours' bounds but not their footprints: the
    // wall keeps 16 m^2 less their areas, and no piece of it lies under a
    // decal.
    let mut b = SceneBuilder::new("decals");
    b.overlaps(None);
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let red = b
        .material("red", Rgb::new(0.5, 0.0, 0.0), Rgb::ZERO)
        .unwrap();
    b.object("wall");
    square(&mut b, grey, 0.0, 0.0, 4.0, 0.0);
    b.object("decals");
    let (mut covered, mut centres) = (0.0, Vec::new());
    for k in 0..900 {
        let (i, j) = (f64::from(k % 30), f64::from(k / 30));
        let c = v(0.1 + 0.13 * i, 0.0, 0.1 + 0.13 * j);
        if k % 3 == 0 {
            // A diamond of half-diagonal 0.06: area 2 * 0.06^2.
            let r = 0.06;
            b.quad(
                red,
                c + v(-r, 0.0, 0.0),
                c + v(0.0, 0.0, r),
                c + v(r, 0.0, 0.0),
                c + v(0.0, 0.0, -r),
            )
            .unwrap();
            covered += 2.0 * r * r;
        } else {
            square(&mut b, red, c.x - 0.05, c.z - 0.05, 0.1, 0.0);
            covered += 0.01;
        }
        centres.push((c, k % 3 == 0));
    }
    let mut scene = b.build().unwrap();
    scene.resolve_overlaps(Overlaps::Resolve).unwrap();
    let wall = object_area(&scene, "wall");
    assert!((wall - (16.0 - covered)).abs() < 1e-9, "{wall}");
    assert!((object_area(&scene, "decals") - covered).abs() < 1e-9);
    assert_eq!(scene.import_stats.overlapping_pairs, 900);
    for s in scene.surfaces.iter().filter(|s| s.object == 0) {
        let p = s.centroid();
        let under = centres.iter().any(|(c, diamond)| {
            let (dx, dz) = ((p.x - c.x).abs(), (p.z - c.z).abs());
            if *diamond {
                dx + dz < 0.06 - 1e-9
            } else {
                dx.max(dz) < 0.05 - 1e-9
            }
        });
        assert!(!under, "a piece of the wall under a decal at {p}");
    }
    assert!(pairs::find_overlaps(&scene, pairs::Scope::All).is_empty());
}
