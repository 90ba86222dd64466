//! Texture detail in images and baked files: a checkered floor lit by a small
//! lamp 1.5 m above it, built in code. The floor sees only the lamp,
//! which reflects nothing, so the light arriving at a floor point is the
//! lamp's exitance times Lambert's point-to-polygon form factor: an oracle
//! independent of the solve. What is drawn must be the texel's reflectance
//! times that smooth light.

use glam::{DVec2, DVec3};
use radiosity::analytic::point_to_polygon;
use radiosity::gltf_io::{load_baked, write_baked, BakeOptions, ImportLimits};
use radiosity::math::Rgb;
use radiosity::refine::RefineSettings;
use radiosity::render::{self, HdrImage};
use radiosity::scene::{Camera, Scene, SceneBuilder, Texture};
use radiosity::{Settings, Solution};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::Arc;

const DARK: f32 = 0.2;
const BRIGHT: f32 = 0.8;
/// The lamp's emitted radiance.
const LAMP_RADIANCE: f64 = 1e3;
const LAMP_HEIGHT: f64 = 1.5;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// The lamp: a 0.4 m square facing down, off the floor's centre (so that
/// the light changes across the checker's edges), centred over (0.7, 0.8).
fn lamp() -> [DVec3; 4] {
    let (x0, x1, z0, z1, h) = (0.5, 0.9, 0.6, 1.0, LAMP_HEIGHT);
    [v(x0, h, z0), v(x1, h, z0), v(x1, h, z1), v(x0, h, z1)]
}

/// A 2x2 texture of `texels` (row-major, top row first), nearest texel.
fn texture(texels: [f32; 4]) -> Texture {
    Texture::nearest(2, 2, texels.iter().map(|&t| [t; 3]).collect())
}

fn checker() -> Texture {
    texture([DARK, BRIGHT, BRIGHT, DARK])
}

/// The floor `[0, 2]^2` facing up with texture coordinates `u = x / 2`,
/// `v = z / 2` and reflectance `rho` (the texture's mean when it has one),
/// under the lamp.
fn floor_scene(rho: f64, texture: Option<Texture>) -> Scene {
    let mut b = SceneBuilder::new("checker_images");
    let floor = b.material("floor", Rgb::splat(rho), Rgb::ZERO).unwrap();
    let lamp_m = b
        .material("lamp", Rgb::ZERO, Rgb::splat(LAMP_RADIANCE))
        .unwrap();
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
    let l = lamp();
    b.quad(lamp_m, l[0], l[1], l[2], l[3]).unwrap();
    let mut scene = b.build().unwrap();
    if let Some(t) = texture {
        scene.materials[floor as usize].base_texture = Some(Arc::new(t));
        let uv = [(0., 0.), (0., 1.), (1., 1.), (1., 0.)].map(|(u, v)| DVec2::new(u, v));
        scene.surfaces[0] = scene.surfaces[0].clone().with_uv(&uv);
    }
    scene
}

fn checkered() -> Scene {
    floor_scene(f64::from(DARK + BRIGHT) / 2.0, Some(checker()))
}

