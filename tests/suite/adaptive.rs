//! Adaptive subdivision on a penumbra scene, measured against the exact oracle:
//! where the elements go, what they buy, and crack-free shading.

use glam::DVec3;
use radiosity::scenes::penumbra::{penumbra_parallel, PenumbraSpec};
use radiosity::Settings;

use super::penumbra_metrics::measure;

/// The floor's object index in the penumbra scenes.
fn floor_object(spec: &PenumbraSpec) -> u32 {
    let scene = spec.scene().unwrap();
    scene
        .objects
        .iter()
        .position(|o| o.name == "floor")
        .unwrap() as u32
}

#[test]
fn finest_elements_lie_in_the_penumbra() {
    let spec = penumbra_parallel();
    let scene = spec.scene().unwrap();
    let sol = radiosity::solve(&scene, &Settings::default(), &|_| {}).unwrap();
    let oracle = spec.oracle().unwrap();
    let floor = floor_object(&spec);
    let leaves: Vec<_> = sol
        .leaves()
        .into_iter()
        .filter(|e| sol.mesh().surfaces()[e.surface() as usize].object == floor)
        .collect();
    let deepest = leaves.iter().map(|e| e.depth()).max().unwrap();
    let shallowest = leaves.iter().map(|e| e.depth()).min().unwrap();
    assert!(
        deepest >= shallowest + 2,
        "refinement must concentrate somewhere"
    );
    // The visible fraction of the light at a floor point: 1 fully lit, 0 umbra.
    let visible = |p: DVec3| {
        let n = spec.floor_normal();
        oracle.visible_form_factor(p, n).unwrap() / oracle.unoccluded_form_factor(p, n).unwrap()
    };
    for e in leaves.iter().filter(|e| e.depth() == deepest) {
        // Sample a neighbourhood three element widths across: somewhere in it the
        // light must be partly hidden (penumbra), or it must hold both lit and
        // umbra points.
        let r = 1.5 * e.area().sqrt();
        let mut fractions = Vec::new();
        for i in -4..=4 {
            for j in -4..=4 {
                let p = e.centroid() + DVec3::new(f64::from(i), 0.0, f64::from(j)) * (r / 4.0);
                fractions.push(visible(p));
            }
        }
        let partial = fractions.iter().any(|f| *f > 1e-6 && *f < 1.0 - 1e-6);
        assert!(
            partial,
            "a finest element at {:?} is far from the penumbra",
            e.centroid()
        );
    }
}

/// Barycentric interpolation of the display mesh at `p` (on the floor plane),
/// from the first triangle that contains it.
fn shaded_at(mesh: &radiosity::mesh::ShadingMesh, p: DVec3) -> Option<f64> {
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        // Project onto the floor (y up) and solve in x-z.
        let (ax, az, bx, bz, cx, cz) = (a.x, a.z, b.x, b.z, c.x, c.z);
        let det = (bx - ax) * (cz - az) - (cx - ax) * (bz - az);
        if det.abs() < 1e-15 || (a.y - p.y).abs() > 1e-9 {
            continue;
        }
        let u = ((p.x - ax) * (cz - az) - (cx - ax) * (p.z - az)) / det;
        let v = ((bx - ax) * (p.z - az) - (p.x - ax) * (bz - az)) / det;
        if u >= -1e-12 && v >= -1e-12 && u + v <= 1.0 + 1e-12 {
            let [va, vb, vc] = t.map(|i| mesh.radiosity[i as usize][0]);
            return Some(va + u * (vb - va) + v * (vc - va));
        }
    }
    None
}

