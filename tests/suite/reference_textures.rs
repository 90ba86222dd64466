//! Textures in the path-traced reference: reflectance and emission per
//! point, checked against closed forms that share no code with the crate
//! (solid angles of rectangles, Howell's parallel-rectangle form factor via
//! `radiosity::analytic`), against the solver's elements on a quad whose
//! texture map is bilinear, and bit for bit against untextured scenes.
//!
//! Monte Carlo tolerances are four of the reference's own standard errors:
//! for an estimate that is normal to good approximation (tens of thousands
//! of independent samples of a bounded value) a true mean falls outside with
//! probability 6e-5, and the seed is fixed, so a test either always passes
//! or shows a real bias. Every test also checks that the wrong answer (the
//! texture's mean instead of its texels) lies far outside that band.

use glam::{DVec2, DVec3};
use radiosity::analytic::{parallel_rectangles, point_to_rectangle_corner};
use radiosity::gltf_io::{load_scene, ImportLimits};
use radiosity::math::Rgb;
use radiosity::reference::{ProbeEstimate, Reference, ReferenceSettings, SurfacePoint};
use radiosity::refine::RefineSettings;
use radiosity::scene::{Light, Scene, SceneBuilder, Texture, Wrap};
use radiosity::Settings;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::Arc;

const DARK: f32 = 0.2;
const BRIGHT: f32 = 0.8;
/// The point light's intensity (cd) and position over the floor `[0, 2]^2`:
/// off-centre, over a bright check, so that the floor's mean depends on
/// which check is which.
const INTENSITY: f64 = 3.0;
const LIGHT: DVec3 = DVec3::new(0.6, 0.9, 1.4);

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn uvs(pairs: &[(f64, f64)]) -> Vec<DVec2> {
    pairs.iter().map(|&(a, b)| DVec2::new(a, b)).collect()
}

/// A texture of `width x height` linear texels (row-major, row 0 at v = 0),
/// nearest texel, clamped at the edges, with factor 1 and no transform.
fn texture(width: u32, height: u32, texels: Vec<[f32; 3]>, max_value: f64) -> Arc<Texture> {
    Arc::new(Texture {
        wrap: [Wrap::ClampToEdge; 2],
        max_value,
        ..Texture::nearest(width, height, texels)
    })
}

/// The 2x2 checker: texel (column, row) = (u < 1/2, v < 1/2) dark, (u >= 1/2,
/// v < 1/2) bright, (u < 1/2, v >= 1/2) bright, (u >= 1/2, v >= 1/2) dark.
fn checker() -> Arc<Texture> {
    let (d, b) = ([DARK; 3], [BRIGHT; 3]);
    texture(2, 2, vec![d, b, b, d], 1.0)
}

/// The checker's reflectance at texture coordinates `(u, v)` in [0, 1).
fn checker_at(u: f64, v: f64) -> f64 {
    f64::from(if (u >= 0.5) != (v >= 0.5) {
        BRIGHT
    } else {
        DARK
    })
}

/// The floor `[0, 2]^2` (y = 0, facing up) alone under the point light, its
/// texture coordinates `(x / 2, z / 2)`: one quad, or two triangles.
fn checker_floor(triangles: bool) -> Scene {
    let mut b = SceneBuilder::new("checker floor");
    let mean = f64::from(DARK + BRIGHT) / 2.0;
    let floor = b.material("floor", Rgb::splat(mean), Rgb::ZERO).unwrap();
    b.object("floor");
    let c = [v(0., 0., 0.), v(0., 0., 2.), v(2., 0., 2.), v(2., 0., 0.)];
    let t = uvs(&[(0., 0.), (0., 1.), (1., 1.), (1., 0.)]);
    if triangles {
        b.triangle(floor, c[0], c[1], c[2]).unwrap();
        b.triangle(floor, c[0], c[2], c[3]).unwrap();
    } else {
        b.quad(floor, c[0], c[1], c[2], c[3]).unwrap();
    }
    b.light(Light::point("bulb", LIGHT, Rgb::ONE, INTENSITY))
        .unwrap();
    let mut scene = b.build().unwrap();
    scene.materials[floor as usize].base_texture = Some(checker());
    let pieces: [&[usize]; 2] = if triangles {
        [&[0, 1, 2], &[0, 2, 3]]
    } else {
        [&[0, 1, 2, 3], &[]]
    };
    for (surface, corners) in scene.surfaces.iter_mut().zip(pieces) {
        let coords: Vec<DVec2> = corners.iter().map(|k| t[*k]).collect();
        *surface = surface.clone().with_uv(&coords);
    }
    assert!(scene.surfaces.iter().all(|s| !s.uv.is_empty()));
    scene
}

