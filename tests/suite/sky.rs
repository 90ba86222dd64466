//! Daylight (issue 53): a sky over the scene and a sun, against closed
//! forms, and the solvers against the path tracer.

use glam::DVec3;
use radiosity::analytic::parallel_rectangles;
use radiosity::math::Rgb;
use radiosity::pipeline::SolverKind;
use radiosity::reference::{Reference, ReferenceSettings};
use radiosity::refine::RefineSettings;
use radiosity::scene::{sun, Scene, SceneBuilder, Sky, SkyModel, Surface};
use radiosity::Settings;
use std::f64::consts::PI;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A floor `[0, a]^2` of reflectance `rho` facing up, and, with `walls`
/// of height `h`, four black walls around it facing in: a courtyard open to
/// the sky. The floor is the object "floor".
fn courtyard(a: f64, h: Option<f64>, rho: f64, sky: Sky) -> Scene {
    let mut b = SceneBuilder::new("courtyard");
    let grey = b.material("grey", Rgb::splat(rho), Rgb::ZERO).unwrap();
    let black = b.material("black", Rgb::ZERO, Rgb::ZERO).unwrap();
    b.object("floor");
    b.quad(
        grey,
        v(0.0, 0.0, 0.0),
        v(0.0, 0.0, a),
        v(a, 0.0, a),
        v(a, 0.0, 0.0),
    )
    .unwrap();
    if let Some(h) = h {
        b.object("walls");
        let (o, t) = (v(0.0, 0.0, 0.0), v(0.0, h, 0.0));
        let corners = [
            v(0.0, 0.0, 0.0),
            v(a, 0.0, 0.0),
            v(a, 0.0, a),
            v(0.0, 0.0, a),
        ];
        for i in 0..4 {
            let (p, q) = (corners[i], corners[(i + 1) % 4]);
            // Counter-clockwise seen from inside the courtyard.
            b.quad(black, p + o, p + t, q + t, q + o).unwrap();
        }
    }
    let mut scene = b.build().unwrap();
    scene.sky = Some(sky);
    scene
}

fn settings(kind: SolverKind) -> Settings {
    Settings {
        patch_size: Some(0.25),
        solver_kind: kind,
        refine: RefineSettings {
            uniform_depth: Some(2),
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

fn floor_radiosity(scene: &Scene, settings: &Settings) -> f64 {
    let solution = radiosity::solve(scene, settings, &|_| {}).unwrap();
    let objects = solution.object_radiosity(scene);
    objects
        .iter()
        .find(|o| o.name == "floor")
        .unwrap()
        .radiosity
        .0[0]
}

#[test]
fn a_lone_floor_receives_pi_l_under_a_uniform_sky_and_seven_ninths_of_it_under_an_overcast_one() {
    let l = 1000.0;
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let uniform = courtyard(
            1.0,
            None,
            0.5,
            Sky::with_zenith_luminance(SkyModel::Uniform, l),
        );
        let b = floor_radiosity(&uniform, &settings(kind));
        let exact = 0.5 * PI * l;
        assert!(
            (b - exact).abs() < 1e-9 * exact,
            "{kind:?} uniform: {b} against {exact}"
        );
        let overcast = courtyard(
            1.0,
            None,
            0.5,
            Sky::with_zenith_luminance(SkyModel::Overcast, l),
        );
        let b = floor_radiosity(&overcast, &settings(kind));
        let exact = 0.5 * 7.0 * PI * l / 9.0;
        assert!(
            (b - exact).abs() < 1e-9 * exact,
            "{kind:?} overcast: {b} against {exact}"
        );
    }
}

#[test]
fn a_courtyard_floor_receives_the_sky_through_its_opening_as_the_parallel_rectangles_formula_says()
{
    // Black walls: the floor's light is the sky it sees through the square
    // opening, pi L times the floor-to-opening form factor (Howell C-11).
    let (a, h, l, rho) = (1.0, 0.6, 1000.0, 0.5);
    let exact = rho * PI * l * parallel_rectangles(a, a, h).unwrap();
    let scene = courtyard(
        a,
        Some(h),
        rho,
        Sky::with_zenith_luminance(SkyModel::Uniform, l),
    );
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let b = floor_radiosity(&scene, &settings(kind));
        let error = (b - exact) / exact;
        assert!(
            error.abs() < 0.01,
            "{kind:?}: {b} against {exact} ({:+.3}%)",
            100.0 * error
        );
    }
    // The path tracer meets the same sky on its own: paths that leave the
    // scene.
    let reference = Reference::new(&scene).unwrap();
    let means = reference
        .object_means(&ReferenceSettings {
            paths: 200_000,
            seed: 3,
            ..ReferenceSettings::default()
        })
        .unwrap();
    let (traced, se) = (means[0].radiosity.0[0], means[0].std_error.0[0]);
    assert!(
        (traced - exact).abs() < 4.0 * se + 1e-3 * exact,
        "path tracer {traced} +- {se} against {exact}"
    );
}

#[test]
fn a_sun_lights_a_floor_with_its_illuminance_times_the_sine_of_its_elevation() {
    let mut b = SceneBuilder::new("sunlit");
    let grey = b.material("grey", Rgb::splat(0.4), Rgb::ZERO).unwrap();
    b.object("floor");
    b.quad(
        grey,
        v(0.0, 0.0, 0.0),
        v(0.0, 0.0, 1.0),
        v(1.0, 0.0, 1.0),
        v(1.0, 0.0, 0.0),
    )
    .unwrap();
    b.light(sun(135.0, 30.0, 80_000.0).unwrap()).unwrap();
    let scene = b.build().unwrap();
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let got = floor_radiosity(&scene, &settings(kind));
        let exact = 0.4 * 80_000.0 * 0.5;
        assert!(
            (got - exact).abs() < 1e-9 * exact,
            "{kind:?}: {got} against {exact}"
        );
    }
}

#[test]
fn an_interior_shut_from_the_sky_gets_none_of_it() {
    // The courtyard with a black lid: no ray leaves, so no light, and the
    // solve refuses nothing (the sky still counts as light for the scene).
    let mut scene = courtyard(
        1.0,
        Some(0.6),
        0.5,
        Sky::with_zenith_luminance(SkyModel::Uniform, 1.0),
    );
    let walls = &scene.surfaces[1];
    let roof = Surface::new(
        &[
            v(0.0, 0.6, 0.0),
            v(1.0, 0.6, 0.0),
            v(1.0, 0.6, 1.0),
            v(0.0, 0.6, 1.0),
        ],
        walls.material,
        walls.object,
    )
    .unwrap();
    assert!(
        roof.normal.y < 0.0,
        "the roof faces down, into the courtyard"
    );
    scene.surfaces.push(roof);
    let b = floor_radiosity(&scene, &settings(SolverKind::GaussSeidel));
    assert_eq!(b, 0.0);
}
