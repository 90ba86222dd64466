use super::clipping::FEW_CASTERS;
use super::*;
use crate::formfactor::{point_to_polygon, SourcePolygon};

/// A square of half-width `half` centred at `centre` in a plane of
/// constant z, facing `normal` (+Z or -Z).
fn square(centre: DVec3, half: f64, normal: DVec3, surface: u32) -> SourcePolygon {
    let (t1, t2) = normal.any_orthonormal_pair();
    let corners = [
        centre - t1 * half - t2 * half,
        centre + t1 * half - t2 * half,
        centre + t1 * half + t2 * half,
        centre - t1 * half + t2 * half,
    ];
    SourcePolygon::new(&corners, normal, surface)
}

/// A floor (surface 0, polygon 0) under a light facing down at z = 2
/// (surface 1, polygon 1).
fn floor_and_light() -> Vec<SourcePolygon> {
    vec![
        square(DVec3::ZERO, 4.0, DVec3::Z, 0),
        square(DVec3::new(0.0, 0.0, 2.0), 0.5, DVec3::NEG_Z, 1),
    ]
}

/// A floor (surface 0) under a light facing down at z = 2 (surface 1,
/// polygon 1), with small screens scattered at z = 1 (facing either
/// way) that hide parts of the light from parts of the floor.
fn lit_floor() -> Sources {
    let mut polygons = floor_and_light();
    for i in 0..12u32 {
        let a = f64::from(i) * 0.9;
        let centre = DVec3::new(0.6 * a.cos(), 0.6 * a.sin(), 1.0 + 0.02 * f64::from(i));
        let normal = if i % 2 == 0 { DVec3::Z } else { DVec3::NEG_Z };
        polygons.push(square(centre, 0.08, normal, 2 + i));
    }
    Sources::one_per_patch(polygons)
}

/// Four points of a square element of half-width `half` at `(x, y)` on
/// the floor, with equal weights.
fn element(x: f64, y: f64, half: f64) -> [(DVec3, f64); 4] {
    let lift = 1e-7;
    let g = half / 3f64.sqrt();
    [(-g, -g), (g, -g), (-g, g), (g, g)].map(|(dx, dy)| (DVec3::new(x + dx, y + dy, lift), 0.25))
}

#[test]
fn one_walk_gives_each_point_what_a_walk_of_its_own_gives() {
    let sources = lit_floor();
    let occluders = Occluders::new(&sources);
    let mut shadowed = 0;
    for i in 0..40 {
        let (x, y) = (-1.5 + 0.075 * f64::from(i), 0.4 - 0.02 * f64::from(i));
        let points = element(x, y, 0.1);
        let together = occluders
            .mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, false)
            .found();
        let mut alone = Some(0.0);
        for &(p, w) in &points {
            let one = occluders
                .mean_visible_form_factor(&sources, &[(p, 1.0)], DVec3::Z, 0, 1, false)
                .found();
            alone = alone.zip(one).map(|(sum, f)| sum + w * f);
        }
        assert_eq!(
            together.map(f64::to_bits),
            alone.map(f64::to_bits),
            "at ({x}, {y}): {together:?} against {alone:?}"
        );
        let unoccluded: f64 = points
            .iter()
            .map(|&(p, w)| w * point_to_polygon(p, DVec3::Z, sources.polygons[1].corners()))
            .sum();
        if together.is_some_and(|f| f < unoccluded * (1.0 - 1e-9)) {
            shadowed += 1;
        }
    }
    // The screens hide part of the light from some of the elements.
    assert!(shadowed >= 5, "{shadowed} of 40 elements in shadow");
}

