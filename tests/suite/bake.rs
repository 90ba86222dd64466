//! Baked solutions: the display mesh with per-vertex radiosity as glTF
//! (`write_baked`), read back by an independent reader (the `gltf` crate) and by
//! `load_baked`, rendered again, and the `bake`, `render` and `diff` commands.

use super::common::{closed_box, FaceMaterial};
use glam::DVec3;
use radiosity::gltf_io::{load_baked, write_baked, BakeGroup, BakeOptions, ImportLimits};
use radiosity::light_groups::{solve_with_light_groups, LightGroups};
use radiosity::math::Rgb;
use radiosity::mesh::ShadingMesh;
use radiosity::refine::RefineSettings;
use radiosity::render::{diff, render, ShadedMesh, ToneMap};
use radiosity::scene::{Camera, Scene};
use radiosity::{scenes, Error, Settings, Solution};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Coarse adaptive settings (T-vertices appear), fast enough for tests.
fn coarse() -> Settings {
    Settings {
        patch_size: Some(0.15),
        hemicube_resolution: 64,
        refine: RefineSettings {
            max_depth: 2,
            tolerance: 0.05,
            ..RefineSettings::default()
        },
        ..Settings::default()
    }
}
const COARSE_FLAGS: [&str; 6] = [
    "--patch-size",
    "0.15",
    "--hemicube-res",
    "64",
    "--max-depth",
    "2",
];

fn solve(scene: &Scene) -> Solution {
    radiosity::solve(scene, &coarse(), &|_| {}).unwrap()
}

fn work_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("bake")
        .join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The display triangles grouped as the baked file must hold them: object by
/// object, then material by material in order of first use within the object,
/// each list in display-mesh order. Entries: (object, material, triangles).
fn expected_groups(scene: &Scene, shading: &ShadingMesh) -> Vec<(u32, u32, Vec<usize>)> {
    let mut groups: Vec<(u32, u32, Vec<usize>)> = Vec::new();
    for o in 0..scene.objects.len() as u32 {
        for (t, &s) in shading.triangle_surface.iter().enumerate() {
            let surface = &scene.surfaces[s as usize];
            if surface.object != o {
                continue;
            }
            match groups
                .iter_mut()
                .find(|g| g.0 == o && g.1 == surface.material)
            {
                Some(g) => g.2.push(t),
                None => groups.push((o, surface.material, vec![t])),
            }
        }
    }
    groups
}

/// `got` equals `want` up to one `f32` rounding of a value no larger than
/// `size` (2^-24 relative; allowed twice that).
fn assert_f32_close(got: Rgb, want: Rgb, size: f64, what: &str) {
    for k in 0..3 {
        let tolerance = size * 2f64.powi(-23);
        assert!(
            (got[k] - want[k]).abs() <= tolerance,
            "{what}: band {k}: got {} want {}",
            got[k],
            want[k]
        );
    }
}

/// The file's `asset.extras.radiosity`.
fn description(path: &Path) -> serde_json::Value {
    let gltf = gltf::Gltf::open(path).unwrap();
    let extras = gltf
        .document
        .as_json()
        .asset
        .extras
        .as_ref()
        .expect("asset extras");
    let v: serde_json::Value = serde_json::from_str(extras.get()).unwrap();
    v["radiosity"].clone()
}

