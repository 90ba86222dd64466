//! A logo of many small coplanar triangles in a closed room (issue 18): the
//! word RADIOSITY as a decal 1 mm in front of the back wall, and the word LUX
//! lying 1 mm above the floor under the lamp, each letter drawn from a 5 x 7
//! pixel font whose pixels are split into triangles of mixed sizes and
//! shapes, and underlined by a bar of long slivers. Such a decal is
//! thousands of triangles far smaller than a patch, all in one plane, in
//! front of a surface it hides: the room must see all of it (reciprocity),
//! the surface under it must see only its back, the room must keep its
//! energy balance, and the per-object error against the path tracer must
//! fall as the user makes patches smaller.

use super::common::lamp_room;
use glam::{DVec2, DVec3};
use radiosity::math::Rgb;
use radiosity::reference::{ProbeEstimate, Reference, ReferenceSettings};
use radiosity::scene::{Scene, SceneBuilder};
use radiosity::{Settings, Solution};
use std::sync::OnceLock;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

const ROOM: f64 = 2.0;
/// How far the decals stand off the wall and floor: enough not to be
/// coplanar with them, as a modeller places a decal to avoid z-fighting.
const GAP: f64 = 0.001;
/// Lattice steps along each font pixel's edge. Every pixel puts the same
/// vertices on its edges, so neighbouring pixels meet edge to edge (no
/// T-junctions), as an exported mesh does; only the insides differ.
const STEPS: i64 = 4;

/// 5 x 7 glyphs, top row first.
fn glyph(letter: char) -> [&'static str; 7] {
    match letter {
        'R' => [
            "####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#",
        ],
        'A' => [
            ".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#",
        ],
        'D' => [
            "####.", "#...#", "#...#", "#...#", "#...#", "#...#", "####.",
        ],
        'I' => [
            ".###.", "..#..", "..#..", "..#..", "..#..", "..#..", ".###.",
        ],
        'O' => [
            ".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###.",
        ],
        'S' => [
            ".####", "#....", "#....", ".###.", "....#", "....#", "####.",
        ],
        'T' => [
            "#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#..",
        ],
        'Y' => [
            "#...#", "#...#", ".#.#.", "..#..", "..#..", "..#..", "..#..",
        ],
        'L' => [
            "#....", "#....", "#....", "#....", "#....", "#....", "#####",
        ],
        'U' => [
            "#...#", "#...#", "#...#", "#...#", "#...#", "#...#", ".###.",
        ],
        'X' => [
            "#...#", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "#...#",
        ],
        _ => panic!("no glyph for {letter}"),
    }
}

/// Where a word lies: `origin + a * right + b * up` for plane coordinates
/// `(a, b)` in metres; the decal faces `right x up`.
struct Plane {
    origin: DVec3,
    right: DVec3,
    up: DVec3,
}

impl Plane {
    fn at(&self, p: DVec2) -> DVec3 {
        self.origin + p.x * self.right + p.y * self.up
    }

    /// Adds triangle `t` (plane coordinates) turned to face the plane's
    /// front, whichever way round it was listed.
    fn triangle(&self, b: &mut SceneBuilder, material: u32, t: [DVec2; 3]) {
        let turn = (t[1] - t[0]).perp_dot(t[2] - t[0]);
        assert!(turn.abs() > 1e-12, "degenerate triangle {t:?}");
        let [p, q, r] = t.map(|p| self.at(p));
        if turn > 0.0 {
            b.triangle(material, p, q, r).unwrap();
        } else {
            b.triangle(material, p, r, q).unwrap();
        }
    }
}

