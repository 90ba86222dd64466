//! The scale scene (`many_boxes`) and the memory figures of the solve stats.

use super::stress_scenes::assert_finite_non_negative;
use glam::DVec3;
use radiosity::formfactor::{Row, RowState};
use radiosity::math::Rgb;
use radiosity::mesh::{Element, Mesh, Patch};
use radiosity::refine::RefineSettings;
use radiosity::scenes::many_boxes::{lights_per_side, many_boxes, many_boxes_with};
use radiosity::{Settings, Solution};
use std::mem::size_of;
use std::path::Path;
use std::process::Command;

/// Patches a rectangle is cut into: along each pair of opposite edges, the
/// longer one over the patch size, rounded up (no patch edge longer than the
/// patch size).
fn rectangle_patches(v: &[DVec3], patch_size: f64) -> usize {
    let along = |a: f64, b: f64| (a.max(b) / patch_size).ceil() as usize;
    along((v[1] - v[0]).length(), (v[2] - v[3]).length())
        * along((v[3] - v[0]).length(), (v[2] - v[1]).length())
}

#[test]
fn many_boxes_is_cut_into_the_patches_its_rectangles_ask_for() {
    for n in [2, 5] {
        let scene = many_boxes_with(n).unwrap();
        let lights = lights_per_side(n) as usize;
        assert_eq!(
            scene.surfaces.len(),
            6 + lights * lights + 5 * (n * n) as usize
        );
        let patch_size = Settings::default().patch_size_for(&scene);
        let expected: usize = scene
            .surfaces
            .iter()
            .map(|s| {
                assert_eq!(s.vertices.len(), 4, "every surface is a rectangle");
                rectangle_patches(&s.vertices, patch_size)
            })
            .sum();
        let mesh = Mesh::new(&scene, patch_size, usize::MAX).unwrap();
        assert_eq!(mesh.patches().len(), expected, "n = {n}");
    }
}

#[test]
fn the_built_in_many_boxes_has_2000_patches_and_100000_elements_at_depth_3() {
    let scene = many_boxes();
    let patch_size = Settings::default().patch_size_for(&scene);
    let mesh = Mesh::new(&scene, patch_size, Settings::default().max_patches).unwrap();
    let patches = mesh.patches().len();
    assert!(patches >= 2000, "{patches} patches");
    // Uniform depth 3 splits every patch into 4^3 elements.
    assert!(patches * 64 >= 100_000, "{} elements", patches * 64);
}

#[test]
fn a_small_many_boxes_solves_with_energy_balanced_and_radiosities_sane() {
    let scene = many_boxes_with(3).unwrap();
    let settings = Settings {
        hemicube_resolution: 64,
        refine: RefineSettings {
            max_passes: 2,
            ..RefineSettings::default()
        },
        ..Settings::default()
    };
    let sol = radiosity::solve(&scene, &settings, &|_| {}).unwrap();
    assert_finite_non_negative(&sol, "many_boxes_with(3)");
    let s = &sol.stats();
    assert_eq!(s.patches, sol.mesh().patches().len());
    assert_eq!(s.elements, sol.mesh().leaf_count());
    // A closed room: everything emitted is absorbed.
    assert!(
        s.energy.relative_difference.abs() < 0.01,
        "energy balance {}",
        s.energy.relative_difference
    );
    // Lights are brighter than anything they light (exitance 4 pi against
    // reflected light of at most 0.8 of what arrives).
    let brightest_reflector = sol
        .mesh()
        .patches()
        .iter()
        .enumerate()
        .filter(|(p, _)| sol.mesh().patch_emission(*p as u32).max_band() == 0.0)
        .map(|(p, _)| sol.patch_radiosity()[p].max_band())
        .fold(0.0, f64::max);
    assert!(brightest_reflector > 0.0);
    assert!(brightest_reflector < 4.0 * std::f64::consts::PI);
}

/// A uniform solve of `many_boxes_with(2)` at `depth`, coarse hemi-cubes.
fn uniform_solve(depth: u8) -> Solution {
    let settings = Settings {
        hemicube_resolution: 32,
        refine: RefineSettings {
            uniform_depth: Some(depth),
            ..RefineSettings::default()
        },
        ..Settings::default()
    };
    radiosity::solve(&many_boxes_with(2).unwrap(), &settings, &|_| {}).unwrap()
}

