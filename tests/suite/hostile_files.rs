//! Hostile scene files and settings. `tests/gltf_import.rs` covers each kind of
//! broken file by hand (truncation at every length, single corrupted bytes, NaN
//! positions, bad indices, escaping URIs, hostile counts, cycles, deep trees);
//! here valid files are mutated at random, many changes at once, in their
//! binary bytes and in their JSON fields, and every outcome must be an error
//! or a sound solve: never a panic, a hang, or memory out of proportion to the
//! file. Then every configurable limit is hit once and must say so.

use super::stress_scenes::{leaves, lit_room_with_box};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestRunner};
use radiosity::gltf_io::{load_scene, write_scene, ImportLimits};
use radiosity::refine::RefineSettings;
use radiosity::solve::SolverSettings;
use radiosity::{Error, Settings};
use serde_json::Value;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

// ---------------------------------------------------------------------------
// Memory: a counting allocator (per thread, so that tests running in parallel
// do not disturb each other; the importer is single-threaded).
// ---------------------------------------------------------------------------

struct Counting;

thread_local! {
    static LIVE: Cell<usize> = const { Cell::new(0) };
    static PEAK: Cell<usize> = const { Cell::new(0) };
}

fn count(grow: usize, shrink: usize) {
    let _ = LIVE.try_with(|live| {
        let now = live.get().saturating_add(grow).saturating_sub(shrink);
        live.set(now);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
    });
}

// SAFETY: every call is forwarded unchanged to the system allocator; the
// bookkeeping touches only const-initialised thread-locals (no allocation).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size(), 0);
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size(), 0);
        System.alloc_zeroed(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        count(0, layout.size());
        System.dealloc(ptr, layout);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size, layout.size());
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// Runs `f` and returns its result with the most bytes this thread held at once
/// while it ran, above what it held before.
fn peak_bytes<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let start = LIVE.with(Cell::get);
    PEAK.with(|p| p.set(start));
    let out = f();
    (out, PEAK.with(Cell::get) - start)
}

// ---------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------

fn dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("stress_hostile");
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The lit room with a box, written once as `.gltf` and as `.glb`.
fn base_file(extension: &str) -> Vec<u8> {
    let path = dir().join(format!("base.{extension}"));
    write_scene(&lit_room_with_box(1.0, 3.0, 0.01), &path).unwrap();
    std::fs::read(&path).unwrap()
}

/// Limits for mutated files: small enough that any file they admit is cheap.
fn mutation_limits() -> ImportLimits {
    ImportLimits {
        max_triangles: 20_000,
        max_node_depth: 64,
        max_file_bytes: 4 << 20,
        max_texture_pixels: 1 << 16,
    }
}

/// Cheap solve settings scaled to the scene: a handful of patches per surface.
fn mutation_settings(scene: &radiosity::scene::Scene) -> Settings {
    let d = scene.diameter();
    Settings {
        hemicube_resolution: 16,
        patch_size: (d.is_finite() && d > 0.0).then_some(d / 3.0),
        refine: RefineSettings {
            uniform_depth: Some(0),
            max_elements: 4000,
            ..RefineSettings::default()
        },
        solver: SolverSettings {
            max_iterations: 5000,
            ..SolverSettings::default()
        },
        max_patches: 4000,
        ..Settings::default()
    }
}

/// Outcomes of the mutated files tried so far.
#[derive(Default)]
struct Tally {
    tried: AtomicUsize,
    solved: AtomicUsize,
    load_errors: AtomicUsize,
    solve_errors: AtomicUsize,
    peak_bytes: AtomicUsize,
    largest_file: AtomicUsize,
}

