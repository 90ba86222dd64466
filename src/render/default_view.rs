//! The default view of a baked solution that carries no camera: the same
//! framing as a scene's ([`Camera::framing`]), found from the mesh itself.
//!
//! A baked mesh keeps no materials or lights, so they are read from the
//! light it shows: the triangles at least [`GLOW`] as bright as the
//! brightest one stand for the emitters (the lamps of a bake are its
//! brightest surfaces), and every triangle counts as double-sided (a bake
//! does not say which way its faces look).

use super::ShadedMesh;
use crate::math::Rgb;
use crate::scene::{Camera, Material, Object, Scene, Surface};

/// Share of the brightest triangle's radiance from which a triangle stands
/// for an emitter.
pub(crate) const GLOW: f64 = 0.5;

/// The default view of `mesh` (see the module notes); the view of a unit
/// box when the mesh has no usable triangle.
#[must_use]
pub fn default_view(mesh: &ShadedMesh) -> Camera {
    let brightness: Vec<f64> = mesh
        .triangles
        .iter()
        .map(|t| {
            t.iter()
                .map(|&v| mesh.values.get(v as usize).map_or(0.0, |c| c.max_band()))
                .sum::<f64>()
                / 3.0
        })
        .collect();
    let brightest = brightness
        .iter()
        .copied()
        .filter(|b| b.is_finite())
        .fold(0.0, f64::max);
    let mut plain =
        Material::from_radiance("baked", Rgb::splat(0.5), Rgb::ZERO).expect("a valid material");
    plain.double_sided = true;
    let mut glow =
        Material::from_radiance("glow", Rgb::splat(0.5), Rgb::ONE).expect("a valid material");
    glow.double_sided = true;
    let mut scene = Scene {
        name: "baked".to_string(),
        materials: vec![plain, glow],
        objects: vec![Object {
            name: "baked".to_string(),
        }],
        ..Scene::default()
    };
    for (t, b) in mesh.triangles.iter().zip(&brightness) {
        let corners: Option<Vec<_>> = t
            .iter()
            .map(|&v| mesh.positions.get(v as usize).copied())
            .collect();
        let Some(corners) = corners else { continue };
        let material = u32::from(brightest > 0.0 && *b >= GLOW * brightest);
        if let Ok(s) = Surface::new(&corners, material, 0) {
            scene.surfaces.push(s);
        }
    }
    Camera::framing(&scene)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// Quad `a b c d` as two triangles of `mesh`, every vertex showing `value`.
    fn quad(mesh: &mut ShadedMesh, corners: [DVec3; 4], value: f64) {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(corners);
        mesh.values.extend([Rgb::splat(value); 4]);
        mesh.triangles.push([base, base + 1, base + 2]);
        mesh.triangles.push([base, base + 2, base + 3]);
    }

    #[test]
    fn a_bake_of_two_rooms_is_seen_from_inside_the_bright_one() {
        let v = DVec3::new;
        let mut mesh = ShadedMesh {
            positions: Vec::new(),
            values: Vec::new(),
            triangles: Vec::new(),
            texels: None,
            cull_back_faces: false,
        };
        // Room A (x 0..6) lit, room B (x 6..10) dark, joined by a door at
        // z 2..3; a lamp under A's ceiling is the brightest.
        let (a, b, lamp) = (0.4, 0.01, 10.0);
        let h = 3.0;
        quad(
            &mut mesh,
            [v(0., 0., 0.), v(0., 0., 5.), v(6., 0., 5.), v(6., 0., 0.)],
            a,
        );
        quad(
            &mut mesh,
            [v(6., 0., 0.), v(6., 0., 5.), v(10., 0., 5.), v(10., 0., 0.)],
            b,
        );
        quad(
            &mut mesh,
            [v(0., h, 0.), v(6., h, 0.), v(6., h, 5.), v(0., h, 5.)],
            a,
        );
        quad(
            &mut mesh,
            [v(6., h, 0.), v(10., h, 0.), v(10., h, 5.), v(6., h, 5.)],
            b,
        );
        quad(
            &mut mesh,
            [v(0., 0., 0.), v(6., 0., 0.), v(6., h, 0.), v(0., h, 0.)],
            a,
        );
        quad(
            &mut mesh,
            [v(6., 0., 0.), v(10., 0., 0.), v(10., h, 0.), v(6., h, 0.)],
            b,
        );
        quad(
            &mut mesh,
            [v(0., 0., 5.), v(0., h, 5.), v(6., h, 5.), v(6., 0., 5.)],
            a,
        );
        quad(
            &mut mesh,
            [v(6., 0., 5.), v(6., h, 5.), v(10., h, 5.), v(10., 0., 5.)],
            b,
        );
        quad(
            &mut mesh,
            [v(0., 0., 0.), v(0., h, 0.), v(0., h, 5.), v(0., 0., 5.)],
            a,
        );
        quad(
            &mut mesh,
            [v(10., 0., 0.), v(10., 0., 5.), v(10., h, 5.), v(10., h, 0.)],
            b,
        );
        quad(
            &mut mesh,
            [v(6., 0., 0.), v(6., 0., 2.), v(6., h, 2.), v(6., h, 0.)],
            a,
        );
        quad(
            &mut mesh,
            [v(6., 0., 3.), v(6., 0., 5.), v(6., h, 5.), v(6., h, 3.)],
            a,
        );
        quad(
            &mut mesh,
            [v(6., 2.2, 2.), v(6., 2.2, 3.), v(6., h, 3.), v(6., h, 2.)],
            a,
        );
        let y = 2.99;
        quad(
            &mut mesh,
            [v(2.5, y, 2.), v(3.5, y, 2.), v(3.5, y, 3.), v(2.5, y, 3.)],
            lamp,
        );
        let p = default_view(&mesh).position;
        assert!(
            p.x > 0.0 && p.x < 6.0 && p.y > 0.0 && p.y < h && p.z > 0.0 && p.z < 5.0,
            "the eye {p} is not in the bright room"
        );
    }
}
