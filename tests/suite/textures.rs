//! Base-colour textures per element: a checkered floor lit from far above,
//! built in code and read from glTF (KHR_texture_transform, TEXCOORD_1).

use glam::{DVec2, DVec3};
use radiosity::gltf_io::{load_scene, ImportLimits};
use radiosity::math::Rgb;
use radiosity::pipeline::SolverKind;
use radiosity::refine::RefineSettings;
use radiosity::scene::{Scene, SceneBuilder, Texture};
use radiosity::{Settings, Solution};
use std::path::{Path, PathBuf};
use std::sync::Arc;

const DARK: f32 = 0.2;
const BRIGHT: f32 = 0.8;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A 2x2 checker of reflectances 0.2 and 0.8, nearest texel.
fn checker() -> Texture {
    let (d, b) = ([DARK; 3], [BRIGHT; 3]);
    Texture::nearest(2, 2, vec![d, b, b, d])
}

/// A floor `[0, 2]^2` facing up, its texture coordinates `u = x / 2`,
/// `v = z / 2`, under a 0.4 m light 20 m above its centre; `textured` gives
/// it the checker, else its mean reflectance 0.5.
fn checkered_floor(textured: bool) -> Scene {
    let mut b = SceneBuilder::new("checker");
    let mean = f64::from(DARK + BRIGHT) / 2.0;
    let floor = b.material("floor", Rgb::splat(mean), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(1e4)).unwrap();
    b.object("floor");
    b.quad(
        floor,
        v(0., 0., 0.),
        v(0., 0., 2.),
        v(2., 0., 2.),
        v(2., 0., 0.),
    )
    .unwrap();
    b.object("lamp");
    let (lo, hi, h) = (0.8, 1.2, 20.0);
    b.quad(lamp, v(lo, h, lo), v(hi, h, lo), v(hi, h, hi), v(lo, h, hi))
        .unwrap();
    let mut scene = b.build().unwrap();
    if textured {
        scene.materials[floor as usize].base_texture = Some(Arc::new(checker()));
        let uv = [(0., 0.), (0., 1.), (1., 1.), (1., 0.)].map(|(u, v)| DVec2::new(u, v));
        scene.surfaces[0] = scene.surfaces[0].clone().with_uv(&uv);
    }
    scene
}