impl Tally {
    fn report(&self, what: &str) -> (usize, usize) {
        let tried = self.tried.load(Ordering::Relaxed);
        let solved = self.solved.load(Ordering::Relaxed);
        let load = self.load_errors.load(Ordering::Relaxed);
        let solve = self.solve_errors.load(Ordering::Relaxed);
        eprintln!(
            "{what}: {tried} mutated files: {solved} solved ({:.0}%), {load} refused on load \
             ({:.0}%), {solve} refused by the solve ({:.0}%); importer peak {} KiB for files \
             up to {} KiB",
            100.0 * solved as f64 / tried as f64,
            100.0 * load as f64 / tried as f64,
            100.0 * solve as f64 / tried as f64,
            self.peak_bytes.load(Ordering::Relaxed) >> 10,
            self.largest_file.load(Ordering::Relaxed) >> 10,
        );
        (tried, solved)
    }
}

/// The importer may hold this much beyond 16 times the file's size: whatever
/// the file, the mutation limits admit 20,000 triangles (60,000 vertices of 24
/// bytes in an accessor without data, which glTF fills with zeros). Measured
/// peaks are about 100 KiB.
const MEMORY_ALLOWANCE: usize = 4 << 20;

/// Loads `bytes` as a file called `name` and solves it if it loads. Returns a
/// failure message for a panic, an empty error message, a non-finite or
/// negative radiosity, or memory out of proportion.
fn try_file(name: &str, bytes: &[u8], tally: &Tally) -> Result<(), String> {
    let path = dir().join(name);
    std::fs::write(&path, bytes).unwrap();
    tally.tried.fetch_add(1, Ordering::Relaxed);
    tally.largest_file.fetch_max(bytes.len(), Ordering::Relaxed);
    let limits = mutation_limits();
    let (loaded, peak) = peak_bytes(|| {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| load_scene(&path, &limits)))
    });
    tally.peak_bytes.fetch_max(peak, Ordering::Relaxed);
    if peak > 16 * bytes.len() + MEMORY_ALLOWANCE {
        return Err(format!(
            "loading held {peak} bytes for a file of {}",
            bytes.len()
        ));
    }
    let scene = match loaded {
        Err(_) => return Err("the importer panicked".to_string()),
        Ok(Err(e)) => {
            tally.load_errors.fetch_add(1, Ordering::Relaxed);
            return if e.to_string().trim().is_empty() {
                Err("an empty import error".to_string())
            } else {
                Ok(())
            };
        }
        Ok(Ok(scene)) => scene,
    };
    let settings = mutation_settings(&scene);
    let solved = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        radiosity::solve(&scene, &settings, &|_| {})
    }));
    match solved {
        Err(_) => Err("the solve panicked".to_string()),
        Ok(Err(e)) => {
            tally.solve_errors.fetch_add(1, Ordering::Relaxed);
            if e.to_string().trim().is_empty() {
                Err("an empty solve error".to_string())
            } else {
                Ok(())
            }
        }
        Ok(Ok(sol)) => {
            tally.solved.fetch_add(1, Ordering::Relaxed);
            for e in leaves(&sol) {
                if !(e.radiosity.is_finite() && e.radiosity.min_band() >= 0.0) {
                    return Err(format!(
                        "element at {} has radiosity {:?}",
                        e.centroid(),
                        e.radiosity.0
                    ));
                }
            }
            Ok(())
        }
    }
}

fn runner(cases: u32, seed: u64) -> TestRunner {
    TestRunner::new(Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(seed),
        max_shrink_iters: 64,
        ..Config::default()
    })
}

// ---------------------------------------------------------------------------
// Binary mutations of a .glb
// ---------------------------------------------------------------------------

/// Four-byte words that make numbers and counts hostile.
const WORDS: [u32; 10] = [
    0x0000_0000,
    0xFFFF_FFFF,
    0x7FFF_FFFF,
    0x8000_0000,
    0x7FC0_0000, // f32 NaN
    0x7F80_0000, // f32 +inf
    0xFF80_0000, // f32 -inf
    0x7149_F2CA, // f32 1e30
    0x0000_0001, // f32 subnormal / count 1
    0x4000_0000, // count 2^30 / f32 2
];

/// Where a byte mutation lands: anywhere, or in the binary chunk (positions and
/// indices), which random positions would rarely reach past the JSON.
#[derive(Clone, Copy, Debug)]
enum Region {
    Anywhere,
    Binary,
}

