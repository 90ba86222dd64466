//! glTF import: geometry, transforms, primitive modes, quad merging, materials,
//! cameras, and an error (never a panic) for every kind of bad input. Test files are
//! built in code and written under the target directory.

use glam::DVec3;
use radiosity::gltf_io::{load_scene, load_scene_with, ImportLimits, LoadOptions};
use radiosity::scene::Overlaps;
use radiosity::scene::Scene;
use radiosity::{Error, GeometryFault, GltfKind, GltfObject, LimitKind};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------
// Building test files
// ---------------------------------------------------------------------------

fn dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf_import");
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Binary data plus the buffer views and accessors that describe it.
#[derive(Default)]
struct Bin {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    fn view(&mut self, data: &[u8]) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(data);
        self.views
            .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len()}));
        self.views.len() - 1
    }

    fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        let data: Vec<u8> = p.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
        let view = self.view(&data);
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for v in p {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        self.accessors.push(json!({
            "bufferView": view, "componentType": 5126, "count": p.len(), "type": "VEC3",
            "min": lo, "max": hi
        }));
        self.accessors.len() - 1
    }

    fn indices(&mut self, ix: &[u32]) -> usize {
        let data: Vec<u8> = ix.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&data);
        self.accessors.push(json!({
            "bufferView": view, "componentType": 5125, "count": ix.len(), "type": "SCALAR"
        }));
        self.accessors.len() - 1
    }

    /// A complete document: `rest` supplies meshes, nodes, scenes, materials...
    fn document(self, rest: Value) -> Value {
        let mut doc = json!({
            "asset": {"version": "2.0"},
            "buffers": [{
                "byteLength": self.bytes.len(),
                "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&self.bytes))
            }],
            "bufferViews": self.views,
            "accessors": self.accessors,
        });
        for (k, v) in rest.as_object().expect("object").clone() {
            doc[k] = v;
        }
        doc
    }
}

fn write(name: &str, doc: &Value) -> PathBuf {
    let path = dir().join(name);
    std::fs::write(&path, serde_json::to_vec_pretty(doc).unwrap()).unwrap();
    path
}

fn load(path: &Path) -> radiosity::Result<Scene> {
    load_scene(path, &ImportLimits::default())
}

