//! Hostile scene files the importer must refuse or bound (issue 19): images
//! decoded once per file within a pixel budget (defect 4), FIFOs and other
//! non-regular files named by a URI or as the scene (defect 7), coordinates
//! beyond what the solver represents (defect 1), node matrices that are not
//! affine (defect 12). Fixtures are generated here.

use radiosity::gltf_io::{load_scene, ImportLimits};
use radiosity::scene::{Scene, SceneBuilder, MAX_COORDINATE};
use radiosity::{Error, GeometryFault};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// A fresh, empty folder for one test.
fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("hostile_import")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A glTF document under construction: one embedded buffer, triangle-list
/// meshes (one primitive each), nodes placing them.
#[derive(Default)]
struct Fixture {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
}

impl Fixture {
    /// A mesh named `name` of the triangles `points` (three per triangle),
    /// drawn in `mode` with `material`; returns its index.
    fn mesh(
        &mut self,
        name: &str,
        points: &[[f32; 3]],
        material: Option<usize>,
        mode: u32,
    ) -> usize {
        let data: Vec<u8> = points
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": data.len()}));
        self.bytes.extend_from_slice(&data);
        self.accessors.push(json!({
            "bufferView": self.views.len() - 1, "componentType": 5126,
            "count": points.len(), "type": "VEC3"
        }));
        let mut primitive =
            json!({"attributes": {"POSITION": self.accessors.len() - 1}, "mode": mode});
        if let Some(m) = material {
            primitive["material"] = json!(m);
        }
        self.meshes
            .push(json!({"name": name, "primitives": [primitive]}));
        self.meshes.len() - 1
    }

    /// A node (its JSON as given); returns its index.
    fn node(&mut self, node: Value) -> usize {
        self.nodes.push(node);
        self.nodes.len() - 1
    }

    /// The document with `materials`, every node a root of the one scene.
    fn document(&self, materials: Value) -> Value {
        json!({
            "asset": {"version": "2.0"},
            "buffers": [{
                "byteLength": self.bytes.len(),
                "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&self.bytes))
            }],
            "bufferViews": self.views,
            "accessors": self.accessors,
            "meshes": self.meshes,
            "nodes": self.nodes,
            "materials": materials,
            "scenes": [{"nodes": (0..self.nodes.len()).collect::<Vec<_>>()}],
            "scene": 0
        })
    }
}

fn write(dir: &Path, name: &str, doc: &Value) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(doc).unwrap()).unwrap();
    path
}

fn load(path: &Path) -> radiosity::Result<Scene> {
    load_scene(path, &ImportLimits::default())
}

/// A small triangle at height `y`, offset along x by `x`.
fn triangle(x: f32, y: f32) -> [[f32; 3]; 3] {
    [[x, y, 0.0], [x, y, 0.1], [x + 0.1, y, 0.0]]
}

/// A PNG of `w` x `h` texels whose red channel runs 0..255 along x and whose
/// green and blue are fixed.
fn gradient_png(w: u32, h: u32) -> (Vec<u8>, Vec<[u8; 3]>) {
    let texels: Vec<[u8; 3]> = (0..h)
        .flat_map(|_| (0..w).map(move |x| [(x * 255 / (w - 1)) as u8, 128, 40]))
        .collect();
    let image =
        image::RgbImage::from_raw(w, h, texels.iter().flatten().copied().collect()).unwrap();
    let mut png = std::io::Cursor::new(Vec::new());
    image.write_to(&mut png, image::ImageFormat::Png).unwrap();
    (png.into_inner(), texels)
}

