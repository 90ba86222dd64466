//! Punctual lights (issue 16): closed forms for point, spot, range and
//! directional light over a floor, a hard shadow, the solvers against the
//! path tracer in a room lit by a point light.

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::pipeline::SolverKind;
use radiosity::reference::{Reference, ReferenceSettings};
use radiosity::refine::RefineSettings;
use radiosity::scene::{Light, Scene, SceneBuilder};
use radiosity::{Settings, Solution};
use std::f64::consts::PI;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// An upward-facing rectangle `[x0, x1] x [z0, z1]` at height `y`.
fn up_quad(b: &mut SceneBuilder, m: u32, y: f64, (x0, x1): (f64, f64), (z0, z1): (f64, f64)) {
    b.quad(m, v(x0, y, z0), v(x0, y, z1), v(x1, y, z1), v(x1, y, z0))
        .unwrap();
}

/// A downward-facing rectangle, the same way round.
fn down_quad(b: &mut SceneBuilder, m: u32, y: f64, (x0, x1): (f64, f64), (z0, z1): (f64, f64)) {
    b.quad(m, v(x0, y, z0), v(x1, y, z0), v(x1, y, z1), v(x0, y, z1))
        .unwrap();
}

/// A floor `[0, 2]^2` of reflectance `rho` lit by `lights` alone.
fn floor_under(lights: Vec<Light>, rho: f64) -> Scene {
    let mut b = SceneBuilder::new("floor");
    let grey = b.material("grey", Rgb::splat(rho), Rgb::ZERO).unwrap();
    b.object("floor");
    up_quad(&mut b, grey, 0.0, (0.0, 2.0), (0.0, 2.0));
    for l in lights {
        b.light(l).unwrap();
    }
    b.build().unwrap()
}