#[test]
fn shading_is_continuous_across_refined_and_unrefined_neighbours() {
    let spec = penumbra_parallel();
    let scene = spec.scene().unwrap();
    let sol = radiosity::solve(&scene, &Settings::default(), &|_| {}).unwrap();
    let mesh = sol.shading_mesh();
    let floor = floor_object(&spec);
    let mut checked = 0;
    let scale = mesh.radiosity.iter().map(|b| b[0]).fold(0.0, f64::max);
    for (key, e) in sol.mesh().elements() {
        let lattice = &sol.mesh().surfaces()[e.surface() as usize];
        if !e.is_leaf() || lattice.object != floor {
            continue;
        }
        let poly = lattice.polygon(&e.cell());
        for (i, n) in sol.mesh().edge_neighbours(key).into_iter().enumerate() {
            let Some(n) = n else { continue };
            if sol.mesh()[n].depth() >= e.depth() {
                continue; // only edges where the other side is coarser
            }
            let (p0, p1) = (poly[i], poly[(i + 1) % poly.len()]);
            let inward = (e.centroid() - (p0 + p1) * 0.5).normalize() * 1e-7;
            for t in [0.25, 0.5, 0.75] {
                let p = p0.lerp(p1, t);
                let fine = shaded_at(&mesh, p + inward).unwrap();
                let coarse = shaded_at(&mesh, p - inward).unwrap();
                assert!(
                    (fine - coarse).abs() <= 1e-5 * scale,
                    "jump {} at {p:?} between depth {} and {}",
                    fine - coarse,
                    e.depth(),
                    sol.mesh()[n].depth()
                );
                checked += 1;
            }
        }
    }
    assert!(
        checked > 20,
        "the test needs refined/unrefined boundaries ({checked})"
    );
}

/// Floor leaves and their area-weighted mean error against the exact element
/// means, relative to the light-on value.
fn floor_error(spec: &PenumbraSpec, settings: &Settings) -> (usize, f64) {
    let errors = measure(spec, settings);
    (errors.floor.len(), errors.mean)
}

/// The substructuring claim: adaptive subdivision reaches the error of the
/// uniform depth-4 mesh with at most a quarter of its elements. Measured on
/// the narrow penumbra (a 0.25 m light), where sharp shadows occupy a small
/// part of the floor, with emitter form factors as element means so that the
/// smooth lit regions need no subdivision. "Reaches" allows 1% of the uniform
/// mesh's error: the adaptive mesh has the same finest elements in the
/// penumbra, and the rest differ in the fifth digit (6.13e-5 against 6.12e-5
/// when written).
#[test]
fn adaptive_reaches_uniform_depth_four_with_a_quarter_of_its_elements() {
    let spec = radiosity::scenes::penumbra::penumbra_narrow();
    let mut uniform = Settings {
        emitter_sampling: radiosity::formfactor::EmitterSampling::Element,
        ..Settings::default()
    };
    uniform.refine.uniform_depth = Some(4);
    let mut adaptive = Settings {
        emitter_sampling: radiosity::formfactor::EmitterSampling::Element,
        ..Settings::default()
    };
    adaptive.refine.max_depth = 4;
    let (n_uniform, e_uniform) = floor_error(&spec, &uniform);
    let (n_adaptive, e_adaptive) = floor_error(&spec, &adaptive);
    assert!(
        4 * n_adaptive <= n_uniform,
        "adaptive used {n_adaptive} floor elements, uniform depth 4 {n_uniform}"
    );
    assert!(
        e_adaptive <= 1.01 * e_uniform,
        "adaptive error {e_adaptive:.3e} against uniform depth 4's {e_uniform:.3e}"
    );
}

/// With exact emitter visibility and element-mean form factors, a penumbra
/// whose edges cross the elements at an angle is within 1e-5 of the light-on
/// radiosity already at uniform depth 2 (measured 4.1e-6 when written; the
/// shadow rays it replaces left 8e-4).
#[test]
fn element_mean_emitters_match_the_exact_penumbra() {
    let spec = radiosity::scenes::penumbra::penumbra_rotated();
    let mut settings = Settings {
        emitter_sampling: radiosity::formfactor::EmitterSampling::Element,
        ..Settings::default()
    };
    settings.refine.uniform_depth = Some(2);
    let (_, error) = floor_error(&spec, &settings);
    assert!(error < 1e-5, "mean floor error {error:.3e}");
}