#[derive(Clone, Debug)]
enum ByteMutation {
    Set(Region, f64, u8),
    FlipBit(Region, f64, u8),
    Word(Region, f64, usize),
    Truncate(f64),
    Insert(f64, u8),
}

fn byte_mutation() -> impl Strategy<Value = ByteMutation> {
    let at = 0.0..1.0f64;
    let region = prop_oneof![1 => Just(Region::Anywhere), 3 => Just(Region::Binary)];
    prop_oneof![
        3 => (region.clone(), at.clone(), any::<u8>()).prop_map(|(r, p, b)| ByteMutation::Set(r, p, b)),
        3 => (region.clone(), at.clone(), 0..8u8).prop_map(|(r, p, b)| ByteMutation::FlipBit(r, p, b)),
        4 => (region, at.clone(), 0..WORDS.len()).prop_map(|(r, p, w)| ByteMutation::Word(r, p, w)),
        1 => at.clone().prop_map(ByteMutation::Truncate),
        1 => (at, 1..8u8).prop_map(|(p, n)| ByteMutation::Insert(p, n)),
    ]
}

/// The byte range of a GLB's binary chunk (the second chunk), read from its
/// headers.
fn binary_chunk(glb: &[u8]) -> std::ops::Range<usize> {
    let word = |at: usize| u32::from_le_bytes(glb[at..at + 4].try_into().unwrap()) as usize;
    let json_len = word(12);
    let bin_start = 20 + json_len + 8;
    assert_eq!(&glb[bin_start - 4..bin_start], b"BIN\0");
    bin_start..bin_start + word(bin_start - 8)
}

fn mutate_bytes(
    mut bytes: Vec<u8>,
    bin: std::ops::Range<usize>,
    mutations: &[ByteMutation],
) -> Vec<u8> {
    for m in mutations {
        if bytes.is_empty() {
            break;
        }
        let pos = |r: Region, p: f64, len: usize| {
            let (lo, hi) = match r {
                Region::Anywhere => (0, len),
                Region::Binary => (bin.start.min(len - 1), bin.end.min(len)),
            };
            (lo + (p * (hi - lo) as f64) as usize).min(len - 1)
        };
        match *m {
            ByteMutation::Set(r, p, b) => {
                let i = pos(r, p, bytes.len());
                bytes[i] = b;
            }
            ByteMutation::FlipBit(r, p, bit) => {
                let i = pos(r, p, bytes.len());
                bytes[i] ^= 1 << bit;
            }
            ByteMutation::Word(r, p, w) => {
                let i = pos(r, p, bytes.len()) & !3;
                let word = WORDS[w].to_le_bytes();
                let end = (i + 4).min(bytes.len());
                bytes[i..end].copy_from_slice(&word[..end - i]);
            }
            ByteMutation::Truncate(p) => bytes.truncate(pos(Region::Anywhere, p, bytes.len())),
            ByteMutation::Insert(p, n) => {
                let i = pos(Region::Anywhere, p, bytes.len());
                bytes.splice(i..i, std::iter::repeat_n(0xA5, n as usize));
            }
        }
    }
    bytes
}

#[test]
fn mutated_glb_files_are_refused_or_solved_never_a_panic() {
    let base = base_file("glb");
    let bin = binary_chunk(&base);
    let tally = Tally::default();
    let strategy = prop::collection::vec(byte_mutation(), 1..=4);
    let result = runner(600, 0x61b_0008).run(&strategy, |mutations| {
        let bytes = mutate_bytes(base.clone(), bin.clone(), &mutations);
        try_file("mutated.glb", &bytes, &tally).map_err(TestCaseError::fail)
    });
    let (tried, solved) = tally.report("glb bytes");
    if let Err(e) = result {
        panic!("{e}");
    }
    assert!(tried >= 600);
    assert!(
        solved > 0,
        "no mutation left a usable file: the test tests nothing"
    );
}

// ---------------------------------------------------------------------------
// Field mutations of a .gltf
// ---------------------------------------------------------------------------