/// One mesh of one primitive on one node.
fn one_primitive(p: &[[f32; 3]], indices: Option<&[u32]>, mode: u32) -> Value {
    let mut bin = Bin::default();
    let pos = bin.positions(p);
    let mut prim = json!({"attributes": {"POSITION": pos}, "mode": mode, "material": 0});
    if let Some(ix) = indices {
        prim["indices"] = json!(bin.indices(ix));
    }
    bin.document(json!({
        "materials": [{"name": "grey", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.5, 0.5, 0.5, 1.0]}}],
        "meshes": [{"name": "m", "primitives": [prim]}],
        "nodes": [{"name": "n", "mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    }))
}

/// A binary glTF container around `json` and `bin`.
fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let mut out = b"glTF".to_vec();
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    for (kind, data, pad) in [(b"JSON", json, b' '), (b"BIN\0", bin, 0u8)] {
        let padded = (data.len() + 3) & !3;
        out.extend_from_slice(&(padded as u32).to_le_bytes());
        out.extend_from_slice(kind);
        out.extend_from_slice(data);
        out.resize(out.len() + padded - data.len(), pad);
    }
    let total = out.len() as u32;
    out[8..12].copy_from_slice(&total.to_le_bytes());
    out
}

fn vertices(scene: &Scene) -> Vec<Vec<DVec3>> {
    scene.surfaces.iter().map(|s| s.vertices.to_vec()).collect()
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn assert_close(a: DVec3, b: DVec3, tol: f64) {
    assert!((a - b).length() <= tol, "{a} != {b}");
}

/// The error for `path`, whose message must name the file and `expected`.
fn error_naming(path: &Path, expected: &str) -> Error {
    let e = load(path).expect_err("bad input must be an error");
    let text = e.to_string();
    let file = path.file_name().unwrap().to_string_lossy();
    assert!(
        text.contains(&*file),
        "message does not name the file: {text}"
    );
    assert!(
        text.contains(expected),
        "message does not say '{expected}': {text}"
    );
    e
}

// ---------------------------------------------------------------------------
// The Cornell box file
// ---------------------------------------------------------------------------

/// Twice the area vector of a polygon (Newell), in the test's own words.
fn area_mm2(p: &[[f64; 3]]) -> f64 {
    let mut n = [0.0; 3];
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        n[0] += a[1] * b[2] - a[2] * b[1];
        n[1] += a[2] * b[0] - a[0] * b[2];
        n[2] += a[0] * b[1] - a[1] * b[0];
    }
    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}

/// A non-planar quad as two triangles split along the shorter diagonal.
fn split_area_mm2(q: &[[f64; 3]; 4]) -> f64 {
    let d = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    if d(q[0], q[2]) <= d(q[1], q[3]) {
        area_mm2(&[q[0], q[1], q[2]]) + area_mm2(&[q[0], q[2], q[3]])
    } else {
        area_mm2(&[q[0], q[1], q[3]]) + area_mm2(&[q[1], q[2], q[3]])
    }
}

#[test]
fn cornell_box_file_has_the_published_areas() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell_box.gltf");
    let scene = load(&path).expect("the committed Cornell box loads");
    // Published vertex table (millimetres), as in the Cornell data page.
    let ceiling = [
        [556.0, 548.8, 0.0],
        [556.0, 548.8, 559.2],
        [0.0, 548.8, 559.2],
        [0.0, 548.8, 0.0],
    ];
    let back = [
        [549.6, 0.0, 559.2],
        [0.0, 0.0, 559.2],
        [0.0, 548.8, 559.2],
        [556.0, 548.8, 559.2],
    ];
    let right = [
        [0.0, 0.0, 559.2],
        [0.0, 0.0, 0.0],
        [0.0, 548.8, 0.0],
        [0.0, 548.8, 559.2],
    ];
    let left = [
        [552.8, 0.0, 0.0],
        [549.6, 0.0, 559.2],
        [556.0, 548.8, 559.2],
        [556.0, 548.8, 0.0],
    ];
    let short_block: [[[f64; 3]; 4]; 5] = [
        [
            [130.0, 165.0, 65.0],
            [82.0, 165.0, 225.0],
            [240.0, 165.0, 272.0],
            [290.0, 165.0, 114.0],
        ],
        [
            [290.0, 0.0, 114.0],
            [290.0, 165.0, 114.0],
            [240.0, 165.0, 272.0],
            [240.0, 0.0, 272.0],
        ],
        [
            [130.0, 0.0, 65.0],
            [130.0, 165.0, 65.0],
            [290.0, 165.0, 114.0],
            [290.0, 0.0, 114.0],
        ],
        [
            [82.0, 0.0, 225.0],
            [82.0, 165.0, 225.0],
            [130.0, 165.0, 65.0],
            [130.0, 0.0, 65.0],
        ],
        [
            [240.0, 0.0, 272.0],
            [240.0, 165.0, 272.0],
            [82.0, 165.0, 225.0],
            [82.0, 0.0, 225.0],
        ],
    ];
    let tall_block: [[[f64; 3]; 4]; 5] = [
        [
            [423.0, 330.0, 247.0],
            [265.0, 330.0, 296.0],
            [314.0, 330.0, 456.0],
            [472.0, 330.0, 406.0],
        ],
        [
            [423.0, 0.0, 247.0],
            [423.0, 330.0, 247.0],
            [472.0, 330.0, 406.0],
            [472.0, 0.0, 406.0],
        ],
        [
            [472.0, 0.0, 406.0],
            [472.0, 330.0, 406.0],
            [314.0, 330.0, 456.0],
            [314.0, 0.0, 456.0],
        ],
        [
            [314.0, 0.0, 456.0],
            [314.0, 330.0, 456.0],
            [265.0, 330.0, 296.0],
            [265.0, 0.0, 296.0],
        ],
        [
            [265.0, 0.0, 296.0],
            [265.0, 330.0, 296.0],
            [423.0, 330.0, 247.0],
            [423.0, 0.0, 247.0],
        ],
    ];
    let expected_mm2 = [
        // Floor: a trapezoid with parallel sides 552.8 (z = 0) and 549.6 (z = 559.2),
        // 559.2 apart: (552.8 + 549.6) / 2 * 559.2 = 308231.04 mm^2.
        ("floor", 308_231.04),
        ("ceiling", area_mm2(&ceiling)),
        ("back_wall", area_mm2(&back)),
        ("left_wall", split_area_mm2(&left)),
        ("right_wall", area_mm2(&right)),
        // Light: 130 x 105 mm.
        ("light", 13_650.0),
        ("short_block", short_block.iter().map(|q| area_mm2(q)).sum()),
        ("tall_block", tall_block.iter().map(|q| area_mm2(q)).sum()),
    ];
    assert_eq!(scene.objects.len(), expected_mm2.len());
    for (name, mm2) in expected_mm2 {
        let o = scene
            .objects
            .iter()
            .position(|o| o.name == name)
            .unwrap_or_else(|| panic!("no {name}")) as u32;
        let area: f64 = scene
            .surfaces
            .iter()
            .filter(|s| s.object == o)
            .map(|s| s.area)
            .sum();
        let expected = mm2 * 1e-6;
        // Vertices are stored as f32: relative error well under 1e-6.
        assert!(
            (area - expected).abs() <= 1e-6 * expected,
            "{name}: {area} vs {expected} m^2"
        );
    }
    // Every published quad except the warped red wall comes back as one quad.
    assert_eq!(scene.import_stats.merged_quads, 15);
    assert_eq!(scene.surfaces.len(), 17);
    assert_eq!(scene.name, "cornell_box");
    assert_eq!(scene.cameras.len(), 1);
}

// ---------------------------------------------------------------------------
// Transforms
// ---------------------------------------------------------------------------

const UNIT_TRIANGLE: [[f32; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn with_nodes(nodes: Value, scene_roots: Value) -> Value {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["nodes"] = nodes;
    doc["scenes"] = json!([{"nodes": scene_roots}]);
    doc
}

#[test]
fn translation_rotation_and_non_uniform_scale_compose_down_a_parent_chain() {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    // Parent: rotate 90 degrees about +Z ((x, y, z) -> (-y, x, z)), then move by (1, 2, 3).
    // Child: scale (2, 3, 4), then move by (0.5, 0, 0).
    let doc = with_nodes(
        json!([
            {"name": "parent", "translation": [1.0, 2.0, 3.0], "rotation": [0.0, 0.0, h, h], "children": [1]},
            {"name": "child", "mesh": 0, "scale": [2.0, 3.0, 4.0], "translation": [0.5, 0.0, 0.0]}
        ]),
        json!([0]),
    );
    let scene = load(&write("trs.gltf", &doc)).unwrap();
    // (1,0,0) -> child (2.5,0,0) -> rotated (0,2.5,0) -> (1,4.5,3)
    // (0,1,0) -> child (0.5,3,0) -> rotated (-3,0.5,0) -> (-2,2.5,3)
    // (0,0,1) -> child (0.5,0,4) -> rotated (0,0.5,4) -> (1,2.5,7)
    let got = vertices(&scene);
    assert_eq!(got.len(), 1);
    let expected = [v(1.0, 4.5, 3.0), v(-2.0, 2.5, 3.0), v(1.0, 2.5, 7.0)];
    for (a, b) in got[0].iter().zip(expected) {
        assert_close(*a, b, 1e-12);
    }
    assert_eq!(scene.objects[0].name, "child");
}

#[test]
fn a_matrix_transform_is_column_major() {
    // Rows: [2 0 0 5], [0 1 1 0], [0 0 3 -1], [0 0 0 1].
    let doc = with_nodes(
        json!([{"mesh": 0, "matrix": [2.0, 0.0, 0.0, 0.0,  0.0, 1.0, 0.0, 0.0,  0.0, 1.0, 3.0, 0.0,  5.0, 0.0, -1.0, 1.0]}]),
        json!([0]),
    );
    let scene = load(&write("matrix.gltf", &doc)).unwrap();
    // (1,0,0) -> (7,0,-1); (0,1,0) -> (5,1,-1); (0,0,1) -> (5,1,2).
    assert_eq!(
        vertices(&scene),
        vec![vec![v(7.0, 0.0, -1.0), v(5.0, 1.0, -1.0), v(5.0, 1.0, 2.0)]]
    );
    // Unnamed node: the mesh's name.
    assert_eq!(scene.objects[0].name, "m");
}

#[test]
fn a_mirroring_transform_keeps_the_front_face_in_front() {
    let doc = with_nodes(json!([{"mesh": 0, "scale": [-1.0, 1.0, 1.0]}]), json!([0]));
    let scene = load(&write("mirror.gltf", &doc)).unwrap();
    // The unit triangle's front normal (1,1,1)/sqrt3 mirrored in x is (-1,1,1)/sqrt3.
    assert_close(
        scene.surfaces[0].normal,
        v(-1.0, 1.0, 1.0) / 3f64.sqrt(),
        1e-15,
    );
}

#[test]
fn nodes_without_a_scene_are_read_from_their_roots() {
    let mut doc = with_nodes(
        json!([{"children": [1]}, {"mesh": 0, "translation": [0.0, 0.0, 1.0]}]),
        json!([0]),
    );
    doc.as_object_mut().unwrap().remove("scenes");
    doc.as_object_mut().unwrap().remove("scene");
    let scene = load(&write("no_scene.gltf", &doc)).unwrap();
    assert_eq!(scene.surfaces.len(), 1);
    assert_eq!(scene.surfaces[0].vertices[2], v(0.0, 0.0, 2.0));
    assert_eq!(scene.objects[0].name, "m");
}

#[test]
fn a_node_reached_twice_or_nested_too_deep_is_an_error() {
    let cyclic = with_nodes(
        json!([{"children": [1]}, {"mesh": 0, "children": [0]}]),
        json!([0]),
    );
    let e = error_naming(&write("cycle.gltf", &cyclic), "reached twice");
    assert_eq!(
        e.gltf_object(),
        Some(&GltfObject::new(GltfKind::Node, 0, None)),
        "{e}"
    );
    let chain: Vec<Value> = (0..10)
        .map(|i| {
            if i < 9 {
                json!({"children": [i + 1]})
            } else {
                json!({"mesh": 0})
            }
        })
        .collect();
    let deep = write("deep.gltf", &with_nodes(json!(chain), json!([0])));
    assert!(load(&deep).is_ok());
    let shallow = ImportLimits {
        max_node_depth: 5,
        ..ImportLimits::default()
    };
    assert!(matches!(
        load_scene(&deep, &shallow),
        Err(Error::Limit {
            limit: LimitKind::NodeDepth,
            ..
        })
    ));
}

// ---------------------------------------------------------------------------
// Primitive modes and quad merging
// ---------------------------------------------------------------------------

#[test]
fn strips_give_the_specified_triangles() {
    // Not coplanar, so no pair merges.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 1.0],
        [0.0, 2.0, 0.0],
    ];
    let scene = load(&write("strip.gltf", &one_primitive(&p, None, 5))).unwrap();
    let q = |i: usize| v(p[i][0] as f64, p[i][1] as f64, p[i][2] as f64);
    // glTF: triangle i is (i, i+1+i%2, i+2-i%2).
    assert_eq!(
        vertices(&scene),
        vec![
            vec![q(0), q(1), q(2)],
            vec![q(1), q(3), q(2)],
            vec![q(2), q(3), q(4)]
        ]
    );
    assert_eq!(scene.import_stats.triangles_read, 3);
    assert_eq!(scene.import_stats.merged_quads, 0);
}

#[test]
fn fans_give_the_specified_triangles() {
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 0.0, 1.0],
        [0.0, -1.0, 0.5],
    ];
    let scene = load(&write("fan.gltf", &one_primitive(&p, None, 6))).unwrap();
    let q = |i: usize| v(p[i][0] as f64, p[i][1] as f64, p[i][2] as f64);
    // glTF: triangle i is (i+1, i+2, 0).
    assert_eq!(
        vertices(&scene),
        vec![
            vec![q(1), q(2), q(0)],
            vec![q(2), q(3), q(0)],
            vec![q(3), q(4), q(0)]
        ]
    );
}

