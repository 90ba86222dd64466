//! The case behind most of `many_boxes`' error (issue 18; see
//! `papers/substructuring.md`, "many_boxes face by face"): a low box whose
//! side faces a tall box across a narrow gap, on a floor of coarse patches,
//! in a closed room lit by one lamp under the ceiling. Prints each face's
//! error against the path tracer under several settings, and with
//! `--points` the error at points along the low box's gap side, the gap's
//! floor, the floor behind the tall box and the tall box's gap side.
//!
//! ```text
//! cargo run --release --example gap_between_boxes [-- --points] [--no-tall] [--floor-reflectance R] [--shaped-sweep]
//! ```
//!
//! The room is 8 m square and 4 m high; patches are at most 3.15 m unless a
//! setting says otherwise, about as in `many_boxes`. Every material is grey, so one band
//! is printed. `--no-tall` leaves the tall box out; `--floor-reflectance 0`
//! takes the floor's light out of the exchange. `--shaped-sweep` compares
//! the defaults with 0 to 8 shaped gathers instead of the settings above.

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::reference::{Reference, ReferenceSettings, SurfacePoint};
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::Settings;

/// The largest patch edge: about `many_boxes`' default (3.14 m). Either
/// makes the 8 m floor three by three patches of 2.67 m.
const PATCH: f64 = 3.15;

/// The low box: centre, footprint edge and height.
const LOW: (f64, f64, f64) = (4.5, 0.62, 0.47);
/// The gap between the low box's +z side and the tall box.
const GAP: f64 = 0.35;
/// The tall box: footprint edge and height.
const TALL: (f64, f64) = (0.67, 1.07);

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Adds quad `c` of material `m`, wound to face `out`.
fn face(b: &mut SceneBuilder, m: u32, c: [DVec3; 4], out: DVec3) {
    if (c[1] - c[0]).cross(c[3] - c[0]).dot(out) > 0.0 {
        b.quad(m, c[0], c[1], c[2], c[3]).unwrap();
    } else {
        b.quad(m, c[3], c[2], c[1], c[0]).unwrap();
    }
}

/// A box standing on the floor, each face an object `NAME_FACE`.
fn standing_box(b: &mut SceneBuilder, m: u32, lo: DVec3, hi: DVec3, name: &str) {
    let (x0, x1, y0, y1, z0, z1) = (lo.x, hi.x, lo.y, hi.y, lo.z, hi.z);
    let faces = [
        (
            "top",
            [v(x0, y1, z0), v(x1, y1, z0), v(x1, y1, z1), v(x0, y1, z1)],
            DVec3::Y,
        ),
        (
            "xlo",
            [v(x0, y0, z0), v(x0, y1, z0), v(x0, y1, z1), v(x0, y0, z1)],
            DVec3::NEG_X,
        ),
        (
            "xhi",
            [v(x1, y0, z0), v(x1, y1, z0), v(x1, y1, z1), v(x1, y0, z1)],
            DVec3::X,
        ),
        (
            "zlo",
            [v(x0, y0, z0), v(x1, y0, z0), v(x1, y1, z0), v(x0, y1, z0)],
            DVec3::NEG_Z,
        ),
        (
            "zhi",
            [v(x0, y0, z1), v(x1, y0, z1), v(x1, y1, z1), v(x0, y1, z1)],
            DVec3::Z,
        ),
    ];
    for (which, corners, out) in faces {
        b.object(&format!("{name}_{which}"));
        face(b, m, corners, out);
    }
}

