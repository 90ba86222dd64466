//! How an element's direct light is sampled (`EmitterSampling`), against a
//! closed form: a unit floor that is one element, lit by a square lamp above
//! it, with and without a screen whose shadow edge crosses part of the floor.
//!
//! The oracle is the form factor from a point to an axis-aligned rectangle in
//! a parallel plane (the corner formula), written out here; the screen is
//! parallel to the lamp, so what a point sees of the lamp is the lamp less
//! the screen's projection, another rectangle. The floor's mean is taken by
//! the midpoint rule on a fine grid.

use glam::DVec3;
use radiosity::formfactor::EmitterSampling;
use radiosity::math::Rgb;
use radiosity::pipeline::Skips;
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::Settings;

/// The lamp: a square of this half-width centred over the floor's centre.
const LAMP_HALF: f64 = 0.2;
/// The lamp's height above the floor.
const LAMP_HEIGHT: f64 = 1.0;
/// The screen's height, and the x below which it covers everything.
const SCREEN_HEIGHT: f64 = 0.5;
const SCREEN_EDGE: f64 = 0.3;
const FLOOR_REFLECTANCE: f64 = 0.5;

/// The form factor from a point to the rectangle `[0, x] x [0, y]` of a
/// parallel plane at height `h`, the point under the origin (signed in x
/// and y, so that rectangles can be added and taken away by corners).
fn corner(x: f64, y: f64, h: f64) -> f64 {
    let (a, b) = ((x * x + h * h).sqrt(), (y * y + h * h).sqrt());
    (x / a * (y / a).atan() + y / b * (x / b).atan()) / (2.0 * std::f64::consts::PI)
}

/// The form factor from a floor point `(px, pz)` to the rectangle `x0..x1` by
/// `z0..z1` at height `h` above it.
fn rectangle(px: f64, pz: f64, (x0, x1, z0, z1): (f64, f64, f64, f64), h: f64) -> f64 {
    if x1 <= x0 || z1 <= z0 {
        return 0.0;
    }
    let f = |x: f64, z: f64| corner(x - px, z - pz, h);
    f(x1, z1) - f(x0, z1) - f(x1, z0) + f(x0, z0)
}

/// What a floor point sees of the lamp, the screen (when there is one)
/// hiding the lamp's part whose x, seen from the point, lies under its edge.
fn visible(px: f64, pz: f64, screen: bool) -> f64 {
    let lamp = (
        0.5 - LAMP_HALF,
        0.5 + LAMP_HALF,
        0.5 - LAMP_HALF,
        0.5 + LAMP_HALF,
    );
    let whole = rectangle(px, pz, lamp, LAMP_HEIGHT);
    if !screen {
        return whole;
    }
    // The screen's edge projected from the point onto the lamp's plane.
    let edge = px + (SCREEN_EDGE - px) * LAMP_HEIGHT / SCREEN_HEIGHT;
    let hidden = (lamp.0, edge.min(lamp.1), lamp.2, lamp.3);
    whole - rectangle(px, pz, hidden, LAMP_HEIGHT)
}

/// The floor's mean of [`visible`], by the midpoint rule.
fn floor_mean(screen: bool) -> f64 {
    let n = 400;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (x, z) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            sum += visible(x, z, screen);
        }
    }
    sum / f64::from(n * n)
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// The unit floor (facing up), the lamp (facing down) and, when asked, the
/// screen: a horizontal quad covering x below [`SCREEN_EDGE`] over the
/// whole depth of the floor and beyond.
fn scene(screen: bool) -> Scene {
    let mut b = SceneBuilder::new("emitter sampling");
    let black = floor_and_lamp(&mut b);
    if screen {
        b.object("screen");
        b.quad(
            black,
            v(-1.0, SCREEN_HEIGHT, -1.0),
            v(-1.0, SCREEN_HEIGHT, 2.0),
            v(SCREEN_EDGE, SCREEN_HEIGHT, 2.0),
            v(SCREEN_EDGE, SCREEN_HEIGHT, -1.0),
        )
        .unwrap();
    }
    b.build().unwrap()
}

/// Adds the unit floor and the lamp over it to `b`; returns a black
/// material for what hides the lamp.
fn floor_and_lamp(b: &mut SceneBuilder) -> u32 {
    let floor = b
        .material("floor", Rgb::splat(FLOOR_REFLECTANCE), Rgb::ZERO)
        .unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(1.0)).unwrap();
    let black = b.material("black", Rgb::ZERO, Rgb::ZERO).unwrap();
    b.object("floor");
    b.quad(
        floor,
        v(0.0, 0.0, 0.0),
        v(0.0, 0.0, 1.0),
        v(1.0, 0.0, 1.0),
        v(1.0, 0.0, 0.0),
    )
    .unwrap();
    b.object("lamp");
    let (lo, hi) = (0.5 - LAMP_HALF, 0.5 + LAMP_HALF);
    b.quad(
        lamp,
        v(lo, LAMP_HEIGHT, lo),
        v(hi, LAMP_HEIGHT, lo),
        v(hi, LAMP_HEIGHT, hi),
        v(lo, LAMP_HEIGHT, hi),
    )
    .unwrap();
    black
}