/// Adds the font pixel whose lower-left lattice point is `(i, j)` (in
/// steps of `step` metres) as triangles; `style` picks one of three
/// triangulations, so the word mixes sizes and shapes. Returns how many.
fn pixel(
    b: &mut SceneBuilder,
    m: u32,
    plane: &Plane,
    step: f64,
    i: i64,
    j: i64,
    style: u32,
) -> usize {
    // Plane coordinates from integer lattice points, so a vertex two pixels
    // share is the same bits in both.
    let at = |x: i64, y: i64| DVec2::new(x as f64 * step, y as f64 * step);
    // The pixel's boundary, counter-clockwise from its lower-left corner,
    // STEPS segments a side.
    let mut ring = Vec::new();
    for k in 0..STEPS {
        ring.push(at(i + k, j));
    }
    for k in 0..STEPS {
        ring.push(at(i + STEPS, j + k));
    }
    for k in 0..STEPS {
        ring.push(at(i + STEPS - k, j + STEPS));
    }
    for k in 0..STEPS {
        ring.push(at(i, j + STEPS - k));
    }
    let n = ring.len();
    match style {
        // A grid of STEPS x STEPS cells, two triangles each: the smallest.
        0 | 1 => {
            for y in 0..STEPS {
                for x in 0..STEPS {
                    let (a, c) = (at(i + x, j + y), at(i + x + 1, j + y + 1));
                    let (bb, d) = (at(i + x + 1, j + y), at(i + x, j + y + 1));
                    // Alternate the diagonal, as a mesher's output does.
                    if (x + y) % 2 == 0 {
                        plane.triangle(b, m, [a, bb, c]);
                        plane.triangle(b, m, [a, c, d]);
                    } else {
                        plane.triangle(b, m, [a, bb, d]);
                        plane.triangle(b, m, [bb, c, d]);
                    }
                }
            }
            (2 * STEPS * STEPS) as usize
        }
        // A fan from the centre to every boundary vertex: mid-sized.
        2 => {
            let centre = at(i + STEPS / 2, j + STEPS / 2);
            for k in 0..n {
                plane.triangle(b, m, [centre, ring[k], ring[(k + 1) % n]]);
            }
            n
        }
        // A fan from the lower-left corner to the two far edges: slivers
        // with an aspect of up to about STEPS, the largest triangles. The
        // corner's own edges keep their vertices through small fans from
        // the first vertex off each of them.
        _ => {
            let s = STEPS as usize;
            let (right, top) = (s + 1, 3 * s - 1);
            for k in 0..s {
                plane.triangle(b, m, [ring[right], ring[k], ring[k + 1]]);
            }
            for k in right..top {
                plane.triangle(b, m, [ring[0], ring[k], ring[k + 1]]);
            }
            for k in 3 * s..n {
                plane.triangle(b, m, [ring[top], ring[k], ring[(k + 1) % n]]);
            }
            n - 2
        }
    }
}

/// Adds `text` in `plane`, each font pixel `size` metres across, and a bar
/// below it cut into `pieces` equal parts, each split along its diagonal
/// into two slivers, as exporters leave them. Returns the triangle count
/// and the area the triangles should cover.
fn word(
    b: &mut SceneBuilder,
    m: u32,
    plane: &Plane,
    text: &str,
    size: f64,
    pieces: usize,
) -> (usize, f64) {
    let step = size / STEPS as f64;
    let (mut count, mut pixels) = (0, 0);
    for (n, letter) in text.chars().enumerate() {
        for (row, line) in glyph(letter).iter().enumerate() {
            for (col, c) in line.chars().enumerate() {
                if c != '#' {
                    continue;
                }
                let (col, up) = ((6 * n + col) as i64, (6 - row) as i64);
                // A fixed scramble of the position: half grids, a quarter
                // each of centre and corner fans.
                let style = ((col * 7 + up * 3 + n as i64) % 4) as u32;
                count += pixel(b, m, plane, step, col * STEPS, up * STEPS, style);
                pixels += 1;
            }
        }
    }
    let length = (6 * text.len() - 1) as f64 * size;
    let (low, high) = (-1.6 * size, -size);
    for k in 0..pieces {
        let x0 = length * k as f64 / pieces as f64;
        let x1 = length * (k + 1) as f64 / pieces as f64;
        let corners = [
            DVec2::new(x0, low),
            DVec2::new(x1, low),
            DVec2::new(x1, high),
            DVec2::new(x0, high),
        ];
        plane.triangle(b, m, [corners[0], corners[1], corners[2]]);
        plane.triangle(b, m, [corners[0], corners[2], corners[3]]);
    }
    let area = f64::from(pixels) * size * size + length * (high - low);
    (count + 2 * pieces, area)
}