/// Reads the baked file with the `gltf` crate and checks nodes, materials and
/// every vertex of every triangle against the solution: `COLOR_0` is the
/// radiance at the file's exposure, tone mapped as `render` does; each group
/// attribute times its scale is the group's radiosity (`groups`, in order).
fn check_with_gltf_crate(
    path: &Path,
    scene: &Scene,
    shading: &ShadingMesh,
    groups: &[&ShadingMesh],
) {
    let (doc, buffers, _) = gltf::import(path).unwrap();
    let d = description(path);
    assert_eq!(d["version"], 2);
    assert_eq!(d["toneMap"], "aces");
    let gain = d["exposure"].as_f64().unwrap().exp2();
    let listed = d["groups"].as_array().unwrap();
    assert_eq!(listed.len(), groups.len());
    let scales: Vec<f64> = listed
        .iter()
        .map(|g| g["scale"].as_f64().unwrap())
        .collect();
    for (k, g) in listed.iter().enumerate() {
        assert_eq!(g["attribute"], format!("_GROUP_{k}"));
        assert!(scales[k] > 0.0 && scales[k].log2().fract() == 0.0, "{g}");
    }
    let groups_of = expected_groups(scene, shading);
    let mut next_group = groups_of.iter();
    let mesh_nodes: Vec<gltf::Node> = doc
        .default_scene()
        .unwrap()
        .nodes()
        .filter(|n| n.camera().is_none())
        .collect();
    assert_eq!(mesh_nodes.len(), scene.objects.len(), "one node per object");
    let mut triangles_seen = 0;
    for (o, node) in mesh_nodes.iter().enumerate() {
        assert_eq!(node.name(), Some(scene.objects[o].name.as_str()));
        let Some(mesh) = node.mesh() else {
            continue;
        };
        assert_eq!(mesh.name(), Some(scene.objects[o].name.as_str()));
        for prim in mesh.primitives() {
            let (object, material, tris) = next_group.next().expect("no more groups expected");
            assert_eq!(*object as usize, o);
            assert_eq!(prim.material().index(), Some(*material as usize));
            let m = prim.material();
            assert_eq!(
                m.name(),
                Some(scene.materials[*material as usize].name.as_str())
            );
            assert!(m.unlit(), "bakes are unlit");
            assert_eq!(m.pbr_metallic_roughness().base_color_factor(), [1.0; 4]);
            assert_eq!(m.emissive_factor(), [0.0; 3]);
            let reader = prim.reader(|b| Some(&buffers[b.index()]));
            let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
            let colours: Vec<[f32; 3]> = reader.read_colors(0).unwrap().into_rgb_f32().collect();
            let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
            let attributes: Vec<Vec<[f32; 3]>> = (0..groups.len())
                .map(|k| {
                    let (_, accessor) = prim
                        .attributes()
                        .find(|(s, _)| *s == gltf::Semantic::Extras(format!("GROUP_{k}")))
                        .expect("group attribute");
                    gltf::accessor::Iter::<[f32; 3]>::new(accessor, |b| Some(&buffers[b.index()]))
                        .unwrap()
                        .collect()
                })
                .collect();
            assert_eq!(indices.len(), 3 * tris.len());
            for c in colours.iter().flatten() {
                assert!((0.0..=1.0).contains(c), "COLOR_0 outside [0, 1]: {c}");
            }
            for (k, &t) in tris.iter().enumerate() {
                for corner in 0..3 {
                    let v = shading.triangles[t][corner] as usize;
                    let i = indices[3 * k + corner] as usize;
                    let p = shading.positions[v];
                    assert_eq!(positions[i], [p.x as f32, p.y as f32, p.z as f32]);
                    let what = format!("triangle {t} vertex {v}");
                    let b = shading.radiosity[v];
                    let shown = ToneMap::AcesFitted.apply(b * (gain / PI));
                    assert_f32_close(Rgb(colours[i].map(f64::from)), shown, 1.0, &what);
                    for (g, group) in groups.iter().enumerate() {
                        let got = Rgb(attributes[g][i].map(f64::from)) * scales[g];
                        let want = group.radiosity[v];
                        assert_f32_close(got, want, want.max_band(), &format!("{what} group {g}"));
                    }
                }
            }
            triangles_seen += tris.len();
        }
    }
    assert!(next_group.next().is_none(), "groups missing from the file");
    assert_eq!(triangles_seen, shading.triangles.len());
}