#[test]
fn indexed_and_non_indexed_strips_agree() {
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 1.0],
        [0.0, 2.0, 0.0],
    ];
    let plain = load(&write("strip_plain.gltf", &one_primitive(&p, None, 5))).unwrap();
    // The same vertices shuffled, addressed through indices.
    let shuffled = [p[3], p[0], p[4], p[2], p[1]];
    let indexed = load(&write(
        "strip_indexed.gltf",
        &one_primitive(&shuffled, Some(&[1, 4, 3, 0, 2]), 5),
    ))
    .unwrap();
    assert_eq!(vertices(&plain), vertices(&indexed));
    // And as a triangle list.
    let list = load(&write(
        "strip_list.gltf",
        &one_primitive(&p, Some(&[0, 1, 2, 1, 3, 2, 2, 3, 4]), 4),
    ))
    .unwrap();
    assert_eq!(vertices(&plain), vertices(&list));
}

#[test]
fn a_two_triangle_square_merges_into_one_quad() {
    let p = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
        [0.0, 2.0, 0.0],
    ];
    for (name, doc) in [
        (
            "square_indexed.gltf",
            one_primitive(&p, Some(&[0, 1, 2, 0, 2, 3]), 4),
        ),
        (
            "square_plain.gltf",
            one_primitive(&[p[0], p[1], p[2], p[0], p[2], p[3]], None, 4),
        ),
    ] {
        let scene = load(&write(name, &doc)).unwrap();
        assert_eq!(scene.surfaces.len(), 1, "{name}");
        assert!(scene.surfaces[0].is_quad());
        assert_eq!(scene.surfaces[0].area, 4.0);
        assert_eq!(scene.surfaces[0].normal, DVec3::Z);
        assert_eq!(scene.import_stats.merged_quads, 1);
        assert_eq!(scene.import_stats.triangles_read, 2);
    }
}

#[test]
fn a_non_convex_or_folded_pair_does_not_merge() {
    // A dart: (0,0) (1,0) (0.9,0.1) (1,1) is concave at (0.9,0.1).
    let dart = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.9, 0.1, 0.0],
    ];
    let scene = load(&write(
        "dart.gltf",
        &one_primitive(&dart, Some(&[0, 3, 2, 0, 1, 3]), 4),
    ))
    .unwrap();
    assert_eq!(scene.surfaces.len(), 2);
    assert_eq!(scene.import_stats.merged_quads, 0);
    // Folded along the diagonal by a tiny 1e-4 (relative) out of plane.
    let fold = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 1e-4],
    ];
    let scene = load(&write(
        "fold.gltf",
        &one_primitive(&fold, Some(&[0, 1, 2, 0, 2, 3]), 4),
    ))
    .unwrap();
    assert_eq!(scene.surfaces.len(), 2);
}

#[test]
fn points_and_lines_are_skipped_and_counted() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    let triangles = doc["meshes"][0]["primitives"][0].clone();
    let mut lines = triangles.clone();
    lines["mode"] = json!(1);
    let mut points = triangles.clone();
    points["mode"] = json!(0);
    doc["meshes"][0]["primitives"] = json!([lines, triangles, points]);
    let scene = load(&write("lines.gltf", &doc)).unwrap();
    assert_eq!(scene.surfaces.len(), 1);
    assert_eq!(scene.import_stats.skipped_primitives, 2);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("Lines") && w.contains("skipped")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn degenerate_triangles_are_skipped_and_counted() {
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        // Collinear, and one with a repeated vertex.
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 1.0],
        [2.0, 2.0, 2.0],
        [5.0, 0.0, 0.0],
        [5.0, 0.0, 0.0],
        [6.0, 1.0, 0.0],
    ];
    let scene = load(&write("degenerate.gltf", &one_primitive(&p, None, 4))).unwrap();
    assert_eq!(scene.surfaces.len(), 1);
    assert_eq!(scene.import_stats.degenerate_triangles, 2);
    assert_eq!(scene.import_stats.triangles_read, 3);
}

#[test]
fn a_file_with_too_many_triangles_hits_the_limit() {
    let path = write(
        "limit.gltf",
        &one_primitive(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0, 1.0],
            ],
            None,
            5,
        ),
    );
    let limits = ImportLimits {
        max_triangles: 1,
        ..ImportLimits::default()
    };
    assert!(matches!(
        load_scene(&path, &limits),
        Err(Error::Limit {
            limit: LimitKind::Triangles,
            ..
        })
    ));
}

// ---------------------------------------------------------------------------
// Materials, objects, cameras
// ---------------------------------------------------------------------------

#[test]
fn materials_give_reflectance_emission_and_double_sided_surfaces() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["materials"] = json!([{
        "name": "lamp",
        "doubleSided": true,
        "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.25, 0.5, 0.75, 0.3]},
        "emissiveFactor": [1.0, 0.5, 0.25],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8.0}}
    }]);
    doc["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    let scene = load(&write("lamp.gltf", &doc)).unwrap();
    let m = &scene.materials[0];
    assert_eq!(m.name, "lamp");
    assert_eq!(m.reflectance.0, [0.25, 0.5, 0.75]);
    let pi = std::f64::consts::PI;
    assert_eq!(m.emission.0, [8.0 * pi, 4.0 * pi, 2.0 * pi]);
    assert!(m.double_sided);
    assert_eq!(scene.surfaces.len(), 2);
    assert_eq!(scene.surfaces[1].normal, -scene.surfaces[0].normal);
    assert_eq!(scene.surfaces[1].area, scene.surfaces[0].area);
}

#[test]
fn a_primitive_without_material_gets_default_grey_with_a_warning() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["meshes"][0]["primitives"][0]
        .as_object_mut()
        .unwrap()
        .remove("material");
    let scene = load(&write("no_material.gltf", &doc)).unwrap();
    let m = scene.material_of(&scene.surfaces[0]);
    assert_eq!(m.reflectance.0, [0.8; 3]);
    assert!(!m.is_emitter());
    assert!(scene.warnings.iter().any(|w| w.contains("no material")));
}