/// Patches of `patch` metres split `depth` times everywhere.
fn uniform(patch: f64, depth: u8, kind: SolverKind) -> Settings {
    Settings {
        patch_size: Some(patch),
        solver_kind: kind,
        refine: RefineSettings {
            uniform_depth: Some(depth),
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

fn solve(scene: &Scene, settings: &Settings) -> Solution {
    radiosity::solve(scene, settings, &|_| {}).unwrap()
}

/// Whether the checker is bright at floor point (x, z) (u = x / 2, v = z / 2;
/// texel row v, column u; bright off the diagonal).
fn bright_at(x: f64, z: f64) -> bool {
    (x >= 1.0) != (z >= 1.0)
}

#[test]
fn elements_inside_a_square_take_its_texel_and_straddling_ones_the_mean() {
    // 0.5 m patches split twice: no element crosses the checker's edges.
    let sol = solve(
        &checkered_floor(true),
        &uniform(0.5, 2, SolverKind::GaussSeidel),
    );
    let mut floor = 0;
    for leaf in sol.leaves().iter().filter(|l| l.surface() == 0) {
        let c = leaf.centroid();
        let want = if bright_at(c.x, c.z) { BRIGHT } else { DARK };
        assert_eq!(leaf.reflectance(), Rgb::splat(f64::from(want)), "at {c}");
        floor += 1;
    }
    assert_eq!(floor, 256);
    // Thirds of the floor: the middle row and column straddle an edge, half
    // on each side; the corners lie inside one square.
    let sol = solve(
        &checkered_floor(true),
        &uniform(2.0 / 3.0, 0, SolverKind::GaussSeidel),
    );
    for leaf in sol.leaves().iter().filter(|l| l.surface() == 0) {
        let c = leaf.centroid();
        let straddles = (c.x - 1.0).abs() < 0.1 || (c.z - 1.0).abs() < 0.1;
        let rho = leaf.reflectance().0[0];
        if straddles {
            let mean = f64::from(DARK + BRIGHT) / 2.0;
            assert!((rho - mean).abs() < 1e-7, "{rho} at {c}");
        } else {
            let want = if bright_at(c.x, c.z) { BRIGHT } else { DARK };
            assert_eq!(rho, f64::from(want), "at {c}");
        }
    }
}

/// Area-weighted mean radiosity (first band) of the floor's leaves.
fn floor_mean(sol: &Solution) -> f64 {
    let (mut sum, mut area) = (0.0, 0.0);
    for leaf in sol.leaves().iter().filter(|l| l.surface() == 0) {
        sum += leaf.radiosity.0[0] * leaf.area();
        area += leaf.area();
    }
    sum / area
}

#[test]
fn the_checker_keeps_the_floors_light_and_bright_squares_are_four_times_the_dark() {
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let settings = uniform(0.5, 2, kind);
        let textured = solve(&checkered_floor(true), &settings);
        let plain = solve(&checkered_floor(false), &settings);
        let (t, p) = (floor_mean(&textured), floor_mean(&plain));
        eprintln!("{kind:?}: floor mean textured {t:.6}, plain {p:.6}");
        assert!((t / p - 1.0).abs() < 0.01, "{t} vs {p}");
        // An element and its mirror image across x = 1 get the same light
        // from the centred lamp; one is bright, the other dark.
        let leaves = textured.leaves();
        let floor: Vec<_> = leaves.iter().filter(|l| l.surface() == 0).collect();
        let mut worst: f64 = 0.0;
        for a in floor
            .iter()
            .filter(|l| bright_at(l.centroid().x, l.centroid().z))
        {
            let mirror = v(2.0 - a.centroid().x, 0.0, a.centroid().z);
            let b = floor
                .iter()
                .find(|l| (l.centroid() - mirror).length() < 1e-6)
                .expect("mirror element");
            let ratio = a.radiosity.0[0] / b.radiosity.0[0];
            worst = worst.max((ratio / 4.0 - 1.0).abs());
        }
        eprintln!("{kind:?}: bright / dark element ratio off 4 by at most {worst:e}");
        assert!(worst < 0.01, "{worst}");
    }
}

// glTF files, written here: a floor quad with a 2x2 checker PNG.

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("textures");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn png_checker() -> Vec<u8> {
    // sRGB 255 is linear 1; the factor 0.8 makes it 0.8. sRGB 0 is 0.
    let (d, b) = ([0u8; 3], [255u8; 3]);
    let pixels: Vec<u8> = [d, b, b, d].iter().flatten().copied().collect();
    let img = image::RgbImage::from_raw(2, 2, pixels).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::encode(bytes))
}

/// A glTF floor `[0, 2]^2` (two triangles) with texture coordinate sets 0
/// (all zero) and 1 (`x / 2, z / 2`), a lamp above, and the checker read from
/// `set` with the texture reference's `extensions` JSON.
fn gltf_floor(set: u32, extensions: &str) -> PathBuf {
    let pos: [[f32; 3]; 4] = [[0., 0., 0.], [0., 0., 2.], [2., 0., 2.], [2., 0., 0.]];
    let uv0 = [[0f32; 2]; 4];
    let uv1: [[f32; 2]; 4] = [[0., 0.], [0., 1.], [1., 1.], [1., 0.]];
    let lamp: [[f32; 3]; 4] = [
        [0.8, 20., 0.8],
        [1.2, 20., 0.8],
        [1.2, 20., 1.2],
        [0.8, 20., 1.2],
    ];
    let idx: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bytes = Vec::new();
    for p in pos.iter().chain(&lamp) {
        p.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    for t in uv0.iter().chain(&uv1) {
        t.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    idx.iter().for_each(|i| bytes.extend(i.to_le_bytes()));
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"name":"floor"}},{{"mesh":1,"name":"lamp"}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":2,"TEXCOORD_1":3}},"indices":4,"material":0}}]}},
{{"primitives":[{{"attributes":{{"POSITION":1}},"indices":4,"material":1}}]}}],
"materials":[{{"name":"checker","pbrMetallicRoughness":{{"baseColorFactor":[0.8,0.8,0.8,1],"metallicFactor":0,
"baseColorTexture":{{"index":0,"texCoord":{set}{extensions}}}}}}},
{{"name":"lamp","emissiveFactor":[1,1,1],"pbrMetallicRoughness":{{"baseColorFactor":[0,0,0,1],"metallicFactor":0}}}}],
"textures":[{{"source":0,"sampler":0}}],"samplers":[{{"magFilter":9728,"minFilter":9728}}],
"images":[{{"uri":"{png}"}}],
"buffers":[{{"byteLength":{len},"uri":"{buf}"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":96}},{{"buffer":0,"byteOffset":96,"byteLength":64}},{{"buffer":0,"byteOffset":160,"byteLength":12}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[2,0,2]}},
{{"bufferView":0,"byteOffset":48,"componentType":5126,"count":4,"type":"VEC3","min":[0.8,20,0.8],"max":[1.2,20,1.2]}},
{{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}},
{{"bufferView":1,"byteOffset":32,"componentType":5126,"count":4,"type":"VEC2"}},
{{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}}]}}"#,
        png = data_uri("image/png", &png_checker()),
        buf = data_uri("application/octet-stream", &bytes),
        len = bytes.len(),
    );
    let path = scratch(&format!("floor_{set}_{}.gltf", extensions.len()));
    std::fs::write(&path, json).unwrap();
    path
}

