//! One solve with chosen skips turned off, for measuring what each skip saves
//! (run it under `perf stat -e instructions:u`, once with and once without a
//! skip, and compare), and its figures as JSON on standard output.
//!
//! `cargo run --release --example skip_costs -- SCENE [--off NAME,...] [--res N]
//! [--patch-size M] [--depth D] [--threads T]`
//!
//! - SCENE: a built-in scene name; `grey_cornell` (the Cornell box with every
//!   material's bands replaced by their mean); `black_light_cornell` (the
//!   Cornell box whose light reflects nothing); `grey_box` (a closed 1 x 0.8 x
//!   1.2 m box reflecting 0.9 grey, the ceiling emitting 1); `cube6` (the unit
//!   cube reflecting 0.5, the ceiling emitting 1).
//! - `--off`: skips to turn off: zero_reflectance, grey, convex, empty_faces,
//!   hidden_back_faces, all, or none.
//! - `--res`, `--patch-size`: hemi-cube resolution and patch size.
//! - `--depth`: a uniform subdivision depth instead of adaptive refinement.
//! - `--threads`: worker threads (1 for CPU counts that do not depend on
//!   scheduling).

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::pipeline::Skips;
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::{scenes, Settings};

fn closed_box(size: DVec3, rho: f64) -> Scene {
    let mut b = SceneBuilder::new("box");
    let wall = b.material("wall", Rgb::splat(rho), Rgb::ZERO).unwrap();
    let lamp = b
        .material(
            "lamp",
            Rgb::splat(rho),
            Rgb::splat(1.0 / std::f64::consts::PI),
        )
        .unwrap();
    let p = |x: f64, y: f64, z: f64| DVec3::new(x * size.x, y * size.y, z * size.z);
    let quads = [
        (
            "floor",
            [p(0., 0., 0.), p(0., 0., 1.), p(1., 0., 1.), p(1., 0., 0.)],
        ),
        (
            "ceiling",
            [p(0., 1., 0.), p(1., 1., 0.), p(1., 1., 1.), p(0., 1., 1.)],
        ),
        (
            "z0",
            [p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)],
        ),
        (
            "z1",
            [p(0., 0., 1.), p(0., 1., 1.), p(1., 1., 1.), p(1., 0., 1.)],
        ),
        (
            "x0",
            [p(0., 0., 0.), p(0., 1., 0.), p(0., 1., 1.), p(0., 0., 1.)],
        ),
        (
            "x1",
            [p(1., 0., 0.), p(1., 0., 1.), p(1., 1., 1.), p(1., 1., 0.)],
        ),
    ];
    for (name, q) in quads {
        b.object(name);
        let m = if name == "ceiling" { lamp } else { wall };
        b.polygon(m, &q).unwrap();
    }
    b.build().unwrap()
}

fn scene(name: &str) -> Scene {
    match name {
        "grey_cornell" => {
            let mut s = scenes::cornell_box();
            for m in &mut s.materials {
                m.reflectance = Rgb::splat(m.reflectance.mean());
                m.emission = Rgb::splat(m.emission.mean());
            }
            s
        }
        "black_light_cornell" => {
            let mut s = scenes::cornell_box();
            for m in &mut s.materials {
                if m.emission.max_band() > 0.0 {
                    m.reflectance = Rgb::ZERO;
                }
            }
            s
        }
        "grey_box" => closed_box(DVec3::new(1.0, 0.8, 1.2), 0.9),
        "cube6" => closed_box(DVec3::ONE, 0.5),
        _ => scenes::by_name(name).unwrap_or_else(|| panic!("no scene called {name}")),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().expect("a scene name").clone();
    let mut settings = Settings::default();
    let mut threads = None;
    let mut i = 1;
    while i < args.len() {
        let value = args.get(i + 1).expect("a value after each option");
        match args[i].as_str() {
            "--off" => {
                for skip in value.split(',') {
                    let s = &mut settings.skips;
                    match skip {
                        "zero_reflectance" => s.zero_reflectance = false,
                        "grey" => s.grey = false,
                        "convex" => s.convex = false,
                        "empty_faces" => s.empty_faces = false,
                        "hidden_back_faces" => s.hidden_back_faces = false,
                        "all" => *s = Skips::NONE,
                        "none" => {}
                        other => panic!("no skip called {other}"),
                    }
                }
            }
            "--res" => settings.hemicube_resolution = value.parse().unwrap(),
            "--patch-size" => settings.patch_size = Some(value.parse().unwrap()),
            "--depth" => {
                settings.refine = RefineSettings {
                    uniform_depth: Some(value.parse().unwrap()),
                    ..RefineSettings::default()
                }
            }
            "--threads" => threads = Some(value.parse::<usize>().unwrap()),
            other => panic!("unknown option {other}"),
        }
        i += 2;
    }
    let scene = scene(&name);
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        pool = pool.num_threads(t);
    }
    let pool = pool.build().unwrap();
    let sol = pool
        .install(|| radiosity::solve(&scene, &settings, &|_| {}))
        .unwrap();
    let s = &sol.stats();
    let out = serde_json::json!({
        "scene": name,
        "skips": s.skips,
        "seconds": s.seconds,
        "hemicube": s.hemicube,
        "iterations": s.total_iterations,
        "elements": s.elements,
        "energy": s.energy,
    });
    println!("{out}");
}