/// The Cornell box baked without light groups, read back with the `gltf`
/// crate: `COLOR_0` is what `render` shows at the file's exposure, and the
/// one group's attribute times its scale the solution's vertex radiosity,
/// within `f32` rounding, at every vertex of every triangle, with positions
/// exact in `f32` and one node per object; both containers.
#[test]
fn baked_colours_show_the_solution_and_the_group_holds_it() {
    let scene = scenes::cornell_box();
    let sol = solve(&scene);
    let shading = sol.shading_mesh();
    let dir = work_dir("colours");
    for file in ["cornell.glb", "cornell.gltf"] {
        let path = dir.join(file);
        let summary = write_baked(&scene, &shading, &[], &BakeOptions::default(), &path).unwrap();
        assert_eq!(summary.triangles, shading.triangles.len());
        assert_eq!(summary.groups, 1);
        assert_eq!(
            summary.bytes as u64,
            std::fs::metadata(&path).unwrap().len()
        );
        check_with_gltf_crate(&path, &scene, &shading, &[&shading]);
        assert_eq!(description(&path)["groups"][0]["name"], "all");
    }
}

/// A room with four sources solved in light groups: each group is its own
/// attribute, and `load_baked` gives back their sum, the solution's vertex
/// radiosity (emission included), within `f32` rounding.
#[test]
fn light_groups_are_baked_apart_and_read_back_as_their_sum() {
    let scene = super::light_groups::room();
    let groups = LightGroups::each(&scene);
    let settings = Settings {
        patch_size: Some(1.0),
        hemicube_resolution: 32,
        ..Settings::default()
    };
    let mut sol = solve_with_light_groups(&scene, &settings, &groups, &|_| {}).unwrap();
    let shading = sol.shading_mesh();
    let parts = sol.group_shading_meshes();
    let names: Vec<&str> = groups.groups.iter().map(|g| g.name.as_str()).collect();
    let bake_groups: Vec<BakeGroup<'_>> = names
        .iter()
        .zip(&parts)
        .map(|(name, shading)| BakeGroup { name, shading })
        .collect();
    let path = work_dir("groups").join("room.glb");
    let options = BakeOptions {
        exposure: Some(-1.5),
        ..BakeOptions::default()
    };
    let summary = write_baked(&scene, &shading, &bake_groups, &options, &path).unwrap();
    assert_eq!(summary.groups, 4);
    assert_eq!(summary.exposure, -1.5);
    assert_eq!(summary.group_bytes, 4 * 12 * summary.vertices);
    let refs: Vec<&ShadingMesh> = parts.iter().collect();
    check_with_gltf_crate(&path, &scene, &shading, &refs);
    let baked = load_baked(&path, &ImportLimits::default()).unwrap();
    assert_eq!(baked.exposure, Some(-1.5));
    let read: Vec<&str> = baked.groups.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(read, names);
    // The room has no camera: the default view is written.
    assert_eq!(baked.cameras.len(), 1);
    assert_eq!(baked.cameras[0].name, "default view");
    let order: Vec<usize> = expected_groups(&scene, &shading)
        .into_iter()
        .flat_map(|g| g.2)
        .collect();
    for (k, &t) in order.iter().enumerate() {
        for corner in 0..3 {
            let v = shading.triangles[t][corner] as usize;
            let i = baked.mesh.triangles[k][corner] as usize;
            let b = shading.radiosity[v];
            // Each group rounded once: allowed once per group.
            assert_f32_close(baked.mesh.values[i] * PI, b, 4.0 * b.max_band(), "sum");
        }
    }
}