/// The solid angle of the rectangle `[x0, x1] x [z0, z1]` (y = 0) seen from
/// `p` above it: inclusion-exclusion over its corners of the solid angle of
/// a rectangle with one corner below `p`, `atan(a b / (h sqrt(h^2 + a^2 + b^2)))`
/// (odd in `a` and in `b`).
fn solid_angle(p: DVec3, (x0, x1): (f64, f64), (z0, z1): (f64, f64)) -> f64 {
    let h = p.y;
    let corner = |x: f64, z: f64| {
        let (a, b) = (x - p.x, z - p.z);
        (a * b / (h * (h * h + a * a + b * b).sqrt())).atan()
    };
    corner(x1, z1) - corner(x0, z1) - corner(x1, z0) + corner(x0, z0)
}

/// The exact mean radiosity of the checker floor: `(1/A) sum_checks rho I
/// Omega`, since `integral I cos / r^2 dA` over a check is `I` times the
/// solid angle it subtends from the light.
fn exact_floor_mean(checks: bool) -> f64 {
    let mut sum = 0.0;
    for (i, j) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let (x, z) = (f64::from(i), f64::from(j));
        let rho = if checks {
            checker_at(x / 2.0 + 0.25, z / 2.0 + 0.25)
        } else {
            f64::from(DARK + BRIGHT) / 2.0
        };
        sum += rho * INTENSITY * solid_angle(LIGHT, (x, x + 1.0), (z, z + 1.0));
    }
    sum / 4.0
}

/// The exact radiosity at floor point `p`: `rho I cos / r^2`.
fn exact_at(p: DVec3) -> f64 {
    let span = LIGHT - p;
    let r = span.length();
    checker_at(p.x / 2.0, p.z / 2.0) * INTENSITY * span.y / (r * r * r)
}

fn settings(paths: u64) -> ReferenceSettings {
    ReferenceSettings {
        paths,
        seed: 5,
        ..ReferenceSettings::default()
    }
}

/// Asserts `estimate` (first band) is within four standard errors of `exact`.
fn assert_within_error(what: &str, estimate: &ProbeEstimate, exact: f64) {
    let (got, error) = (estimate.radiosity.0[0], estimate.std_error.0[0]);
    eprintln!(
        "{what}: reference {got:.6} +- {error:.2e}, exact {exact:.6} ({:+.2} standard errors)",
        (got - exact) / error
    );
    assert!(error > 0.0 && (got - exact).abs() < 4.0 * error, "{what}");
}

#[test]
fn a_checker_floor_under_a_point_light_has_the_exact_mean_and_texels() {
    for triangles in [false, true] {
        let scene = checker_floor(triangles);
        let reference = Reference::new(&scene).unwrap();
        // Nothing else reflects: B(x) = rho(x) I cos / r^2 at each point, so
        // the object mean's only error is the choice of 200 000 uniform points.
        let mean = &reference.object_means(&settings(200_000)).unwrap()[0];
        let exact = exact_floor_mean(true);
        assert_within_error(&format!("floor mean (triangles: {triangles})"), mean, exact);
        // The floor's mean with the texture's mean reflectance is far off.
        let plain = exact_floor_mean(false);
        assert!(
            (plain - exact).abs() > 20.0 * mean.std_error.0[0],
            "{plain}"
        );
        // Probes inside each check, a millimetre from its edges too, carry no
        // noise (a path from the floor escapes): each is rho I cos / r^2 to
        // the ray-offset's relative 1e-6.
        let mut points = Vec::new();
        for x in [0.3, 0.999, 1.001, 1.7] {
            for z in [0.001, 0.6, 0.999, 1.001, 1.5, 1.999] {
                let p = reference
                    .locate(v(x, 0.0, z), DVec3::Y)
                    .expect("on the floor");
                points.push(p);
            }
        }
        let estimates = reference.radiosity_at(&points, &settings(2)).unwrap();
        for (p, e) in points.iter().zip(&estimates) {
            let want = exact_at(p.position);
            let got = e.radiosity.0[0];
            assert!(
                (got / want - 1.0).abs() < 1e-5,
                "{got} at {}, want {want}",
                p.position
            );
        }
    }
}

