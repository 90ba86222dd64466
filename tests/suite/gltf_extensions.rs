//! glTF extensions (issue 51): each extension the importer honours, warns
//! about or refuses, on a file built here (or, for Draco and KTX2, on the
//! small files `scripts/fixtures/make_compressed.mjs` made with gltf-pipeline
//! and basisu, checked against the values that script wrote into them).

use glam::{DVec2, DVec3};
use radiosity::gltf_io::{load_scene, ImportLimits};
use radiosity::scene::Scene;
use serde_json::{json, Value};
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// A fresh, empty folder for one test.
fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("gltf_extensions")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

/// The sRGB transfer function, inverted (the test's own).
fn linear(byte: u8) -> f64 {
    let c = f64::from(byte) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A unit square in z = 0 facing +z (two triangles), with texture
/// coordinates u = x, v = 1 - y, using material 0; `materials`, `textures`
/// and `images` as given, the rest of the document in `extra`.
fn square(materials: Value, textures: Value, images: Value, extra: Value) -> Value {
    let positions: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
    let uvs: [[f32; 2]; 4] = [[0., 1.], [1., 1.], [1., 0.], [0., 0.]];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    bytes.extend(uvs.iter().flatten().flat_map(|c| c.to_le_bytes()));
    bytes.extend(indices.iter().flat_map(|c| c.to_le_bytes()));
    let mut doc = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bytes.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bytes))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "meshes": [{"name": "square", "primitives": [{
            "attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "nodes": [{"name": "square", "mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
        "materials": materials,
        "textures": textures,
        "images": images
    });
    for (k, v) in extra.as_object().unwrap() {
        doc[k] = v.clone();
    }
    doc
}

fn write(dir: &Path, name: &str, doc: &Value) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(doc).unwrap()).unwrap();
    path
}

fn load(path: &Path) -> radiosity::Result<Scene> {
    load_scene(path, &ImportLimits::default())
}

/// An RGBA image encoded as `format`, `pixel(x, y)` per texel.
fn encoded(
    w: u32,
    h: u32,
    format: image::ImageFormat,
    pixel: impl Fn(u32, u32) -> [u8; 4],
) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| image::Rgba(pixel(x, y)));
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, format).unwrap();
    out.into_inner()
}

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::encode(bytes))
}

fn warned<'a>(scene: &'a Scene, words: &[&str]) -> Vec<&'a String> {
    scene
        .warnings
        .iter()
        .filter(|w| words.iter().all(|x| w.contains(x)))
        .collect()
}

/// Two texels across: red on the left, blue on the right (nearest filter).
fn red_blue() -> (Value, Value) {
    let png = encoded(2, 1, image::ImageFormat::Png, |x, _| {
        if x == 0 {
            [255, 0, 0, 255]
        } else {
            [0, 0, 255, 255]
        }
    });
    (
        json!([{"uri": data_uri("image/png", &png)}]),
        json!([{"source": 0, "sampler": 0}]),
    )
}

#[test]
fn a_required_texture_transform_is_accepted_and_moves_the_texture() {
    let dir = folder("transform");
    let (images, textures) = red_blue();
    let material = json!([{"name": "shifted", "pbrMetallicRoughness": {"metallicFactor": 0.0,
        "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform":
            {"offset": [0.5, 0.0], "scale": [0.5, 1.0]}}}}}]);
    let extra = json!({
        "extensionsUsed": ["KHR_texture_transform"],
        "extensionsRequired": ["KHR_texture_transform"],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}]
    });
    let doc = square(material, textures, images, extra);
    let scene = load(&write(&dir, "transform.gltf", &doc)).expect("a required transform is read");
    assert!(
        warned(&scene, &["KHR_texture_transform"]).is_empty(),
        "{:?}",
        scene.warnings
    );
    let texture = scene.materials[0].base_texture.as_ref().expect("textured");
    // u = 0.25 maps to 0.5 + 0.25 * 0.5 = 0.625: the right (blue) texel;
    // without the transform it would be the left (red) one.
    let value = texture.value_at(DVec2::new(0.25, 0.5));
    assert_eq!(value.0[0], 0.0, "{value:?}");
    assert!(value.0[2] > 0.9, "{value:?}");
}