/// `load_baked` gives back every vertex radiosity of the solution (emission
/// included) within `f32` rounding, with the objects' names and the
/// triangles in file order.
#[test]
fn load_baked_returns_the_vertex_radiosities() {
    let grey = FaceMaterial::grey(0.5, 0.0);
    let mut faces = [grey; 6];
    faces[0] = FaceMaterial {
        reflectance: Rgb::new(0.6, 0.0, 0.3),
        exitance: Rgb::ZERO,
    };
    faces[1] = FaceMaterial {
        reflectance: Rgb::new(0.4, 0.4, 0.4),
        exitance: Rgb::new(3.0, 2.0, 1.0),
    };
    let scene = closed_box(DVec3::new(1.0, 0.8, 1.2), faces);
    let sol = solve(&scene);
    let shading = sol.shading_mesh();
    let path = work_dir("round_trip").join("box.gltf");
    write_baked(&scene, &shading, &[], &BakeOptions::default(), &path).unwrap();
    check_with_gltf_crate(&path, &scene, &shading, &[&shading]);
    let baked = load_baked(&path, &ImportLimits::default()).unwrap();
    assert_eq!(baked.name, "box");
    let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(baked.objects, names);
    // load_baked lists triangles in file order: the expected groups, concatenated.
    let order: Vec<usize> = expected_groups(&scene, &shading)
        .into_iter()
        .flat_map(|g| g.2)
        .collect();
    assert_eq!(baked.mesh.triangles.len(), order.len());
    assert!(
        baked.mesh.cull_back_faces,
        "a bake's materials are single-sided"
    );
    for (k, &t) in order.iter().enumerate() {
        for corner in 0..3 {
            let v = shading.triangles[t][corner] as usize;
            let i = baked.mesh.triangles[k][corner] as usize;
            let p = shading.positions[v];
            let q = baked.mesh.positions[i];
            assert!((p - q).abs().max_element() <= 1e-7 * p.abs().max_element().max(1.0));
            let b = shading.radiosity[v];
            let what = format!("triangle {t} vertex {v}");
            assert_f32_close(baked.mesh.values[i] * PI, b, b.max_band(), &what);
        }
    }
}

/// Renders of baked files, from the scene's camera and from another one,
/// match renders of the solution itself within 1% relative RMSE (they should
/// differ only by `f32` rounding).
#[test]
fn baked_files_render_like_the_solution() {
    let scene = scenes::cornell_box();
    let sol = solve(&scene);
    let shading = sol.shading_mesh();
    let direct = ShadedMesh {
        positions: shading.positions.clone(),
        values: shading.radiosity.iter().map(|b| *b / PI).collect(),
        triangles: shading.triangles.clone(),
        texels: None,
        cull_back_faces: false,
    };
    let corner = Camera::look_at(
        DVec3::new(0.05, 0.5, 0.05),
        DVec3::new(0.4, 0.1, 0.5),
        DVec3::Y,
        70.0,
    );
    let path = work_dir("render").join("cornell.glb");
    write_baked(&scene, &shading, &[], &BakeOptions::default(), &path).unwrap();
    let baked = load_baked(&path, &ImportLimits::default()).unwrap();
    assert_eq!(baked.cameras.len(), 1);
    let original = &baked.cameras[0];
    assert!((original.position - scene.cameras[0].position).length() < 1e-12);
    assert!((original.yfov - scene.cameras[0].yfov).abs() < 1e-12);
    for camera in [original, &corner] {
        let want = render(&direct, camera, 96, 96).unwrap();
        let got = render(&baked.mesh, camera, 96, 96).unwrap();
        let (_, m) = diff(&got, &want).unwrap();
        assert!(want.mean().max_band() > 0.01, "the view sees the room");
        assert!(m.relative_rmse < 0.01, "{m:?}");
    }
}

/// A double-sided interior, baked: each surface and its back copy share one
/// plane, but in `f32` a plane at an angle to the axes is not flat, and the
/// two copies are cut differently (the fronts refine where the light
/// changes, the dark backs do not). Rendering the baked file from inside
/// shows the lit fronts, never a black back copy through them (back faces
/// are culled as glTF's single-sided materials ask), within 1% relative
/// RMSE of a render of the solution itself.
#[test]
fn a_baked_double_sided_interior_shows_no_back_copies() {
    let turn = glam::DQuat::from_euler(glam::EulerRot::YXZ, 0.5, 0.3, 0.2);
    let place = |p: DVec3| turn * p + DVec3::new(3.1, -1.7, 0.9);
    let mut scene = scenes::cornell_box();
    for s in &mut scene.surfaces {
        let v: Vec<DVec3> = s.vertices.iter().map(|p| place(*p)).collect();
        *s = radiosity::scene::Surface::new(&v, s.material, s.object).unwrap();
    }
    scene.make_double_sided();
    let sol = solve(&scene);
    let shading = sol.shading_mesh();
    let direct = ShadedMesh::radiance_of(shading.clone());
    let path = work_dir("double_sided").join("cornell.glb");
    write_baked(&scene, &shading, &[], &BakeOptions::default(), &path).unwrap();
    let baked = load_baked(&path, &ImportLimits::default()).unwrap();
    let inside = Camera::look_at(
        place(DVec3::new(0.25, 0.3, 0.1)),
        place(DVec3::new(0.3, 0.25, 0.559)),
        turn * DVec3::Y,
        80.0,
    );
    let want = render(&direct, &inside, 128, 128).unwrap();
    let got = render(&baked.mesh, &inside, 128, 128).unwrap();
    let black = got.pixels.iter().filter(|p| p.max_band() <= 0.0).count();
    assert_eq!(black, 0, "black pixels: back copies showing through");
    let (_, m) = diff(&got, &want).unwrap();
    assert!(m.relative_rmse < 0.01, "{m:?}");
}