/// A lamp facing up and a grey ceiling tile facing down 2 m above it, far to
/// the side of and below the penumbra scene's floor: the two light only each
/// other, and the tile is `brighter` times as bright as the penumbra floor's
/// light-on value, roughly (the lamp's radiance is scaled by it).
fn penumbra_beside_a_bright_tile(spec: &PenumbraSpec, brighter: f64) -> radiosity::scene::Scene {
    use radiosity::math::Rgb;
    use radiosity::scene::SceneBuilder;
    let mut b = SceneBuilder::new("penumbra_beside_a_bright_tile");
    let light = b.material("light", Rgb::ZERO, spec.light_radiance).unwrap();
    let black = b.material("occluder", Rgb::ZERO, Rgb::ZERO).unwrap();
    let floor = b
        .material("floor", spec.floor_reflectance, Rgb::ZERO)
        .unwrap();
    b.object("light");
    b.polygon(light, &spec.light).unwrap();
    b.object("occluder");
    b.polygon(black, &spec.occluders[0]).unwrap();
    b.object("floor");
    b.polygon(floor, &spec.floor).unwrap();
    // The tile's middle, 2 m above a 1 m lamp, sees it with a form factor of
    // about 1 / (4 pi): its radiosity is about 0.8 * pi * radiance / (4 pi).
    let light_on = super::penumbra_metrics::light_on_value(spec);
    let radiance = Rgb::splat(brighter * light_on / 0.2);
    let lamp = b.material("far lamp", Rgb::ZERO, radiance).unwrap();
    let grey = b.material("far tile", Rgb::splat(0.8), Rgb::ZERO).unwrap();
    let square = |x0: f64, y: f64, half: f64, up: bool| {
        let (x1, z0, z1) = (x0 + 2.0 * half, -half, half);
        let mut p = vec![
            DVec3::new(x0, y, z0),
            DVec3::new(x0, y, z1),
            DVec3::new(x1, y, z1),
            DVec3::new(x1, y, z0),
        ];
        if !up {
            p.reverse();
        }
        p
    };
    b.object("far lamp");
    b.polygon(lamp, &square(99.5, -20.0, 0.5, true)).unwrap();
    b.object("far tile");
    b.polygon(grey, &square(99.0, -18.0, 1.0, false)).unwrap();
    b.build().unwrap()
}

/// With a dim floor below 1, refinement measures a difference against the
/// brighter neighbour, not the scene's brightest surface: beside an unrelated
/// tile five times as bright, a penumbra with a floor of 0.2 is refined as it
/// is alone at the default floor (1, where it is the brightest surface). At
/// the default floor the same penumbra beside the tile gets coarser elements
/// and a larger error: what leaves the contact shadows of dim corridors
/// whole in large interiors.
#[test]
fn a_dim_floor_refines_a_dim_shadow_as_one_in_full_light() {
    let spec = radiosity::scenes::penumbra::penumbra_narrow();
    let alone = super::penumbra_metrics::measure(&spec, &Settings::default());
    let scene = penumbra_beside_a_bright_tile(&spec, 5.0);
    let mut local = Settings::default();
    local.refine.dim_floor = 0.2;
    let beside = super::penumbra_metrics::measure_scene(&spec, &scene, &local);
    let beside_global = super::penumbra_metrics::measure_scene(&spec, &scene, &Settings::default());
    // The tile is as bright as intended.
    let sol = &beside.solution;
    let tile = sol
        .mesh()
        .surfaces()
        .iter()
        .position(|s| scene.objects[s.object as usize].name == "far tile")
        .unwrap();
    let tile_value = sol
        .leaves()
        .into_iter()
        .filter(|e| e.surface() as usize == tile)
        .map(|e| e.radiosity[0])
        .fold(0.0, f64::max);
    let ratio = tile_value / alone.light_on;
    eprintln!(
        "tile {ratio:.2}x; floor leaves alone {} beside (floor 0.2) {} beside (floor 1) {}; \
         mean error {:.3e} {:.3e} {:.3e}",
        alone.floor.len(),
        beside.floor.len(),
        beside_global.floor.len(),
        alone.mean,
        beside.mean,
        beside_global.mean
    );
    assert!((3.0..8.0).contains(&ratio), "tile {ratio}x the floor");
    assert!(
        beside.mean <= 1.1 * alone.mean,
        "beside a bright tile {:.3e}, alone {:.3e}",
        beside.mean,
        alone.mean
    );
    assert!(
        beside_global.mean > 1.5 * alone.mean,
        "the scene-wide scale's {:.3e} against {:.3e}: the test would not see it",
        beside_global.mean,
        alone.mean
    );
}