/// 11 x 11 elements of 2/11 m, not refined: the middle row and column
/// straddle the checker's edges at x = 1 and z = 1 (their reflectance is the
/// mean of the two checks), which element shading would smear out.
fn settings() -> Settings {
    Settings {
        patch_size: Some(0.19),
        refine: RefineSettings {
            uniform_depth: Some(0),
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}

fn solve(scene: &Scene) -> Solution {
    radiosity::solve(scene, &settings(), &|_| {}).unwrap()
}

/// The irradiance at floor point `(x, z)`: the lamp's exitance times the
/// point-to-polygon form factor (the only light the floor receives).
fn oracle_irradiance(x: f64, z: f64) -> f64 {
    PI * LAMP_RADIANCE * point_to_polygon(v(x, 0.0, z), DVec3::Y, &lamp()).unwrap()
}

/// The checker's reflectance at floor point `(x, z)`.
fn texel_at(x: f64, z: f64) -> f64 {
    f64::from(if (x >= 1.0) != (z >= 1.0) {
        BRIGHT
    } else {
        DARK
    })
}

const SIDE: u32 = 256;
const CAMERA_HEIGHT: f64 = 1.0;
const YFOV_DEGREES: f64 = 80.0;

/// Looking straight down at the floor's centre from 1 m, below the lamp,
/// with image up along +z: image x runs along -x.
fn camera() -> Camera {
    Camera::look_at(
        v(1.0, CAMERA_HEIGHT, 1.0),
        v(1.0, 0.0, 1.0),
        DVec3::Z,
        YFOV_DEGREES,
    )
}

/// The pixel whose centre sees floor point `(x, z)` (within half a pixel),
/// and that pixel centre's own floor point.
fn pixel_of(x: f64, z: f64) -> ((u32, u32), (f64, f64)) {
    let half = CAMERA_HEIGHT * (YFOV_DEGREES.to_radians() / 2.0).tan();
    let scale = f64::from(SIDE) / 2.0;
    let px = (scale * (1.0 - (x - 1.0) / half)).floor();
    let py = (scale * (1.0 - (z - 1.0) / half)).floor();
    let back = |p: f64| 1.0 - ((p + 0.5) / scale - 1.0) * half;
    ((px as u32, py as u32), (back(px), back(py)))
}

fn render_floor(sol: &Solution) -> HdrImage {
    render::render(&sol.radiance_mesh(), &camera(), SIDE, SIDE).unwrap()
}

/// The rendered radiance at the pixel seeing `(x, z)` (first band), and that
/// pixel's own floor point.
fn pixel(image: &HdrImage, x: f64, z: f64) -> (f64, (f64, f64)) {
    let ((px, py), at) = pixel_of(x, z);
    (image.get(px, py).0[0], at)
}

#[test]
fn pixels_are_the_texels_reflectance_times_smooth_light() {
    let sol = solve(&checkered());
    let image = render_floor(&sol);
    // One pixel is about 6.6 mm of floor.
    let step = 0.0066;
    let mut worst_ratio: f64 = 0.0;
    let mut worst_same: f64 = 0.0;
    let mut worst_oracle: f64 = 0.0;
    for z in [0.3, 0.5, 0.7, 0.9] {
        // Across the edge x = 1: dark at x < 1, bright at x > 1 (z < 1).
        let (dark, a) = pixel(&image, 1.0 - 1.5 * step, z);
        let (bright, b) = pixel(&image, 1.0 + 1.5 * step, z);
        assert!(texel_at(a.0, a.1) == f64::from(DARK) && texel_at(b.0, b.1) == f64::from(BRIGHT));
        let want = f64::from(BRIGHT) / f64::from(DARK);
        worst_ratio = worst_ratio.max((bright / dark / want - 1.0).abs());
        // Two pixels of the same check a few pixels apart see the same light.
        let (further, _) = pixel(&image, 1.0 + 4.5 * step, z);
        worst_same = worst_same.max((further / bright - 1.0).abs());
        // Against the oracle: radiance = rho(texel) * H / pi.
        for (value, (x, zz)) in [(dark, a), (bright, b)] {
            let want = texel_at(x, zz) * oracle_irradiance(x, zz) / PI;
            worst_oracle = worst_oracle.max((value / want - 1.0).abs());
        }
    }
    eprintln!(
        "bright/dark across the edge off 0.8/0.2 by {worst_ratio:.2e}; same check 3 pixels \
         apart differs by {worst_same:.2e}; pixels off rho * H_exact / pi by {worst_oracle:.2e}"
    );
    assert!(worst_ratio < 0.02, "{worst_ratio}");
    assert!(worst_same < 0.02, "{worst_same}");
    assert!(worst_oracle < 0.05, "{worst_oracle}");
}

/// The light at each display vertex of the untextured floor of mean
/// reflectance 0.5 (the old path: vertex radiosity / 0.5), by position.
fn plain_light() -> Vec<(DVec3, f64)> {
    let shading = solve(&floor_scene(0.5, None)).shading_mesh();
    shading
        .positions
        .iter()
        .zip(&shading.radiosity)
        .map(|(p, b)| (*p, b.0[0] / 0.5))
        .collect()
}

/// Whether floor point `p` lies at least one element (2/11 m) inside the
/// floor's edges, where a vertex mean of elements is a fair estimate of the
/// irradiance at the point.
fn inside(p: DVec3) -> bool {
    let e = 2.0 / 11.0 - 1e-9;
    [p.x, p.z].iter().all(|c| *c >= e && *c <= 2.0 - e)
}

#[test]
fn vertex_irradiance_is_the_smooth_light_with_no_jump_at_check_edges() {
    let sol = solve(&checkered());
    let shading = sol.shading_mesh();
    let texels = shading.texels.as_ref().expect("the floor is textured");
    let plain = plain_light();
    assert_eq!(plain.len(), shading.positions.len());
    let (mut worst_plain, mut worst_oracle): (f64, f64) = (0.0, 0.0);
    let (mut at_edges, mut floor) = (0, 0);
    for (i, p) in shading.positions.iter().enumerate() {
        if p.y.abs() > 1e-9 {
            continue;
        }
        floor += 1;
        let h = texels.irradiance[i].0[0];
        // The checker changes what the floor reflects, not the light it gets:
        // the same field as the untextured floor's, checks or no checks.
        assert_eq!(plain[i].0, *p);
        worst_plain = worst_plain.max((h / plain[i].1 - 1.0).abs());
        if inside(*p) {
            worst_oracle = worst_oracle.max((h / oracle_irradiance(p.x, p.z) - 1.0).abs());
        }
        at_edges += usize::from((p.x - 1.0).abs() < 1e-9 || (p.z - 1.0).abs() < 1e-9);
        // The coordinates are the surface's map.
        assert!((texels.uv[i] - DVec2::new(p.x / 2.0, p.z / 2.0)).length() < 1e-12);
    }
    eprintln!(
        "{floor} floor vertices ({at_edges} on check edges): H off the untextured floor's \
         light by {worst_plain:.1e}, inner ones off the exact irradiance by {worst_oracle:.2e}"
    );
    assert!(at_edges > 10 && floor > 200);
    assert!(worst_plain < 1e-9, "{worst_plain}");
    assert!(worst_oracle < 0.03, "{worst_oracle}");
}

#[test]
fn a_uniform_texture_renders_as_the_untextured_material() {
    // Same reflectance everywhere: texel times light must be the radiosity
    // the untextured path interpolates, to rounding.
    let plain = solve(&floor_scene(0.5, None));
    let uniform = solve(&floor_scene(0.5, Some(texture([0.5; 4]))));
    let a = render_floor(&plain);
    let b = render_floor(&uniform);
    let mut worst: f64 = 0.0;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for k in 0..3 {
            worst = worst.max((p[k] - q[k]).abs() / p[k].abs().max(1e-9));
        }
    }
    eprintln!("uniform texture vs untextured: worst relative pixel difference {worst:e}");
    assert!(worst < 1e-9, "{worst}");
    // And the untextured scene takes the old path: no texel data at all.
    assert!(plain.shading_mesh().texels.is_none());
    assert!(plain.radiance_mesh().texels.is_none());
}

#[test]
fn black_texels_take_the_light_of_their_neighbours() {
    // A checker of black and 0.8: black elements say nothing about the light
    // (B = E = 0), yet the vertex light stays the lamp's everywhere.
    let scene = floor_scene(0.4, Some(texture([0.0, BRIGHT, BRIGHT, 0.0])));
    let sol = solve(&scene);
    let shading = sol.shading_mesh();
    let texels = shading.texels.as_ref().unwrap();
    let plain = plain_light();
    let (mut worst, mut worst_oracle): (f64, f64) = (0.0, 0.0);
    let (mut lit, mut unknown) = (0, 0);
    for (i, p) in shading.positions.iter().enumerate() {
        if p.y.abs() > 1e-9 {
            continue;
        }
        let h = texels.irradiance[i].0[0];
        // Distance to the checks' edges; the straddling elements reach 1/11 m.
        let d = (p.x - 1.0).abs().min((p.z - 1.0).abs());
        if texel_at(p.x, p.z) == f64::from(BRIGHT) || d < 0.1 {
            // A reflecting element touches the vertex: its light is known.
            worst = worst.max((h / plain[i].1 - 1.0).abs());
            if inside(*p) {
                worst_oracle = worst_oracle.max((h / oracle_irradiance(p.x, p.z) - 1.0).abs());
            }
            lit += 1;
        } else if d > 0.2 {
            // Only black elements around: the light is unknown, 0 (and the
            // texture is black there, so nothing is lost).
            assert_eq!(h, 0.0, "at {p}");
            unknown += 1;
        }
    }
    eprintln!(
        "black checks: {lit} vertices with light, off the untextured floor's light by at \
         most {worst:.2e}, inner ones off the exact irradiance by {worst_oracle:.2e}; \
         {unknown} vertices amid black only"
    );
    assert!(lit > 100 && unknown > 20, "{lit} {unknown}");
    // Where black elements are left out of the mean, a vertex takes the
    // light of the elements on one side only: close to, not equal to, the
    // mean of all of them.
    assert!(worst < 0.08, "{worst}");
    assert!(worst_oracle < 0.06, "{worst_oracle}");
    let image = render_floor(&sol);
    let (black, _) = pixel(&image, 0.5, 0.5);
    assert_eq!(black, 0.0);
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("texture_images");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// sRGB byte to linear.
fn srgb_to_linear(b: u8) -> f64 {
    let c = f64::from(b) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The floor primitive of a baked file: per vertex position, the light (its
/// one light group's attribute times the group's scale), `TEXCOORD_0`, and
/// the base colour's texture value there (nearest texel of the decoded
/// image, times `baseColorFactor`).
fn baked_floor(path: &Path) -> Vec<(DVec3, f64, DVec2, f64)> {
    let (doc, buffers, images) = gltf::import(path).unwrap();
    let mesh = doc
        .meshes()
        .find(|m| m.name() == Some("floor"))
        .expect("floor mesh");
    let prim = mesh.primitives().next().unwrap();
    let material = prim.material();
    let pbr = material.pbr_metallic_roughness();
    let info = pbr.base_color_texture().expect("the texture is kept");
    assert_eq!(info.tex_coord(), 0);
    let factor = f64::from(pbr.base_color_factor()[0]);
    let image = &images[info.texture().source().index()];
    let extras = doc.as_json().asset.extras.as_ref().unwrap();
    let extras: serde_json::Value = serde_json::from_str(extras.get()).unwrap();
    let scale = extras["radiosity"]["groups"][0]["scale"].as_f64().unwrap();
    let reader = prim.reader(|b| Some(&buffers[b.index()]));
    let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    let group = prim
        .attributes()
        .find(|(s, _)| *s == gltf::Semantic::Extras("GROUP_0".to_string()))
        .map(|(_, a)| a)
        .expect("the light group");
    let colours: Vec<[f32; 3]> =
        gltf::accessor::Iter::<[f32; 3]>::new(group, |b| Some(&buffers[b.index()]))
            .unwrap()
            .collect();
    let uvs: Vec<[f32; 2]> = reader
        .read_tex_coords(0)
        .expect("TEXCOORD_0")
        .into_f32()
        .collect();
    assert_eq!(uvs.len(), positions.len());
    let channels = image.pixels.len() / (image.width * image.height) as usize;
    positions
        .iter()
        .zip(&colours)
        .zip(&uvs)
        .map(|((p, c), t)| {
            let uv = DVec2::new(f64::from(t[0]), f64::from(t[1]));
            let x = ((uv.x * f64::from(image.width)).floor() as u32).min(image.width - 1);
            let y = ((uv.y * f64::from(image.height)).floor() as u32).min(image.height - 1);
            let byte = image.pixels[(y * image.width + x) as usize * channels];
            let p = DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
            (
                p,
                f64::from(c[0]) * scale,
                uv,
                srgb_to_linear(byte) * factor,
            )
        })
        .collect()
}

#[test]
fn baked_files_keep_the_texture_and_colour_holds_the_light() {
    let scene = checkered();
    let sol = solve(&scene);
    let shading = sol.shading_mesh();
    let path = scratch("checker_radiosity.glb");
    write_baked(&scene, &shading, &[], &BakeOptions::default(), &path).unwrap();
    let vertices = baked_floor(&path);
    assert!(vertices.len() > 100);
    let plain = plain_light();
    let mut checked = 0;
    let (mut worst, mut worst_oracle): (f64, f64) = (0.0, 0.0);
    for (p, light, uv, texel) in &vertices {
        assert!(
            (*uv - DVec2::new(p.x / 2.0, p.z / 2.0)).length() < 1e-6,
            "{uv} at {p}"
        );
        // Away from the check edges, where the nearest texel is unambiguous.
        if (uv.x - 0.5).abs() < 1e-3 || (uv.y - 0.5).abs() < 1e-3 {
            continue;
        }
        // The texel is the checker's (to 8-bit sRGB rounding) ...
        let rho = texel_at(p.x, p.z);
        assert!(
            (texel / rho - 1.0).abs() < 0.01,
            "texel {texel} vs {rho} at {p}"
        );
        // ... and texel times the light is the drawn radiosity rho(texel) H,
        // H the untextured floor's light there (and near the exact one).
        let drawn = texel * light;
        let h = plain
            .iter()
            .find(|(q, _)| (*q - *p).length() < 1e-6)
            .map(|(_, h)| *h)
            .unwrap();
        worst = worst.max((drawn / (rho * h) - 1.0).abs());
        if inside(*p) {
            let exact = rho * oracle_irradiance(p.x, p.z);
            worst_oracle = worst_oracle.max((drawn / exact - 1.0).abs());
        }
        checked += 1;
    }
    eprintln!(
        "{checked} baked floor vertices: texture x COLOR_0 off rho * H by at most {worst:.1e} \
         (inner ones off rho * H_exact by {worst_oracle:.1e})"
    );
    assert!(checked > 50);
    // 8-bit sRGB rounds linear 0.2 by at most 0.87 %.
    assert!(worst < 0.01, "{worst}");
    assert!(worst_oracle < 0.04, "{worst_oracle}");

    // The library's own drawn radiosity at a vertex: the same product, to
    // f32 and 8-bit rounding.
    let texels = shading.texels.as_ref().unwrap();
    let material = &scene.materials[0];
    let (i, p) = shading
        .positions
        .iter()
        .enumerate()
        .find(|(_, p)| {
            p.y == 0.0 && inside(**p) && (p.x - 1.0).abs() > 0.05 && (p.z - 1.0).abs() > 0.05
        })
        .expect("an inner floor vertex off the check edges");
    let drawn = material.reflectance_at(Some(texels.uv[i])).0[0] * texels.irradiance[i].0[0];
    let baked = vertices
        .iter()
        .find(|(q, ..)| (*q - *p).length() < 1e-6)
        .map(|(_, light, _, texel)| texel * light)
        .unwrap();
    assert!((baked / drawn - 1.0).abs() < 0.01, "{baked} vs {drawn}");
}

/// Bakes `sol` (a solve of `scene`, without light groups) to `path`.
fn bake(scene: &Scene, sol: &Solution, path: &Path) {
    write_baked(
        scene,
        &sol.shading_mesh(),
        &[],
        &BakeOptions::default(),
        path,
    )
    .unwrap();
}

#[test]
fn untextured_bakes_carry_no_texture_coordinates() {
    let scene = floor_scene(0.5, None);
    let sol = solve(&scene);
    let path = scratch("plain.glb");
    bake(&scene, &sol, &path);
    let (doc, ..) = gltf::import(&path).unwrap();
    assert_eq!(doc.textures().count(), 0);
    assert_eq!(doc.images().count(), 0);
    for mesh in doc.meshes() {
        for prim in mesh.primitives() {
            assert!(prim.get(&gltf::Semantic::TexCoords(0)).is_none());
        }
    }
}

#[test]
fn textured_bakes_read_back_render_like_the_solution() {
    let scene = checkered();
    let sol = solve(&scene);
    let direct = render_floor(&sol);
    for name in ["back.glb", "back.gltf"] {
        let path = scratch(name);
        bake(&scene, &sol, &path);
        let baked = load_baked(&path, &ImportLimits::default()).unwrap();
        assert!(baked.mesh.texels.is_some(), "{name}");
        assert!(baked.warnings.is_empty(), "{:?}", baked.warnings);
        let image = render::render(&baked.mesh, &camera(), SIDE, SIDE).unwrap();
        // f32 colours and 8-bit texels: within 1 %, but for pixels on a check
        // edge, where f32 coordinates may pick the texel across it.
        let (mut off, mut lit) = (0, 0);
        for (p, q) in direct.pixels.iter().zip(&image.pixels) {
            if p[0] > 0.0 {
                lit += 1;
                off += usize::from((q[0] / p[0] - 1.0).abs() > 0.01);
            }
        }
        eprintln!("{name}: {off} of {lit} pixels off the solution's image by more than 1 %");
        assert!(lit > SIDE as usize * SIDE as usize / 2);
        assert!(off * 200 < lit, "{off} of {lit}");
    }
}
