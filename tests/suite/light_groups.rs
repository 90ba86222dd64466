//! Light groups: the groups of a solve add up to the solve with every light
//! on, and a mix of them is a new solve of the scene with each group's
//! emission scaled, for emissive surfaces (plain and textured) and punctual
//! lights alike.

use glam::{DVec2, DVec3};
use radiosity::light_groups::{
    solve_with_light_groups, GroupPattern, GroupRule, LightGroups, GROUP_TOLERANCE,
};
use radiosity::math::Rgb;
use radiosity::pipeline::{ProgressiveSettings, SolverKind, SolverSettings};
use radiosity::refine::RefineSettings;
use radiosity::scene::{Light, Scene, SceneBuilder, Texture, Wrap};
use radiosity::{Error, Settings, Solution};
use std::f64::consts::PI;
use std::sync::Arc;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A closed 4 x 3 x 4 m room with a box on the floor and four sources: a
/// warm panel under the ceiling, a panel on a wall whose emission is a
/// texture (a bright stripe), a point light and a spot light.
pub(crate) fn room() -> Scene {
    let mut b = SceneBuilder::new("room");
    let wall = b
        .material("wall", Rgb::new(0.7, 0.65, 0.6), Rgb::ZERO)
        .unwrap();
    let floor = b
        .material("floor", Rgb::new(0.4, 0.5, 0.3), Rgb::ZERO)
        .unwrap();
    let warm = b
        .material("warm panel", Rgb::splat(0.5), Rgb::new(8.0, 6.0, 4.0))
        .unwrap();
    let stripe = b
        .material("stripe panel", Rgb::splat(0.5), Rgb::new(1.0, 1.0, 2.0))
        .unwrap();
    let crate_ = b
        .material("crate", Rgb::new(0.6, 0.3, 0.2), Rgb::ZERO)
        .unwrap();
    let (x, y, z) = (4.0, 3.0, 4.0);
    b.object("room");
    b.quad(
        floor,
        v(0., 0., 0.),
        v(0., 0., z),
        v(x, 0., z),
        v(x, 0., 0.),
    )
    .unwrap();
    b.quad(wall, v(0., y, 0.), v(x, y, 0.), v(x, y, z), v(0., y, z))
        .unwrap();
    b.quad(wall, v(0., 0., 0.), v(x, 0., 0.), v(x, y, 0.), v(0., y, 0.))
        .unwrap();
    b.quad(wall, v(0., 0., z), v(0., y, z), v(x, y, z), v(x, 0., z))
        .unwrap();
    b.quad(wall, v(0., 0., 0.), v(0., y, 0.), v(0., y, z), v(0., 0., z))
        .unwrap();
    b.quad(wall, v(x, 0., 0.), v(x, 0., z), v(x, y, z), v(x, y, 0.))
        .unwrap();
    b.object("ceiling lamp");
    b.quad(
        warm,
        v(1.5, 2.9, 1.5),
        v(1.5, 2.9, 2.5),
        v(2.5, 2.9, 2.5),
        v(2.5, 2.9, 1.5),
    )
    .unwrap();
    b.object("wall strip");
    b.quad(
        stripe,
        v(0.05, 0.5, 1.0),
        v(0.05, 0.5, 3.0),
        v(0.05, 1.5, 3.0),
        v(0.05, 1.5, 1.0),
    )
    .unwrap();
    b.axis_box("crate", crate_, v(2.2, 0.0, 0.8), v(3.0, 0.8, 1.6))
        .unwrap();
    b.light(Light::point(
        "bulb",
        v(3.0, 2.0, 3.0),
        Rgb::new(1.0, 0.9, 0.7),
        6.0,
    ))
    .unwrap();
    b.light(Light::spot(
        "spot",
        v(1.0, 2.5, 1.0),
        v(0.3, -1.0, 0.2).normalize(),
        (0.2, 0.5),
        Rgb::new(0.6, 0.7, 1.0),
        20.0,
    ))
    .unwrap();
    let mut scene = b.build().unwrap();
    // The wall strip's emission is a texture: dark but for a bright stripe
    // along its middle.
    let texels: Vec<[f32; 3]> = (0..8 * 8)
        .map(|i| {
            if (i / 8) % 8 == 4 {
                [1.0; 3]
            } else {
                [0.05; 3]
            }
        })
        .collect();
    let texture = Texture {
        wrap: [Wrap::ClampToEdge; 2],
        factor: Rgb::new(2.0, 2.0, 4.0) * PI,
        max_value: f64::INFINITY,
        ..Texture::nearest(8, 8, texels)
    };
    scene.materials[stripe as usize].emissive_texture = Some(Arc::new(texture));
    let strip = scene
        .surfaces
        .iter()
        .position(|s| s.material == stripe)
        .unwrap();
    let uv = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(|(u, v)| DVec2::new(u, v));
    scene.surfaces[strip] = scene.surfaces[strip].clone().with_uv(&uv);
    scene
}

