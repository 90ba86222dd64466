//! Emissive textures per element: a panel that is black but for a small
//! bright square lights what faces the square as the square alone would
//! (Howell's closed form), not as the panel's mean emission spread over it.

use glam::{DVec2, DVec3};
use radiosity::analytic::{parallel_rectangles, point_to_rectangle_corner};
use radiosity::gltf_io::{load_scene, ImportLimits};
use radiosity::math::Rgb;
use radiosity::pipeline::SolverKind;
use radiosity::scene::{Scene, SceneBuilder, Texture, Wrap};
use radiosity::solution::Leaf;
use radiosity::{Settings, Solution};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Texels along each side of the panel's texture.
const TEXELS: usize = 10;
/// The bright texel's column and row: the square `[0.7, 0.8]^2` of the
/// panel, whose edges fall on no binary fraction of it.
const BRIGHT_TEXEL: usize = 7;
/// Exitance of the bright texel.
const EXITANCE: f64 = 50.0;
/// How far below the panel the receiver lies.
const GAP: f64 = 0.2;
/// The receiver's reflectance.
const RHO: f64 = 0.5;

/// The bright square's lower and upper coordinate along x and z.
fn square() -> (f64, f64) {
    let lo = BRIGHT_TEXEL as f64 / TEXELS as f64;
    (lo, lo + 1.0 / TEXELS as f64)
}

/// A `TEXELS`-square image, black but for one white texel, nearest filter.
fn one_bright_texel() -> Texture {
    let mut texels = vec![[0.0f32; 3]; TEXELS * TEXELS];
    texels[BRIGHT_TEXEL * TEXELS + BRIGHT_TEXEL] = [1.0; 3];
    Texture {
        wrap: [Wrap::ClampToEdge; 2],
        factor: Rgb::splat(EXITANCE),
        max_value: f64::INFINITY,
        ..Texture::nearest(TEXELS as u32, TEXELS as u32, texels)
    }
}

/// A black 1 m panel at height `GAP` facing down, its texture coordinates
/// `u = x`, `v = z`, and under the bright square a receiver of the square's
/// size facing up; nothing else. `textured` gives the panel the texture,
/// else its mean emission everywhere.
fn panel_over_receiver(textured: bool) -> Scene {
    let mut b = SceneBuilder::new("emissive square");
    let texels = (TEXELS * TEXELS) as f64;
    let mean_radiance = EXITANCE / texels / PI;
    let panel = b
        .material("panel", Rgb::ZERO, Rgb::splat(mean_radiance))
        .unwrap();
    let grey = b.material("receiver", Rgb::splat(RHO), Rgb::ZERO).unwrap();
    b.object("panel");
    b.quad(
        panel,
        v(0., GAP, 0.),
        v(1., GAP, 0.),
        v(1., GAP, 1.),
        v(0., GAP, 1.),
    )
    .unwrap();
    b.object("receiver");
    let (lo, hi) = square();
    b.quad(
        grey,
        v(lo, 0., lo),
        v(lo, 0., hi),
        v(hi, 0., hi),
        v(hi, 0., lo),
    )
    .unwrap();
    let mut scene = b.build().unwrap();
    if textured {
        scene.materials[panel as usize].emissive_texture = Some(Arc::new(one_bright_texel()));
        let uv = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(|(u, v)| DVec2::new(u, v));
        scene.surfaces[0] = scene.surfaces[0].clone().with_uv(&uv);
    }
    scene
}

fn solve(scene: &Scene, kind: SolverKind) -> Solution {
    let settings = Settings {
        patch_size: Some(0.25),
        solver_kind: kind,
        ..Settings::default()
    };
    radiosity::solve(scene, &settings, &|_| {}).unwrap()
}

/// Area-weighted mean of the first band of `value` over surface `s`'s leaves.
fn mean_over(sol: &Solution, s: u32, value: impl Fn(&Leaf) -> f64) -> f64 {
    let (mut sum, mut area) = (0.0, 0.0);
    for leaf in sol.leaves().iter().filter(|l| l.surface() == s) {
        sum += value(leaf) * leaf.area();
        area += leaf.area();
    }
    sum / area
}

/// The form factor from a point at `(x, z)` facing up, `GAP` below the
/// bright square, to the square: four corner rectangles added and taken away.
fn point_to_square(x: f64, z: f64) -> f64 {
    let (lo, hi) = square();
    let corner = |a: f64, b: f64| {
        if a == 0.0 || b == 0.0 {
            return 0.0;
        }
        let f = point_to_rectangle_corner(a.abs(), b.abs(), GAP).unwrap();
        f * a.signum() * b.signum()
    };
    corner(hi - x, hi - z) - corner(lo - x, hi - z) - corner(hi - x, lo - z)
        + corner(lo - x, lo - z)
}