#[test]
fn an_unknown_or_instancing_requirement_is_refused_naming_it() {
    let dir = folder("required");
    for (name, words) in [
        ("EXT_made_up_here", "does not know"),
        ("EXT_mesh_gpu_instancing", "instances would be missing"),
    ] {
        let doc = square(
            json!([{"name": "grey"}]),
            json!([]),
            json!([]),
            json!({"extensionsUsed": [name], "extensionsRequired": [name]}),
        );
        let path = write(&dir, &format!("{name}.gltf"), &doc);
        let e = load(&path).expect_err("refused").to_string();
        assert!(
            e.contains(name) && e.contains(words) && e.contains(".gltf"),
            "{e}"
        );
        // Used, not required: a warning, the scene loads.
        let doc = square(
            json!([{"name": "grey"}]),
            json!([]),
            json!([]),
            json!({"extensionsUsed": [name]}),
        );
        let scene = load(&write(&dir, &format!("{name}_used.gltf"), &doc)).unwrap();
        assert_eq!(warned(&scene, &[name]).len(), 1, "{:?}", scene.warnings);
    }
}

#[test]
fn material_extensions_are_warned_once_each_and_keep_the_diffuse_colour() {
    let dir = folder("materials");
    let glass = |name: &str| {
        json!({"name": name, "pbrMetallicRoughness": {"metallicFactor": 0.0,
            "baseColorFactor": [0.2, 0.4, 0.6, 1.0]},
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                           "KHR_materials_volume": {"thicknessFactor": 0.1},
                           "KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1]}}})
    };
    let doc = square(
        json!([glass("a"), glass("b")]),
        json!([]),
        json!([]),
        json!({"extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume",
                                   "KHR_materials_sheen"],
               "extensionsRequired": ["KHR_materials_transmission"]}),
    );
    let scene = load(&write(&dir, "glass.gltf", &doc)).expect("required transmission still loads");
    for name in [
        "KHR_materials_transmission",
        "KHR_materials_volume",
        "KHR_materials_sheen",
    ] {
        let w = warned(&scene, &[name]);
        assert_eq!(w.len(), 1, "{name}: {:?}", scene.warnings);
        assert!(w[0].contains("diffuse base colour"), "{}", w[0]);
    }
    assert_eq!(scene.materials[0].reflectance.0, [0.2, 0.4, 0.6]);
}

#[test]
fn blend_is_warned_opaque_naming_the_material() {
    let dir = folder("blend");
    let doc = square(
        json!([{"name": "glow cone", "alphaMode": "BLEND",
            "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [1, 1, 1, 0.05]}}]),
        json!([]),
        json!([]),
        json!({}),
    );
    let scene = load(&write(&dir, "blend.gltf", &doc)).unwrap();
    let w = warned(&scene, &["BLEND", "'glow cone' (alpha 0.050)", "opaque"]);
    assert_eq!(w.len(), 1, "{:?}", scene.warnings);
    assert!(
        (area(&scene) - 1.0).abs() < 1e-9,
        "the whole square is kept"
    );
}

/// The area of the surfaces of `scene` (each side once: the test's squares
/// are single-sided).
fn area(scene: &Scene) -> f64 {
    scene
        .surfaces
        .iter()
        .map(|s| {
            let v = &s.vertices;
            (1..v.len() - 1)
                .map(|k| 0.5 * (v[k] - v[0]).cross(v[k + 1] - v[0]).length())
                .sum::<f64>()
        })
        .sum()
}

#[test]
fn mask_cuts_away_where_the_alpha_is_below_the_cutoff() {
    let dir = folder("mask");
    // 32 texels across: alpha 0 where x < 8 (the left quarter), 255 beyond.
    let png = encoded(32, 1, image::ImageFormat::Png, |x, _| {
        [90, 160, 40, if x < 8 { 0 } else { 255 }]
    });
    let material = |cutoff: f64, factor_alpha: f64| {
        json!([{"name": "leaf", "alphaMode": "MASK", "alphaCutoff": cutoff,
            "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [1, 1, 1, factor_alpha],
                "baseColorTexture": {"index": 0}}}])
    };
    let images = json!([{"uri": data_uri("image/png", &png)}]);
    let textures = json!([{"source": 0, "sampler": 0}]);
    let extra = json!({"samplers": [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}]});
    let doc = square(
        material(0.5, 1.0),
        textures.clone(),
        images.clone(),
        extra.clone(),
    );
    let scene = load(&write(&dir, "leaf.gltf", &doc)).unwrap();
    // Three quarters of the unit square are opaque. The lattice (a division
    // every two texels along the longest edge: 17 here) samples the
    // nearest-texel alpha and places the step between its lines: within one
    // division, 1/17 of the side, of x = 1/4.
    let division = 1.0 / 17.0;
    let kept = area(&scene);
    assert!((kept - 0.75).abs() <= division, "{kept}");
    for s in &scene.surfaces {
        for p in s.vertices.iter() {
            assert!(p.x >= 0.25 - division, "a piece in the hole: {p}");
        }
    }
    let w = warned(&scene, &["'leaf'", "alphaMode MASK", "cut"]);
    assert_eq!(w.len(), 1, "{:?}", scene.warnings);
    // The factor's alpha times the texture's: at 0.4 nothing reaches 0.5.
    let doc = square(material(0.5, 0.4), textures, images, extra);
    let e = load(&write(&dir, "faded.gltf", &doc)).expect_err("nothing is left");
    assert!(e.to_string().contains("no surfaces"), "{e}");
}

#[test]
fn a_webp_texture_is_read_through_its_extension() {
    let dir = folder("webp");
    let webp = encoded(2, 2, image::ImageFormat::WebP, |x, _| {
        if x == 0 {
            [200, 100, 50, 255]
        } else {
            [50, 100, 200, 255]
        }
    });
    let doc = square(
        json!([{"name": "webp", "pbrMetallicRoughness": {"metallicFactor": 0.0,
            "baseColorTexture": {"index": 0}}}]),
        json!([{"extensions": {"EXT_texture_webp": {"source": 0}}}]),
        json!([{"uri": data_uri("image/webp", &webp)}]),
        json!({"extensionsUsed": ["EXT_texture_webp"], "extensionsRequired": ["EXT_texture_webp"]}),
    );
    let scene = load(&write(&dir, "webp.gltf", &doc)).unwrap();
    assert_eq!(scene.import_stats.images_decoded, 1);
    // Lossless WebP: the mean of the two columns' linear values.
    let expected = [
        (linear(200) + linear(50)) / 2.0,
        linear(100),
        (linear(50) + linear(200)) / 2.0,
    ];
    let got = scene.materials[0].reflectance.0;
    for (g, e) in got.iter().zip(expected) {
        assert!((g - e).abs() < 1e-6, "{got:?} {expected:?}");
    }
}

#[test]
fn an_undecodable_texture_falls_back_to_its_factor_naming_the_image() {
    let dir = folder("broken_ktx2");
    // A KTX2 identifier followed by nothing a transcoder can read.
    let mut bytes = vec![
        0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
    ];
    bytes.extend([7u8; 40]);
    let doc = square(
        json!([{"name": "painted", "pbrMetallicRoughness": {"metallicFactor": 0.0,
            "baseColorFactor": [0.3, 0.6, 0.9, 1.0], "baseColorTexture": {"index": 0}}}]),
        json!([{"extensions": {"KHR_texture_basisu": {"source": 0}}}]),
        json!([{"name": "bricks", "uri": data_uri("image/ktx2", &bytes)}]),
        json!({"extensionsUsed": ["KHR_texture_basisu"], "extensionsRequired": ["KHR_texture_basisu"]}),
    );
    let scene = load(&write(&dir, "broken.gltf", &doc)).expect("never refused over a texture");
    let w = warned(
        &scene,
        &["'painted'", "image 0 ('bricks')", "baseColorFactor alone"],
    );
    assert_eq!(w.len(), 1, "{:?}", scene.warnings);
    assert_eq!(scene.materials[0].reflectance.0, [0.3, 0.6, 0.9]);
}

/// The KTX2 fixtures' texture: sRGB (200, 40, 40) where x < 4, (40, 40, 200)
/// beyond, 8 x 8 texels; the mean in linear values.
fn ktx2_mean() -> [f64; 3] {
    let (hi, lo) = (linear(200), linear(40));
    [(hi + lo) / 2.0, lo, (hi + lo) / 2.0]
}

#[test]
fn ktx2_etc1s_and_uastc_textures_decode_to_the_colours_they_were_made_from() {
    for (file, tolerance) in [("square_etc1s.glb", 6u8), ("square_uastc.glb", 2u8)] {
        let scene = load(&fixture(file)).unwrap();
        assert_eq!(scene.import_stats.images_decoded, 1, "{file}");
        assert_eq!(scene.import_stats.texture_pixels, 64, "{file}");
        let texture = scene.materials[0].base_texture.as_ref().expect("decoded");
        let image = &texture.image;
        assert_eq!((image.width, image.height), (8, 8));
        // Each texel within `tolerance` sRGB steps of what was encoded.
        for y in 0..8 {
            for x in 0..8 {
                let want = if x < 4 {
                    [200u8, 40, 40]
                } else {
                    [40, 40, 200]
                };
                for (got, want) in image.texel(x, y).iter().zip(want) {
                    let (lo, hi) = (
                        linear(want.saturating_sub(tolerance)),
                        linear(want.saturating_add(tolerance)),
                    );
                    assert!(
                        (lo - 1e-6..=hi + 1e-6).contains(&f64::from(*got)),
                        "{file} texel ({x}, {y}): {got} not within {tolerance} steps of {want}"
                    );
                }
            }
        }
        let mean = scene.materials[0].reflectance.0;
        for (m, e) in mean.iter().zip(ktx2_mean()) {
            assert!((m - e).abs() < 0.03, "{file}: {mean:?}");
        }
    }
}

#[test]
fn a_texture_over_the_budget_is_reduced_not_dropped() {
    // The UASTC fixture has mip levels 8, 4, 2, 1: a budget of 20 texels
    // takes the 4 x 4 level.
    let limits = ImportLimits {
        max_texture_pixels: 20,
        ..ImportLimits::default()
    };
    let scene = load_scene(&fixture("square_uastc.glb"), &limits).unwrap();
    let image = &scene.materials[0]
        .base_texture
        .as_ref()
        .expect("kept")
        .image;
    assert_eq!((image.width, image.height), (4, 4));
    assert_eq!(scene.import_stats.texture_pixels, 16);
    let w = warned(&scene, &["reduced from 8 x 8 to 4 x 4", "limit of 20"]);
    assert_eq!(w.len(), 1, "{:?}", scene.warnings);
    for (m, e) in scene.materials[0].reflectance.0.iter().zip(ktx2_mean()) {
        assert!((m - e).abs() < 0.03, "the mean survives: {m} {e}");
    }
}

/// The Draco fixture's source grid: vertex (i, j) at (i / 4, j / 3, 0.1 i j)
/// for i in 0..5, j in 0..4; cell (i, j) split into (a, b, d) and (a, d, c)
/// with a = (i, j), b = (i + 1, j), c = (i, j + 1), d = (i + 1, j + 1).
fn grid_triangles() -> Vec<[DVec3; 3]> {
    let p = |i: usize, j: usize| DVec3::new(i as f64 / 4.0, j as f64 / 3.0, 0.1 * (i * j) as f64);
    let mut out = Vec::new();
    for j in 0..3 {
        for i in 0..4 {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i, j + 1), p(i + 1, j + 1));
            out.push([a, b, d]);
            out.push([a, d, c]);
        }
    }
    out
}

#[test]
fn a_draco_file_decodes_to_the_grid_it_was_compressed_from() {
    let scene = load(&fixture("grid_draco.glb")).unwrap();
    let expected = grid_triangles();
    assert_eq!(scene.import_stats.triangles_read, expected.len());
    // The grid's cells are not planar (z = 0.1 i j), so no pair merges.
    assert_eq!(scene.surfaces.len(), expected.len());
    // gltf-pipeline quantizes positions to 11 bits over the largest side
    // (1 m): within 1 / 2047 m of the source, corner by corner.
    let tolerance = 1.0 / 2047.0;
    for want in &expected {
        let found = scene.surfaces.iter().any(|s| {
            (0..3).any(|rot| {
                (0..3).all(|k| (s.vertices[(k + rot) % 3] - want[k]).length() <= tolerance)
            })
        });
        assert!(found, "triangle {want:?} (counter-clockwise) not decoded");
    }
}