/// Coarse settings: the room solves in a second or two.
fn settings() -> Settings {
    Settings {
        patch_size: Some(1.0),
        hemicube_resolution: 32,
        ..Settings::default()
    }
}

/// The same mesh every time: no adaptive refinement, no shaped gather (a
/// plain gather is linear in emission as it stands), and a tight solver.
fn linear_settings() -> Settings {
    Settings {
        refine: RefineSettings {
            uniform_depth: Some(2),
            ..RefineSettings::default()
        },
        shaped_gathers: Some(0),
        solver: SolverSettings {
            tolerance: 1e-12,
            ..SolverSettings::default()
        },
        ..settings()
    }
}

/// The display mesh's vertex radiosities.
fn vertices(solution: &Solution) -> Vec<Rgb> {
    solution.shading_mesh().radiosity
}

/// The largest difference between `a` and `b` in any band of any vertex,
/// over the largest value of `b`.
fn largest_difference(a: &[Rgb], b: &[Rgb]) -> f64 {
    assert_eq!(a.len(), b.len(), "the display meshes differ");
    let largest = b.iter().map(|x| x.max_band()).fold(0.0, f64::max);
    assert!(largest > 0.0);
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).abs().max_band())
        .fold(0.0, f64::max);
    worst / largest
}

#[test]
fn each_source_is_a_group_named_after_its_material_or_light() {
    let scene = room();
    let groups = LightGroups::each(&scene);
    let names: Vec<&str> = groups.groups.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["warm panel", "stripe panel", "bulb", "spot"]);
    groups.validate(&scene).unwrap();
    let one = LightGroups::one(&scene);
    assert_eq!(one.len(), 1);
    assert_eq!(one.groups[0].lights, [0, 1]);
    one.validate(&scene).unwrap();
}

#[test]
fn patterns_merge_sources_and_a_pattern_that_names_nothing_is_refused() {
    let scene = room();
    let lamps = GroupPattern::parse("lamps = bulb, ceiling").unwrap();
    let groups = LightGroups::by_rule(&scene, GroupRule::Each, &[lamps]).unwrap();
    let names: Vec<&str> = groups.groups.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["lamps", "stripe panel", "spot"]);
    assert_eq!(groups.groups[0].lights, [0]);
    assert_eq!(groups.groups[0].surfaces.len(), 1);
    groups.validate(&scene).unwrap();
    let typo = GroupPattern::parse("x=bulbb").unwrap();
    let e = LightGroups::by_rule(&scene, GroupRule::Each, &[typo]).unwrap_err();
    assert!(e.to_string().contains("'bulbb'"), "{e}");
    assert!(GroupPattern::parse("no equals").is_err());
    assert!(GroupPattern::parse("=x").is_err());
    assert!(GroupPattern::parse("a=x,,y").is_err());
}

