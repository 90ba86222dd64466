//! Where a solution's error comes from, object group by object group: at
//! points spread over objects, the solver's value against a one-bounce
//! gather from the solver's own radiosity (`Reference::gather_at`) and
//! against the path tracer.
//!
//! If the gather agrees with the path tracer but the solver does not, the
//! receivers' own gathers (their rows, the source shapes) are wrong; if the
//! gather is as wrong as the solver, what they see is. Seen surfaces give
//! their visible part's radiosity (`Leaf::visible_radiosity`), since that is
//! what a ray meets.
//!
//! `cargo run --release --example gather_check -- SCENE GROUPS [PATHS
//! [POINTS [OBJECTS]]]`: a built-in scene, comma-separated object-name
//! prefixes (`column,arch,bench`), paths and gather rays per point (default
//! 2 000), points per object (12) and objects per group (6). Points lie on
//! the visible parts; the figures are means over each group's points, split
//! by which way the surfaces face (up, down, sideways).

use radiosity::math::Rgb;
use radiosity::reference::{Reference, ReferenceSettings, SurfacePoint};
use radiosity::scene::Scene;
use radiosity::Settings;

fn grey(c: Rgb) -> f64 {
    (c[0] + c[1] + c[2]) / 3.0
}

/// A generator of uniforms in [0, 1), fixed so that runs repeat.
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `count` points uniform by area over object `object`'s surfaces.
fn points_on(scene: &Scene, object: usize, count: usize, u: &mut Uniform) -> Vec<SurfacePoint> {
    let surfaces: Vec<usize> = (0..scene.surfaces.len())
        .filter(|&i| scene.surfaces[i].object as usize == object)
        .collect();
    let total: f64 = surfaces.iter().map(|&i| scene.surfaces[i].area).sum();
    (0..count)
        .map(|_| {
            let mut left = u.next() * total;
            let mut pick = surfaces[surfaces.len() - 1];
            for &i in &surfaces {
                if left < scene.surfaces[i].area {
                    pick = i;
                    break;
                }
                left -= scene.surfaces[i].area;
            }
            let s = &scene.surfaces[pick];
            let v = &s.vertices;
            let (a, b) = (u.next(), u.next());
            let position = if v.len() == 4 {
                v[0].lerp(v[1], a).lerp(v[3].lerp(v[2], a), b)
            } else {
                let (a, b) = if a + b > 1.0 {
                    (1.0 - a, 1.0 - b)
                } else {
                    (a, b)
                };
                v[0] + (v[1] - v[0]) * a + (v[2] - v[0]) * b
            };
            SurfacePoint {
                surface: pick as u32,
                position,
                normal: s.normal,
            }
        })
        .collect()
}

/// The ways a surface can face, for the table's rows.
const FACINGS: [&str; 3] = ["up", "down", "sideways"];

/// Which way a surface of unit `normal` faces (y is up).
fn facing_of(normal: glam::DVec3) -> &'static str {
    if normal.y > 0.7 {
        FACINGS[0]
    } else if normal.y < -0.7 {
        FACINGS[1]
    } else {
        FACINGS[2]
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: gather_check SCENE GROUPS [PATHS [POINTS [OBJECTS]]]";
    let name = args.first().expect(usage);
    let groups = args.get(1).expect(usage);
    let number = |i: usize, default: usize| {
        args.get(i)
            .map_or(default, |a| a.parse().expect("a whole number"))
    };
    let (paths, per_object, objects) = (number(2, 2_000), number(3, 12), number(4, 6));
    let scene = radiosity::scenes::by_name(name).expect("a built-in scene");
    let solution = radiosity::solve(&scene, &Settings::default(), &|_| {}).expect("solved");
    let prober = solution.probe();
    let reference = Reference::new(&scene).expect("traceable");
    let mut u = Uniform(0x1234_5678_9abc_def0);
    let mut points: Vec<(&str, SurfacePoint)> = Vec::new();
    for group in groups.split(',') {
        let members: Vec<usize> = (0..scene.objects.len())
            .filter(|&o| scene.objects[o].name.starts_with(group))
            .collect();
        let stride = (members.len() / objects.max(1)).max(1);
        for &o in members.iter().step_by(stride).take(objects) {
            points.extend(
                points_on(&scene, o, per_object, &mut u)
                    .into_iter()
                    .map(|p| (group, p)),
            );
        }
    }
    // Only points on visible parts: elsewhere every estimate is about 0.
    let visible = |p: &SurfacePoint| {
        prober
            .hit_on(p.surface, p.position)
            .is_some_and(|h| solution.leaf(h.element).visible() >= 1.0)
    };
    points.retain(|(_, p)| visible(p));
    let at: Vec<SurfacePoint> = points.iter().map(|p| p.1).collect();
    let settings = ReferenceSettings {
        paths: paths as u64,
        ..ReferenceSettings::default()
    };
    let gathered = reference
        .gather_at(&at, &settings, |y| {
            prober
                .hit_on(y.surface, y.position)
                .map(|h| solution.leaf(h.element).visible_radiosity())
        })
        .expect("gathered");
    let traced = reference.radiosity_at(&at, &settings).expect("traced");
    println!(
        "| group | points | solver (leaf) | gather from the solution | solver against the gather |"
    );
    println!("| --- | ---: | ---: | ---: | ---: |");
    let rows = groups
        .split(',')
        .flat_map(|g| FACINGS.iter().map(move |f| (g, *f)));
    for (group, facing) in rows {
        let (mut n, mut solver, mut gather, mut truth) = (0usize, 0.0, 0.0, 0.0);
        for (k, (g, p)) in points.iter().enumerate() {
            if *g != group || facing_of(p.normal) != facing {
                continue;
            }
            let hit = prober
                .hit_on(p.surface, p.position)
                .expect("on its surface");
            n += 1;
            solver += grey(solution.leaf(hit.element).radiosity);
            gather += grey(gathered[k].estimate.radiosity);
            truth += grey(traced[k].radiosity);
        }
        if n == 0 || truth <= 0.0 {
            continue;
        }
        let pct = |x: f64, y: f64| 100.0 * (x / y - 1.0);
        println!(
            "| {group}, {facing} | {n} | {:+.2}% | {:+.2}% | {:+.2}% |",
            pct(solver, truth),
            pct(gather, truth),
            pct(solver, gather)
        );
    }
}
