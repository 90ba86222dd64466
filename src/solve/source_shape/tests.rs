use super::correction::{Correction, UNSURE_LIMIT};
use super::near_weights::NearEntry;
use super::*;
use crate::formfactor::RowScene;
use crate::scene::{Scene, SceneBuilder};
use crate::solution::Solution;
use crate::solve::ragged::Ragged;
use crate::Settings;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A 4 m floor of one patch lit by a lamp over its west end, and a panel
/// standing on its east half.
fn scene() -> Scene {
    let mut b = SceneBuilder::new("floor");
    let grey = b.material("grey", Rgb::splat(0.8), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
    b.object("floor");
    b.quad(
        grey,
        v(0., 0., 0.),
        v(0., 0., 4.),
        v(4., 0., 4.),
        v(4., 0., 0.),
    )
    .unwrap();
    b.object("lamp");
    b.quad(
        lamp,
        v(0.5, 2., 1.5),
        v(1.5, 2., 1.5),
        v(1.5, 2., 2.5),
        v(0.5, 2., 2.5),
    )
    .unwrap();
    b.object("panel");
    b.quad(
        grey,
        v(2.5, 0., 1.5),
        v(2.5, 0.6, 1.5),
        v(2.5, 0.6, 2.5),
        v(2.5, 0., 2.5),
    )
    .unwrap();
    b.build().unwrap()
}

fn solved() -> Solution {
    solved_scene(&scene())
}

fn solved_scene(scene: &Scene) -> Solution {
    let settings = Settings {
        patch_size: Some(4.0),
        shaped_gathers: Some(0),
        ..Settings::default()
    };
    crate::solve(scene, &settings, &|_| {}).unwrap()
}

/// The lit floor of [`scene`] without the panel, a small shelf facing
/// it 0.5 m over its middle, and a blind halfway between them that hides
/// the floor's west half from the middle of the shelf: a ray from
/// (x, 0.5, z) to the floor crosses the blind's height at the mean of
/// the two x.
fn blinded_scene() -> Scene {
    let mut b = SceneBuilder::new("blinded");
    let grey = b.material("grey", Rgb::splat(0.8), Rgb::ZERO).unwrap();
    let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
    b.object("floor");
    b.quad(
        grey,
        v(0., 0., 0.),
        v(0., 0., 4.),
        v(4., 0., 4.),
        v(4., 0., 0.),
    )
    .unwrap();
    let down = |b: &mut SceneBuilder, m, y: f64, x: [f64; 2], z: [f64; 2]| {
        b.quad(
            m,
            v(x[0], y, z[0]),
            v(x[1], y, z[0]),
            v(x[1], y, z[1]),
            v(x[0], y, z[1]),
        )
        .unwrap();
    };
    b.object("lamp");
    down(&mut b, lamp, 2.0, [0.5, 1.5], [1.5, 2.5]);
    b.object("shelf");
    down(&mut b, grey, 0.5, [1.9, 2.1], [1.9, 2.1]);
    b.object("blind");
    down(&mut b, grey, 0.25, [0.9, 2.0], [0.9, 3.1]);
    b.build().unwrap()
}

/// Through the whole solve: with part views the shelf, which the blind
/// keeps from the floor's west half, gathers more (the test below finds
/// what it sees of the floor brighter than the mean of every part), the
/// views are counted, and the energy balance stays as it was.
#[test]
fn part_views_brighten_the_blinded_shelf_and_keep_the_balance() {
    let scene = blinded_scene();
    let solve = |part_views: bool| {
        let settings = Settings {
            patch_size: Some(4.0),
            part_views: Some(part_views),
            ..Settings::default()
        };
        crate::solve(&scene, &settings, &|_| {}).unwrap()
    };
    let (plain, viewed) = (solve(false), solve(true));
    assert_eq!(plain.stats.shaped_views, vec![0]);
    assert!(
        viewed.stats.shaped_views[0] >= 1,
        "{:?}",
        viewed.stats.shaped_views
    );
    let shelf = |sol: &Solution| {
        let (mut area, mut power) = (0.0, 0.0);
        for k in sol.mesh.leaves() {
            let e = &sol.mesh.elements[k];
            if (e.centroid.y - 0.5).abs() < 1e-9 && e.centroid.x > 1.8 {
                area += e.area;
                power += sol.radiosity.element(k)[0] * e.area;
            }
        }
        power / area
    };
    let (before, after) = (shelf(&plain), shelf(&viewed));
    assert!(after > before * 1.02, "shelf {before} -> {after}");
    let (a, b) = (
        plain.stats.energy.relative_difference,
        viewed.stats.energy.relative_difference,
    );
    assert!((a - b).abs() < 1e-3, "energy balance {a} -> {b}");
}

/// A receiver with part of an unevenly lit patch hidden from it weighs
/// the parts its hemi-cube shows, not all of them: its ratio comes out
/// near the one weighing only the parts the geometry leaves in sight,
/// far from the one weighing every part.
#[test]
fn a_receiver_weighs_only_the_parts_its_hemicube_shows() {
    let sol = solved_scene(&blinded_scene());
    let shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
    let floor = floor_patch(&sol);
    let s = shapes.slot[floor as usize];
    assert!(s != u32::MAX, "the floor is uneven");
    let shaped = &shapes.shaped[s as usize];
    let mesh = &sol.mesh;
    // The shelf's leaf nearest its middle.
    let shelf = mesh
        .leaves()
        .into_iter()
        .filter(|&k| {
            let e = &mesh.elements[k];
            (e.centroid.y - 0.5).abs() < 1e-9
                && mesh.surfaces()[e.surface as usize].normal.y < -0.9
                && e.centroid.x > 1.8
        })
        .min_by(|&a, &b| {
            let d = |k: ElementKey| (mesh.elements[k].centroid - v(2.0, 0.5, 2.0)).length();
            d(a).total_cmp(&d(b))
        })
        .expect("a shelf leaf");
    let e = &mesh.elements[shelf];
    let entries = sol.form_factors.entries(shelf);
    let i = entries.iter().position(|x| x.0 == floor).unwrap() as u32;
    let (all, _) = shapes.ratio(floor, e.centroid, DVec3::NEG_Y).unwrap();
    // The floor in sight: beyond x = 4 - eye x, where rays pass the
    // blind's east edge at x = 2.
    let cut = 4.0 - e.centroid.x;
    let (mut weight, mut seen) = (0.0, Rgb::ZERO);
    for (p, f) in shaped.weighed_parts(e.centroid, DVec3::NEG_Y) {
        let part = &shaped.parts[p as usize];
        if part.source.centre.x > cut {
            weight += f * part.share;
            seen += shaped.values[p as usize] * (f * part.share);
        }
    }
    let in_sight = shaped.ratio_of(seen, weight).unwrap();
    let sources = crate::formfactor::Sources::from_mesh(mesh);
    let settings = crate::formfactor::RowSettings {
        table: std::sync::Arc::new(crate::formfactor::hemicube::DeltaTable::new(64)),
        seed: 1,
        method: crate::formfactor::FormFactorMethod::Hybrid,
        emitter_sampling: crate::formfactor::EmitterSampling::default(),
        level_of_detail: true,
    };
    let skips = crate::formfactor::RowSkips::default();
    let mut near = Ragged::default();
    near.push_row([NearEntry {
        index: i,
        weight: 1.0,
        parts: 0..0,
        kept: false,
        look: true,
        hidden: 0.5,
    }]);
    let scene = || RowScene::new(mesh, &sources, &settings, &skips);
    let views = PartViews {
        scene: &scene,
        progress: &|_, _| {},
    };
    let mut weights = Vec::new();
    let views = shapes.seen_weights(
        mesh,
        &sol.form_factors,
        &[shelf],
        &near,
        &views,
        |n, m, w| {
            weights.push((n, m, w));
        },
    );
    assert_eq!(views, 1);
    assert_eq!(weights.len(), 1, "the shelf sees part of the floor");
    let by_view = shaped.ratio_from(&weights[0].2).unwrap();
    let (all, in_sight, by_view) = (all[0], in_sight[0], by_view[0]);
    eprintln!("every part {all:.4}, in sight {in_sight:.4}, by the hemi-cube {by_view:.4}");
    assert!(
        (all - in_sight).abs() > 0.1 * in_sight,
        "hiding the west half matters: {all} against {in_sight}"
    );
    assert!(
        (by_view - in_sight).abs() < 0.2 * (all - in_sight).abs(),
        "by its hemi-cube {by_view}, in sight {in_sight}, every part {all}"
    );
}

fn floor_patch(sol: &Solution) -> u32 {
    let floor = sol
        .mesh
        .patches
        .iter()
        .position(|p| sol.mesh.surfaces()[p.surface as usize].normal.y > 0.9)
        .unwrap();
    floor as u32
}

#[test]
fn a_receiver_over_the_dark_end_sees_less_than_the_mean_and_one_over_the_lit_end_more() {
    let sol = solved();
    let shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
    let floor = floor_patch(&sol);
    assert!(
        shapes.slot[floor as usize] != u32::MAX,
        "the floor is uneven"
    );
    let down = DVec3::NEG_Y;
    let dark = shapes.ratio(floor, v(3.9, 0.1, 0.1), down).unwrap().0;
    let lit = shapes.ratio(floor, v(1.0, 0.1, 2.0), down).unwrap().0;
    for band in 0..3 {
        assert!(dark[band] < 0.7, "{dark:?}");
        assert!(lit[band] > 1.2, "{lit:?}");
    }
    // Far away every part weighs by its area: no correction.
    let shaped = &shapes.shaped[shapes.slot[floor as usize] as usize];
    assert_eq!(shaped.nearness(v(2.0, 50.0, 2.0)), 0.0);
    assert_eq!(shaped.nearness(v(3.9, 0.1, 0.1)), 1.0);
    // The floor's back sees none of it.
    assert!(shapes.ratio(floor, v(2.0, -0.1, 2.0), down).is_none());
}

#[test]
fn a_correction_leaves_sure_ratios_alone_while_the_unsure_share_can_take_the_difference() {
    // Three receivers of one patch, weights w, ratios r, unsure shares u.
    let w = [2.0, 1.0, 3.0];
    let r = [Rgb::splat(0.5), Rgb::splat(1.2), Rgb::ONE];
    let u = [0.0, 0.5, 1.0];
    let gathered = |c: &Correction| -> f64 { (0..3).map(|i| c.apply(r[i], u[i])[0] * w[i]).sum() };
    let with: f64 = (0..3).map(|i| r[i][0] * w[i]).sum(); // 5.2
    let unsure: f64 = (0..3).map(|i| r[i][0] * w[i] * u[i]).sum(); // 3.6
    for target in [5.6, 4.9] {
        let c = Correction::of(Rgb::splat(target), Rgb::splat(with), Rgb::splat(unsure));
        assert!(
            (gathered(&c) - target).abs() < 1e-12,
            "{target}: {}",
            gathered(&c)
        );
        // The sure receiver keeps its ratio; the far one takes the most.
        assert_eq!(c.apply(r[0], u[0]), r[0]);
        let factor = 1.0 + (target - with) / unsure;
        assert!((c.apply(r[2], u[2])[0] - factor).abs() < 1e-12);
    }
    // A difference the unsure share cannot take within the limit: the
    // rest is spread over every ratio alike, and the total still holds.
    let target = 20.0;
    let c = Correction::of(Rgb::splat(target), Rgb::splat(with), Rgb::splat(unsure));
    assert_eq!(c.unsure[0], UNSURE_LIMIT);
    assert!(c.all[0] > 1.0);
    assert!((gathered(&c) - target).abs() < 1e-9);
    // Nothing unsure: the old scaling, every ratio alike.
    let c = Correction::of(Rgb::splat(6.0), Rgb::splat(with), Rgb::ZERO);
    assert_eq!(c.unsure, Rgb::ONE);
    assert!((c.apply(r[0], 0.0)[0] - 0.5 * 6.0 / with).abs() < 1e-15);
}

/// Refreshing a patch's values from another radiosity gives what
/// building the shapes from that radiosity gives: the parts' values,
/// the means, the swings and what the patches send, while what the
/// receivers weigh stays as it was.
#[test]
fn a_refresh_takes_the_values_a_new_build_would() {
    let sol = solved();
    let mut shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
    assert!(shapes.len() >= 1);
    // Another radiosity: every leaf brighter the farther east it lies.
    let mut other = sol.radiosity.clone();
    for k in sol.mesh.leaves() {
        let x = sol.mesh.elements[k].centroid.x;
        other.set_element(k, sol.radiosity.element(k) * (1.0 + 0.25 * x));
    }
    shapes.refresh(&sol.mesh, &sol.form_factors, &other, false);
    let fresh = SourceShapes::new(&sol.mesh, &sol.form_factors, &other, false);
    // The patches shaped before are compared (the new values may make
    // others uneven too, which a refresh does not add).
    let close = |a: Rgb, b: Rgb| (a - b).abs().max_band() <= 1e-12 * b.max_band().max(1e-300);
    for (p, &s) in shapes.slot.iter().enumerate() {
        if s == u32::MAX {
            continue;
        }
        assert!(fresh.slot[p] != u32::MAX, "patch {p} is still uneven");
        let a = &shapes.shaped[s as usize];
        let b = &fresh.shaped[fresh.slot[p] as usize];
        assert!(
            close(a.mean, b.mean),
            "mean {:?} against {:?}",
            a.mean,
            b.mean
        );
        assert!(
            close(a.swing, b.swing),
            "swing {:?} against {:?}",
            a.swing,
            b.swing
        );
        assert!(
            close(a.sent, b.sent),
            "sent {:?} against {:?}",
            a.sent,
            b.sent
        );
        assert_eq!(a.values.len(), b.values.len());
        for (p, q) in a.values.iter().zip(&b.values) {
            assert!(close(*p, *q), "part {p:?} against {q:?}");
        }
    }
    // The scaling moved the patch's light east: a ratio changed.
    let unchanged = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
    let moved = shapes
        .shaped
        .iter()
        .zip(&unchanged.shaped)
        .flat_map(|(a, b)| a.values.iter().zip(&b.values).map(|(p, q)| (*p, *q)))
        .any(|(p, q)| (p[0] / q[0] - 1.0).abs() > 0.01);
    assert!(moved, "the refresh took the new values");
}

/// Receivers past the budget weigh their parts again each time: the
/// factors are the same bits as with every weight kept.
#[test]
fn weights_not_kept_give_the_same_factors() {
    let sol = solved();
    let shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
    let leaves = sol.mesh.leaves();
    let (mesh, ff) = (&sol.mesh, &sol.form_factors);
    let all = shapes
        .near_weights_within(mesh, ff, &leaves, None, usize::MAX)
        .unwrap();
    let none = shapes
        .near_weights_within(mesh, ff, &leaves, None, 0)
        .unwrap();
    let kept = |w: &NearWeights| w.near.rows().flatten().filter(|e| e.kept).count();
    assert!(kept(&all) > 0);
    assert_eq!(kept(&none), 0);
    let a = shapes.factors(mesh, ff, &leaves, |_| 1.0, &all);
    let b = shapes.factors(mesh, ff, &leaves, |_| 1.0, &none);
    assert_eq!(a.near, b.near);
    assert_eq!(a.patch, b.patch);
}

#[test]
fn the_factors_keep_what_the_receivers_gather_from_each_patch() {
    let sol = solved();
    let shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
    assert!(shapes.len() >= 1);
    let leaves = sol.mesh.leaves();
    let factors = shapes
        .entry_factors(&sol.mesh, &sol.form_factors, &leaves, |_| 1.0, None)
        .unwrap();
    let patches = sol.mesh.patches.len();
    let (mut with, mut without) = (vec![Rgb::ZERO; patches], vec![0.0; patches]);
    let mut moved = 0.0f64;
    for (n, &k) in leaves.iter().enumerate() {
        let e = &sol.mesh.elements[k];
        let reflects = e.reflectance.max_band() > 0.0;
        let mut near = factors.near.row(n).iter().peekable();
        for (i, &(j, f)) in sol.form_factors.entries(k).iter().enumerate() {
            let r = factors.factor(&mut near, i, j, reflects);
            if !reflects {
                // Receivers that reflect nothing (the lamp) gather means.
                assert_eq!(r, Rgb::ONE);
                continue;
            }
            let w = e.area * f64::from(f);
            with[j as usize] += r * w;
            without[j as usize] += w;
            moved = moved.max((r[0] - 1.0).abs());
        }
    }
    assert!(moved > 0.1, "the factors change something: {moved}");
    // Each patch's receivers gather its mean times its `sent` ratio; an
    // even patch's gather is unchanged.
    for j in 0..patches {
        let sent = match shapes.slot[j] {
            u32::MAX => Rgb::ONE,
            s => shapes.shaped[s as usize].sent,
        };
        for band in 0..3 {
            let (a, b) = (with[j][band], without[j] * sent[band]);
            assert!(
                (a - b).abs() <= 1e-12 * b.max(1e-300),
                "patch {j}: {a} vs {b}"
            );
        }
    }
}