#[test]
fn a_base_colour_texture_multiplies_by_its_mean_or_is_ignored_with_a_warning() {
    // A 1x1 PNG of sRGB (255, 255, 0): linear mean (1, 1, 0).
    let mut png = std::io::Cursor::new(Vec::new());
    image::RgbImage::from_raw(1, 1, vec![255, 255, 0])
        .unwrap()
        .write_to(&mut png, image::ImageFormat::Png)
        .unwrap();
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["images"] =
        json!([{"uri": format!("data:image/png;base64,{}", base64::encode(png.get_ref()))}]);
    doc["textures"] = json!([{"source": 0}]);
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    let scene = load(&write("textured.gltf", &doc)).unwrap();
    assert_eq!(scene.materials[0].reflectance.0, [0.5, 0.5, 0.0]);
    doc["images"] = json!([{"uri": "data:image/png;base64,AAAA"}]);
    let scene = load(&write("bad_texture.gltf", &doc)).unwrap();
    assert_eq!(scene.materials[0].reflectance.0, [0.5; 3]);
    assert!(
        scene.warnings.iter().any(|w| w.contains("texture ignored")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn objects_are_named_after_node_then_mesh_then_index() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["meshes"] =
        json!([doc["meshes"][0].clone(), {"primitives": doc["meshes"][0]["primitives"].clone()}]);
    doc["nodes"] = json!([
        {"name": "named_node", "mesh": 0},
        {"mesh": 0, "translation": [0.0, 0.0, 1.0]},
        {"mesh": 1, "translation": [0.0, 0.0, 2.0]}
    ]);
    doc["scenes"] = json!([{"nodes": [0, 1, 2]}]);
    let scene = load(&write("names.gltf", &doc)).unwrap();
    let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["named_node", "m", "node 2"]);
    let objects: Vec<u32> = scene.surfaces.iter().map(|s| s.object).collect();
    assert_eq!(objects, [0, 1, 2]);
}

#[test]
fn perspective_cameras_are_placed_by_their_node_and_orthographic_ones_skipped() {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["cameras"] = json!([
        {"name": "persp", "type": "perspective", "perspective": {"yfov": 0.7, "aspectRatio": 1.5, "znear": 0.01}},
        {"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.01, "zfar": 10.0}}
    ]);
    // Rotation of 90 degrees about +Y maps (x, y, z) to (z, y, -x): local -Z looks along -X.
    doc["nodes"] = json!([
        {"mesh": 0},
        {"camera": 0, "translation": [4.0, 5.0, 6.0], "rotation": [0.0, h, 0.0, h]},
        {"camera": 1}
    ]);
    doc["scenes"] = json!([{"nodes": [0, 1, 2]}]);
    let scene = load(&write("cameras.gltf", &doc)).unwrap();
    assert_eq!(scene.cameras.len(), 1);
    let c = &scene.cameras[0];
    assert_eq!(c.name, "persp");
    assert_eq!(c.position, v(4.0, 5.0, 6.0));
    assert_close(c.forward, v(-1.0, 0.0, 0.0), 1e-15);
    assert_close(c.up, v(0.0, 1.0, 0.0), 1e-15);
    assert_eq!(c.yfov, 0.7);
    assert_eq!(c.aspect, Some(1.5));
    assert!(scene.warnings.iter().any(|w| w.contains("orthographic")));
}

#[test]
fn external_buffers_and_glb_files_load() {
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let mut doc = one_primitive(&p, None, 4);
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let bytes = base64::decode(uri.split(',').nth(1).unwrap()).unwrap();
    std::fs::create_dir_all(dir().join("sub dir")).unwrap();
    std::fs::write(dir().join("sub dir/tri angle.bin"), &bytes).unwrap();
    doc["buffers"][0]["uri"] = json!("sub%20dir/tri%20angle.bin");
    let scene = load(&write("external.gltf", &doc)).unwrap();
    assert_eq!(scene.surfaces[0].area, 0.5);

    doc["buffers"][0].as_object_mut().unwrap().remove("uri");
    let path = dir().join("binary.glb");
    std::fs::write(&path, glb(&serde_json::to_vec(&doc).unwrap(), &bytes)).unwrap();
    let scene = load(&path).unwrap();
    assert_eq!(scene.surfaces[0].area, 0.5);
    assert_eq!(scene.name, "binary");
}

// ---------------------------------------------------------------------------
// Bad input: an error naming the file and the culprit, never a panic
// ---------------------------------------------------------------------------

#[test]
fn a_missing_file_is_an_io_error() {
    let path = dir().join("does_not_exist.gltf");
    assert!(matches!(load(&path), Err(Error::Io { .. })));
}

#[test]
fn files_that_are_not_gltf_are_named_as_such() {
    let png = dir().join("picture.gltf");
    std::fs::write(&png, b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR").unwrap();
    error_naming(&png, "PNG");
    let noise = dir().join("noise.glb");
    std::fs::write(
        &noise,
        (0..200u32)
            .map(|i| (i * 97 % 251) as u8)
            .collect::<Vec<_>>(),
    )
    .unwrap();
    error_naming(&noise, "not a glTF file");
    error_naming(
        &write("not_gltf.gltf", &json!({"hello": "world"})),
        "not a glTF document",
    );
    let broken = dir().join("broken.gltf");
    std::fs::write(&broken, b"{\"asset\": {\"version\": \"2.0\"}, ").unwrap();
    error_naming(&broken, "not valid JSON");
    error_naming(
        &write("gltf1.gltf", &json!({"asset": {"version": "1.0"}})),
        "version",
    );
}

#[test]
fn a_file_without_surfaces_is_a_geometry_error() {
    let path = write(
        "empty.gltf",
        &json!({"asset": {"version": "2.0"}, "nodes": [{"name": "lonely"}]}),
    );
    let e = error_naming(&path, "no surfaces");
    assert!(matches!(
        e,
        Error::Geometry {
            fault: GeometryFault::NoSurfaces,
            ..
        }
    ));
}

#[test]
fn a_nan_position_names_the_mesh() {
    let p = [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]];
    error_naming(
        &write("nan.gltf", &one_primitive(&p, None, 4)),
        "mesh 0 ('m')",
    );
    error_naming(
        &write("nan2.gltf", &one_primitive(&p, None, 4)),
        "non-finite",
    );
}

#[test]
fn an_index_out_of_range_names_the_mesh() {
    let doc = one_primitive(&UNIT_TRIANGLE, Some(&[0, 1, 3]), 4);
    let e = error_naming(&write("bad_index.gltf", &doc), "mesh 0 ('m')");
    assert!(e.to_string().contains("index 3"), "{e}");
    assert_eq!(
        e.gltf_object(),
        Some(&GltfObject::new(GltfKind::Mesh, 0, Some("m"))),
        "{e}"
    );
}

#[test]
fn a_buffer_uri_escaping_the_folder_is_refused() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    std::fs::write(dir().join("../outside.bin"), [0u8; 36]).unwrap();
    for uri in [
        "../outside.bin",
        "/etc/passwd",
        "file:///etc/passwd",
        "http://example.com/a.bin",
    ] {
        doc["buffers"][0]["uri"] = json!(uri);
        error_naming(&write("escape.gltf", &doc), "buffer 0");
    }
}

#[test]
fn a_buffer_whose_length_differs_from_its_byte_length_is_refused() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["buffers"][0]["byteLength"] = json!(64);
    error_naming(&write("short_buffer.gltf", &doc), "byteLength");
}