/// The floor's leaf reflectances (first band) by centroid, from a solve of
/// 0.25 m patches split once (elements of 1/8 m, inside the checks).
fn floor_reflectances(path: &Path) -> Vec<(DVec3, f64)> {
    let scene = load_scene(path, &ImportLimits::default()).unwrap();
    let sol = solve(&scene, &uniform(0.25, 1, SolverKind::GaussSeidel));
    let floor: Vec<u32> = scene
        .surfaces
        .iter()
        .enumerate()
        .filter(|(_, s)| scene.objects[s.object as usize].name == "floor")
        .map(|(i, _)| i as u32)
        .collect();
    sol.leaves()
        .iter()
        .filter(|l| floor.contains(&l.surface()))
        .map(|l| (l.centroid(), l.reflectance().0[0]))
        .collect()
}

/// Checks that every floor element is bright (0.8) where `bright` says and
/// black elsewhere.
fn assert_checks(leaves: &[(DVec3, f64)], bright: impl Fn(f64, f64) -> bool) {
    assert!(leaves.len() >= 256, "{}", leaves.len());
    for (c, rho) in leaves {
        let want = if bright(c.x, c.z) { 0.8 } else { 0.0 };
        assert!((rho - want).abs() < 1e-6, "{rho} at {c}, want {want}");
    }
}

#[test]
fn a_gltf_checker_read_from_texcoord_1_gives_2x2_checks() {
    assert_checks(&floor_reflectances(&gltf_floor(1, "")), bright_at);
    // Set 0 is all zero: every element takes the texel at (0, 0), dark.
    assert_checks(&floor_reflectances(&gltf_floor(0, "")), |_, _| false);
}

#[test]
fn khr_texture_transform_scale_2_makes_4x4_checks() {
    let ext = r#","extensions":{"KHR_texture_transform":{"scale":[2,2]}}"#;
    let leaves = floor_reflectances(&gltf_floor(1, ext));
    // u = x, v = z: a check is 0.5 m.
    let bright = |x: f64, z: f64| ((x / 0.5).floor() as i64 + (z / 0.5).floor() as i64) % 2 == 1;
    assert_checks(&leaves, bright);
}

#[test]
fn a_dark_texture_its_light_would_clip_by_more_than_a_stop_is_baked_untextured_and_named() {
    // A viewer draws texel times COLOR_0, each at most 1: where the display
    // value of the mean texel exceeds the mean reflectance, the colour
    // clips. A checker of 0.1 and 0.4 (mean 0.25) filling the view is
    // shown at the automatic exposure brighter than twice its mean, which
    // its vertices' colours would have to be clipped by more than a stop to
    // show: the floor is baked in its own colours, untextured, and the
    // warning names it. Three stops darker, the texture is kept.
    use radiosity::gltf_io::{write_baked, BakeOptions};
    let mut scene = checkered_floor(true);
    let (d, b) = ([0.1f32; 3], [0.4f32; 3]);
    scene.materials[0].base_texture = Some(Arc::new(Texture::nearest(2, 2, vec![d, b, b, d])));
    scene.materials[0].reflectance = Rgb::splat(0.25);
    let sol = solve(&scene, &uniform(1.0, 2, SolverKind::GaussSeidel));
    let shading = sol.shading_mesh();
    let dir = std::env::temp_dir().join(format!("radiosity-clip-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bake = |exposure: Option<f64>, file: &str| {
        let path = dir.join(file);
        let options = BakeOptions {
            exposure,
            ..BakeOptions::default()
        };
        let summary = write_baked(&scene, &shading, &[], &options, &path).unwrap();
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let textured = json["materials"][0]["pbrMetallicRoughness"]
            .get("baseColorTexture")
            .is_some();
        (summary, textured)
    };
    let (bright, textured) = bake(None, "auto.gltf");
    assert!(!textured, "the clipped checker must not be kept");
    assert!(
        bright
            .warnings
            .iter()
            .any(|w| w.contains("without their textures") && w.contains("'floor'")),
        "{:?}",
        bright.warnings
    );
    let (dim, textured) = bake(Some(bright.exposure - 3.0), "dim.gltf");
    assert!(
        textured,
        "three stops darker the checker is kept: {:?}",
        dim.warnings
    );
    assert!(
        dim.warnings
            .iter()
            .all(|w| !w.contains("without their textures")),
        "{:?}",
        dim.warnings
    );
    std::fs::remove_dir_all(&dir).ok();
}