/// A floor quad that is a trapezoid (not a parallelogram) under the point
/// light, the checker over it by the quad's bilinear map (u along vertex 0
/// to 3, v along 0 to 1).
fn trapezoid_floor() -> Scene {
    let mut b = SceneBuilder::new("trapezoid");
    let floor = b.material("floor", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    b.object("floor");
    b.quad(
        floor,
        v(0., 0., 0.),
        v(0.6, 0., 2.),
        v(1.4, 0., 2.),
        v(2., 0., 0.),
    )
    .unwrap();
    b.light(Light::point("bulb", LIGHT, Rgb::ONE, INTENSITY))
        .unwrap();
    let mut scene = b.build().unwrap();
    scene.materials[floor as usize].base_texture = Some(checker());
    let t = uvs(&[(0., 0.), (0., 1.), (1., 1.), (1., 0.)]);
    scene.surfaces[0] = scene.surfaces[0].clone().with_uv(&t);
    scene
}

#[test]
fn on_a_trapezoid_the_reference_reads_the_texel_the_solvers_element_has() {
    // The bilinear map puts the checker's u = 1/2 edge on x = 1; the two
    // triangles the quad is traced as would put it elsewhere (on the line
    // from (0.7, 1) to (1, 2) in the first), so elements beside x = 1 tell.
    let scene = trapezoid_floor();
    let settings_solve = Settings {
        patch_size: Some(0.5),
        refine: RefineSettings {
            uniform_depth: Some(1),
            ..RefineSettings::default()
        },
        ..Settings::default()
    };
    let solution = radiosity::solve(&scene, &settings_solve, &|_| {}).unwrap();
    let reference = Reference::new(&scene).unwrap();
    let leaves = solution.leaves();
    let points: Vec<SurfacePoint> = leaves
        .iter()
        .map(|l| {
            reference
                .locate(l.centroid(), DVec3::Y)
                .expect("on the floor")
        })
        .collect();
    assert!(points.len() >= 64, "{}", points.len());
    let estimates = reference.radiosity_at(&points, &settings(2)).unwrap();
    let mut near_edge = 0;
    for ((leaf, p), e) in leaves.iter().zip(&points).zip(&estimates) {
        let rho = leaf.reflectance().0[0];
        assert!(
            rho == f64::from(DARK) || rho == f64::from(BRIGHT),
            "the solver's element at {} straddles a check ({rho})",
            leaf.centroid()
        );
        let span = LIGHT - p.position;
        let direct = INTENSITY * span.y / span.length().powi(3);
        let seen = e.radiosity.0[0] / direct;
        assert!(
            (seen - rho).abs() < 1e-5,
            "at {}: reference reflectance {seen}, solver's element {rho}",
            leaf.centroid()
        );
        near_edge += usize::from((leaf.centroid().x - 1.0).abs() < 0.2);
    }
    assert!(near_edge >= 8, "{near_edge}");
}

// An emissive texture, from a glTF file: a 1 m panel facing down, black but
// for its central quarter-side square, over a small grey receiver.

/// The panel's height above the receiver, and the bright square's side.
const GAP: f64 = 0.25;
const SIDE: f64 = 0.25;
const RECEIVER_RHO: f64 = 0.5;

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference_textures");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// An 8x8 PNG, black but for the four central texels (sRGB 255, linear 1).
fn png_bright_centre() -> Vec<u8> {
    let mut pixels = Vec::new();
    for y in 0..8 {
        for x in 0..8 {
            let bright = (3..5).contains(&x) && (3..5).contains(&y);
            pixels.extend([if bright { 255u8 } else { 0 }; 3]);
        }
    }
    let img = image::RgbImage::from_raw(8, 8, pixels).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::encode(bytes))
}

