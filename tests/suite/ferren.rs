//! The seed paper's example: the Ferren sculpture's white fronts take the
//! colour of the backs that face them in the full solution, and stay white
//! with direct light only; and a one-bounce solve against the exact form
//! factor.

use glam::DVec3;
use radiosity::analytic::QuadratureSettings;
use radiosity::analytic::{integrate_over_polygon, parallel_rectangles, point_to_polygon};
use radiosity::formfactor::EmitterSampling;
use radiosity::math::Rgb;
use radiosity::pipeline::SolverKind;
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::scenes::ferren::{ferren_sculpture, WHITE_PAINT};
use radiosity::solution::ObjectRadiosity;
use radiosity::{Error, Settings};

/// Coarse settings: one element per patch, a small hemi-cube, no shadow rays
/// (a second or two per solve). Chromaticity does not depend on them: form
/// factors are the same in every band.
fn coarse(bounces: Option<u32>) -> Settings {
    Settings {
        hemicube_resolution: 64,
        emitter_sampling: EmitterSampling::Pixels,
        refine: RefineSettings {
            uniform_depth: Some(0),
            ..RefineSettings::default()
        },
        bounces,
        ..Settings::default()
    }
}

/// `(r, g) = (R, G) / (R + G + B)`.
fn chromaticity(b: Rgb) -> [f64; 2] {
    let sum = b[0] + b[1] + b[2];
    [b[0] / sum, b[1] / sum]
}

/// The chromaticity of white light on neutral paint (`R = G = B`).
const NEUTRAL: [f64; 2] = [1.0 / 3.0, 1.0 / 3.0];

fn from_neutral(c: [f64; 2]) -> [f64; 2] {
    [c[0] - NEUTRAL[0], c[1] - NEUTRAL[1]]
}

fn length(v: [f64; 2]) -> f64 {
    v[0].hypot(v[1])
}

fn surfaces_ending<'a>(all: &'a [ObjectRadiosity], suffix: &str) -> Vec<&'a ObjectRadiosity> {
    all.iter().filter(|o| o.name.ends_with(suffix)).collect()
}

/// The single polygon of object `name`, with its normal.
fn polygon_of(scene: &Scene, name: &str) -> (Vec<DVec3>, DVec3) {
    let object = scene.objects.iter().position(|o| o.name == name).unwrap() as u32;
    let surfaces: Vec<_> = scene
        .surfaces
        .iter()
        .filter(|s| s.object == object)
        .collect();
    assert_eq!(surfaces.len(), 1, "{name}");
    (surfaces[0].vertices.to_vec(), surfaces[0].normal)
}

/// Area-mean form factor from the polygon `from` (facing `normal`) to `to`,
/// by Lambert's formula under adaptive quadrature (visibility not considered).
fn mean_form_factor(from: &[DVec3], normal: DVec3, to: &[DVec3]) -> f64 {
    let area = radiosity::math::polygon_area(from);
    let settings = QuadratureSettings::with_tolerance(1e-5 * area);
    let integral = integrate_over_polygon(
        from,
        |p| point_to_polygon(p, normal, to).unwrap(),
        &settings,
    )
    .unwrap();
    integral.value / area
}

#[test]
fn direct_light_leaves_the_white_fronts_neutral() {
    let scene = ferren_sculpture();
    let solution = radiosity::solve(&scene, &coarse(Some(1)), &|_| {}).unwrap();
    assert_eq!(solution.stats().bounces, Some(1));
    assert!(solution.stats().energy.truncated);
    let all = solution.object_radiosity(&scene);
    let fronts = surfaces_ending(&all, "_front");
    assert_eq!(fronts.len(), 27);
    // With one reflection a front's radiosity is rho_white * sum_j F_j E_j over
    // the emitters; both emitters are white (E_R = E_G = E_B) and the paint is
    // neutral, so every band gets the same products of the same numbers: the
    // chromaticity is the neutral point up to rounding.
    for f in &fronts {
        let b = f.radiosity;
        assert!(b[0] > 0.0, "{} is unlit", f.name);
        let c = chromaticity(b);
        assert!(length(from_neutral(c)) < 1e-12, "{}: {c:?}", f.name);
    }
}