/// A closed 2 m room (one blue wall), a 0.4 m lamp 1 mm under the ceiling,
/// RADIOSITY 1 mm in front of the back wall and LUX 1 mm above the floor
/// under the lamp. Also returns the two logos' triangle counts and areas.
fn logo_room() -> (Scene, [(usize, f64); 2]) {
    let w = ROOM;
    let mut b = lamp_room("logo mesh", Rgb::new(0.15, 0.3, 0.7));
    let gold = b
        .material("gold", Rgb::new(0.8, 0.6, 0.1), Rgb::ZERO)
        .unwrap();
    let green = b
        .material("green", Rgb::new(0.2, 0.65, 0.3), Rgb::ZERO)
        .unwrap();
    // RADIOSITY: 53 pixels of 3.2 cm, 1.70 m by 0.22 m, centred across the
    // back wall at about eye height, facing into the room (+z).
    b.object("logo");
    let size = 0.032;
    let on_wall = Plane {
        origin: v(0.5 * (w - 53.0 * size), 0.9, GAP),
        right: DVec3::X,
        up: DVec3::Y,
    };
    // The bar in nine parts, slivers of aspect 10 and 20: the lattice cuts
    // a triangle into (longest edge / patch size)^2 patches, so whole-length
    // slivers cost more than all the letters (a fan of 28 made 1 900 of the
    // logo's 2 400 patches at a patch size of 0.125 m and tripled the
    // solve's time).
    let logo = word(&mut b, gold, &on_wall, "RADIOSITY", size, 9);
    // LUX: 17 pixels of 5 cm, 0.85 m by 0.35 m, centred under the lamp,
    // read from the front wall and facing up (+x cross -z = +y).
    b.object("floor_logo");
    let size = 0.05;
    let on_floor = Plane {
        origin: v(0.5 * (w - 17.0 * size), GAP, 0.5 * (w + 7.0 * size)),
        right: DVec3::X,
        up: DVec3::NEG_Z,
    };
    // The bar whole: two slivers of 0.85 m, aspect 30 and 60, far longer
    // than a patch.
    let floor_logo = word(&mut b, green, &on_floor, "LUX", size, 1);
    (b.build().unwrap(), [logo, floor_logo])
}

/// The decals and the surfaces they lie on.
const DECALS: [(&str, &str); 2] = [("logo", "wall_back"), ("floor_logo", "floor")];

fn object_id(scene: &Scene, name: &str) -> u32 {
    scene.objects.iter().position(|o| o.name == name).unwrap() as u32
}

/// Per object of `scene`: its area, the leaves' total of `A_e F_eq` over
/// its patches `q` (how much of it the room sees) and its leaves' total of
/// `A_e` times their row sums (how much of the room it sees, back faces
/// left out), the last two divided by the area.
fn views(scene: &Scene, sol: &Solution) -> Vec<(f64, f64, f64)> {
    let object_of = |surface: u32| scene.surfaces[surface as usize].object as usize;
    let patch_object: Vec<usize> = sol
        .mesh()
        .patches()
        .iter()
        .map(|p| object_of(p.surface()))
        .collect();
    let mut out = vec![(0.0, 0.0, 0.0); scene.objects.len()];
    for leaf in sol.leaves() {
        let o = &mut out[object_of(leaf.surface())];
        o.0 += leaf.area();
        o.2 += leaf.area() * leaf.row_sum();
        for &(q, f) in leaf.entries() {
            out[patch_object[q as usize]].1 += leaf.area() * f64::from(f);
        }
    }
    out.iter()
        .map(|&(a, seen, sees)| (a, seen / a, sees / a))
        .collect()
}

/// The scene solved at default settings, shared by the tests that look at
/// it.
fn default_solution() -> &'static (Scene, Solution) {
    static SHARED: OnceLock<(Scene, Solution)> = OnceLock::new();
    SHARED.get_or_init(|| {
        let (scene, _) = logo_room();
        let sol = radiosity::solve(&scene, &Settings::default(), &|_| {}).unwrap();
        for w in scene.warnings.iter().chain(&sol.stats().warnings) {
            eprintln!("warning at default settings: {w}");
        }
        for (o, (area, seen, sees)) in scene.objects.iter().zip(views(&scene, &sol)) {
            eprintln!(
                "default settings, {}: area {area:.4}, the room sees {seen:.4} of it, \
                 it sees {sees:.4} of the room",
                o.name
            );
        }
        (scene, sol)
    })
}