#[test]
fn a_truncated_glb_is_an_error_at_every_length() {
    let doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let bin = base64::decode(uri.split(',').nth(1).unwrap()).unwrap();
    let mut doc = doc;
    doc["buffers"][0].as_object_mut().unwrap().remove("uri");
    let whole = glb(&serde_json::to_vec(&doc).unwrap(), &bin);
    let path = dir().join("truncated.glb");
    std::fs::write(&path, &whole).unwrap();
    assert!(load(&path).is_ok());
    for cut in (0..whole.len()).step_by(7).chain([whole.len() - 1]) {
        std::fs::write(&path, &whole[..cut]).unwrap();
        assert!(
            load(&path).is_err(),
            "truncated at {cut} of {} was accepted",
            whole.len()
        );
    }
    std::fs::write(&path, &whole[..whole.len() - 8]).unwrap();
    error_naming(&path, "truncated");
}

#[test]
fn an_accessor_past_the_end_of_its_buffer_names_the_accessor() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["accessors"][0]["count"] = json!(4);
    error_naming(&write("long_accessor.gltf", &doc), "accessor 0");
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["bufferViews"][0]["byteLength"] = json!(4000);
    error_naming(&write("long_view.gltf", &doc), "buffer view 0");
    // A hostile count with no data behind it is refused before allocating.
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["accessors"][0]
        .as_object_mut()
        .unwrap()
        .remove("bufferView");
    doc["accessors"][0]["count"] = json!(4_000_000_000u64);
    error_naming(&write("huge_count.gltf", &doc), "accessor 0");
}

#[test]
fn references_to_missing_objects_are_errors() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7);
    error_naming(&write("missing_accessor.gltf", &doc), "accessor 7");
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["meshes"][0]["primitives"][0]["material"] = json!(3);
    error_naming(&write("missing_material.gltf", &doc), "material");
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["extensionsRequired"] = json!(["EXT_nobody_knows"]);
    error_naming(&write("unknown_required.gltf", &doc), "EXT_nobody_knows");
}

#[test]
fn corrupting_any_byte_of_a_glb_never_panics() {
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let doc = one_primitive(&p, Some(&[0, 1, 2, 0, 2, 3]), 4);
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let bin = base64::decode(uri.split(',').nth(1).unwrap()).unwrap();
    let mut doc = doc;
    doc["buffers"][0].as_object_mut().unwrap().remove("uri");
    let whole = glb(&serde_json::to_vec(&doc).unwrap(), &bin);
    let path = dir().join("corrupt.glb");
    // Every byte of the headers, then every fourth byte (file writes are the cost).
    for at in (0..whole.len()).filter(|&at| at < 32 || at % 4 == 1) {
        for value in [0x00u8, 0xFF, b'9'] {
            let mut bytes = whole.clone();
            bytes[at] = value;
            std::fs::write(&path, &bytes).unwrap();
            // Either outcome is fine; a panic fails the test.
            let _ = load(&path);
        }
    }
}

#[test]
fn a_cube_with_shared_or_separate_vertices_becomes_six_outward_quads() {
    let corner = |i: u32| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32];
    // Corners as bit patterns x + 2y + 4z; each face counter-clockwise from outside.
    let faces: [[u32; 4]; 6] = [
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
    ];
    let shared_positions: Vec<[f32; 3]> = (0..8).map(corner).collect();
    let shared_indices: Vec<u32> = faces
        .iter()
        .flat_map(|f| [f[0], f[1], f[2], f[0], f[2], f[3]])
        .collect();
    let separate_positions: Vec<[f32; 3]> = faces.iter().flatten().map(|&i| corner(i)).collect();
    let separate_indices: Vec<u32> = (0..6u32)
        .flat_map(|f| [4 * f, 4 * f + 1, 4 * f + 2, 4 * f, 4 * f + 2, 4 * f + 3])
        .collect();
    for (name, p, ix) in [
        ("cube_shared.gltf", &shared_positions, &shared_indices),
        ("cube_separate.gltf", &separate_positions, &separate_indices),
    ] {
        let scene = load(&write(name, &one_primitive(p, Some(ix), 4))).unwrap();
        assert_eq!(scene.surfaces.len(), 6, "{name}");
        assert_eq!(scene.import_stats.merged_quads, 6);
        for s in &scene.surfaces {
            assert!(s.is_quad());
            assert_eq!(s.area, 1.0);
            assert_eq!(s.normal, (s.centroid() - DVec3::splat(0.5)) * 2.0, "{name}");
        }
    }
}

#[test]
fn sparse_accessors_override_zeros() {
    let mut bin = Bin::default();
    let indices = bin.view(&[0, 0, 1, 0, 2, 0, 0, 0]); // u16 0, 1, 2 and padding
    let values: Vec<u8> = UNIT_TRIANGLE
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    let values = bin.view(&values);
    bin.accessors.push(json!({
        "componentType": 5126, "count": 3, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 1.0],
        "sparse": {"count": 3, "indices": {"bufferView": indices, "componentType": 5123}, "values": {"bufferView": values}}
    }));
    let mut doc = bin.document(json!({
        "meshes": [{"name": "sparse", "primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}]
    }));
    let scene = load(&write("sparse.gltf", &doc)).unwrap();
    assert_eq!(
        vertices(&scene),
        vec![vec![v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 1.0)]]
    );
    // A sparse index past the accessor's count.
    doc["accessors"][0]["count"] = json!(2);
    doc["accessors"][0]["sparse"]["count"] = json!(2);
    doc["bufferViews"][0]["byteOffset"] = json!(2);
    error_naming(&write("sparse_bad.gltf", &doc), "sparse index 2");
}

// ---------------------------------------------------------------------------
// Repairs of messy files: reflectance, light, facing, overlaps
// ---------------------------------------------------------------------------

fn load_with(path: &Path, options: &LoadOptions) -> radiosity::Result<Scene> {
    load_scene_with(path, &ImportLimits::default(), options)
}