#[test]
fn a_small_bright_square_lights_what_faces_it_as_the_square_alone() {
    let side = 1.0 / TEXELS as f64;
    // Identical coaxial squares: the receiver's mean irradiance is the
    // square's exitance times the form factor between them.
    let exact = EXITANCE * parallel_rectangles(side, side, GAP).unwrap();
    for kind in [SolverKind::GaussSeidel, SolverKind::Progressive] {
        let sol = solve(&panel_over_receiver(true), kind);
        // Each receiving element's irradiance is found at its centroid, so
        // it is compared with the exact irradiance there (the mean over
        // the receiver differs from the centroids' by how coarsely the
        // receiver is cut, which is not what this test is about).
        let (mut got, mut want, mut area, mut worst) = (0.0, 0.0, 0.0, 0.0f64);
        for leaf in sol.leaves().iter().filter(|l| l.surface() == 1) {
            let h = leaf.radiosity.0[0] / RHO;
            let exact_here = EXITANCE * point_to_square(leaf.centroid().x, leaf.centroid().z);
            worst = worst.max((h / exact_here - 1.0).abs());
            got += h * leaf.area();
            want += exact_here * leaf.area();
            area += leaf.area();
        }
        let (got, want) = (got / area, want / area);
        let error = got / want - 1.0;
        eprintln!(
            "{kind:?}: irradiance {got:.5} (exact at the centroids {want:.5}, error {error:+.4}, \
             worst element {worst:.4}; mean over the receiver {exact:.5})"
        );
        // The issue asks for 2%; measured 0.14% (Gauss-Seidel), 0.36%
        // (progressive).
        assert!(error.abs() < 0.01, "{kind:?}: {got} vs {want}");
        assert!(worst < 0.03, "{kind:?}: {worst}");
        // The panel emits what its texture holds, in total.
        let emitted = mean_over(&sol, 0, |l| l.emission().0[0]);
        let texture = EXITANCE / (TEXELS * TEXELS) as f64;
        assert!(
            (emitted / texture - 1.0).abs() < 0.01,
            "{emitted} vs {texture}"
        );
    }
    // The panel's mean emission spread over it lights the receiver far less.
    let spread = solve(&panel_over_receiver(false), SolverKind::GaussSeidel);
    let irradiance = mean_over(&spread, 1, |l| l.radiosity.0[0]) / RHO;
    assert!(irradiance < 0.5 * exact, "{irradiance} vs {exact}");
}

#[test]
fn the_bright_square_gets_patches_of_its_own_size_and_the_rest_stays_dark() {
    let sol = solve(&panel_over_receiver(true), SolverKind::GaussSeidel);
    let mesh = sol.mesh();
    let panel: Vec<_> = (0..mesh.patches().len() as u32)
        .filter(|&p| mesh.patches()[p as usize].surface() == 0)
        .collect();
    let untextured = solve(&panel_over_receiver(false), SolverKind::GaussSeidel);
    let plain = (0..untextured.mesh().patches().len())
        .filter(|&p| untextured.mesh().patches()[p].surface() == 0)
        .count();
    // Cut finer than the 4 x 4 the patch size gives, to patches no wider
    // than half the square.
    assert!(panel.len() > plain, "{} vs {plain}", panel.len());
    let side = 1.0 / TEXELS as f64;
    let widest = panel
        .iter()
        .map(|&p| mesh.patches()[p as usize].area().sqrt())
        .fold(0.0, f64::max);
    assert!(widest <= side / 2.0 + 1e-12, "{widest}");
    // Patches wholly inside the square emit all of it; those clear of it,
    // nothing.
    let (lo, hi) = square();
    let (mut inside, mut outside) = (0, 0);
    for &p in &panel {
        let poly = &mesh.patches()[p as usize].polygon();
        let min = poly.iter().fold(DVec3::INFINITY, |a, q| a.min(*q));
        let max = poly.iter().fold(DVec3::NEG_INFINITY, |a, q| a.max(*q));
        let e = mesh.patch_emission(p).0[0];
        if min.x >= lo && max.x <= hi && min.z >= lo && max.z <= hi {
            assert_eq!(e, EXITANCE, "patch {p}");
            inside += 1;
        } else if max.x <= lo || min.x >= hi || max.z <= lo || min.z >= hi {
            assert_eq!(e, 0.0, "patch {p}");
            outside += 1;
        }
    }
    assert!(inside > 0 && outside > 0, "{inside} {outside}");
}