#[test]
fn mesh_bytes_are_the_sum_of_parts_counted_independently_and_grow_with_elements() {
    // A row entry is a 32-bit patch id and a single-precision factor.
    assert_eq!(size_of::<(u32, f32)>(), 8);
    let mut last = 0;
    for depth in [0, 1, 2] {
        let sol = uniform_solve(depth);
        let (mesh, m) = (&sol.mesh(), &sol.stats().memory);
        let nodes = mesh.element_count();
        let leaves = mesh.leaf_count();
        let entries: usize = sol.leaves().iter().map(|e| e.entries().len()).sum();
        assert_eq!(m.row_entries, entries);
        assert_eq!(m.row_bytes, 8 * entries, "rows are allocated exactly");
        // The row store keeps a slot per element key with the row's state.
        assert!(m.row_table_bytes >= leaves * size_of::<(u32, RowState)>());
        assert_eq!(m.row_entries, sol.stats().hemicube.element_form_factors);
        // The arena holds at least every node, each an element plus a 32-bit
        // version, and at most twice that (it grows by doubling) plus its
        // reserved slot.
        let slot_low = size_of::<Element>() + 4;
        let slot_high = size_of::<Element>() + 8;
        assert!(m.element_arena_bytes >= nodes * slot_low);
        assert!(m.element_arena_bytes <= (2 * nodes + 1) * slot_high);
        // Patches: four-vertex polygons stay inline.
        let patches = mesh.patches().len();
        assert!(m.patch_bytes >= std::mem::size_of_val(mesh.patches()));
        assert!(m.patch_bytes <= 2 * patches * size_of::<Patch>());
        assert!(m.lattice_bytes > 0);
        // Radiosity: one value per element node and per patch.
        assert!(m.radiosity_bytes >= (nodes + patches) * size_of::<Rgb>());
        assert_eq!(
            m.mesh_bytes,
            m.element_arena_bytes
                + m.row_bytes
                + m.row_table_bytes
                + m.radiosity_bytes
                + m.patch_bytes
                + m.lattice_bytes
        );
        let per = m.mesh_bytes as f64 / leaves as f64;
        assert!((m.mesh_bytes_per_element - per).abs() <= 1e-9 * per);
        assert!((m.row_bytes_per_element * leaves as f64 - m.row_bytes as f64).abs() < 1e-6);
        // The patch system holds at least its double-precision entries.
        assert!(m.system_bytes >= 16 * sol.patch_system().nonzeros());
        assert!(m.mesh_bytes > last, "depth {depth}: {} bytes", m.mesh_bytes);
        last = m.mesh_bytes;
    }
    // An empty row holds no heap bytes (the figure counts only real entries).
    assert_eq!(Row::default().heap_bytes(), 0);
}

#[test]
fn the_solve_json_reports_mesh_bytes_and_the_peak_resident_memory() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("scale_scene_json");
    let status = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(["solve", "cornell_box", "--hemicube-res", "32"])
        .args(["--uniform-depth", "1", "--width", "32", "--height", "32"])
        .arg("--quiet")
        .arg("--out")
        .arg(&out)
        .status()
        .expect("the radiosity binary runs");
    assert!(status.success());
    let text = std::fs::read_to_string(out.join("cornell_box.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let memory = &json["memory"];
    let bytes = |key: &str| memory[key].as_u64().unwrap_or_else(|| panic!("{key}"));
    let mesh = bytes("mesh_bytes");
    assert_eq!(
        mesh,
        bytes("element_arena_bytes")
            + bytes("row_bytes")
            + bytes("row_table_bytes")
            + bytes("radiosity_bytes")
            + bytes("patch_bytes")
            + bytes("lattice_bytes")
    );
    let elements = json["counts"]["elements"].as_u64().unwrap();
    let per = memory["mesh_bytes_per_element"].as_f64().unwrap();
    assert!((per * elements as f64 - mesh as f64).abs() < 1e-6 * mesh as f64);
    if cfg!(target_os = "linux") {
        // The mesh was resident when the JSON was written.
        let peak = bytes("peak_resident_bytes");
        assert!(peak > mesh, "peak {peak} <= mesh {mesh}");
    } else {
        assert!(memory["peak_resident_bytes"].is_null());
    }
}