/// One triangle in each of three materials: white (1, 1, 1), one band above
/// glTF's range, and grey.
fn three_materials() -> Value {
    let mut bin = Bin::default();
    let mut prims = Vec::new();
    for m in 0..3 {
        let x = m as f32 * 2.0;
        let pos = bin.positions(&[[x, 0.0, 0.0], [x + 1.0, 0.0, 0.0], [x, 1.0, 0.0]]);
        prims.push(json!({"attributes": {"POSITION": pos}, "material": m}));
    }
    bin.document(json!({
        "materials": [
            {"name": "white", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [1.0, 1.0, 1.0, 1.0]}},
            {"name": "bright", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.5, 1.2, 0.5, 1.0]}},
            {"name": "grey", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.5, 0.5, 0.5, 1.0]}}
        ],
        "meshes": [{"name": "m", "primitives": prims}],
        "nodes": [{"name": "n", "mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    }))
}

#[test]
fn reflectance_above_the_maximum_is_clamped_with_one_warning_naming_each_material() {
    let path = write("white.gltf", &three_materials());
    let scene = load(&path).unwrap();
    let max = radiosity::gltf_io::DEFAULT_MAX_REFLECTANCE;
    assert_eq!(max, 0.95);
    assert_eq!(scene.materials[0].reflectance.0, [max; 3]);
    assert_eq!(scene.materials[1].reflectance.0, [0.5, max, 0.5]);
    assert_eq!(scene.materials[2].reflectance.0, [0.5; 3]);
    let clamped: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("clamped"))
        .collect();
    assert_eq!(clamped.len(), 1, "{:?}", scene.warnings);
    assert!(
        clamped[0].contains("'white'")
            && clamped[0].contains("'bright'")
            && !clamped[0].contains("'grey'"),
        "{}",
        clamped[0]
    );
    // Another maximum.
    let options = LoadOptions {
        max_reflectance: 0.99,
        ..LoadOptions::default()
    };
    let scene = load_with(&path, &options).unwrap();
    assert_eq!(scene.materials[0].reflectance.0, [0.99; 3]);
    assert_eq!(scene.materials[1].reflectance.0, [0.5, 0.99, 0.5]);
    // A maximum the solver cannot take, or none at all, is refused by name.
    for bad in [1.0, 0.0, f64::NAN, 2.0] {
        let options = LoadOptions {
            max_reflectance: bad,
            ..LoadOptions::default()
        };
        let e = load_with(&path, &options).unwrap_err();
        assert!(e.to_string().contains("max_reflectance"), "{e}");
    }
    // Negative reflectance is still an error naming the material.
    let mut doc = three_materials();
    doc["materials"][2]["pbrMetallicRoughness"]["baseColorFactor"] = json!([0.5, -0.1, 0.5, 1.0]);
    let e = error_naming(&write("negative.gltf", &doc), "material 'grey'");
    assert_eq!(
        e.gltf_object(),
        Some(&GltfObject::new(GltfKind::Material, 2, Some("grey"))),
        "{e}"
    );
}

#[test]
fn a_file_without_light_is_refused_before_any_form_factor_and_punctual_lights_count() {
    let doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    let scene = load(&write("dark.gltf", &doc)).unwrap();
    assert!(!scene.has_light());
    let e = scene.check_light().unwrap_err();
    assert!(
        matches!(&e, Error::NoLight { scene, dark_lights, .. }
            if scene == "dark" && dark_lights.is_empty()),
        "{e}"
    );
    assert!(
        e.to_string().contains("no light") && e.to_string().contains("'dark'"),
        "{e}"
    );
    assert!(
        e.to_string().contains("add a KHR_lights_punctual light"),
        "{e}"
    );
    // The solve refuses it at its checks, before any form factor: no solution.
    let e = radiosity::solve(&scene, &Default::default(), &|_| {
        panic!("no progress may be reported for a scene without light")
    })
    .unwrap_err();
    assert!(matches!(e, Error::NoLight { .. }), "{e}");
    // Lights the file defines but no node places give no light, and are
    // named in a warning; a placed light of intensity 0 is named by the
    // refusal.
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "intensity": 10.0},
        {"name": "dim", "type": "spot", "intensity": 0.0, "spot": {}}
    ]}});
    let scene = load(&write("punctual.gltf", &doc)).unwrap();
    assert_eq!(scene.import_stats.punctual_lights, 0);
    assert!(scene
        .warnings
        .iter()
        .any(|w| w.contains("2 KHR_lights_punctual lights are placed by no node")));
    assert!(scene.check_light().is_err());
    doc["nodes"] = json!([
        {"name": "n", "mesh": 0},
        {"name": "lamp", "extensions": {"KHR_lights_punctual": {"light": 1}}}
    ]);
    doc["scenes"] = json!([{"nodes": [0, 1]}]);
    let scene = load(&write("punctual_dim.gltf", &doc)).unwrap();
    assert_eq!(scene.import_stats.punctual_lights, 1);
    let e = scene.check_light().unwrap_err();
    assert!(
        matches!(&e, Error::NoLight { dark_lights, .. }
            if dark_lights.len() == 1 && dark_lights[0].contains("dim")),
        "{e}"
    );
    let e = e.to_string();
    assert!(
        e.contains("'dim'") && e.contains("intensity or colour 0"),
        "{e}"
    );
    // A placed light of some intensity is light.
    doc["nodes"][1]["extensions"]["KHR_lights_punctual"]["light"] = json!(0);
    let scene = load(&write("punctual_lit.gltf", &doc)).unwrap();
    scene.check_light().unwrap();
    // An emissive material is light.
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["materials"][0]["emissiveFactor"] = json!([1.0, 1.0, 1.0]);
    let scene = load(&write("lit.gltf", &doc)).unwrap();
    assert!(scene.has_light());
    scene.check_light().unwrap();
}

/// A 2 x 1 floor of two triangles facing up, the second wound the other way
/// when `turned`, as one mesh; `double_sided` on its material.
fn floor_doc(turned: bool, double_sided: bool) -> Value {
    let p = [
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [2.0, 0.0, 1.0],
        [2.0, 0.0, 0.0],
    ];
    let second: [u32; 3] = if turned { [0, 3, 2] } else { [0, 2, 3] };
    let ix = [0, 1, 2, second[0], second[1], second[2]];
    let mut doc = one_primitive(&p, Some(&ix), 4);
    doc["meshes"][0]["name"] = json!("floor mesh");
    doc["nodes"][0]["name"] = json!("floor");
    doc["materials"][0]["doubleSided"] = json!(double_sided);
    doc
}

#[test]
fn faces_wound_against_their_neighbours_are_named_and_double_sided_takes_both() {
    let consistent = load(&write("floor_ok.gltf", &floor_doc(false, false))).unwrap();
    assert!(consistent.warnings.is_empty(), "{:?}", consistent.warnings);
    let path = write("floor_turned.gltf", &floor_doc(true, false));
    let turned = load(&path).unwrap();
    assert_eq!(turned.surfaces.len(), 2, "the turned pair cannot merge");
    let w: Vec<&String> = turned
        .warnings
        .iter()
        .filter(|w| w.contains("other way"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", turned.warnings);
    assert!(
        w[0].contains("'floor'") && w[0].contains("1 of its 2"),
        "{}",
        w[0]
    );
    // A double-sided material: both sides reflect, nothing to say.
    let doubled = load(&write("floor_doubled.gltf", &floor_doc(true, true))).unwrap();
    assert!(doubled.warnings.is_empty(), "{:?}", doubled.warnings);
    // --double-sided: every surface gets its back, facing the other way.
    let options = LoadOptions {
        double_sided: true,
        ..LoadOptions::default()
    };
    let both = load_with(&path, &options).unwrap();
    assert!(both.warnings.is_empty(), "{:?}", both.warnings);
    assert_eq!(both.surfaces.len(), 4);
    let up = both.surfaces.iter().filter(|s| s.normal.y > 0.5).count();
    assert_eq!(up, 2, "one surface of each pair faces up");
    assert!(both.materials.iter().all(|m| m.double_sided));
}

/// A 4 m wall (node "wall") and a 1 m decal inside it in the same plane
/// (node "decal"), of two materials.
fn wall_and_decal_doc() -> Value {
    let mut bin = Bin::default();
    let wall = bin.positions(&[
        [0.0, 0.0, 0.0],
        [4.0, 0.0, 0.0],
        [4.0, 4.0, 0.0],
        [0.0, 4.0, 0.0],
    ]);
    let decal = bin.positions(&[
        [1.0, 1.0, 0.0],
        [2.0, 1.0, 0.0],
        [2.0, 2.0, 0.0],
        [1.0, 2.0, 0.0],
    ]);
    let ix = bin.indices(&[0, 1, 2, 0, 2, 3]);
    bin.document(json!({
        "materials": [
            {"name": "paint", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.5, 0.5, 0.5, 1.0]}},
            {"name": "sticker", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.5, 0.1, 0.1, 1.0]}}
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": wall}, "indices": ix, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": decal}, "indices": ix, "material": 1}]}
        ],
        "nodes": [{"name": "wall", "mesh": 0}, {"name": "decal", "mesh": 1}],
        "scenes": [{"nodes": [0, 1]}],
        "scene": 0
    }))
}