#[test]
fn groups_that_leave_a_source_out_are_refused() {
    let scene = room();
    let mut groups = LightGroups::each(&scene);
    groups.groups.pop();
    let e = groups.validate(&scene).unwrap_err();
    assert!(e.to_string().contains("spot"), "{e}");
    let e = solve_with_light_groups(&scene, &settings(), &groups, &|_| {}).unwrap_err();
    assert!(matches!(e, Error::Setting { .. }), "{e}");
}

#[test]
fn a_progressive_solve_that_may_stop_early_is_refused_before_any_work() {
    // Each group is solved to convergence: a shot limit, a time budget or a
    // loose unshot tolerance would leave the groups adding up to another
    // solve than the one asked for.
    let scene = room();
    let bounded = [
        ProgressiveSettings {
            max_shots: Some(10),
            ..ProgressiveSettings::default()
        },
        ProgressiveSettings {
            time_budget: Some(std::time::Duration::from_secs(60)),
            ..ProgressiveSettings::default()
        },
        ProgressiveSettings {
            tolerance: 0.01,
            ..ProgressiveSettings::default()
        },
    ];
    for progressive in bounded {
        let settings = Settings {
            solver_kind: SolverKind::Progressive,
            progressive,
            ..settings()
        };
        let e = solve_with_light_groups(&scene, &settings, &LightGroups::each(&scene), &|_| {})
            .unwrap_err();
        assert!(
            matches!(
                e,
                radiosity::Error::Setting {
                    name: "light_groups",
                    ..
                }
            ),
            "{e}"
        );
    }
}

#[test]
fn without_shaped_gathers_groups_add_up_to_the_solve_with_every_light_on() {
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        groups_add_up_without_shaped_gathers(kind);
    }
}

fn groups_add_up_without_shaped_gathers(kind: SolverKind) {
    // Adaptive refinement, as by default: the two solves refine the same
    // mesh (the same input and seed), so one group holding every source is
    // the solve with every light on.
    let scene = room();
    let settings = Settings {
        shaped_gathers: Some(0),
        solver_kind: kind,
        ..settings()
    };
    let mut each =
        solve_with_light_groups(&scene, &settings, &LightGroups::each(&scene), &|_| {}).unwrap();
    let one =
        solve_with_light_groups(&scene, &settings, &LightGroups::one(&scene), &|_| {}).unwrap();
    assert_eq!(each.light_groups().len(), 4);
    let whole = vertices(&one);
    let parts = each.group_shading_meshes();
    let sum = mix(&parts, &[Rgb::ONE; 4]);
    let largest = whole.iter().map(|x| x.max_band()).fold(0.0, f64::max);
    // Every vertex within 1e-6 of its own value; values that are nearly 0
    // within 1e-6 of 1e-3 of the brightest (where the groups' own
    // convergence, 1e-12 of each one's brightest, is all there is).
    for (i, (s, w)) in sum.iter().zip(&whole).enumerate() {
        for band in 0..3 {
            let allowed = 1e-6 * w[band].max(1e-3 * largest);
            assert!(
                (s[band] - w[band]).abs() <= allowed,
                "vertex {i} band {band}: groups add up to {} against {}",
                s[band],
                w[band]
            );
        }
    }
    // The solution's own radiosity is the groups' sum, and every group
    // lights something.
    assert!(largest_difference(&vertices(&each), &sum) < 1e-12);
    for part in &parts {
        assert!(part.radiosity.iter().any(|b| b.max_band() > 0.0));
    }
}

/// `sum_k factors[k] * parts[k]` per vertex.
fn mix(parts: &[radiosity::mesh::ShadingMesh], factors: &[Rgb]) -> Vec<Rgb> {
    let mut out = vec![Rgb::ZERO; parts[0].radiosity.len()];
    for (part, f) in parts.iter().zip(factors) {
        assert_eq!(part.radiosity.len(), out.len(), "the display meshes differ");
        for (m, x) in out.iter_mut().zip(&part.radiosity) {
            *m += *x * *f;
        }
    }
    out
}

