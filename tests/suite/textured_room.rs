//! A textured room lit only by punctual lights (a point light and a spot
//! light): the solver's per-object radiosity against the independent path
//! tracer, which reads the same textures per texel (issue 16's check).

use glam::{DVec2, DVec3};
use radiosity::math::Rgb;
use radiosity::pipeline::SolverKind;
use radiosity::reference::{Reference, ReferenceSettings};
use radiosity::scene::{Light, Scene, SceneBuilder, Texture};
use radiosity::Settings;
use std::sync::Arc;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

const W: f64 = 3.0;
const H: f64 = 2.5;

/// A nearest-texel texture of `width x height` texels.
fn texture(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Arc<Texture> {
    Arc::new(Texture::nearest(width, height, texels))
}

/// A 3 x 2.5 x 3 m room facing in, a 0.8 m box on its floor, a 4 x 4
/// checker on the floor and two coloured stripes on the back wall, lit by a
/// warm point light under the ceiling and a spot light aimed at the box.
fn textured_room() -> Scene {
    let mut b = SceneBuilder::new("textured room");
    let grey = |b: &mut SceneBuilder, name: &str, rho: [f64; 3]| {
        b.material(name, Rgb(rho), Rgb::ZERO).unwrap()
    };
    let floor = grey(&mut b, "floor", [0.45, 0.43, 0.4]);
    let stripes = grey(&mut b, "stripes", [0.45, 0.4, 0.2]);
    let walls = grey(&mut b, "walls", [0.6, 0.6, 0.6]);
    let ceiling = grey(&mut b, "ceiling", [0.7, 0.7, 0.7]);
    let wood = grey(&mut b, "box", [0.6, 0.4, 0.3]);
    let quad = |b: &mut SceneBuilder, object: &str, m: u32, c: [DVec3; 4]| {
        b.object(object);
        b.quad(m, c[0], c[1], c[2], c[3]).unwrap();
    };
    quad(
        &mut b,
        "floor",
        floor,
        [v(0., 0., 0.), v(0., 0., W), v(W, 0., W), v(W, 0., 0.)],
    );
    quad(
        &mut b,
        "ceiling",
        ceiling,
        [v(0., H, 0.), v(W, H, 0.), v(W, H, W), v(0., H, W)],
    );
    quad(
        &mut b,
        "wall_left",
        walls,
        [v(0., 0., 0.), v(0., H, 0.), v(0., H, W), v(0., 0., W)],
    );
    quad(
        &mut b,
        "wall_right",
        walls,
        [v(W, 0., 0.), v(W, 0., W), v(W, H, W), v(W, H, 0.)],
    );
    quad(
        &mut b,
        "wall_back",
        stripes,
        [v(0., 0., 0.), v(W, 0., 0.), v(W, H, 0.), v(0., H, 0.)],
    );
    quad(
        &mut b,
        "wall_front",
        walls,
        [v(0., 0., W), v(0., H, W), v(W, H, W), v(W, 0., W)],
    );
    let (x0, x1, top, z0, z1) = (1.0, 1.8, 0.8, 1.2, 2.0);
    b.object("box");
    for c in [
        [
            v(x0, top, z0),
            v(x0, top, z1),
            v(x1, top, z1),
            v(x1, top, z0),
        ],
        [v(x0, 0., z0), v(x0, 0., z1), v(x0, top, z1), v(x0, top, z0)],
        [v(x1, 0., z0), v(x1, top, z0), v(x1, top, z1), v(x1, 0., z1)],
        [v(x0, 0., z0), v(x0, top, z0), v(x1, top, z0), v(x1, 0., z0)],
        [v(x0, 0., z1), v(x1, 0., z1), v(x1, top, z1), v(x0, top, z1)],
    ] {
        b.quad(wood, c[0], c[1], c[2], c[3]).unwrap();
    }
    b.light(Light::point(
        "bulb",
        v(0.8, 2.2, 2.3),
        Rgb::new(1.0, 0.9, 0.75),
        4.0,
    ))
    .unwrap();
    b.light(Light::spot(
        "spot",
        v(2.7, 2.3, 0.3),
        v(1.4, 0.4, 1.6) - v(2.7, 2.3, 0.3),
        (0.25, 0.45),
        Rgb::new(0.8, 0.9, 1.0),
        12.0,
    ))
    .unwrap();
    let mut scene = b.build().unwrap();
    let (dark, light) = ([0.15f32, 0.15, 0.15], [0.75f32, 0.72, 0.65]);
    let checker = (0..16)
        .map(|i| {
            if (i % 4 + i / 4) % 2 == 0 {
                dark
            } else {
                light
            }
        })
        .collect();
    scene.materials[floor as usize].base_texture = Some(texture(4, 4, checker));
    scene.materials[stripes as usize].base_texture =
        Some(texture(2, 1, vec![[0.7, 0.2, 0.15], [0.2, 0.6, 0.25]]));
    // Texture coordinates: the floor u = x / W, v = z / W; the back wall
    // u = x / W, v = y / H.
    let uv = |c: [(f64, f64); 4]| c.map(|(a, b)| DVec2::new(a, b));
    scene.surfaces[0] =
        scene.surfaces[0]
            .clone()
            .with_uv(&uv([(0., 0.), (0., 1.), (1., 1.), (1., 0.)]));
    scene.surfaces[4] =
        scene.surfaces[4]
            .clone()
            .with_uv(&uv([(0., 0.), (1., 0.), (1., 1.), (0., 1.)]));
    scene
}

#[test]
fn a_textured_room_under_a_point_and_a_spot_light_matches_the_path_tracer_per_object() {
    let scene = textured_room();
    let reference = Reference::new(&scene)
        .unwrap()
        .object_means(&ReferenceSettings {
            paths: 400_000,
            seed: 11,
            ..ReferenceSettings::default()
        })
        .unwrap();
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let settings = Settings {
            solver_kind: kind,
            ..Settings::default()
        };
        let sol = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
        let objects = sol.object_radiosity(&scene);
        let mut sum = 0.0;
        for (o, r) in objects.iter().zip(&reference) {
            for band in 0..3 {
                let (got, want, sigma) = (
                    o.radiosity.0[band],
                    r.radiosity.0[band],
                    r.std_error.0[band],
                );
                let error = got / want - 1.0;
                sum += error.abs();
                eprintln!(
                    "{kind:?} {} band {band}: solver {got:.5}, reference {want:.5} +- {sigma:.1e} \
                     ({error:+.4})",
                    o.name
                );
                // 1% (the bound) plus three of the reference's
                // standard errors.
                assert!(
                    (got - want).abs() <= 0.01 * want + 3.0 * sigma,
                    "{kind:?} {} band {band}: {got} vs {want} +- {sigma}",
                    o.name
                );
            }
        }
        eprintln!(
            "{kind:?}: mean error {:.4}",
            sum / (3 * objects.len()) as f64
        );
    }
}