fn scene(tall: bool, floor_reflectance: f64) -> Scene {
    let mut b = SceneBuilder::new("gap between boxes");
    let wall = b.material("wall", Rgb::splat(0.7), Rgb::ZERO).unwrap();
    let floor = b
        .material("floor", Rgb::splat(floor_reflectance), Rgb::ZERO)
        .unwrap();
    let lamp = b
        .material("lamp", Rgb::splat(0.8), Rgb::splat(4.0))
        .unwrap();
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let (s, h) = (8.0, 4.0);
    b.object("floor");
    face(
        &mut b,
        floor,
        [v(0., 0., 0.), v(s, 0., 0.), v(s, 0., s), v(0., 0., s)],
        DVec3::Y,
    );
    b.object("ceiling");
    face(
        &mut b,
        wall,
        [v(0., h, 0.), v(s, h, 0.), v(s, h, s), v(0., h, s)],
        DVec3::NEG_Y,
    );
    b.object("walls");
    face(
        &mut b,
        wall,
        [v(0., 0., 0.), v(s, 0., 0.), v(s, h, 0.), v(0., h, 0.)],
        DVec3::Z,
    );
    face(
        &mut b,
        wall,
        [v(0., 0., s), v(s, 0., s), v(s, h, s), v(0., h, s)],
        DVec3::NEG_Z,
    );
    face(
        &mut b,
        wall,
        [v(0., 0., 0.), v(0., h, 0.), v(0., h, s), v(0., 0., s)],
        DVec3::X,
    );
    face(
        &mut b,
        wall,
        [v(s, 0., 0.), v(s, h, 0.), v(s, h, s), v(s, 0., s)],
        DVec3::NEG_X,
    );
    b.object("lamp");
    let (lx, ly, lz) = (2.5, h - 0.01, 2.5);
    let lamp_quad = [
        v(lx - 0.5, ly, lz - 0.5),
        v(lx + 0.5, ly, lz - 0.5),
        v(lx + 0.5, ly, lz + 0.5),
        v(lx - 0.5, ly, lz + 0.5),
    ];
    face(&mut b, lamp, lamp_quad, DVec3::NEG_Y);
    let (c, foot, height) = LOW;
    let half = foot / 2.0;
    standing_box(
        &mut b,
        grey,
        v(c - half, 0., c - half),
        v(c + half, height, c + half),
        "low",
    );
    if tall {
        let z0 = c + half + GAP;
        let half = TALL.0 / 2.0;
        standing_box(
            &mut b,
            grey,
            v(c - half, 0., z0),
            v(c + half, TALL.1, z0 + TALL.0),
            "tall",
        );
    }
    b.build().unwrap()
}

fn with_patches(patch: f64) -> Settings {
    Settings {
        patch_size: Some(patch),
        ..Settings::default()
    }
}

fn with_refine(refine: RefineSettings) -> Settings {
    Settings {
        refine,
        ..with_patches(PATCH)
    }
}

/// The settings compared, each against the same reference.
fn settings() -> Vec<(&'static str, Settings)> {
    vec![
        ("defaults", with_patches(PATCH)),
        (
            "4 shaped",
            Settings {
                shaped_gathers: Some(4),
                ..with_patches(PATCH)
            },
        ),
        (
            "no part views",
            Settings {
                part_views: Some(false),
                ..with_patches(PATCH)
            },
        ),
        (
            "centre",
            Settings {
                emitter_sampling: radiosity::formfactor::EmitterSampling::Centre,
                ..with_patches(PATCH)
            },
        ),
        (
            "depth 6",
            with_refine(RefineSettings {
                max_depth: 6,
                ..RefineSettings::default()
            }),
        ),
        (
            "sources 0.1",
            with_refine(RefineSettings {
                source_tolerance: Some(0.1),
                ..RefineSettings::default()
            }),
        ),
        ("patch 1 m", with_patches(1.0)),
        ("patch 0.5 m", with_patches(0.5)),
    ]
}

/// Defaults with 0, 1, 2, 3, 4 and 8 shaped gathers.
fn shaped_sweep() -> Vec<(&'static str, Settings)> {
    [
        ("0 shaped", 0),
        ("1 shaped", 1),
        ("2 shaped", 2),
        ("3 shaped", 3),
        ("4 shaped", 4),
        ("8 shaped", 8),
    ]
    .into_iter()
    .map(|(name, n)| {
        (
            name,
            Settings {
                shaped_gathers: Some(n),
                ..with_patches(PATCH)
            },
        )
    })
    .collect()
}