/// JSON pointers to every number and every array of a document (the buffer's
/// data URI aside, which is mutated as binary).
fn slots(v: &Value, at: &str, numbers: &mut Vec<String>, arrays: &mut Vec<String>) {
    match v {
        Value::Number(_) => numbers.push(at.to_string()),
        Value::Array(items) => {
            arrays.push(at.to_string());
            for (i, x) in items.iter().enumerate() {
                slots(x, &format!("{at}/{i}"), numbers, arrays);
            }
        }
        Value::Object(map) => {
            for (k, x) in map {
                let k = k.replace('~', "~0").replace('/', "~1");
                slots(x, &format!("{at}/{k}"), numbers, arrays);
            }
        }
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum FieldMutation {
    /// Replace a number with the value of the given kind.
    Number(f64, u8),
    /// Truncate an array to a fraction of its length.
    Truncate(f64, f64),
    /// Append a copy of an array's first element.
    Grow(f64),
    /// Write a hostile word into the buffer data at a fraction of its length.
    Data(f64, usize),
}

fn field_mutation() -> impl Strategy<Value = FieldMutation> {
    let at = 0.0..1.0f64;
    prop_oneof![
        4 => (at.clone(), 0..14u8).prop_map(|(p, k)| FieldMutation::Number(p, k)),
        1 => (at.clone(), 0.0..1.0f64).prop_map(|(p, f)| FieldMutation::Truncate(p, f)),
        1 => at.clone().prop_map(FieldMutation::Grow),
        2 => (at, 0..WORDS.len()).prop_map(|(p, w)| FieldMutation::Data(p, w)),
    ]
}

/// A hostile replacement for `old`: huge, negative, fractional, out of range,
/// not a number at all, or an index moved.
fn hostile_number(old: &Value, kind: u8) -> Value {
    let x = old.as_f64().unwrap_or(0.0);
    match kind {
        0 => serde_json::json!(1e30),
        1 => serde_json::json!(-1),
        2 => serde_json::json!(u32::MAX),
        3 => serde_json::json!(9_007_199_254_740_993u64),
        4 => serde_json::json!(0),
        5 => serde_json::json!(1e308),
        6 => serde_json::json!(-1e308),
        7 => serde_json::json!(x + 0.5),
        8 => serde_json::json!("NaN"),
        9 => Value::Null,
        10 => serde_json::json!(x + 1.0),
        11 => serde_json::json!(x * 1000.0),
        12 => serde_json::json!(1e-300),
        _ => serde_json::json!(-x),
    }
}

fn pick(list: &[String], p: f64) -> Option<&String> {
    if list.is_empty() {
        None
    } else {
        list.get(((p * list.len() as f64) as usize).min(list.len() - 1))
    }
}

fn mutate_document(mut doc: Value, mutations: &[FieldMutation]) -> Value {
    for m in mutations {
        let (mut numbers, mut arrays) = (Vec::new(), Vec::new());
        slots(&doc, "", &mut numbers, &mut arrays);
        match *m {
            FieldMutation::Number(p, kind) => {
                if let Some(at) = pick(&numbers, p) {
                    let slot = doc.pointer_mut(at).unwrap();
                    *slot = hostile_number(slot, kind);
                }
            }
            FieldMutation::Truncate(p, f) => {
                if let Some(Value::Array(items)) = pick(&arrays, p).and_then(|a| doc.pointer_mut(a))
                {
                    items.truncate((f * items.len() as f64) as usize);
                }
            }
            FieldMutation::Grow(p) => {
                if let Some(Value::Array(items)) = pick(&arrays, p).and_then(|a| doc.pointer_mut(a))
                {
                    if let Some(first) = items.first().cloned() {
                        items.push(first);
                    }
                }
            }
            FieldMutation::Data(p, w) => {
                let Some(Value::String(uri)) = doc.pointer_mut("/buffers/0/uri") else {
                    continue;
                };
                let Some((head, data)) = uri.split_once(',') else {
                    continue;
                };
                let Ok(mut bytes) = base64::decode(data) else {
                    continue;
                };
                if bytes.len() >= 4 {
                    let i = ((p * bytes.len() as f64) as usize).min(bytes.len() - 4) & !3;
                    bytes[i..i + 4].copy_from_slice(&WORDS[w].to_le_bytes());
                    *uri = format!("{head},{}", base64::encode(&bytes));
                }
            }
        }
    }
    doc
}

#[test]
fn mutated_gltf_fields_are_refused_or_solved_never_a_panic() {
    let base: Value = serde_json::from_slice(&base_file("gltf")).unwrap();
    assert!(
        base.pointer("/buffers/0/uri")
            .and_then(Value::as_str)
            .is_some_and(|u| u.starts_with("data:")),
        "the test expects the exporter to embed its buffer"
    );
    let tally = Tally::default();
    let strategy = prop::collection::vec(field_mutation(), 1..=3);
    let result = runner(600, 0x61f_0008).run(&strategy, |mutations| {
        let doc = mutate_document(base.clone(), &mutations);
        let bytes = serde_json::to_vec(&doc).unwrap();
        try_file("mutated.gltf", &bytes, &tally).map_err(TestCaseError::fail)
    });
    let (tried, solved) = tally.report("gltf fields");
    if let Err(e) = result {
        panic!("{e}");
    }
    assert!(tried >= 600);
    assert!(
        solved > 0,
        "no mutation left a usable file: the test tests nothing"
    );
}

// ---------------------------------------------------------------------------
// Every limit, hit once
// ---------------------------------------------------------------------------

fn limit_message(e: Error) -> String {
    let text = e.to_string();
    assert!(
        matches!(e, Error::Limit { .. }),
        "not a limit error: {text}"
    );
    assert!(text.contains("limit") || text.contains("budget"), "{text}");
    text
}

#[test]
fn a_file_larger_than_the_byte_limit_is_refused() {
    let path = dir().join("limit_bytes.glb");
    std::fs::write(&path, base_file("glb")).unwrap();
    let limits = ImportLimits {
        max_file_bytes: 1000,
        ..ImportLimits::default()
    };
    let text = limit_message(load_scene(&path, &limits).unwrap_err());
    assert!(
        text.contains("limit_bytes.glb") && text.contains("1000"),
        "{text}"
    );
}

/// The index of the first mesh a node of `doc` places, after `more` more
/// nodes (roots of the first scene, a centimetre apart) place it too.
fn place_first_mesh_again(doc: &mut Value, more: usize) -> usize {
    let nodes = doc["nodes"].as_array().unwrap().len();
    let mesh = doc["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find_map(|n| n.get("mesh").and_then(Value::as_u64))
        .unwrap() as usize;
    let extra: Vec<Value> = (1..=more)
        .map(|i| serde_json::json!({"mesh": mesh, "translation": [0.0, 0.0, i as f64 * 0.01]}))
        .collect();
    doc["nodes"].as_array_mut().unwrap().extend(extra);
    let roots = doc["scenes"][0]["nodes"].as_array_mut().unwrap();
    roots.extend((nodes..nodes + more).map(|i| serde_json::json!(i)));
    mesh
}

#[test]
fn instances_count_towards_the_triangle_limit() {
    // One mesh placed by 40 more nodes: each instance's triangles count.
    let mut doc: Value = serde_json::from_slice(&base_file("gltf")).unwrap();
    place_first_mesh_again(&mut doc, 40);
    let path = dir().join("limit_instances.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let total = load_scene(&path, &ImportLimits::default())
        .unwrap()
        .import_stats
        .triangles_read;
    let limits = ImportLimits {
        max_triangles: total - 1,
        ..ImportLimits::default()
    };
    let text = limit_message(load_scene(&path, &limits).unwrap_err());
    assert!(text.contains(&format!("{}", total - 1)), "{text}");
}

#[test]
fn a_mesh_placed_by_several_nodes_warns_of_a_fault_once() {
    // The base file's first mesh loses its material and is placed by two
    // more nodes: the default-grey warning is said once, not three times.
    let mut doc: Value = serde_json::from_slice(&base_file("gltf")).unwrap();
    let mesh = place_first_mesh_again(&mut doc, 2);
    for prim in doc["meshes"][mesh]["primitives"].as_array_mut().unwrap() {
        prim.as_object_mut().unwrap().remove("material");
    }
    let path = dir().join("instanced_without_material.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let scene = load_scene(&path, &ImportLimits::default()).unwrap();
    let grey: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("has no material"))
        .collect();
    let primitives = doc["meshes"][mesh]["primitives"].as_array().unwrap().len();
    assert_eq!(grey.len(), primitives, "{grey:?}");
}

#[test]
fn the_patch_limit_is_an_error_before_anything_is_allocated() {
    let scene = lit_room_with_box(1.0, 1.0, 0.01);
    let settings = Settings {
        max_patches: 50,
        ..Settings::default()
    };
    let text = limit_message(radiosity::solve(&scene, &settings, &|_| {}).unwrap_err());
    assert!(text.contains("50 patches"), "{text}");
    // A patch size of 1e-7 m would cut a 2 m wall into 2^36 patches: refused
    // at once (the count used to overflow and be allocated cell by cell).
    let (result, peak) = peak_bytes(|| {
        radiosity::solve(
            &scene,
            &Settings {
                patch_size: Some(1e-7),
                ..Settings::default()
            },
            &|_| {},
        )
    });
    let text = limit_message(result.unwrap_err());
    assert!(text.contains("68719476736"), "{text}");
    assert!(peak < 1 << 20, "{peak} bytes before refusing");
}

#[test]
fn the_element_budget_is_an_error_up_front_and_a_cap_when_adapting() {
    let scene = lit_room_with_box(1.0, 1.0, 0.01);
    // Uniform subdivision beyond the budget: refused before any hemi-cube.
    let uniform = Settings {
        hemicube_resolution: 16,
        patch_size: Some(0.6),
        refine: RefineSettings {
            uniform_depth: Some(4),
            max_elements: 5000,
            ..RefineSettings::default()
        },
        ..Settings::default()
    };
    let text = limit_message(radiosity::solve(&scene, &uniform, &|_| {}).unwrap_err());
    assert!(text.contains("element budget of 5000"), "{text}");
    // Adaptive refinement treats it as a budget: it stops splitting there and
    // reports the leaves it could not split.
    let adaptive = Settings {
        hemicube_resolution: 16,
        patch_size: Some(0.6),
        refine: RefineSettings {
            max_elements: 400,
            tolerance: 0.001,
            ..RefineSettings::default()
        },
        ..Settings::default()
    };
    let sol = radiosity::solve(&scene, &adaptive, &|_| {}).unwrap();
    assert!(
        sol.stats().elements <= 400,
        "{} elements",
        sol.stats().elements
    );
    assert!(
        sol.stats().passes.iter().any(|p| p.blocked > 0),
        "the budget must show as blocked splits"
    );
}

#[test]
fn a_tiny_file_cannot_claim_millions_of_zero_vertices() {
    // An accessor without a buffer view reads as zeros (glTF): its count costs
    // the file nothing. 6 million of them in a 250-byte file are refused
    // before they are allocated (they used to take 511 MiB).
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "accessors": [{
            "componentType": 5126, "count": 6_000_000, "type": "VEC3",
            "min": [0.0, 0.0, 0.0], "max": [0.0, 0.0, 0.0]
        }],
        "meshes": [{"name": "zeros", "primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    });
    let path = dir().join("zeros.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let (result, peak) = peak_bytes(|| load_scene(&path, &ImportLimits::default()));
    let text = result.unwrap_err().to_string();
    assert!(
        text.contains("zeros.gltf") && text.contains("accessor 0"),
        "{text}"
    );
    assert!(text.contains("out of proportion"), "{text}");
    assert!(peak < 1 << 20, "{peak} bytes");
}