#[test]
fn interreflection_tints_each_white_front_with_the_back_facing_it() {
    let scene = ferren_sculpture();
    let solution = radiosity::solve(&scene, &coarse(None), &|_| {}).unwrap();
    assert_eq!(solution.stats().bounces, None);
    assert!(!solution.stats().energy.truncated);
    let all = solution.object_radiosity(&scene);
    let backs = surfaces_ending(&all, "_back");
    let back_polygons: Vec<Vec<DVec3>> = backs
        .iter()
        .map(|b| polygon_of(&scene, &b.name).0)
        .collect();
    let mut tinted = 0;
    for f in surfaces_ending(&all, "_front") {
        let (front, normal) = polygon_of(&scene, &f.name);
        // The back this front faces: the largest form factor from its centre.
        let centre = front.iter().copied().sum::<DVec3>() / front.len() as f64;
        let (k, f_centre) = back_polygons
            .iter()
            .map(|p| point_to_polygon(centre, normal, p).unwrap())
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        if f_centre < 0.2 {
            // The last board of a row faces the side wall, not a back.
            continue;
        }
        tinted += 1;
        let back = backs[k];
        // Light from that back alone: H_b = F_fb B_b (nothing stands between
        // neighbouring boards). The front's whole irradiance is
        // H = B_front / rho_white. Were the rest of its light neutral, the
        // front's chromaticity would lie the fraction
        // alpha = sum(H_b) / sum(H) of the way from neutral to the back's: a
        // shift of alpha |c_back - neutral| in that direction. The rest is not
        // quite neutral (other backs are seen too) and the back's radiosity is
        // not uniform, so the measured shift may differ from the prediction,
        // but not by a factor of two; and it must point at the back's colour.
        let f_mean = mean_form_factor(&front, normal, &back_polygons[k]);
        let from_back = back.radiosity * f_mean;
        let irradiance = f.radiosity / WHITE_PAINT;
        let alpha = from_back.mean() / irradiance.mean();
        let towards = from_neutral(chromaticity(back.radiosity));
        let unit = [towards[0] / length(towards), towards[1] / length(towards)];
        let shift = from_neutral(chromaticity(f.radiosity));
        let along = shift[0] * unit[0] + shift[1] * unit[1];
        let predicted = alpha * length(towards);
        let what = format!(
            "{} facing {}: shift {:.4}, {along:.4} towards the back, predicted {predicted:.4} \
             (alpha {alpha:.3})",
            f.name,
            back.name,
            length(shift)
        );
        // Well away from neutral (the direct-only solve is within 1e-12).
        assert!(predicted > 0.05, "{what}");
        assert!(along > 0.6 * predicted && along < 2.0 * predicted, "{what}");
        assert!(along > 0.9 * length(shift), "{what}");
    }
    // Eight of nine boards per row face a neighbour's back.
    assert_eq!(tinted, 24);
}

#[test]
fn bounded_bounces_need_the_gathering_solver_and_at_least_one() {
    let scene = ferren_sculpture();
    for settings in [
        Settings {
            solver_kind: SolverKind::Progressive,
            ..coarse(Some(2))
        },
        coarse(Some(0)),
    ] {
        match radiosity::solve(&scene, &settings, &|_| {}) {
            Err(Error::Setting { name, .. }) => assert_eq!(name, "bounces"),
            other => panic!("expected a bounces setting error, got {other:?}"),
        }
    }
}

/// A square light of side 1 facing down 1 m above a square floor of side 1,
/// coaxial; the light reflects 0.5 so that light comes back to the floor in
/// the full solution.
fn light_over_floor(rho_floor: f64, radiance: f64) -> Scene {
    let mut b = SceneBuilder::new("light_over_floor");
    let light = b
        .material("light", Rgb::splat(0.5), Rgb::splat(radiance))
        .unwrap();
    let floor = b
        .material(
            "floor",
            Rgb::new(rho_floor, 0.5 * rho_floor, 0.25 * rho_floor),
            Rgb::ZERO,
        )
        .unwrap();
    let p = DVec3::new;
    b.object("light");
    b.quad(
        light,
        p(0.0, 1.0, 0.0),
        p(1.0, 1.0, 0.0),
        p(1.0, 1.0, 1.0),
        p(0.0, 1.0, 1.0),
    )
    .unwrap();
    b.object("floor");
    b.quad(
        floor,
        p(0.0, 0.0, 0.0),
        p(0.0, 0.0, 1.0),
        p(1.0, 0.0, 1.0),
        p(1.0, 0.0, 0.0),
    )
    .unwrap();
    b.build().unwrap()
}

#[test]
fn one_bounce_is_emission_times_reflectance_times_the_exact_form_factor() {
    let rho = 0.8;
    let radiance = 2.0;
    let scene = light_over_floor(rho, radiance);
    let exitance = radiance * std::f64::consts::PI;
    // Howell C-11: unit squares 1 apart, about 0.1998.
    let form_factor = parallel_rectangles(1.0, 1.0, 1.0).unwrap();
    let settings = |bounces| Settings {
        refine: RefineSettings {
            uniform_depth: Some(3),
            ..RefineSettings::default()
        },
        patch_size: Some(0.5),
        bounces,
        ..Settings::default()
    };
    let floor_of = |bounces| {
        let solution = radiosity::solve(&scene, &settings(bounces), &|_| {}).unwrap();
        let all = solution.object_radiosity(&scene);
        all.iter().find(|o| o.name == "floor").unwrap().radiosity
    };
    let direct = floor_of(Some(1));
    let reflectance = [rho, 0.5 * rho, 0.25 * rho];
    for band in 0..3 {
        let exact = exitance * reflectance[band] * form_factor;
        // The hybrid method takes the exact point-to-polygon factor at every
        // element centre: the midpoint rule over 8 x 8 elements of a smooth
        // integrand, within 0.2% (0.06% measured).
        let error = (direct[band] - exact).abs() / exact;
        assert!(
            error < 5e-3,
            "band {band}: {} vs {exact} ({error:.2e})",
            direct[band]
        );
    }
    // Light that returns to the floor has been reflected three times (floor,
    // light, floor), so two bounces give the floor nothing new, three add
    // about (0.5 F) (rho_floor F) times the direct light: 1.6% in the red band
    // (half of it is required, the factor varying over the squares). The full
    // solution has that and more.
    let two = floor_of(Some(2));
    for band in 0..3 {
        assert!(
            (two[band] - direct[band]).abs() <= 1e-12 * direct[band],
            "band {band}"
        );
    }
    let three = floor_of(Some(3));
    let full = floor_of(None);
    let round_trip = 0.5 * form_factor * reflectance[0] * form_factor;
    assert!(
        three[0] > direct[0] * (1.0 + 0.5 * round_trip),
        "{three:?} vs {direct:?}"
    );
    assert!(
        three[0] < direct[0] * (1.0 + 2.0 * round_trip),
        "{three:?} vs {direct:?}"
    );
    assert!(full[0] >= three[0]);
}