/// A seat 0.3 m above a floor of 2 m patches, beside a tile forty times as
/// bright: at the scene-wide scale the seat's shadow is too dim to split the
/// floor's 1 m leaves. The leaf whose centroid lies under the seat sees it
/// nearer than its own size over half its view, so a near floor of 0.1
/// measures its differences against its own light and splits it: the
/// bench in a dim corridor. The error about the seat (the leaves within
/// 0.25 m of its footprint) against the exact oracle falls. (Its children
/// each see the seat over a quarter of their view, below
/// `radiosity::refine::NEAR_SHARE`, so they split no further here.)
#[test]
fn a_near_floor_refines_a_low_seat_s_shadow_in_a_dim_region() {
    let mut spec = penumbra_parallel();
    // Centred over the centroid of one of the floor's first 1 m leaves:
    // the share is taken at centroids, and a seat narrower than a leaf
    // that lay between them would not be seen (a limit of the criterion).
    let (x0, x1, z0, z1, y) = (0.0, 1.0, 0.3, 0.7, 0.3);
    spec.occluders = vec![[
        DVec3::new(x0, y, z0),
        DVec3::new(x1, y, z0),
        DVec3::new(x1, y, z1),
        DVec3::new(x0, y, z1),
    ]];
    let scene = penumbra_beside_a_bright_tile(&spec, 40.0);
    let about_the_seat = |settings: &Settings| {
        let m = super::penumbra_metrics::measure_scene(&spec, &scene, settings);
        let margin = 0.25;
        let near: Vec<_> = m
            .floor
            .iter()
            .filter(|e| {
                let c = e.polygon.iter().copied().sum::<DVec3>() / e.polygon.len() as f64;
                (x0 - margin..x1 + margin).contains(&c.x)
                    && (z0 - margin..z1 + margin).contains(&c.z)
            })
            .collect();
        let area: f64 = near.iter().map(|e| e.area).sum();
        let error = near
            .iter()
            .map(|e| (e.solved - e.exact).abs() * e.area)
            .sum::<f64>()
            / area
            / m.light_on;
        let largest = near.iter().map(|e| e.area.sqrt()).fold(0.0, f64::max);
        (near.len(), largest, error)
    };
    // Patches as large as an interior's: the floor's first leaves are 1 m.
    let interior = Settings {
        patch_size: Some(2.0),
        ..Settings::default()
    };
    let mut near = interior.clone();
    near.refine.near_floor = 0.1;
    let (count, largest, error) = about_the_seat(&near);
    let (count_wide, largest_wide, error_wide) = about_the_seat(&interior);
    eprintln!(
        "about the seat: {count} leaves up to {largest:.3} m, error {error:.3e}; \
         near floor 1: {count_wide} up to {largest_wide:.3} m, error {error_wide:.3e}"
    );
    assert!(largest <= 0.5, "leaves about the seat up to {largest} m");
    assert!(
        largest_wide >= 1.0,
        "near floor 1 splits them too ({largest_wide} m): the test would not see it"
    );
    assert!(
        error_wide > 2.0 * error,
        "about the seat {error:.3e}, at near floor 1 {error_wide:.3e}"
    );
}

/// A dim or near floor outside (0, 1] is refused before any form factor,
/// naming the setting: 0 would divide by nothing in black regions, and above
/// 1 it would only loosen the tolerance.
#[test]
fn a_dim_floor_out_of_range_is_refused_naming_the_setting() {
    for name in ["refine.dim_floor", "refine.near_floor"] {
        for bad in [0.0, -0.1, 1.5, f64::NAN] {
            let mut settings = Settings::default();
            if name == "refine.dim_floor" {
                settings.refine.dim_floor = bad;
            } else {
                settings.refine.near_floor = bad;
            }
            let message = settings.validate().unwrap_err().to_string();
            assert!(message.contains(name), "{name} {bad}: {message}");
        }
    }
    let mut fine = Settings::default();
    fine.refine.dim_floor = 0.1;
    fine.refine.near_floor = 1.0;
    assert!(fine.validate().is_ok());
}