/// The scene and its path-traced object means, traced once for the tests
/// that share them.
fn room_and_reference() -> &'static (Scene, Vec<ProbeEstimate>) {
    static SHARED: OnceLock<(Scene, Vec<ProbeEstimate>)> = OnceLock::new();
    SHARED.get_or_init(|| {
        let (scene, _) = logo_room();
        let reference = Reference::new(&scene)
            .unwrap()
            .object_means(&ReferenceSettings {
                paths: 400_000,
                seed: 29,
                ..ReferenceSettings::default()
            })
            .unwrap();
        for (o, r) in scene.objects.iter().zip(&reference) {
            let relative = [0, 1, 2].map(|k| r.std_error.0[k] / r.radiosity.0[k]);
            eprintln!(
                "reference {}: {:.4?}, relative standard error {relative:.5?}",
                o.name, r.radiosity.0
            );
        }
        (scene, reference)
    })
}

/// One patch size's solution against the path tracer.
#[derive(Debug)]
struct Level {
    patch_size: f64,
    /// Mean and worst relative error of the object means, over objects
    /// (but the lamp) and bands.
    mean: f64,
    worst: f64,
    /// What [`views`] says of the solution.
    views: Vec<(f64, f64, f64)>,
}

/// The scene solved at each of [`PATCH_SIZES`] with `shaped_gathers`
/// shaped gathers (`None`: the default), and compared with the path tracer.
fn levels(shaped_gathers: Option<usize>) -> Vec<Level> {
    let (scene, reference) = room_and_reference();
    let mut levels = Vec::new();
    for patch_size in PATCH_SIZES {
        let settings = Settings {
            patch_size: Some(patch_size),
            shaped_gathers,
            ..Settings::default()
        };
        let sol = radiosity::solve(scene, &settings, &|_| {}).unwrap();
        let stats = sol.stats();
        for w in &stats.warnings {
            eprintln!("warning at patch size {patch_size}: {w}");
        }
        let (mut sum, mut worst, mut n, mut worst_at) = (0.0, 0.0f64, 0, String::new());
        for (o, r) in sol.object_radiosity(scene).iter().zip(reference) {
            if o.name == "lamp" {
                continue;
            }
            let mut signed = [0.0; 3];
            for (band, e) in signed.iter_mut().enumerate() {
                *e = o.radiosity.0[band] / r.radiosity.0[band] - 1.0;
                sum += e.abs();
                if e.abs() > worst {
                    worst = e.abs();
                    worst_at = format!("{} band {band}", o.name);
                }
                n += 1;
            }
            eprintln!(
                "  shaped {shaped_gathers:?}, patch size {patch_size}, {}: {signed:+.4?}",
                o.name
            );
        }
        let mean = sum / f64::from(n);
        eprintln!(
            "shaped {shaped_gathers:?}, patch size {patch_size}: mean error {mean:.4}, \
             worst {worst:.4} ({worst_at}); {} patches, {} elements, {:.1} s, energy {:.1e}",
            stats.patches, stats.elements, stats.seconds.total, stats.energy.relative_difference
        );
        levels.push(Level {
            patch_size,
            mean,
            worst,
            views: views(scene, &sol),
        });
    }
    levels
}

/// [`levels`] at default settings, solved once for the tests that share
/// them.
fn default_levels() -> &'static [Level] {
    static SHARED: OnceLock<Vec<Level>> = OnceLock::new();
    SHARED.get_or_init(|| levels(None))
}

const PATCH_SIZES: [f64; 3] = [0.5, 0.25, 0.125];

/// Every level's mean error within the issue's 0.5%. The reference's
/// standard errors are 0.07% to 0.19% per object and band, so levels whose
/// errors differ by less than that cannot be put in order.
const MEAN_BOUND: f64 = 0.005;

/// Every level within the issue's bounds against the path tracer:
/// [`MEAN_BOUND`] mean and 1.5% worst. Measured with contacts matched in
/// the surface's slab: 0.26%, 0.11%, 0.18% mean and 0.71%, 0.23%, 0.39%
/// worst at 0.5, 0.25 and 0.125 m. Before, when the floor under the floor
/// logo counted as lit at the coarser levels (see the test on the surfaces
/// under the logos): 1.08%, 1.71%, 0.25% mean and 3.4%, 2.4%, 0.56% worst.
fn assert_converges(levels: &[Level]) {
    let errors: Vec<(f64, f64, f64)> = levels
        .iter()
        .map(|l| (l.patch_size, l.mean, l.worst))
        .collect();
    for &(size, mean, worst) in &errors {
        assert!(mean < MEAN_BOUND, "patch size {size} mean: {errors:?}");
        assert!(worst < 0.015, "patch size {size} worst: {errors:?}");
    }
}