/// Points on the low box's gap side, the gap's floor, the floor behind the
/// tall box and the tall box's gap side, by surface index in `scene`'s
/// order (floor 0; the low box's faces 7 to 11; the tall box's 12 to 16).
fn probe_points() -> Vec<(&'static str, SurfacePoint)> {
    let (c, foot, _) = LOW;
    let side = c + foot / 2.0;
    let far = side + GAP;
    let mut points = Vec::new();
    let mut add = |name, surface, position, normal| {
        points.push((
            name,
            SurfacePoint {
                surface,
                position,
                normal,
            },
        ));
    };
    for y in [0.05, 0.15, 0.25, 0.35, 0.45] {
        add("low gap side", 11, v(c, y, side), DVec3::Z);
    }
    for t in [0.1, 0.25, 0.5, 0.75, 0.9] {
        add("gap floor", 0, v(c, 0.0, side + t * GAP), DVec3::Y);
    }
    for d in [0.1, 0.4, 0.7, 1.1] {
        add("floor behind", 0, v(c, 0.0, far + TALL.0 + d), DVec3::Y);
    }
    for y in [0.05, 0.2, 0.4, 0.6, 0.8, 1.0] {
        add("tall gap side", 15, v(c, y, far), DVec3::NEG_Z);
    }
    points
}

fn percent(value: f64, reference: f64) -> f64 {
    (value / reference - 1.0) * 100.0
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let points = args.iter().any(|a| a == "--points");
    let tall = !args.iter().any(|a| a == "--no-tall");
    let floor_reflectance = args
        .iter()
        .position(|a| a == "--floor-reflectance")
        .and_then(|i| args.get(i + 1))
        .map_or(0.7, |r| r.parse().expect("a reflectance"));
    if points && !tall {
        eprintln!("--points needs the tall box");
        std::process::exit(2);
    }
    let scene = scene(tall, floor_reflectance);
    let reference = Reference::new(&scene).unwrap();
    let paths = |paths, seed| ReferenceSettings {
        paths,
        seed,
        ..ReferenceSettings::default()
    };
    let settings = if args.iter().any(|a| a == "--shaped-sweep") {
        shaped_sweep()
    } else {
        settings()
    };
    let solutions: Vec<_> = settings
        .iter()
        .map(|(_, s)| radiosity::solve(&scene, s, &|_| {}).unwrap())
        .collect();
    print!("{:<15}", if points { "point" } else { "object" });
    for (name, _) in &settings {
        print!(" {name:>11}");
    }
    println!("   reference (standard error)");
    if points {
        let probes = probe_points();
        let at: Vec<SurfacePoint> = probes.iter().map(|p| p.1).collect();
        let truth = reference.radiosity_at(&at, &paths(200_000, 5)).unwrap();
        for ((name, p), truth) in probes.iter().zip(&truth) {
            print!("{name:<15}");
            for s in &solutions {
                let got = s.probe().radiosity_at(p.position, p.normal);
                print!(
                    " {:>+10.1}%",
                    percent(got.map_or(f64::NAN, |g| g[0]), truth.radiosity[0])
                );
            }
            let (r, e) = (truth.radiosity[0], truth.std_error[0]);
            println!(
                "   {r:.4} ({:.1}%) at {:.2?}",
                e / r * 100.0,
                p.position.to_array()
            );
        }
        return;
    }
    let truth = reference.object_means(&paths(200_000, 3)).unwrap();
    let means: Vec<_> = solutions
        .iter()
        .map(|s| s.object_radiosity(&scene))
        .collect();
    for (i, object) in scene.objects.iter().enumerate() {
        if object.name == "lamp" || truth[i].radiosity[0] <= 0.0 {
            continue;
        }
        print!("{:<15}", object.name);
        for m in &means {
            print!(
                " {:>+10.2}%",
                percent(m[i].radiosity[0], truth[i].radiosity[0])
            );
        }
        let (r, e) = (truth[i].radiosity[0], truth[i].std_error[0]);
        println!("   {r:.4} ({:.2}%)", e / r * 100.0);
    }
}