/// The panel `[0, 1]^2` at y = GAP facing down, its emissive texture the
/// bright centre (emissiveFactor 1: the bright square's exitance is pi),
/// `u = x`, `v = z`, reflectance 0; and the receiver
/// `[3/8, 5/8]^2` at y = 0 facing up, reflectance 1/2, exactly opposite the
/// bright square. Two triangles each.
fn gltf_panel() -> PathBuf {
    let g = GAP as f32;
    let panel: [[f32; 3]; 4] = [[0., g, 0.], [1., g, 0.], [1., g, 1.], [0., g, 1.]];
    let receiver: [[f32; 3]; 4] = [
        [0.375, 0., 0.375],
        [0.375, 0., 0.625],
        [0.625, 0., 0.625],
        [0.625, 0., 0.375],
    ];
    let uv: [[f32; 2]; 4] = [[0., 0.], [1., 0.], [1., 1.], [0., 1.]];
    let idx: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bytes = Vec::new();
    for p in panel.iter().chain(&receiver) {
        p.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    for t in &uv {
        t.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    idx.iter().for_each(|i| bytes.extend(i.to_le_bytes()));
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"name":"panel"}},{{"mesh":1,"name":"receiver"}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":2}},"indices":3,"material":0}}]}},
{{"primitives":[{{"attributes":{{"POSITION":1}},"indices":3,"material":1}}]}}],
"materials":[{{"name":"panel","emissiveFactor":[1,1,1],"emissiveTexture":{{"index":0}},
"pbrMetallicRoughness":{{"baseColorFactor":[0,0,0,1],"metallicFactor":0}}}},
{{"name":"receiver","pbrMetallicRoughness":{{"baseColorFactor":[{rho},{rho},{rho},1],"metallicFactor":0}}}}],
"textures":[{{"source":0,"sampler":0}}],"samplers":[{{"magFilter":9728,"minFilter":9728}}],
"images":[{{"uri":"{png}"}}],
"buffers":[{{"byteLength":{len},"uri":"{buf}"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":96}},{{"buffer":0,"byteOffset":96,"byteLength":32}},{{"buffer":0,"byteOffset":128,"byteLength":12}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,{g},0],"max":[1,{g},1]}},
{{"bufferView":0,"byteOffset":48,"componentType":5126,"count":4,"type":"VEC3","min":[0.375,0,0.375],"max":[0.625,0,0.625]}},
{{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}},
{{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}}]}}"#,
        rho = RECEIVER_RHO,
        png = data_uri("image/png", &png_bright_centre()),
        buf = data_uri("application/octet-stream", &bytes),
        len = bytes.len(),
    );
    let path = scratch("panel.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

/// The objects named `panel` and `receiver`, by index.
fn panel_objects(scene: &Scene) -> (usize, usize) {
    let find = |name: &str| scene.objects.iter().position(|o| o.name == name).unwrap();
    (find("panel"), find("receiver"))
}

#[test]
fn an_emissive_texture_lights_a_receiver_from_its_bright_square_only() {
    let scene = load_scene(&gltf_panel(), &ImportLimits::default()).unwrap();
    let (panel, receiver) = panel_objects(&scene);
    let bright = PI; // pi times emissiveFactor 1 times the texel 1.
    let panel_material = &scene.materials[scene
        .surfaces
        .iter()
        .find(|s| s.object as usize == panel)
        .unwrap()
        .material as usize];
    // The importer's mean exitance: 4 bright texels of 64.
    let mean = bright / 16.0;
    assert!((panel_material.emission.0[0] / mean - 1.0).abs() < 1e-6);
    assert!(panel_material.emissive_texture.is_some());

    let reference = Reference::new(&scene).unwrap();
    let paths = 40_000;
    let means = reference.object_means(&settings(paths)).unwrap();
    // The receiver sees the bright square alone (the panel reflects
    // nothing): its mean radiosity is rho E F, F the form factor between
    // identical coaxial parallel squares (Howell C-11).
    let form_factor = parallel_rectangles(SIDE, SIDE, GAP).unwrap();
    let exact = RECEIVER_RHO * bright * form_factor;
    assert_within_error("receiver mean", &means[receiver], exact);
    // A uniform panel of the mean exitance E/16 gives any receiver point
    // at most E/16 of irradiance: the texels' answer is over 3 times that.
    let uniform_bound = RECEIVER_RHO * mean;
    assert!(means[receiver].radiosity.0[0] > 3.0 * uniform_bound);
    // The panel's mean radiosity is its area mean exitance, E/16: its points
    // are uniform, each bright with probability 1/16 (binomial error).
    let binomial = bright * (1.0f64 / 16.0 * 15.0 / 16.0 / paths as f64).sqrt();
    let got = means[panel].radiosity.0[0];
    eprintln!("panel mean {got:.5}, exact {mean:.5}, binomial error {binomial:.2e}");
    assert!((got - mean).abs() < 4.0 * binomial);

    // The receiver's centre: E times the point-to-square form factor, four
    // corner rectangles of half the side (Howell's point-to-corner formula).
    let centre = reference
        .locate(v(0.5, 0.0, 0.5), DVec3::Y)
        .expect("on the receiver");
    let at_centre = &reference
        .radiosity_at(&[centre], &settings(40_000))
        .unwrap()[0];
    let point_factor = 4.0 * point_to_rectangle_corner(SIDE / 2.0, SIDE / 2.0, GAP).unwrap();
    assert_within_error(
        "receiver centre",
        at_centre,
        RECEIVER_RHO * bright * point_factor,
    );

    // The same panel with its texture dropped emits its mean everywhere: the
    // reference then gives the whole-panel answer, far below.
    let mut flat = scene.clone();
    for m in &mut flat.materials {
        m.emissive_texture = None;
    }
    let flat_means = Reference::new(&flat)
        .unwrap()
        .object_means(&settings(paths))
        .unwrap();
    let (textured, uniform) = (
        means[receiver].radiosity.0[0],
        flat_means[receiver].radiosity.0[0],
    );
    eprintln!("receiver: texels {textured:.5}, mean emission {uniform:.5}");
    assert!(uniform < uniform_bound && textured > 3.0 * uniform);
}

/// A closed-ish scene with interreflection: a floor, a wall and a lamp, all
/// with texture coordinates; `textures` gives the floor and the lamp 1x1
/// textures equal to their constants (reflectance 1/2, exitance 4), or none.
fn uniform_room(textures: bool, coordinates: bool) -> Scene {
    let mut b = SceneBuilder::new("room");
    let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::splat(0.5), Rgb::ZERO).unwrap();
    b.object("floor");
    b.quad(
        grey,
        v(0., 0., 0.),
        v(0., 0., 2.),
        v(2., 0., 2.),
        v(2., 0., 0.),
    )
    .unwrap();
    b.object("wall");
    b.triangle(grey, v(0., 0., 0.), v(2., 0., 0.), v(0., 2., 0.))
        .unwrap();
    b.object("lamp");
    b.quad(
        lamp,
        v(0.5, 1., 0.5),
        v(1.5, 1., 0.5),
        v(1.5, 1., 1.5),
        v(0.5, 1., 1.5),
    )
    .unwrap();
    let mut scene = b.build().unwrap();
    scene.materials[lamp as usize].emission = Rgb::splat(4.0);
    if textures {
        scene.materials[grey as usize].base_texture = Some(texture(1, 1, vec![[0.5; 3]], 1.0));
        scene.materials[lamp as usize].emissive_texture =
            Some(texture(1, 1, vec![[4.0; 3]], f64::INFINITY));
    }
    if coordinates {
        for s in &mut scene.surfaces {
            let t = uvs(&[(0.1, 0.2), (0.9, 0.3), (0.7, 0.8), (0.2, 0.6)]);
            *s = s.clone().with_uv(&t[..s.vertices.len()]);
        }
    }
    scene
}