/// The linear value of an 8-bit sRGB channel, in the test's own words.
fn linear(c: u8) -> f64 {
    let s = f64::from(c) / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn forty_materials_sharing_one_image_decode_it_once() {
    let dir = folder("shared_image");
    let (png, texels) = gradient_png(256, 128);
    std::fs::write(dir.join("shared.png"), &png).unwrap();
    let mut f = Fixture::default();
    let mut materials = Vec::new();
    let mut textures = Vec::new();
    for i in 0..40 {
        let mesh = f.mesh(&format!("tile{i}"), &triangle(i as f32, 0.0), Some(i), 4);
        f.node(json!({"mesh": mesh}));
        // One texture per material, all showing image 0.
        textures.push(json!({"source": 0}));
        materials.push(json!({
            "name": format!("m{i}"),
            "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "baseColorTexture": {"index": i}},
            "emissiveTexture": {"index": i}
        }));
    }
    let mut doc = f.document(json!(materials));
    doc["images"] = json!([{"uri": "shared.png"}]);
    doc["textures"] = json!(textures);
    let scene = load(&write(&dir, "tiles.gltf", &doc)).unwrap();
    assert_eq!(scene.import_stats.images_decoded, 1);
    assert_eq!(scene.import_stats.texture_pixels, 256 * 128);
    // Its triangles have no texture coordinates: the texture's mean is
    // used, with a warning per material, but no texture is ignored.
    assert!(
        !scene.warnings.iter().any(|w| w.contains("ignored")),
        "{:?}",
        scene.warnings
    );
    let mean: Vec<f64> = (0..3)
        .map(|k| texels.iter().map(|t| linear(t[k])).sum::<f64>() / texels.len() as f64)
        .collect();
    for m in &scene.materials {
        for (got, want) in m.reflectance.0.iter().zip(&mean) {
            assert!((got - 0.5 * want).abs() < 1e-6, "{m:?} vs {mean:?}");
        }
        // No emissive factor: the emissive texture multiplies zero.
        assert!(!m.is_emitter());
    }
}

#[test]
fn textures_of_materials_no_triangle_uses_are_not_decoded() {
    let dir = folder("unused");
    let (png, _) = gradient_png(8, 8);
    std::fs::write(dir.join("t.png"), &png).unwrap();
    let mut f = Fixture::default();
    let room = f.mesh("plain", &triangle(0.0, 0.0), Some(0), 4);
    f.node(json!({"mesh": room}));
    // Material 2 is used only by a primitive of points, which is skipped.
    let dots = f.mesh("dots", &triangle(1.0, 0.0), Some(2), 0);
    f.node(json!({"mesh": dots}));
    let textured = |name: &str| {
        json!({"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [0.4, 0.4, 0.4, 1.0], "baseColorTexture": {"index": 0}}})
    };
    let mut doc = f.document(json!([
        {"name": "plain"},
        textured("nobody's"),
        textured("points only")
    ]));
    doc["images"] = json!([{"uri": "t.png"}]);
    doc["textures"] = json!([{"source": 0}]);
    let scene = load(&write(&dir, "unused.gltf", &doc)).unwrap();
    assert_eq!(scene.import_stats.images_decoded, 0);
    assert_eq!(scene.import_stats.texture_pixels, 0);
    assert_eq!(scene.materials[1].reflectance.0, [0.4; 3]);
}

#[test]
fn the_texture_pixel_limit_counts_every_image_of_a_file() {
    let dir = folder("budget");
    let (png, _) = gradient_png(4, 4);
    std::fs::write(dir.join("a.png"), &png).unwrap();
    std::fs::write(dir.join("b.png"), &png).unwrap();
    let mut f = Fixture::default();
    for i in 0..2 {
        let mesh = f.mesh(&format!("tile{i}"), &triangle(i as f32, 0.0), Some(i), 4);
        f.node(json!({"mesh": mesh}));
    }
    let textured = |t: usize| json!({"pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorTexture": {"index": t}}});
    let mut doc = f.document(json!([textured(0), textured(1)]));
    doc["images"] = json!([{"uri": "a.png", "name": "first"}, {"uri": "b.png", "name": "second"}]);
    doc["textures"] = json!([{"source": 0}, {"source": 1}]);
    let path = write(&dir, "two.gltf", &doc);
    // Each image alone is within the limit, both together are not: the
    // second is reduced to the 4 texels left, 2 x 2 blocks averaged.
    let limits = ImportLimits {
        max_texture_pixels: 20,
        ..ImportLimits::default()
    };
    let scene = load_scene(&path, &limits).unwrap();
    assert_eq!(scene.import_stats.images_decoded, 2);
    assert_eq!(scene.import_stats.texture_pixels, 20);
    let warning = scene
        .warnings
        .iter()
        .find(|w| w.contains("reduced"))
        .expect("the second image is reduced with a warning");
    assert!(
        warning.contains("image 1 ('second')")
            && warning.contains("from 4 x 4 to 2 x 2")
            && warning.contains("limit of 20"),
        "{warning}"
    );
    // Averaging keeps the mean: both materials reflect alike.
    let (a, b) = (
        scene.materials[0].reflectance.0,
        scene.materials[1].reflectance.0,
    );
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() < 1e-6, "{a:?} {b:?}");
    }
    // A file whose budget is spent on the first image ignores the second,
    // naming it.
    let limits = ImportLimits {
        max_texture_pixels: 16,
        ..ImportLimits::default()
    };
    let scene = load_scene(&path, &limits).unwrap();
    let warning = scene
        .warnings
        .iter()
        .find(|w| w.contains("texture ignored"))
        .expect("the second image is ignored with a warning");
    assert!(
        warning.contains("image 1 ('second')") && warning.contains("are spent"),
        "{warning}"
    );
    // The texture left out, the white factor is clamped like any other.
    assert_eq!(
        scene.materials[1].reflectance.0,
        [radiosity::gltf_io::DEFAULT_MAX_REFLECTANCE; 3]
    );
}