/// The floor's direct light over the lamp's radiosity, over the floor's
/// reflectance: its element's form factor to the lamp, as `sampling` finds it.
fn floor_factor(scene: &Scene, sampling: EmitterSampling) -> f64 {
    let settings = Settings {
        patch_size: Some(2.0),
        emitter_sampling: sampling,
        bounces: Some(1),
        refine: RefineSettings {
            uniform_depth: Some(0),
            ..RefineSettings::default()
        },
        // Without the screen the scene is convex, and the shortcut would
        // take Lambert's formula at the centre in every mode.
        skips: Skips {
            convex: false,
            ..Skips::default()
        },
        ..Settings::default()
    };
    let sol = radiosity::solve(scene, &settings, &|_| {}).unwrap();
    let means = sol.object_radiosity(scene);
    let of = |name: &str| {
        let i = scene.objects.iter().position(|o| o.name == name).unwrap();
        means[i].radiosity[0]
    };
    of("floor") / of("lamp") / FLOOR_REFLECTANCE
}

#[test]
fn a_floor_in_full_view_of_the_lamp_takes_the_centre_form_factor() {
    let scene = scene(false);
    let centre = visible(0.5, 0.5, false);
    let shadowed = floor_factor(&scene, EmitterSampling::Shadowed);
    assert!(
        // The receiving point sits a hair above the floor, and rows keep
        // single precision.
        (shadowed / centre - 1.0).abs() < 1e-5,
        "shadowed {shadowed} against the centre's closed form {centre}"
    );
    assert_eq!(
        shadowed.to_bits(),
        floor_factor(&scene, EmitterSampling::Centre).to_bits(),
        "where nothing hides the lamp, shadowed sampling is centre sampling"
    );
    // The points' mean differs from the centre here: the two are told apart.
    let element = floor_factor(&scene, EmitterSampling::Element);
    assert!((element / centre - 1.0).abs() > 1e-3, "{element} {centre}");
}

#[test]
fn a_shadow_edge_the_centre_misses_is_found_by_the_points() {
    let scene = scene(true);
    let truth = floor_mean(true);
    let centre = floor_factor(&scene, EmitterSampling::Centre);
    let shadowed = floor_factor(&scene, EmitterSampling::Shadowed);
    // The centre is in full view of the lamp: it sees no shadow at all.
    assert!(
        (centre / visible(0.5, 0.5, true) - 1.0).abs() < 1e-5,
        "{centre}"
    );
    let (centre_error, shadowed_error) = (centre / truth - 1.0, shadowed / truth - 1.0);
    assert!(
        centre_error > 0.15,
        "the centre should miss the shadow: {centre_error}"
    );
    assert!(
        shadowed_error.abs() < 0.5 * centre_error,
        "shadowed {shadowed_error} against centre {centre_error} (truth {truth})"
    );
    assert_eq!(
        shadowed.to_bits(),
        floor_factor(&scene, EmitterSampling::Element).to_bits(),
        "where something hides part of the lamp, the points' mean is taken"
    );
}

/// The floor and lamp of [`scene`] with `n` small black squares just under
/// the lamp, each at its own height (so each is its own surface), all within
/// the part of the lamp every floor point sees: each hides a little of the
/// lamp from every point of the floor, a little differently from each.
fn scene_with_chips(n: usize) -> Scene {
    let mut b = SceneBuilder::new("chips under a lamp");
    let black = floor_and_lamp(&mut b);
    let half = 0.015;
    for i in 0..n {
        let a = i as f64 * std::f64::consts::TAU / n as f64;
        let (x, z) = (0.5 + 0.06 * a.cos(), 0.5 + 0.06 * a.sin());
        let y = 0.9 + 0.01 * i as f64;
        b.object(&format!("chip_{i}"));
        b.quad(
            black,
            v(x - half, y, z - half),
            v(x - half, y, z + half),
            v(x + half, y, z + half),
            v(x + half, y, z - half),
        )
        .unwrap();
    }
    b.build().unwrap()
}

#[test]
fn a_shaft_crowded_by_many_surfaces_takes_the_centre_and_a_few_take_the_points() {
    // Shadowed sampling clips at the element's points while at most four
    // surfaces shadow the first of them, and takes the centre's exact value
    // past that (the limit is the library's `FEW_CASTERS`).
    let few = scene_with_chips(3);
    let unoccluded = visible(0.5, 0.5, false);
    let (few_centre, few_shadowed) = (
        floor_factor(&few, EmitterSampling::Centre),
        floor_factor(&few, EmitterSampling::Shadowed),
    );
    assert_eq!(
        few_shadowed.to_bits(),
        floor_factor(&few, EmitterSampling::Element).to_bits(),
        "three chips: the points' mean"
    );
    assert_ne!(few_shadowed.to_bits(), few_centre.to_bits());
    let many = scene_with_chips(7);
    let many_centre = floor_factor(&many, EmitterSampling::Centre);
    assert!(
        many_centre < few_centre && few_centre < unoccluded * (1.0 - 1e-3),
        "the chips hide some of the lamp: {many_centre} {few_centre} {unoccluded}"
    );
    assert_eq!(
        floor_factor(&many, EmitterSampling::Shadowed).to_bits(),
        many_centre.to_bits(),
        "seven chips: the centre's value"
    );
    assert_ne!(
        floor_factor(&many, EmitterSampling::Element).to_bits(),
        many_centre.to_bits()
    );
}
