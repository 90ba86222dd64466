//! Probes: radiosity at points, as the renderer interpolates it, from the
//! library (`Solution::probe`) and from `radiosity probe`.

use super::penumbra_metrics::light_on_value;
use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::mesh::HIDDEN_WEIGHT;
use radiosity::refine::RefineSettings;
use radiosity::scene::Scene;
use radiosity::scenes::{self, penumbra};
use radiosity::solution::{ProbeTolerance, Solution};
use radiosity::Settings;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Cornell box settings for the probe tests: 10 cm patches split once, a
/// uniform mesh (no T-vertices), small hemi-cubes. The CLI runs get the same
/// through [`CORNELL_FLAGS`].
fn cornell_settings() -> Settings {
    Settings {
        patch_size: Some(0.1),
        hemicube_resolution: 64,
        refine: RefineSettings {
            uniform_depth: Some(1),
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}
const CORNELL_FLAGS: [&str; 6] = [
    "--patch-size",
    "0.1",
    "--hemicube-res",
    "64",
    "--uniform-depth",
    "1",
];

/// The penumbra settings of the regression (adaptive: T-vertices appear).
fn penumbra_settings() -> Settings {
    Settings {
        patch_size: Some(1.0),
        refine: RefineSettings {
            tolerance: 0.05,
            max_depth: 4,
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}
const PENUMBRA_FLAGS: [&str; 6] = [
    "--patch-size",
    "1",
    "--max-depth",
    "4",
    "--refine-tolerance",
    "0.05",
];

fn solve(scene: &Scene, settings: &Settings) -> Solution {
    radiosity::solve(scene, settings, &|_| {}).unwrap()
}

/// One floor leaf of a solution: its corners (world), its weight in the
/// means at its vertices (its area where it can be seen, next to nothing
/// where it cannot: the boxes stand on the floor) and the value it shows
/// (its visible part's radiosity).
struct Leaf {
    surface: u32,
    corners: Vec<DVec3>,
    area: f64,
    value: Rgb,
}

fn floor_leaves(scene: &Scene, sol: &Solution) -> Vec<Leaf> {
    let floor = scene
        .objects
        .iter()
        .position(|o| o.name == "floor")
        .unwrap() as u32;
    sol.mesh()
        .leaves()
        .into_iter()
        .filter_map(|k| {
            let e = &sol.mesh()[k];
            let lattice = &sol.mesh().surfaces()[e.surface() as usize];
            let leaf = sol.leaf(k);
            (lattice.object == floor).then(|| Leaf {
                surface: e.surface(),
                corners: lattice.polygon(&e.cell()).to_vec(),
                area: e.area() * leaf.visible().max(HIDDEN_WEIGHT),
                value: leaf.visible_radiosity(),
            })
        })
        .collect()
}

fn close(a: Rgb, b: Rgb, scale: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-12 * scale.max(1e-300))
}

/// On a uniform mesh the renderer's vertex value is the area-weighted mean of
/// the elements that share the vertex, and the centre of an element's fan is
/// the mean of its corners. Recomputed here from the element values alone, by
/// matching corner positions, the probe must read exactly that at every floor
/// vertex and element centre; and at a centre it lies within the values of
/// the element and its neighbours.
#[test]
fn probes_on_the_cornell_floor_agree_with_the_element_values() {
    let scene = scenes::cornell_box();
    let sol = solve(&scene, &cornell_settings());
    let leaves = floor_leaves(&scene, &sol);
    assert!(leaves.len() >= 100, "{} floor leaves", leaves.len());
    let prober = sol.probe();
    let scale = leaves
        .iter()
        .map(|l| l.value.max_band())
        .fold(0.0, f64::max);
    let touching = |p: DVec3, surface: u32| -> Vec<&Leaf> {
        leaves
            .iter()
            .filter(|l| l.surface == surface && l.corners.iter().any(|c| (*c - p).length() < 1e-12))
            .collect()
    };
    for leaf in &leaves {
        let mut corner_values = Vec::new();
        for &c in &leaf.corners {
            let around = touching(c, leaf.surface);
            let area: f64 = around.iter().map(|l| l.area).sum();
            let expected = around.iter().fold(Rgb::ZERO, |s, l| s + l.value * l.area) / area;
            let hit = prober
                .hit(c, DVec3::Y)
                .expect("a floor vertex is on the floor");
            assert_eq!(hit.surface, leaf.surface);
            assert!(
                close(hit.radiosity, expected, scale),
                "vertex {c}: probe {:?}, mean of {} elements {expected:?}",
                hit.radiosity,
                around.len()
            );
            corner_values.push(expected);
        }
        let centre = leaf.corners.iter().copied().sum::<DVec3>() / leaf.corners.len() as f64;
        let expected =
            corner_values.iter().fold(Rgb::ZERO, |s, v| s + *v) / corner_values.len() as f64;
        let read = sol.radiosity_at(centre, DVec3::Y).unwrap();
        assert!(
            close(read, expected, scale),
            "centre {centre}: {read:?} vs {expected:?}"
        );
        let neighbours: Vec<&Leaf> = leaf
            .corners
            .iter()
            .flat_map(|c| touching(*c, leaf.surface))
            .collect();
        for k in 0..3 {
            let lo = neighbours
                .iter()
                .map(|l| l.value[k])
                .fold(f64::INFINITY, f64::min);
            let hi = neighbours.iter().map(|l| l.value[k]).fold(0.0, f64::max);
            assert!(
                read[k] >= lo - 1e-12 * scale && read[k] <= hi + 1e-12 * scale,
                "centre {centre} band {k}: {} outside the neighbours' [{lo}, {hi}]",
                read[k]
            );
        }
    }
}

/// On an adaptive mesh with T-vertices, a probe inside any triangle of
/// `Solution::shading_mesh` (what the renderer draws) reads the linear
/// interpolation of that triangle's vertex values.
#[test]
fn probes_read_the_shading_mesh_the_renderer_draws() {
    let spec = penumbra::penumbra_parallel();
    let scene = spec.scene().unwrap();
    let sol = solve(&scene, &penumbra_settings());
    let vertices = sol.vertex_radiosity();
    assert!(!vertices.t_vertices.is_empty(), "the test needs T-vertices");
    let shading = sol.shading_mesh();
    let prober = sol.probe();
    let scale = shading
        .radiosity
        .iter()
        .map(|b| b.max_band())
        .fold(0.0, f64::max);
    for t in &shading.triangles {
        let p = t.map(|i| shading.positions[i as usize]);
        let v = t.map(|i| shading.radiosity[i as usize]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]);
        for w in [[1.0 / 3.0; 3], [0.6, 0.3, 0.1], [0.05, 0.15, 0.8]] {
            let point = p[0] * w[0] + p[1] * w[1] + p[2] * w[2];
            let expected = v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
            let read = prober
                .radiosity_at(point, normal)
                .expect("inside a triangle");
            assert!(
                close(read, expected, scale),
                "at {point}: probe {read:?}, triangle {expected:?}"
            );
        }
    }
}

#[test]
fn probes_off_every_surface_or_facing_away_read_nothing() {
    let scene = scenes::cornell_box();
    let sol = solve(&scene, &cornell_settings());
    let prober = sol.probe();
    let on_floor = DVec3::new(0.3, 0.0, 0.2);
    assert!(prober.radiosity_at(on_floor, DVec3::Y).is_some());
    // Within the default tolerance (1e-4 of the 0.97 m diagonal) of the plane,
    // a probe is moved onto it; beyond, it reads nothing.
    let near = prober.hit(on_floor + DVec3::Y * 2e-5, DVec3::Y).unwrap();
    assert_eq!(near.point.y, 0.0);
    assert!(prober.hit(on_floor + DVec3::Y * 1e-3, DVec3::Y).is_none());
    // The floor faces up: a probe facing down, or tilted past 5 degrees, misses.
    assert!(prober.hit(on_floor, -DVec3::Y).is_none());
    let tilt = |deg: f64| DVec3::new(deg.to_radians().sin(), deg.to_radians().cos(), 0.0);
    assert!(prober.hit(on_floor, tilt(3.0)).is_some());
    assert!(prober.hit(on_floor, tilt(10.0)).is_none());
    // Outside the floor's outline (it ends near x = 0.55 m), and bad input.
    assert!(prober.hit(DVec3::new(0.7, 0.0, 0.2), DVec3::Y).is_none());
    assert!(prober.hit(DVec3::splat(f64::NAN), DVec3::Y).is_none());
    assert!(prober.hit(on_floor, DVec3::ZERO).is_none());
    // A tolerance out of range is refused, naming the setting.
    let bad = ProbeTolerance {
        normal_degrees: 90.0,
        ..ProbeTolerance::default()
    };
    let e = sol.probe_with(bad).unwrap_err();
    assert!(e.to_string().contains("normal_tolerance"), "{e}");
}

fn work_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("probe")
        .join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `radiosity probe` and returns its output rows as fields (header
/// first), failing on a non-zero exit.
fn run_probe(dir: &Path, scene: &str, points: &str, extra: &[&str]) -> Vec<Vec<String>> {
    let input = dir.join("points.csv");
    let output = dir.join("out.csv");
    std::fs::write(&input, points).unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(["probe", scene, "--quiet", "--threads", "2", "--points"])
        .arg(&input)
        .arg("--output")
        .arg(&output)
        .args(extra)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    std::fs::read_to_string(&output)
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

fn number(s: &str) -> f64 {
    s.parse()
        .unwrap_or_else(|_| panic!("'{s}' is not a number"))
}

fn csv_line(p: DVec3, n: DVec3) -> String {
    format!("{},{},{},{},{},{}\n", p.x, p.y, p.z, n.x, n.y, n.z)
}

/// The CLI on the Cornell box floor reads what the library reads (the same
/// settings give the same bits), which the library test above ties to the
/// element values; radiance is radiosity over pi; a point on no surface gets
/// an error row.
#[test]
fn probe_command_on_the_cornell_floor_matches_the_library() {
    let scene = scenes::cornell_box();
    let sol = solve(&scene, &cornell_settings());
    let leaves = floor_leaves(&scene, &sol);
    let mut points: Vec<DVec3> = Vec::new();
    for leaf in leaves.iter().step_by(7) {
        points.push(leaf.corners[0]);
        points.push(leaf.corners.iter().copied().sum::<DVec3>() / 4.0);
    }
    let mut text = String::from("x,y,z,nx,ny,nz\n");
    for p in &points {
        text += &csv_line(*p, DVec3::Y);
    }
    text += &csv_line(DVec3::new(0.3, 0.25, 0.2), DVec3::Y);
    let rows = run_probe(&work_dir("cornell"), "cornell_box", &text, &CORNELL_FLAGS);
    assert_eq!(rows[0].len(), 13);
    assert_eq!(rows[0][6], "radiosity_r");
    assert_eq!(rows.len(), points.len() + 2);
    let prober = sol.probe();
    for (p, row) in points.iter().zip(&rows[1..]) {
        let expected = prober.radiosity_at(*p, DVec3::Y).unwrap();
        for k in 0..3 {
            assert_eq!(number(&row[6 + k]), expected[k], "{p} band {k}");
            assert_eq!(
                number(&row[9 + k]),
                expected[k] / std::f64::consts::PI,
                "{p} band {k}"
            );
        }
        assert_eq!(row[12], "ok");
    }
    let miss = rows.last().unwrap();
    assert!(miss[6..12].iter().all(String::is_empty), "{miss:?}");
    assert!(miss[12].starts_with("error"), "{miss:?}");
}

/// With `--exact` on a penumbra scene the CLI adds the oracle's radiosity at
/// each floor point (and nothing for points off the floor); the solution it
/// reads is close to it.
#[test]
fn probe_command_writes_the_oracle_on_a_penumbra_scene() {
    let spec = penumbra::penumbra_parallel();
    let light_on = light_on_value(&spec);
    let mut floor_points = Vec::new();
    for x in [-1.75, -1.0, -0.5, -0.2, 0.0, 0.3, 0.5, 1.0, 1.9] {
        for z in [-1.2, 0.0, 0.35] {
            floor_points.push(DVec3::new(x, 0.0, z));
        }
    }
    let mut text = String::new();
    for p in &floor_points {
        text += &csv_line(*p, DVec3::Y);
    }
    // The occluder's underside: on a surface, but not on the floor.
    text += &csv_line(DVec3::new(0.5, 1.5, 0.0), -DVec3::Y);
    let mut flags = vec!["--exact"];
    flags.extend(PENUMBRA_FLAGS);
    let rows = run_probe(&work_dir("penumbra"), "penumbra_parallel", &text, &flags);
    assert_eq!(rows[0].len(), 16);
    assert_eq!(rows[0][12], "exact_radiosity_r");
    assert_eq!(rows.len(), floor_points.len() + 2);
    for (p, row) in floor_points.iter().zip(&rows[1..]) {
        let exact = spec.exact_radiosity(*p).unwrap();
        for k in 0..3 {
            assert_eq!(number(&row[12 + k]), exact[k], "{p} band {k}");
            let solved = number(&row[6 + k]);
            assert!(
                (solved - exact[k]).abs() < 0.05 * light_on,
                "{p}: solved {solved}, exact {}",
                exact[k]
            );
        }
        assert_eq!(row[15], "ok");
    }
    let occluder = rows.last().unwrap();
    assert_eq!(number(&occluder[6]), 0.0);
    assert!(
        occluder[12..15].iter().all(String::is_empty),
        "{occluder:?}"
    );
    assert!(occluder[15].contains("off the floor"), "{occluder:?}");
}

#[test]
fn probe_command_refuses_exact_where_there_is_no_oracle() {
    let dir = work_dir("no_oracle");
    let input = dir.join("points.csv");
    std::fs::write(&input, "0.3,0,0.2,0,1,0\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(["probe", "cornell_box", "--exact", "--quiet", "--points"])
        .arg(&input)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(
        message.contains("--exact needs a built-in penumbra scene"),
        "{message}"
    );
}