/// The fixtures leave out POSITION's min and max, which glTF requires but the
/// importer does not need: a warning, not an error.
#[test]
fn missing_position_bounds_are_only_a_warning() {
    let dir = folder("bounds");
    let mut f = Fixture::default();
    let mesh = f.mesh("m", &triangle(0.0, 0.0), Some(0), 4);
    f.node(json!({"mesh": mesh}));
    let scene = load(&write(&dir, "no_bounds.gltf", &f.document(json!([{}])))).unwrap();
    assert_eq!(scene.surfaces.len(), 1);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("POSITION") && w.contains(".min") && w.contains("not needed here")),
        "{:?}",
        scene.warnings
    );
}

/// The unit room's floor, so that a far triangle is not the only surface.
fn floor_and(far_scale: f64) -> Value {
    let mut f = Fixture::default();
    let floor = f.mesh(
        "floor_mesh",
        &[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
        Some(0),
        4,
    );
    f.node(json!({"name": "floor", "mesh": floor}));
    let far = f.mesh(
        "far_mesh",
        &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        Some(0),
        4,
    );
    f.node(json!({"name": "far", "mesh": far, "scale": [far_scale, far_scale, far_scale]}));
    f.document(json!([{"name": "grey"}]))
}

#[test]
fn coordinates_beyond_the_solvers_range_are_an_error_naming_node_and_mesh() {
    let dir = folder("far");
    // World coordinates 1e20: finite in f64, beyond what the f32 BVH builds.
    let e = load(&write(&dir, "far.gltf", &floor_and(1e20))).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, Error::Gltf { .. }), "{text}");
    for expected in ["far.gltf", "node 1 ('far')", "mesh 1 ('far_mesh')", "1e15"] {
        assert!(text.contains(expected), "'{expected}' not in: {text}");
    }
    // Just inside the bound the file loads.
    let scene = load(&write(&dir, "near.gltf", &floor_and(MAX_COORDINATE))).unwrap();
    assert_eq!(scene.surfaces.len(), 2);
    // A scene built in code meets the same bound.
    let mut b = SceneBuilder::new("far");
    let m = b
        .material(
            "grey",
            radiosity::math::Rgb::splat(0.5),
            radiosity::math::Rgb::ZERO,
        )
        .unwrap();
    b.object("far");
    let x = 2.0 * MAX_COORDINATE;
    let far = [
        glam::DVec3::new(x, 0.0, 0.0),
        glam::DVec3::new(x, 1.0, 0.0),
        glam::DVec3::new(x, 0.0, 1.0),
    ];
    assert!(matches!(
        b.polygon(m, &far),
        Err(Error::Geometry {
            fault: GeometryFault::OutOfRange,
            ..
        })
    ));
}