#[test]
fn an_element_is_shadowed_exactly_where_something_hides_the_light() {
    let sources = lit_floor();
    let occluders = Occluders::new(&sources);
    let (mut shadowed, mut clear_ones) = (0, 0);
    for i in 0..40 {
        let (x, y) = (-1.5 + 0.075 * f64::from(i), 0.4 - 0.02 * f64::from(i));
        let points = element(x, y, 0.1);
        let unoccluded: f64 = points
            .iter()
            .map(|&(p, w)| w * point_to_polygon(p, DVec3::Z, sources.polygons[1].corners()))
            .sum();
        // Few screens lie in any one shaft here (the crowded case is
        // the next test's): with or without the limit, the same.
        let found = occluders.mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, true);
        assert_eq!(
            found,
            occluders.mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, false)
        );
        let PointsMean::Visible {
            mean,
            shadowed: hidden,
        } = found
        else {
            panic!("{found:?} at ({x}, {y})");
        };
        if hidden {
            assert!(mean < unoccluded * (1.0 - 1e-12), "shadowed at ({x}, {y})");
            shadowed += 1;
        } else {
            assert_eq!(mean.to_bits(), unoccluded.to_bits(), "clear at ({x}, {y})");
            clear_ones += 1;
        }
    }
    assert!(shadowed > 0 && clear_ones > 0, "{shadowed} {clear_ones}");
}

/// The floor and light of [`lit_floor`] with `n` small screens just
/// under the middle of the light, each on its own surface: every floor
/// point near the middle sees all of them against the light.
fn chips(n: u32) -> Sources {
    let mut polygons = floor_and_light();
    for i in 0..n {
        let a = f64::from(i) * std::f64::consts::TAU / f64::from(n);
        let centre = DVec3::new(0.1 * a.cos(), 0.1 * a.sin(), 1.8 + 0.01 * f64::from(i));
        polygons.push(square(centre, 0.02, DVec3::NEG_Z, 2 + i));
    }
    Sources::one_per_patch(polygons)
}

/// The occluders of `sources`, the points of an element near the
/// middle of the floor and their mean visible form factor to the light,
/// with no limit on the casters.
fn beside_the_middle(sources: &Sources) -> (Occluders, [(DVec3, f64); 4], f64) {
    let occluders = Occluders::new(sources);
    let points = element(0.05, -0.02, 0.1);
    let mean = occluders
        .mean_visible_form_factor(sources, &points, DVec3::Z, 0, 1, false)
        .found()
        .unwrap();
    (occluders, points, mean)
}

#[test]
fn more_than_a_few_casters_leave_the_element_to_its_centre() {
    for n in [FEW_CASTERS as u32, FEW_CASTERS as u32 + 1] {
        let sources = chips(n);
        let (occluders, points, mean) = beside_the_middle(&sources);
        let unoccluded: f64 = points
            .iter()
            .map(|&(p, w)| w * point_to_polygon(p, DVec3::Z, sources.polygons[1].corners()))
            .sum();
        assert!(mean < unoccluded * (1.0 - 1e-3), "{n}: {mean} {unoccluded}");
        let few = occluders.mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, true);
        if n as usize > FEW_CASTERS {
            assert_eq!(few, PointsMean::Crowded, "{n} chips");
        } else {
            let shadowed = true;
            assert_eq!(few, PointsMean::Visible { mean, shadowed }, "{n} chips");
        }
    }
}

#[test]
fn one_surface_in_many_polygons_is_one_caster() {
    // A screen cut into a 3 x 3 grid of polygons on one surface.
    let mut polygons = floor_and_light();
    for i in 0..3 {
        for j in 0..3 {
            let centre = DVec3::new(0.04 * f64::from(i) - 0.04, 0.04 * f64::from(j) - 0.04, 1.8);
            polygons.push(square(centre, 0.02, DVec3::NEG_Z, 2));
        }
    }
    let sources = Sources::one_per_patch(polygons);
    let (occluders, points, mean) = beside_the_middle(&sources);
    let shadowed = true;
    assert_eq!(
        occluders.mean_visible_form_factor(&sources, &points, DVec3::Z, 0, 1, true),
        PointsMean::Visible { mean, shadowed }
    );
}