/// The bits of every value, standard error and count of `estimates`.
fn bits<'a>(estimates: impl Iterator<Item = &'a ProbeEstimate>) -> Vec<u64> {
    estimates
        .flat_map(|e| {
            let values = e.radiosity.0.into_iter().chain(e.std_error.0);
            values.map(f64::to_bits).chain([e.paths])
        })
        .collect()
}

#[test]
fn textures_equal_to_the_constants_give_the_same_bits_at_any_thread_count() {
    // The per-point path reads the texel where the constant path reads the
    // material; with equal values every path draws and adds the same
    // numbers, so object means and probes are the same bits.
    let run = |scene: &Scene, threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let reference = Reference::new(scene).unwrap();
            let probes = [
                reference.locate(v(0.3, 0.0, 1.7), DVec3::Y).unwrap(),
                reference.locate(v(0.2, 0.3, 0.0), DVec3::Z).unwrap(),
            ];
            let s = settings(3_000);
            let means = reference.object_means(&s).unwrap();
            let at = reference.radiosity_at(&probes, &s).unwrap();
            bits(means.iter().chain(&at))
        })
    };
    let plain = run(&uniform_room(false, false), 2);
    assert!(plain.iter().filter(|b| **b != 0).count() > 20);
    for (textures, coordinates, threads) in [
        (false, true, 2),
        (true, false, 2),
        (true, true, 1),
        (true, true, 3),
    ] {
        let got = run(&uniform_room(textures, coordinates), threads);
        assert_eq!(
            got, plain,
            "textures {textures}, uv {coordinates}, {threads} threads"
        );
    }
}