#[test]
fn a_node_matrix_that_is_not_affine_is_refused_by_name() {
    let dir = folder("matrix");
    let mut f = Fixture::default();
    let mesh = f.mesh("m", &triangle(0.0, 0.0), Some(0), 4);
    f.node(json!({"name": "bent", "mesh": mesh}));
    let affine = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 2.0, 3.0, 4.0, 1.0,
    ];
    let mut doc = f.document(json!([{"name": "grey"}]));
    doc["nodes"][0]["matrix"] = json!(affine);
    assert!(load(&write(&dir, "affine.gltf", &doc)).is_ok());
    // Bottom rows (elements 3, 7, 11, 15 of the column-major array) that
    // make the matrix projective.
    for (k, value) in [(3, 0.5), (7, -1.0), (11, 1e-3), (15, 2.0)] {
        let mut m = affine;
        m[k] = value;
        doc["nodes"][0]["matrix"] = json!(m);
        let e = load(&write(&dir, "projective.gltf", &doc)).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("node 0 ('bent')") && text.contains("bottom row"),
            "{text}"
        );
    }
}

/// Loads `path` on another thread and returns its outcome, failing the test
/// (instead of hanging the suite) if the load does not return. The limit is
/// generous: the assertion is on the outcome, not on the time.
#[cfg(unix)]
fn load_without_hanging(path: PathBuf) -> radiosity::Result<Scene> {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = send.send(load(&path));
    });
    receive
        .recv_timeout(std::time::Duration::from_secs(120))
        .expect("the load blocked on a FIFO")
}

#[cfg(unix)]
fn make_fifo(path: &Path) {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).unwrap();
    // SAFETY: `c` is a valid NUL-terminated path for the duration of the call.
    let status = unsafe { libc::mkfifo(c.as_ptr(), 0o600) };
    assert_eq!(status, 0, "mkfifo {}", path.display());
}

#[cfg(unix)]
#[test]
fn a_fifo_named_by_a_buffer_uri_is_refused_without_blocking() {
    let dir = folder("fifo_buffer");
    make_fifo(&dir.join("fifo.bin"));
    let mut f = Fixture::default();
    let mesh = f.mesh("m", &triangle(0.0, 0.0), Some(0), 4);
    f.node(json!({"mesh": mesh}));
    let mut doc = f.document(json!([{"name": "grey"}]));
    doc["buffers"][0]["uri"] = json!("fifo.bin");
    let e = load_without_hanging(write(&dir, "fifo_buffer.gltf", &doc)).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("'fifo.bin'") && text.contains("FIFO"),
        "{text}"
    );
    // A folder where the buffer should be is refused the same way.
    std::fs::create_dir(dir.join("folder.bin")).unwrap();
    doc["buffers"][0]["uri"] = json!("folder.bin");
    let e = load_without_hanging(write(&dir, "folder_buffer.gltf", &doc)).unwrap_err();
    assert!(e.to_string().contains("a folder"), "{e}");
}

#[cfg(unix)]
#[test]
fn a_fifo_named_by_an_image_uri_is_refused_without_blocking() {
    let dir = folder("fifo_image");
    make_fifo(&dir.join("fifo.png"));
    let mut f = Fixture::default();
    let mesh = f.mesh("m", &triangle(0.0, 0.0), Some(0), 4);
    f.node(json!({"mesh": mesh}));
    let mut doc = f.document(json!([
        {"name": "textured", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorTexture": {"index": 0}}}
    ]));
    doc["images"] = json!([{"uri": "fifo.png"}]);
    doc["textures"] = json!([{"source": 0}]);
    let e = load_without_hanging(write(&dir, "fifo_image.gltf", &doc)).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("'fifo.png'") && text.contains("FIFO"),
        "{text}"
    );
}

#[cfg(unix)]
#[test]
fn a_scene_file_that_is_a_fifo_is_refused_without_blocking() {
    let dir = folder("fifo_scene");
    let path = dir.join("scene.gltf");
    make_fifo(&path);
    let e = load_without_hanging(path).unwrap_err();
    assert!(e.to_string().contains("FIFO"), "{e}");
}