#[test]
fn a_decal_on_a_wall_is_resolved_at_load_or_refused_by_name() {
    let path = write("decal.gltf", &wall_and_decal_doc());
    let scene = load(&path).unwrap();
    let area = |o: u32| -> f64 {
        scene
            .surfaces
            .iter()
            .filter(|s| s.object == o)
            .map(|s| s.area)
            .sum()
    };
    assert!((area(0) - 15.0).abs() < 1e-9, "{}", area(0));
    assert!((area(1) - 1.0).abs() < 1e-12);
    assert_eq!(scene.import_stats.overlapping_pairs, 1);
    assert!(scene
        .warnings
        .iter()
        .any(|w| w.contains("'decal' over 'wall'")));
    let options = LoadOptions {
        overlaps: Overlaps::Error,
        ..LoadOptions::default()
    };
    let e = load_with(&path, &options).unwrap_err().to_string();
    assert!(
        e.contains("decal.gltf") && e.contains("'decal' and 'wall'") && e.contains("one plane"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------
// Compressed geometry: KHR_mesh_quantization, EXT_meshopt_compression, Draco
// ---------------------------------------------------------------------------

/// A 2 x 1 rectangle in z = 0 facing +z, as millimetres.
const RECTANGLE_MM: [[u16; 3]; 4] = [[0, 0, 0], [2000, 0, 0], [2000, 1000, 0], [0, 1000, 0]];

fn quantized_document(
    component: u32,
    normalized: bool,
    data: &[u8],
    stride: usize,
    scale: f64,
) -> Value {
    let mut doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "buffers": [{"byteLength": data.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64::encode(data))}],
        "bufferViews": [{"buffer": 0, "byteLength": data.len(), "byteStride": stride}],
        "accessors": [{"bufferView": 0, "componentType": component, "count": 4, "type": "VEC3"}],
        "materials": [{"name": "grey", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.5, 0.5, 0.5, 1.0]}}],
        "meshes": [{"name": "m", "primitives": [{"attributes": {"POSITION": 0}, "mode": 6, "material": 0}]}],
        "nodes": [{"name": "n", "mesh": 0, "scale": [scale, scale, scale]}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    });
    if normalized {
        doc["accessors"][0]["normalized"] = json!(true);
    }
    doc
}

fn assert_rectangle(scene: &Scene, tol: f64) {
    assert_eq!(scene.surfaces.len(), 1, "the fan merges into one quad");
    let expected = [
        v(0.0, 0.0, 0.0),
        v(2.0, 0.0, 0.0),
        v(2.0, 1.0, 0.0),
        v(0.0, 1.0, 0.0),
    ];
    let got = &scene.surfaces[0].vertices;
    for e in expected {
        assert!(
            got.iter().any(|p| (*p - e).length() <= tol),
            "{e} not in {got:?}"
        );
    }
    assert_eq!(scene.surfaces[0].normal, DVec3::Z);
}

#[test]
fn quantized_positions_are_read_as_integers_or_normalized_values() {
    // Unsigned shorts, not normalized, scaled by the node: millimetres.
    let data: Vec<u8> = RECTANGLE_MM
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()).chain([0, 0]))
        .collect();
    let scene = load(&write(
        "quantized_u16.gltf",
        &quantized_document(5123, false, &data, 8, 1e-3),
    ))
    .unwrap();
    assert_rectangle(&scene, 1e-12);
    // Signed bytes, normalized: c / 127, so 127 is 1 m and 64 is 64/127 m.
    let bytes: [[i8; 3]; 4] = [[0, 0, 0], [127, 0, 0], [127, 64, 0], [0, 64, 0]];
    let data: Vec<u8> = bytes
        .iter()
        .flat_map(|p| p.iter().map(|&c| c as u8).chain([0]))
        .collect();
    let scene = load(&write(
        "quantized_i8.gltf",
        &quantized_document(5120, true, &data, 4, 2.0),
    ))
    .unwrap();
    let height = 2.0 * 64.0 / 127.0;
    let p = &scene.surfaces[0].vertices;
    assert!(
        p.iter()
            .any(|q| (*q - v(2.0, height, 0.0)).length() < 1e-12),
        "{p:?}"
    );
    // -128 normalized clamps to -1 (glTF's rule).
    let bytes: [[i8; 3]; 4] = [[-128, 0, 0], [127, 0, 0], [127, 127, 0], [-128, 127, 0]];
    let data: Vec<u8> = bytes
        .iter()
        .flat_map(|p| p.iter().map(|&c| c as u8).chain([0]))
        .collect();
    let scene = load(&write(
        "quantized_clamp.gltf",
        &quantized_document(5120, true, &data, 4, 1.0),
    ))
    .unwrap();
    let p = &scene.surfaces[0].vertices;
    assert!(
        p.iter().any(|q| (*q - v(-1.0, 0.0, 0.0)).length() < 1e-12),
        "{p:?}"
    );
}

fn zigzag(d: u8) -> u8 {
    let s = d as i8;
    ((s << 1) ^ (s >> 7)) as u8
}

/// `EXT_meshopt_compression` attribute stream of up to 16 elements, every
/// byte's deltas stored whole (header bits 3), from a zero baseline.
fn raw_attribute_stream(elements: &[Vec<u8>]) -> Vec<u8> {
    let stride = elements[0].len();
    let mut out = vec![0xa0];
    for k in 0..stride {
        out.push(0b11);
        let mut previous = 0u8;
        for i in 0..16 {
            let value = elements.get(i).map_or(previous, |e| e[k]);
            out.push(zigzag(value.wrapping_sub(previous)));
            previous = value;
        }
    }
    out.extend(vec![0u8; 32]);
    out
}