// A glTF panel with an emissive PNG: the importer keeps the texture.

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("emissive_textures");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::encode(bytes))
}

/// A 2x2 PNG, white in the texel of row 0, column 1, black elsewhere.
fn png_one_white() -> Vec<u8> {
    let (d, w) = ([0u8; 3], [255u8; 3]);
    let pixels: Vec<u8> = [d, w, d, d].iter().flatten().copied().collect();
    let img = image::RgbImage::from_raw(2, 2, pixels).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// A 2 m floor panel (two triangles, `u = x / 2`, `v = z / 2`) with an
/// emissive texture and factor `(2, 2, 2)`, facing up under a grey ceiling.
fn gltf_panel() -> PathBuf {
    let pos: [[f32; 3]; 8] = [
        [0., 0., 0.],
        [0., 0., 2.],
        [2., 0., 2.],
        [2., 0., 0.],
        [0., 1., 0.],
        [2., 1., 0.],
        [2., 1., 2.],
        [0., 1., 2.],
    ];
    let uv: [[f32; 2]; 8] = [
        [0., 0.],
        [0., 1.],
        [1., 1.],
        [1., 0.],
        [0., 0.],
        [0., 0.],
        [0., 0.],
        [0., 0.],
    ];
    let idx: [u16; 12] = [0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3];
    let mut bytes = Vec::new();
    pos.iter()
        .flatten()
        .for_each(|c| bytes.extend(c.to_le_bytes()));
    uv.iter()
        .flatten()
        .for_each(|c| bytes.extend(c.to_le_bytes()));
    idx.iter().for_each(|i| bytes.extend(i.to_le_bytes()));
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"name":"panel"}},{{"mesh":1,"name":"ceiling"}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":2}},"indices":3,"material":0}}]}},
{{"primitives":[{{"attributes":{{"POSITION":1}},"indices":4,"material":1}}]}}],
"materials":[{{"name":"glow","emissiveFactor":[2,2,2],"emissiveTexture":{{"index":0}},
"pbrMetallicRoughness":{{"baseColorFactor":[0,0,0,1],"metallicFactor":0}}}},
{{"name":"grey","pbrMetallicRoughness":{{"baseColorFactor":[0.5,0.5,0.5,1],"metallicFactor":0}}}}],
"textures":[{{"source":0,"sampler":0}}],"samplers":[{{"magFilter":9728,"minFilter":9728}}],
"images":[{{"uri":"{png}"}}],
"buffers":[{{"byteLength":{len},"uri":"{buf}"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":96}},{{"buffer":0,"byteOffset":96,"byteLength":64}},{{"buffer":0,"byteOffset":160,"byteLength":24}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[2,0,2]}},
{{"bufferView":0,"byteOffset":48,"componentType":5126,"count":4,"type":"VEC3","min":[0,1,0],"max":[2,1,2]}},
{{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}},
{{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}},
{{"bufferView":2,"byteOffset":12,"componentType":5123,"count":6,"type":"SCALAR"}}]}}"#,
        png = data_uri("image/png", &png_one_white()),
        buf = data_uri("application/octet-stream", &bytes),
        len = bytes.len(),
    );
    let path = scratch("panel.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn a_gltf_emissive_texture_gives_each_element_its_own_emission() {
    let scene = load_scene(&gltf_panel(), &ImportLimits::default()).unwrap();
    let glow = scene.materials.iter().find(|m| m.name == "glow").unwrap();
    assert!(glow.emissive_texture.is_some());
    // The mean over the image: one texel in four at pi times the factor.
    assert!((glow.emission.0[0] - 2.0 * PI / 4.0).abs() < 1e-9);
    let settings = Settings {
        patch_size: Some(0.5),
        ..Settings::default()
    };
    let sol = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
    let mut bright = 0;
    for leaf in sol.leaves() {
        let material = &scene.materials[scene.surfaces[leaf.surface() as usize].material as usize];
        if material.name != "glow" {
            assert_eq!(leaf.emission(), Rgb::ZERO);
            continue;
        }
        // Texel row 0 (v < 1/2: z < 1), column 1 (u >= 1/2: x >= 1).
        let c = leaf.centroid();
        let inside = c.x > 1.0 && c.z < 1.0;
        let e = leaf.emission().0[0];
        if inside {
            assert!((e - 2.0 * PI).abs() < 1e-9, "{e} at {c}");
            bright += 1;
        } else if c.x < 1.0 - 0.26 || c.z > 1.0 + 0.26 {
            assert_eq!(e, 0.0, "at {c}");
        }
    }
    assert!(bright > 0);
}