#[test]
fn the_logos_tile_their_glyphs() {
    // The test's own geometry: the triangles cover the glyphs without gaps
    // or overlaps (equal area, all facing out of their plane), and the
    // scene builder neither merged nor split any as an overlap.
    let (scene, logos) = logo_room();
    for ((count, area), (name, _)) in logos.into_iter().zip(DECALS) {
        let id = object_id(&scene, name);
        let mine: Vec<_> = scene.surfaces.iter().filter(|s| s.object == id).collect();
        let total: f64 = mine.iter().map(|s| s.area).sum();
        eprintln!("{name}: {count} triangles, {total:.5} m^2");
        assert_eq!(mine.len(), count, "{name}");
        assert!(
            (total / area - 1.0).abs() < 1e-9,
            "{name}: {total} vs {area}"
        );
        assert!(mine
            .iter()
            .all(|s| s.normal.dot(mine[0].normal) > 0.999_999));
    }
}

#[test]
fn a_room_with_logos_keeps_its_energy_balance() {
    // Closed, so all light emitted is absorbed. Measured -0.61% while the
    // level of detail lost part of the decals (see the next test); -4e-5
    // since.
    let (_, sol) = default_solution();
    let energy = sol.stats().energy.relative_difference;
    eprintln!("energy relative difference at default settings {energy:.2e}");
    assert!(energy.abs() < 1e-3, "energy {energy}");
}

#[test]
fn the_room_sees_as_much_of_each_logo_as_the_logo_sees_of_the_room() {
    // Every logo facet's row sums to 1 (it faces a closed room), so by
    // reciprocity the room's rows hold the logo's whole area. Measured: the
    // room saw 65% of each logo when hemi-cubes drew its far subtrees as
    // one sample each (`level_of_detail`, the default) and counted every
    // sample falling in one pixel as a pixel covered, testing each at its
    // box's centre depth against the wall 1 mm behind; 100.5% and 100.1%
    // without level of detail. With those fixed, 94.4% and 95.6%: the rest
    // is open, and this bound guards what the fixes brought.
    let (scene, sol) = default_solution();
    let views = views(scene, sol);
    for (name, _) in DECALS {
        let (_, seen, sees) = views[object_id(scene, name) as usize];
        assert!((sees - 1.0).abs() < 1e-3, "{name} sees {sees}");
        assert!(
            (seen - 1.0).abs() < 0.07,
            "the room sees {seen} of the {name}"
        );
    }
}

#[test]
fn the_surfaces_under_the_logos_see_only_their_backs() {
    // The part of the wall (floor) 1 mm behind a decal sees the decal's
    // back faces, and nothing else but through the 1 mm slit round it, so
    // at every patch size the surface's rows sum to the share the decal
    // leaves free (the room then sees that much of the surface). Measured
    // while contacts were matched to an element within a slab of its own
    // size (0.1 to 0.5 mm), not the surface's (2 mm): the floor's sum 1.000
    // at 0.5 and 0.25 m, every element centre there falling between the
    // letters of LUX and no element flagged as partly covered.
    let (scene, _) = room_and_reference();
    let mut wrong = Vec::new();
    for level in default_levels() {
        for (decal, under) in DECALS {
            let decal_area = level.views[object_id(scene, decal) as usize].0;
            let (area, _, sees) = level.views[object_id(scene, under) as usize];
            let free = 1.0 - decal_area / area;
            let size = level.patch_size;
            eprintln!("patch size {size}: {under} sees {sees:.4}, {free:.4} free");
            if (sees - free).abs() > 0.005 {
                wrong.push(format!(
                    "patch size {size}: {under} sees {sees:.4}, {free:.4} free"
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{wrong:?}");
}

#[test]
fn every_level_is_within_the_issues_bounds_against_the_path_tracer() {
    assert_converges(default_levels());
}

#[test]
#[ignore = "measured for the record (50 s more): within the bounds like the default"]
fn patch_means_around_logos() {
    assert_converges(&levels(Some(0)));
}