#[test]
fn meshopt_compressed_quantized_views_decode_into_their_placeholder_buffer() {
    let elements: Vec<Vec<u8>> = RECTANGLE_MM
        .iter()
        .map(|p| {
            p.iter()
                .flat_map(|c| c.to_le_bytes())
                .chain([0, 0])
                .collect()
        })
        .collect();
    let vertices = raw_attribute_stream(&elements);
    // Triangles (0 1 2) from the code table (three new vertices), then
    // (0 2 3) from the last edge and the next vertex.
    let mut triangles = vec![0xe1, 0xf0, 0x00];
    triangles.extend([0u8; 16]);
    let mut bin = vertices.clone();
    let tri_offset = bin.len();
    bin.extend(&triangles);
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_mesh_quantization", "EXT_meshopt_compression"],
        "extensionsRequired": ["KHR_mesh_quantization", "EXT_meshopt_compression"],
        "buffers": [
            {"byteLength": bin.len()},
            {"byteLength": 44, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}
        ],
        "bufferViews": [
            {"buffer": 1, "byteOffset": 0, "byteLength": 32, "byteStride": 8,
             "extensions": {"EXT_meshopt_compression": {"buffer": 0, "byteOffset": 0,
                "byteLength": vertices.len(), "byteStride": 8, "mode": "ATTRIBUTES", "count": 4}}},
            {"buffer": 1, "byteOffset": 32, "byteLength": 12,
             "extensions": {"EXT_meshopt_compression": {"buffer": 0, "byteOffset": tri_offset,
                "byteLength": triangles.len(), "byteStride": 2, "mode": "TRIANGLES", "count": 6}}}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5123, "count": 4, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "materials": [{"name": "grey", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [0.5, 0.5, 0.5, 1.0]}}],
        "meshes": [{"name": "m", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "nodes": [{"name": "n", "mesh": 0, "scale": [1e-3, 1e-3, 1e-3]}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    });
    let path = dir().join("meshopt.glb");
    std::fs::write(&path, glb(&serde_json::to_vec(&doc).unwrap(), &bin)).unwrap();
    let scene = load(&path).unwrap();
    assert_eq!(scene.import_stats.triangles_read, 2);
    assert_rectangle(&scene, 1e-12);
    // A corrupt stream names the buffer view and the extension.
    let mut broken = bin.clone();
    broken[0] = 0xa7;
    std::fs::write(&path, glb(&serde_json::to_vec(&doc).unwrap(), &broken)).unwrap();
    let e = error_naming(&path, "buffer view 0: EXT_meshopt_compression");
    assert!(e.to_string().contains("version"), "{e}");
}

#[test]
fn a_corrupt_draco_stream_is_an_error_naming_the_mesh() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    // The positions' own view, read as a Draco stream: not one.
    doc["meshes"][0]["primitives"][0]["extensions"] = json!({
        "KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}
    });
    let e = error_naming(&write("draco.gltf", &doc), "mesh 0 ('m') primitive 0");
    assert!(e.to_string().contains("KHR_draco_mesh_compression"), "{e}");
}

// ---------------------------------------------------------------------------
// KHR_lights_punctual and metallic materials (issue 16)

/// A triangle on node 0 and lights placed by nodes 1 (a point, translated
/// under a parent) and 2 (a spot turned to shine along +X), with light 2 of
/// type `third_type` placed by node 3.
fn with_lights(required: bool, third_type: &str) -> Value {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    if required {
        doc["extensionsRequired"] = json!(["KHR_lights_punctual"]);
    }
    doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"name": "bulb", "type": "point", "intensity": 20.0, "color": [1.0, 0.5, 0.25], "range": 3.0},
        {"name": "beam", "type": "spot", "intensity": 5.0,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.4}},
        {"name": "odd", "type": third_type, "intensity": 1.0}
    ]}});
    let s = std::f64::consts::FRAC_1_SQRT_2;
    doc["nodes"] = json!([
        {"name": "n", "mesh": 0},
        {"name": "parent", "translation": [1.0, 0.0, 0.0], "children": [4]},
        // -90 degrees about Y takes the node's -Z axis to +X.
        {"name": "spot node", "translation": [0.0, 2.0, 0.0], "rotation": [0.0, -s, 0.0, s],
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"name": "odd node", "extensions": {"KHR_lights_punctual": {"light": 2}}},
        {"name": "lamp", "translation": [0.0, 3.0, 0.0],
         "extensions": {"KHR_lights_punctual": {"light": 0}}}
    ]);
    doc["scenes"] = json!([{"nodes": [0, 1, 2, 3]}]);
    doc
}

#[test]
fn punctual_lights_are_placed_by_their_nodes_required_or_not() {
    use radiosity::scene::LightKind;
    for required in [false, true] {
        let doc = with_lights(required, "point");
        let scene = load(&write("lights.gltf", &doc)).unwrap();
        assert_eq!(scene.lights.len(), 3);
        assert_eq!(scene.import_stats.punctual_lights, 3);
        // Nodes are walked depth first from the roots: 0, 1, 4, 2, 3.
        let bulb = &scene.lights[0];
        assert!(
            bulb.name.contains("bulb") && bulb.name.contains("lamp"),
            "{}",
            bulb.name
        );
        assert_eq!(bulb.kind, LightKind::Point);
        assert_close(bulb.position, v(1.0, 3.0, 0.0), 1e-12);
        assert_eq!(bulb.colour.0, [1.0, 0.5, 0.25]);
        assert_eq!(bulb.intensity, 20.0);
        assert_eq!(bulb.range, Some(3.0));
        let beam = &scene.lights[1];
        assert_eq!(
            beam.kind,
            LightKind::Spot {
                inner_cone: 0.2,
                outer_cone: 0.4
            }
        );
        assert_close(beam.position, v(0.0, 2.0, 0.0), 1e-12);
        assert_close(beam.direction, v(1.0, 0.0, 0.0), 1e-12);
        assert!(scene.has_light());
        scene.check_light().unwrap();
    }
}

#[test]
fn an_unknown_light_type_is_left_out_with_a_warning_naming_it() {
    let doc = with_lights(false, "area");
    let scene = load(&write("odd_light.gltf", &doc)).unwrap();
    assert_eq!(scene.lights.len(), 2);
    let warning = scene
        .warnings
        .iter()
        .find(|w| w.contains("does not know"))
        .expect("a warning");
    assert!(
        warning.contains("'odd'") && warning.contains("'odd node'") && warning.contains("'area'"),
        "{warning}"
    );
    // Values out of range are errors naming the light and its node.
    let mut doc = with_lights(false, "point");
    doc["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"]["innerConeAngle"] = json!(0.5);
    let e = error_naming(
        &write("bad_cone.gltf", &doc),
        "light 1 ('beam') of node 2 ('spot node')",
    );
    assert_eq!(
        e.gltf_object(),
        Some(&GltfObject::new(GltfKind::Light, 1, Some("beam"))),
        "{e}"
    );
    let mut doc = with_lights(false, "point");
    doc["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = json!(-1.0);
    let e = error_naming(&write("bad_intensity.gltf", &doc), "light 0 ('bulb')");
    assert_eq!(
        e.gltf_object(),
        Some(&GltfObject::new(GltfKind::Light, 0, Some("bulb"))),
        "{e}"
    );
}

#[test]
fn metallic_materials_keep_their_diffuse_part_with_one_warning_each() {
    let mut doc = one_primitive(&UNIT_TRIANGLE, None, 4);
    doc["materials"] = json!([{"name": "brass", "pbrMetallicRoughness": {
        "baseColorFactor": [0.8, 0.6, 0.2, 1.0], "metallicFactor": 0.75}}]);
    let scene = load(&write("brass.gltf", &doc)).unwrap();
    let r = scene.materials[0].reflectance.0;
    for (got, want) in r.iter().zip([0.2, 0.15, 0.05]) {
        assert!((got - want).abs() < 1e-12, "{r:?}");
    }
    let warnings: Vec<_> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("'brass'") && w.contains("specular"))
        .collect();
    assert_eq!(warnings.len(), 1, "{:?}", scene.warnings);
    // No metallicFactor: glTF's default, a metal, said so.
    doc["materials"][0]["pbrMetallicRoughness"]
        .as_object_mut()
        .unwrap()
        .remove("metallicFactor");
    let scene = load(&write("metal.gltf", &doc)).unwrap();
    assert_eq!(scene.materials[0].reflectance.0, [0.0; 3]);
    assert!(scene.warnings.iter().any(|w| w.contains("default is 1")));
}