/// A one-triangle glTF file as other tools write them: `COLOR_0` as normalized
/// unsigned bytes with alpha (`colour_count` of them), the primitive's
/// `extras` as given, no material, placed by a node scaled (-1, 1, 1).
fn triangle_file(name: &str, colour_count: usize, extras: &str) -> PathBuf {
    let mut bin: Vec<u8> = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
        for c in p {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    bin.extend_from_slice(&[255, 0, 0, 255, 0, 51, 0, 255, 0, 0, 102, 255]);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"name":"mirrored","mesh":0,"scale":[-1,1,1]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"COLOR_0":1}}{extras}}}]}}],
        "accessors":[
          {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
          {{"bufferView":0,"byteOffset":36,"componentType":5121,"normalized":true,"count":{colour_count},"type":"VEC4"}}],
        "bufferViews":[{{"buffer":0,"byteLength":48}}],
        "buffers":[{{"byteLength":48,"uri":"data:application/octet-stream;base64,{}"}}]}}"#,
        base64_encode(&bin)
    );
    let path = work_dir("triangle_files").join(format!("{name}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

/// Byte colours without a scale or a material (the glTF default material:
/// white, lit, not emitting) read as given, and the mirroring node's winding
/// is turned back to counter-clockwise.
#[test]
fn load_baked_reads_byte_colours_and_mirrored_nodes() {
    let path = triangle_file("plain", 3, "");
    let baked = load_baked(&path, &ImportLimits::default()).unwrap();
    assert_eq!(baked.objects, vec!["mirrored".to_string()]);
    assert_eq!(baked.mesh.triangles.len(), 1);
    let tri = baked.mesh.triangles[0];
    let p = tri.map(|i| baked.mesh.positions[i as usize]);
    // Mirrored in x, then re-wound: the normal still points to +z.
    assert!((p[1] - p[0]).cross(p[2] - p[0]).z > 0.0, "{p:?}");
    let value_at = |x: f64, y: f64| {
        let i = (0..3)
            .find(|&k| (p[k] - DVec3::new(x, y, 0.0)).length() < 1e-12)
            .unwrap();
        baked.mesh.values[tri[i] as usize] * PI
    };
    // 51 / 255 = 0.2 and 102 / 255 = 0.4; the radiance is a pi-th of that.
    for (x, y, want) in [
        (0.0, 0.0, [1.0, 0.0, 0.0]),
        (-1.0, 0.0, [0.0, 0.2, 0.0]),
        (0.0, 1.0, [0.0, 0.0, 0.4]),
    ] {
        let got = value_at(x, y);
        assert!(
            (got - Rgb(want)).abs().max_band() < 1e-15,
            "{got:?} {want:?}"
        );
    }
    // A scale multiplies.
    let scaled = triangle_file("scaled", 3, r#","extras":{"radiosityScale":4}"#);
    let baked = load_baked(&scaled, &ImportLimits::default()).unwrap();
    let top = baked
        .mesh
        .values
        .iter()
        .map(|v| v.max_band() * PI)
        .fold(0.0, f64::max);
    assert!((top - 4.0).abs() < 1e-12, "{top}");
}

/// Malformed baked files are errors that name the fault.
#[test]
fn malformed_baked_files_are_named() {
    let limits = ImportLimits::default();
    let short = triangle_file("short_colours", 2, "");
    let e = load_baked(&short, &limits).unwrap_err();
    assert!(e.to_string().contains("COLOR_0 has 2 values for 3"), "{e}");
    for (name, extras) in [
        ("negative_scale", r#","extras":{"radiosityScale":-1}"#),
        ("text_scale", r#","extras":{"radiosityScale":"big"}"#),
    ] {
        let e = load_baked(&triangle_file(name, 3, extras), &limits).unwrap_err();
        assert!(e.to_string().contains("radiosityScale"), "{name}: {e}");
    }
    let tight = ImportLimits {
        max_triangles: 0,
        ..ImportLimits::default()
    };
    let e = load_baked(&triangle_file("limited", 3, ""), &tight).unwrap_err();
    assert!(matches!(e, Error::Limit { .. }), "{e}");
}

/// Standard base64 (the suite has no encoder of its own).
fn base64_encode(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A scene file without vertex colours is not a baked solution, and a display
/// mesh that does not belong to the scene is refused before anything is
/// written.
#[test]
fn bad_inputs_are_named() {
    let scene_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell_box.gltf");
    let e = load_baked(&scene_file, &ImportLimits::default()).unwrap_err();
    assert!(
        matches!(e, Error::Gltf { .. }) && e.to_string().contains("COLOR_0"),
        "{e}"
    );

    let scene = scenes::cornell_box();
    let mut shading = solve(&scene).shading_mesh();
    let dir = work_dir("bad");
    let options = BakeOptions::default();
    let e = write_baked(&scene, &shading, &[], &options, &dir.join("x.obj")).unwrap_err();
    assert!(e.to_string().contains(".glb"), "{e}");
    let last = shading.triangle_surface.len() - 1;
    shading.triangle_surface[last] = scene.surfaces.len() as u32;
    let path = dir.join("bad.glb");
    let e = write_baked(&scene, &shading, &[], &options, &path).unwrap_err();
    assert!(
        matches!(e, Error::Output { .. }) && e.to_string().contains("surface"),
        "{e}"
    );
    assert!(!path.exists());
}

/// The commands end to end: `bake` (coarse settings), `render` of the baked
/// file with HDR and false-colour output, `solve` with the same settings, and
/// `diff --json` of the two EXR files: well under 1% relative RMSE.
#[test]
fn bake_render_and_diff_commands() {
    let dir = work_dir("cli");
    let run = |args: &[&str]| -> String {
        let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
            .args(args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let d = dir.to_str().unwrap();
    let baked = dir.join("cornell_box.glb");
    let mut bake = vec!["bake", "cornell_box", "--quiet", "-o"];
    bake.push(baked.to_str().unwrap());
    bake.extend(COARSE_FLAGS);
    run(&bake);
    let rendered = format!("{d}/rendered");
    run(&[
        "render",
        baked.to_str().unwrap(),
        "--out",
        &rendered,
        "--width",
        "128",
        "--height",
        "128",
        "--hdr",
        "--false-colour",
        "--quiet",
    ]);
    for f in [
        "cornell_box.exr",
        "cornell_box.hdr",
        "cornell_box.png",
        "cornell_box_false.png",
    ] {
        assert!(Path::new(&rendered).join(f).exists(), "{f} missing");
    }
    let solved = format!("{d}/solved");
    let mut solve = vec![
        "solve",
        "cornell_box",
        "--quiet",
        "--width",
        "128",
        "--height",
        "128",
        "--out",
    ];
    solve.push(&solved);
    solve.extend(COARSE_FLAGS);
    run(&solve);
    let difference = format!("{d}/difference.exr");
    let text = run(&[
        "diff",
        &format!("{rendered}/cornell_box.exr"),
        &format!("{solved}/cornell_box.exr"),
        "-o",
        &difference,
        "--json",
    ]);
    let report: serde_json::Value = serde_json::from_str(&text).unwrap();
    let relative = report["relative_rmse"].as_f64().unwrap();
    assert!(relative < 0.01, "{report}");
    assert!(report["mae"].as_f64().unwrap() >= 0.0 && report["rmse"].is_f64());
    assert!(Path::new(&difference).exists());
}

/// `bake --html` writes the page beside a copy of the bake, and `view`
/// serves the same files on 127.0.0.1 at the address it prints, the bake's
/// bytes unchanged, and nothing else.
#[test]
fn bake_html_and_view_serve_the_page_and_the_bake() {
    use std::io::{BufRead, BufReader, Read, Write};
    let dir = work_dir("view");
    let baked = dir.join("room.glb");
    let site = dir.join("site");
    let mut bake = vec!["bake", "cornell_box", "--quiet", "-o"];
    bake.push(baked.to_str().unwrap());
    bake.extend(["--html", site.to_str().unwrap()]);
    bake.extend(COARSE_FLAGS);
    let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(&bake)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&baked).unwrap();
    assert_eq!(std::fs::read(site.join("scene.glb")).unwrap(), bytes);
    for f in ["index.html", "viewer.js", "gltf.js", "render.js"] {
        assert!(site.join(f).exists(), "{f} missing");
    }
    let page = std::fs::read_to_string(site.join("index.html")).unwrap();
    assert!(page.contains(r#"content="scene.glb""#), "{page}");
    assert!(
        !page.contains("http://") && !page.contains("https://"),
        "nothing fetched from elsewhere"
    );

    /// Ends the server however the test ends.
    struct Server(std::process::Child);
    impl Drop for Server {
        fn drop(&mut self) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
    let mut server = Server(
        Command::new(env!("CARGO_BIN_EXE_radiosity"))
            .args(["view", baked.to_str().unwrap(), "--port", "0"])
            .stdout(std::process::Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let mut line = String::new();
    BufReader::new(server.0.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let start = line.find("http://127.0.0.1:").expect("an address") + "http://".len();
    let address = line[start..].split('/').next().unwrap().to_string();
    let get = |path: &str| {
        let mut s = std::net::TcpStream::connect(&address).unwrap();
        write!(s, "GET {path} HTTP/1.1\r\nHost: x\r\n\r\n").unwrap();
        let mut body = Vec::new();
        s.read_to_end(&mut body).unwrap();
        body
    };
    let scene = get("/scene.glb");
    let head_end = scene.windows(4).position(|w| w == b"\r\n\r\n").unwrap() + 4;
    let (head, body) = scene.split_at(head_end);
    let index = String::from_utf8_lossy(&get("/")).into_owned();
    let other = String::from_utf8_lossy(&get("/Cargo.toml")).into_owned();
    assert!(
        index.starts_with("HTTP/1.1 200") && index.contains("viewer.js"),
        "{index}"
    );
    assert!(String::from_utf8_lossy(head).starts_with("HTTP/1.1 200"));
    assert_eq!(body, &bytes[..]);
    assert!(other.starts_with("HTTP/1.1 404"), "{other}");
}

/// `view` of a scene file (not a bake) and a group name no source has are
/// refused with messages that name them.
#[test]
fn view_of_a_scene_and_unknown_groups_are_refused() {
    let scene_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell_box.gltf");
    let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(["view", scene_file.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(text.contains("COLOR_0"), "{text}");
    let dir = work_dir("groups_cli");
    for (flag, value, named) in [
        ("--group-scale", "sun=0.5", "'sun'"),
        (
            "--light-group",
            "lamps=nothing like it",
            "'nothing like it'",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
            .args(["bake", "cornell_box", "--quiet", flag, value, "-o"])
            .arg(dir.join("x.glb"))
            .output()
            .unwrap();
        assert!(!out.status.success(), "{flag} {value}");
        let text = String::from_utf8_lossy(&out.stderr);
        assert!(text.contains(named), "{flag}: {text}");
    }
}