/// The median over vertices of the largest band's difference between `a`
/// and `b` relative to `b`, leaving out vertices below 1e-3 of the
/// brightest.
fn median_relative_difference(a: &[Rgb], b: &[Rgb]) -> f64 {
    let largest = b.iter().map(|x| x.max_band()).fold(0.0, f64::max);
    let mut relative: Vec<f64> = a
        .iter()
        .zip(b)
        .filter(|(_, y)| y.max_band() > 1e-3 * largest)
        .map(|(x, y)| (*x - *y).abs().max_band() / y.max_band())
        .collect();
    relative.sort_by(f64::total_cmp);
    relative[relative.len() / 2]
}

#[test]
fn shaped_groups_mix_close_to_a_new_shaped_solve() {
    // A shaped gather is not linear in emission (its factors are ratios),
    // so a mix of shaped groups differs from a new shaped solve of the
    // scaled scene. Each group is shaped by its own light: the mix keeps
    // most of what shaping changes, where leaving the groups unshaped (or
    // shaped by the whole light) would lose it.
    let scene = room();
    let groups = LightGroups::each(&scene);
    let shaped = Settings {
        shaped_gathers: None,
        ..linear_settings()
    };
    let mut solution = solve_with_light_groups(&scene, &shaped, &groups, &|_| {}).unwrap();
    let parts = solution.group_shading_meshes();
    for factors in [[Rgb::ONE; 4], MIX] {
        let scaled = groups.scaled_scene(&scene, &factors).unwrap();
        let fresh = vertices(&radiosity::solve(&scaled, &shaped, &|_| {}).unwrap());
        let unshaped = vertices(&radiosity::solve(&scaled, &linear_settings(), &|_| {}).unwrap());
        let nonlinear = median_relative_difference(&mix(&parts, &factors), &fresh);
        let shaping = median_relative_difference(&unshaped, &fresh);
        assert!(
            nonlinear < 0.25 * shaping,
            "{factors:?}: the mix differs from the new solve by {nonlinear:e} (median), \
             shaping changes it by {shaping:e}"
        );
    }
}

/// Factors of a mix: dim the panel, tint the strip blue, double the bulb,
/// nearly put out the spot. (No factor is 0: a surface that stops emitting
/// takes its rows another way, and the mesh would differ.)
const MIX: [Rgb; 4] = [
    Rgb([0.25; 3]),
    Rgb([0.2, 0.5, 1.0]),
    Rgb([2.0; 3]),
    Rgb([0.01; 3]),
];

#[test]
fn a_mix_equals_a_new_solve_of_the_scene_with_scaled_emission() {
    let scene = room();
    let groups = LightGroups::each(&scene);
    let mut solution =
        solve_with_light_groups(&scene, &linear_settings(), &groups, &|_| {}).unwrap();
    let factors = MIX;
    let mix = mix(&solution.group_shading_meshes(), &factors);
    let scaled = groups.scaled_scene(&scene, &factors).unwrap();
    let fresh = radiosity::solve(&scaled, &linear_settings(), &|_| {}).unwrap();
    let difference = largest_difference(&mix, &vertices(&fresh));
    // Both converged to 1e-12 of their brightest patch; the gather and the
    // vertex means only average.
    assert!(
        difference < 1e3 * GROUP_TOLERANCE,
        "the mix differs from the new solve by {difference:e} of its brightest vertex"
    );
}

#[test]
fn without_shaped_gathers_one_group_is_the_plain_solve() {
    // The groups' gather is the driver's when nothing is shaped: one group
    // holding everything repeats the plain solve on its refined mesh.
    let scene = room();
    let settings = Settings {
        shaped_gathers: Some(0),
        solver: SolverSettings {
            tolerance: 1e-12,
            ..SolverSettings::default()
        },
        ..settings()
    };
    let one =
        solve_with_light_groups(&scene, &settings, &LightGroups::one(&scene), &|_| {}).unwrap();
    let plain = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
    let difference = largest_difference(&vertices(&one), &vertices(&plain));
    assert!(difference < 1e3 * GROUP_TOLERANCE, "{difference:e}");
}