/// Uniform elements of 1/32 m: 0.25 m patches split three times.
fn uniform() -> Settings {
    Settings {
        patch_size: Some(0.25),
        refine: RefineSettings {
            uniform_depth: Some(3),
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

fn solve(scene: &Scene, settings: &Settings) -> Solution {
    radiosity::solve(scene, settings, &|_| {}).unwrap()
}

/// The solid angle of triangle `a b c` seen from `o` (Van Oosterom and
/// Strackee).
fn solid_angle(o: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (a, b, c) = (a - o, b - o, c - o);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c)).abs();
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}

/// The square floor element centred at `c` with area `area` (elements of
/// a square patch are squares).
fn element_square(c: DVec3, area: f64) -> [DVec3; 4] {
    let h = area.sqrt() / 2.0;
    [
        c + v(-h, 0.0, -h),
        c + v(-h, 0.0, h),
        c + v(h, 0.0, h),
        c + v(h, 0.0, -h),
    ]
}

#[test]
fn a_point_light_over_a_floor_gives_the_exact_element_means() {
    // The mean over an element of I cos / d^2 is I times its solid angle
    // over its area: a closed form. With no other surface, the floor's
    // radiosity is rho times that, with no indirect light.
    let light = v(0.7, 1.0, 1.1);
    let (intensity, rho) = (10.0, 0.5);
    let scene = floor_under(vec![Light::point("bulb", light, Rgb::ONE, intensity)], rho);
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let sol = solve(
            &scene,
            &Settings {
                solver_kind: kind,
                ..uniform()
            },
        );
        let mut worst: f64 = 0.0;
        for leaf in sol.leaves() {
            let [a, b, c, d] = element_square(leaf.centroid(), leaf.area());
            let omega = solid_angle(light, a, b, c) + solid_angle(light, a, c, d);
            let exact = rho * intensity * omega / leaf.area();
            worst = worst.max((leaf.radiosity[0] / exact - 1.0).abs());
        }
        eprintln!("{kind:?}: point light over a floor, worst element error {worst:e}");
        assert!(worst < 1e-4, "{kind:?}: worst relative error {worst:e}");
        // At the point under the light, I / h^2: the element there is within
        // its curvature of it.
        let below = sol
            .leaves()
            .into_iter()
            .min_by(|a, b| {
                let d =
                    |l: &radiosity::solution::Leaf<'_>| (l.centroid() - v(0.7, 0.0, 1.1)).length();
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        let at_point = rho * intensity / 1.0;
        assert!((below.radiosity[0] / at_point - 1.0).abs() < 1e-3);
        // Everything the light sends down lands on the floor or leaves.
        let incident = sol.stats().direct.as_ref().unwrap().incident_power[0];
        let total: f64 = sol
            .leaves()
            .iter()
            .map(|l| l.radiosity[0] / rho * l.area())
            .sum();
        assert!((incident / total - 1.0).abs() < 1e-9);
    }
}

/// Radiosity of the leaf whose centre is nearest `p`.
fn at(sol: &Solution, p: DVec3) -> f64 {
    sol.leaves()
        .into_iter()
        .min_by(|a, b| {
            (a.centroid() - p)
                .length()
                .total_cmp(&(b.centroid() - p).length())
        })
        .unwrap()
        .radiosity[0]
}

#[test]
fn a_spot_falls_off_between_its_cones_and_a_range_ends_the_light() {
    let (h, intensity, rho) = (1.0, 4.0, 0.5);
    let (inner, outer) = (0.3f64, 0.5f64);
    let spot = Light::spot(
        "spot",
        v(1.0, h, 1.0),
        v(0.0, -1.0, 0.0),
        (inner, outer),
        Rgb::ONE,
        intensity,
    );
    let sol = solve(&floor_under(vec![spot], rho), &uniform());
    // The extension's falloff, written out: the cosine mapped from the outer
    // cone (0) to the inner (1), squared.
    let falloff = |theta: f64| {
        let t = ((theta.cos() - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
        t * t
    };
    let step = 1.0 / 32.0;
    for i in 0..32 {
        // Element centres along x from the axis outwards.
        let x = (i as f64 + 0.5) * step;
        let theta = (x / h).atan();
        let exact = rho * intensity * theta.cos().powi(3) / (h * h) * falloff(theta);
        let got = at(&sol, v(1.0 + x, 0.0, 1.0 + step / 2.0));
        let theta_edges = [((x - step) / h).atan(), ((x + step) / h).atan()];
        if theta_edges[1] < inner {
            // Inside the inner cone: I cos^3 / h^2, up to the element's
            // curvature.
            assert!((got / exact - 1.0).abs() < 2e-3, "x {x}: {got} vs {exact}");
        } else if theta_edges[0] > outer {
            assert_eq!(got, 0.0, "x {x}: outside the outer cone");
        } else {
            // On the ramp the element mean differs from the centre's value
            // by its curvature over an element.
            assert!(
                (got - exact).abs() < 0.02 * rho * intensity,
                "x {x}: {got} vs {exact}"
            );
        }
    }

    // Range: the extension's window (1 - (d / range)^4), zero beyond.
    let mut point = Light::point("near", v(1.0, 0.5, 1.0), Rgb::ONE, intensity);
    point.range = Some(0.8);
    let sol = solve(&floor_under(vec![point], rho), &uniform());
    for i in 0..32 {
        let x = (i as f64 + 0.5) * step;
        let d = (x * x + 0.25f64 + (step / 2.0) * (step / 2.0)).sqrt();
        let window = (1.0 - (d / 0.8).powi(4)).clamp(0.0, 1.0);
        let exact = rho * intensity * (0.5 / d) / (d * d) * window;
        let got = at(&sol, v(1.0 + x, 0.0, 1.0 + step / 2.0));
        if d + step < 0.8 {
            assert!((got / exact - 1.0).abs() < 5e-3, "x {x}: {got} vs {exact}");
        } else if d - step > 0.8 {
            assert_eq!(got, 0.0, "x {x}: beyond the range");
        }
    }
}

#[test]
fn a_sun_lights_the_floor_through_an_opening_exactly() {
    // A black roof at 1 m with a 0.5 m opening over a grey floor; the sun's
    // rays come down at a slant, so the lit patch is the opening shifted by
    // the slant: x in [0.75 + s, 1.25 + s], z in [0.75, 1.25].
    let (rho, lux, s) = (0.5, 100.0, 0.25);
    let mut b = SceneBuilder::new("court");
    let grey = b.material("grey", Rgb::splat(rho), Rgb::ZERO).unwrap();
    let black = b.material("black", Rgb::ZERO, Rgb::ZERO).unwrap();
    b.object("floor");
    up_quad(&mut b, grey, 0.0, (0.0, 2.0), (0.0, 2.0));
    b.object("roof");
    let (lo, hi) = (-2.0, 4.0);
    down_quad(&mut b, black, 1.0, (lo, 0.75), (lo, hi));
    down_quad(&mut b, black, 1.0, (1.25, hi), (lo, hi));
    down_quad(&mut b, black, 1.0, (0.75, 1.25), (lo, 0.75));
    down_quad(&mut b, black, 1.0, (0.75, 1.25), (1.25, hi));
    let dir = v(s, -1.0, 0.0).normalize();
    b.light(Light::directional("sun", dir, Rgb::ONE, lux))
        .unwrap();
    let scene = b.build().unwrap();
    let sol = solve(&scene, &uniform());
    let cos = 1.0 / (1.0 + s * s).sqrt();
    let lit = rho * lux * cos;
    let (mut inside, mut outside) = (0, 0);
    let half = 1.0 / 64.0;
    for leaf in sol.leaves() {
        let c = leaf.centroid();
        if c.y > 0.5 {
            continue;
        }
        let x = c.x - s;
        let in_x = (0.75 + half..=1.25 - half).contains(&x);
        let in_z = (0.75 + half..=1.25 - half).contains(&c.z);
        let out = x + half < 0.75 || x - half > 1.25 || c.z + half < 0.75 || c.z - half > 1.25;
        if in_x && in_z {
            inside += 1;
            assert!(
                (leaf.radiosity[0] / lit - 1.0).abs() < 1e-12,
                "{c}: {}",
                leaf.radiosity[0]
            );
        } else if out {
            outside += 1;
            assert_eq!(leaf.radiosity[0], 0.0, "{c}: in the roof's shadow");
        }
    }
    assert!(
        inside > 100 && outside > 1000,
        "{inside} lit, {outside} dark"
    );
}

#[test]
fn an_occluder_casts_a_hard_shadow_and_refinement_follows_its_edge() {
    // A point light 1 m over the floor, a black 0.2 m square half way down:
    // its shadow is the square scaled by 2 about the point under the light.
    let light = v(1.0, 1.0, 1.0);
    let (intensity, rho) = (5.0, 0.5);
    let mut b = SceneBuilder::new("shadow");
    let grey = b.material("grey", Rgb::splat(rho), Rgb::ZERO).unwrap();
    let black = b.material("black", Rgb::ZERO, Rgb::ZERO).unwrap();
    b.object("floor");
    up_quad(&mut b, grey, 0.0, (0.0, 2.0), (0.0, 2.0));
    b.object("blocker");
    up_quad(&mut b, black, 0.5, (0.9, 1.1), (0.9, 1.1));
    b.light(Light::point("bulb", light, Rgb::ONE, intensity))
        .unwrap();
    let scene = b.build().unwrap();
    // Adaptive refinement from 0.25 m patches: the shadow's edges, at 0.8 and
    // 1.2, cross elements that refinement should split.
    let settings = Settings {
        patch_size: Some(0.25),
        ..Settings::default()
    };
    let sol = solve(&scene, &settings);
    let floor: Vec<_> = sol
        .leaves()
        .into_iter()
        .filter(|l| l.centroid().y < 0.25)
        .collect();
    let (mut shadowed, mut lit) = (0, 0);
    for leaf in &floor {
        let [a, b, c, d] = element_square(leaf.centroid(), leaf.area());
        let half = leaf.area().sqrt() / 2.0;
        let (x, z) = (leaf.centroid().x, leaf.centroid().z);
        let inside =
            (0.8 + half..=1.2 - half).contains(&x) && (0.8 + half..=1.2 - half).contains(&z);
        let outside = x + half <= 0.8 || x - half >= 1.2 || z + half <= 0.8 || z - half >= 1.2;
        if inside {
            shadowed += 1;
            assert_eq!(leaf.radiosity[0], 0.0, "{x} {z} in the umbra");
        } else if outside {
            lit += 1;
            let omega = solid_angle(light, a, b, c) + solid_angle(light, a, c, d);
            let exact = rho * intensity * omega / leaf.area();
            let rel = (leaf.radiosity[0] / exact - 1.0).abs();
            // Large elements far out carry their quadrature error.
            assert!(rel < 2e-3, "{x} {z}: {} vs {exact}", leaf.radiosity[0]);
        }
    }
    assert!(shadowed > 0 && lit > 0);
    // The elements on the shadow's edge are the smallest on the floor.
    let on_edge = |l: &&radiosity::solution::Leaf<'_>| {
        let half = l.area().sqrt() / 2.0;
        [l.centroid().x, l.centroid().z]
            .iter()
            .any(|c| (c - 0.8).abs() < half || (c - 1.2).abs() < half)
            && (0.8 - half..=1.2 + half).contains(&l.centroid().x)
            && (0.8 - half..=1.2 + half).contains(&l.centroid().z)
    };
    let edge_area = floor
        .iter()
        .filter(on_edge)
        .map(|l| l.area())
        .fold(0.0, f64::max);
    let largest = floor.iter().map(|l| l.area()).fold(0.0, f64::max);
    assert!(
        edge_area * 16.0 <= largest,
        "edge elements {edge_area} m^2, largest {largest} m^2"
    );
}

/// A closed 1 m room of reflectance `rho` lit by a point light alone.
fn lit_room(rho: f64) -> Scene {
    let mut b = SceneBuilder::new("lit_room");
    let wall = b
        .material("wall", Rgb::new(rho, rho, rho * 0.6), Rgb::ZERO)
        .unwrap();
    let red = b
        .material("red", Rgb::new(0.6, 0.1, 0.1), Rgb::ZERO)
        .unwrap();
    b.object("floor");
    up_quad(&mut b, wall, 0.0, (0.0, 1.0), (0.0, 1.0));
    b.object("ceiling");
    down_quad(&mut b, wall, 1.0, (0.0, 1.0), (0.0, 1.0));
    b.object("x0");
    b.quad(
        wall,
        v(0.0, 0.0, 0.0),
        v(0.0, 1.0, 0.0),
        v(0.0, 1.0, 1.0),
        v(0.0, 0.0, 1.0),
    )
    .unwrap();
    b.object("x1");
    b.quad(
        red,
        v(1.0, 0.0, 0.0),
        v(1.0, 0.0, 1.0),
        v(1.0, 1.0, 1.0),
        v(1.0, 1.0, 0.0),
    )
    .unwrap();
    b.object("z0");
    b.quad(
        wall,
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(1.0, 1.0, 0.0),
        v(0.0, 1.0, 0.0),
    )
    .unwrap();
    b.object("z1");
    b.quad(
        wall,
        v(0.0, 0.0, 1.0),
        v(0.0, 1.0, 1.0),
        v(1.0, 1.0, 1.0),
        v(1.0, 0.0, 1.0),
    )
    .unwrap();
    b.axis_box("box", wall, v(0.2, 0.0, 0.2), v(0.45, 0.3, 0.45))
        .unwrap();
    b.light(Light::point("bulb", v(0.6, 0.8, 0.55), Rgb::ONE, 1.0))
        .unwrap();
    b.build().unwrap()
}

#[test]
fn both_solvers_agree_with_the_path_tracer_in_a_room_lit_by_a_point_light() {
    let scene = lit_room(0.6);
    let reference = Reference::new(&scene).unwrap();
    let means = reference
        .object_means(&ReferenceSettings {
            paths: 200_000,
            seed: 3,
            ..ReferenceSettings::default()
        })
        .unwrap();
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let sol = solve(
            &scene,
            &Settings {
                solver_kind: kind,
                ..Settings::default()
            },
        );
        let objects = sol.object_radiosity(&scene);
        let mut worst: f64 = 0.0;
        for (o, r) in objects.iter().zip(&means) {
            for band in 0..3 {
                let (got, want, se) = (o.radiosity[band], r.radiosity[band], r.std_error[band]);
                let allowed = 4.0 * se + 0.01 * want;
                worst = worst.max((got - want).abs() / want);
                assert!(
                    (got - want).abs() <= allowed,
                    "{kind:?} {} band {band}: {got} vs {want} +- {se}",
                    o.name
                );
            }
        }
        eprintln!(
            "{kind:?}: worst per-object difference {:.3}%",
            worst * 100.0
        );
        // Closed room: what the light delivers is absorbed.
        let energy = &sol.stats().energy;
        assert!(
            energy.relative_difference.abs() < 5e-3,
            "{kind:?}: {:?}",
            energy.relative_difference
        );
        // All of the point light's 4 pi I lands on the room's surfaces.
        let incident = sol.stats().direct.as_ref().unwrap().incident_power[0];
        assert!((incident / (4.0 * PI) - 1.0).abs() < 5e-3, "{incident}");
    }
}
