//! One hemi-cube against Lambert's exact point-to-polygon form factor (the
//! independent oracle in `radiosity::analytic`).

use glam::DVec3;
use radiosity::analytic::lambert;
use radiosity::analytic::penumbra::OccludedLight;
use radiosity::formfactor::hemicube::{DeltaTable, Hemicube};
use radiosity::formfactor::{FormFactorMethod, SourcePolygon, Sources};
use std::sync::Arc;

fn source(vertices: &[DVec3], surface: u32) -> SourcePolygon {
    let n = (vertices[1] - vertices[0])
        .cross(vertices[2] - vertices[0])
        .normalize();
    let mut v = [DVec3::ZERO; 4];
    v[..vertices.len()].copy_from_slice(vertices);
    let centre = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
    let radius = vertices
        .iter()
        .map(|p| (*p - centre).length())
        .fold(0.0, f64::max);
    SourcePolygon {
        vertices: v,
        count: vertices.len() as u8,
        normal: n,
        surface,
        centre,
        radius,
        patch: 0,
    }
}

/// A square of half-size `h` centred at `c`, facing `facing` (its front normal).
fn square(c: DVec3, facing: DVec3, h: f64) -> Vec<DVec3> {
    let n = facing.normalize();
    let t = n.any_orthonormal_vector();
    let b = n.cross(t);
    vec![
        c - t * h - b * h,
        c + t * h - b * h,
        c + t * h + b * h,
        c - t * h + b * h,
    ]
}

fn one_row(
    polys: &[Vec<DVec3>],
    eye: DVec3,
    normal: DVec3,
    method: FormFactorMethod,
    angle: f64,
) -> Vec<f64> {
    let sources = Sources::one_per_patch(
        polys
            .iter()
            .enumerate()
            .map(|(i, p)| source(p, i as u32 + 1))
            .collect(),
    );
    let mut cube = Hemicube::new(Arc::new(DeltaTable::new(256)), polys.len());
    let row = cube.row(&sources, eye, normal, angle, 0, method);
    (0..polys.len() as u32).map(|j| row.get(j)).collect()
}

#[test]
fn hemicube_matches_lambert_within_one_percent_at_256() {
    let eye = DVec3::ZERO;
    let up = DVec3::Z;
    // (centre, facing, half size): each projects to well over 20 pixels across
    // at resolution 256 (a top-face pixel is 2/256 wide at unit distance).
    let placements = [
        // Facing the receiver straight above it.
        (DVec3::new(0.0, 0.0, 1.0), -DVec3::Z, 0.3),
        // Tilted and off axis, seen partly on a side face.
        (
            DVec3::new(0.8, 0.3, 0.9),
            DVec3::new(-0.8, -0.2, -0.6),
            0.35,
        ),
        // Standing vertically, crossing the top/side face boundary.
        (DVec3::new(-1.2, 0.2, 0.6), DVec3::X, 0.4),
        // Partly behind the receiver's horizon: the part below z = 0 is cut off.
        (DVec3::new(0.2, 1.0, 0.1), -DVec3::Y, 0.4),
    ];
    for (k, (c, facing, h)) in placements.iter().enumerate() {
        let poly = square(*c, *facing, *h);
        let exact = lambert::point_to_polygon(eye, up, &poly).unwrap();
        // Rotations as the solver draws them (seeded, not aligned with the
        // polygon's edges; at angle 0 an axis-aligned square loses a fixed
        // fraction of a pixel along every edge, which is what the rotation is for).
        for angle in [0.3, 1.1, 2.5] {
            let f = one_row(
                std::slice::from_ref(&poly),
                eye,
                up,
                FormFactorMethod::Hemicube,
                angle,
            )[0];
            let err = (f - exact).abs() / exact;
            assert!(
                err < 0.01,
                "placement {k} angle {angle}: hemicube {f} exact {exact} ({:.3}%)",
                100.0 * err
            );
        }
    }
}

#[test]
fn hybrid_is_exact_unoccluded_and_closer_than_pixels_when_occluded() {
    // A 1 x 1 light at height 4 facing down, a half-plane occluder at height 2
    // with its edge at x = 0 covering x > 0 (the research brief's penumbra case),
    // and receiving points on the floor across the penumbra.
    let light = vec![
        DVec3::new(-0.5, -0.5, 4.0),
        DVec3::new(-0.5, 0.5, 4.0),
        DVec3::new(0.5, 0.5, 4.0),
        DVec3::new(0.5, -0.5, 4.0),
    ];
    let occluder = vec![
        DVec3::new(0.0, -50.0, 2.0),
        DVec3::new(0.0, 50.0, 2.0),
        DVec3::new(50.0, 50.0, 2.0),
        DVec3::new(50.0, -50.0, 2.0),
    ];
    let oracle = OccludedLight::new(&light, std::slice::from_ref(&occluder)).unwrap();
    let (mut err_pixels, mut err_hybrid) = (0.0, 0.0);
    for x in [-1.5, -0.3, 0.0, 0.3] {
        let p = DVec3::new(x, 0.0, 0.0);
        let exact = oracle.visible_form_factor(p, DVec3::Z).unwrap();
        let pixels = one_row(
            &[light.clone(), occluder.clone()],
            p,
            DVec3::Z,
            FormFactorMethod::Hemicube,
            0.4,
        )[0];
        let hybrid = one_row(
            &[light.clone(), occluder.clone()],
            p,
            DVec3::Z,
            FormFactorMethod::Hybrid,
            0.4,
        )[0];
        if x < -0.5 {
            // Rows are stored in single precision.
            assert!(
                (hybrid - exact).abs() < 1e-6 * exact,
                "fully lit: hybrid {hybrid} exact {exact}"
            );
        }
        err_pixels += (pixels - exact).abs();
        err_hybrid += (hybrid - exact).abs();
    }
    assert!(
        err_hybrid <= err_pixels,
        "hybrid {err_hybrid} vs pixels {err_pixels}"
    );
}
