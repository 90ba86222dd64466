//! What a stock viewer shows of a bake: `COLOR_0` holds each vertex's
//! display value, the radiance exposed and tone mapped as `radiosity render`
//! draws it, so that a viewer that draws vertex colours on an unlit material
//! (three.js's GLTFLoader with no lights, Blender, model-viewer) shows the
//! picture `render` makes; and the cameras such a viewer looks through.

use crate::math::Rgb;
use crate::mesh::ShadingMesh;
use crate::render::{auto_exposure_above, render, ShadedMesh, ToneMap};
use crate::scene::{Camera, Scene};
use glam::DVec3;
use std::f64::consts::PI;

/// Pixels across the render the default exposure is measured on.
const EXPOSURE_PIXELS: u32 = 256;

/// Pixels dimmer than this fraction of the brightest vertex radiance of the
/// whole bake are left out of the automatic exposure: numerical noise on the
/// outside of a closed room (1e-12 of its lamps) is no scene to expose for.
pub(super) const EXPOSURE_FLOOR: f64 = 1e-6;

/// How a bake maps radiance to `COLOR_0`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Display {
    /// Radiance times this is tone mapped.
    pub gain: f64,
    pub tone: ToneMap,
}

impl Display {
    /// The display value of an untextured vertex of radiosity `b`.
    pub(super) fn of_radiosity(&self, b: Rgb) -> Rgb {
        self.tone.apply(b * (self.gain / PI))
    }

    /// The colour of a vertex of irradiance `h` on a textured material of
    /// mean reflectance `mean`: the display value of the mean texel's
    /// radiance over `mean`, per band, so that the viewer's texel times
    /// colour is the tone-mapped mean scaled by the texel's contrast. Returns
    /// the colour and its largest band before clipping to 1 (above 1 where
    /// a band was clipped).
    pub(super) fn of_irradiance(&self, h: Rgb, mean: Rgb) -> (Rgb, f64) {
        let shown = self.tone.apply(mean * h * (self.gain / PI));
        let mut largest: f64 = 0.0;
        let colour = Rgb([0, 1, 2].map(|k| {
            if mean[k] <= 0.0 {
                return 0.0;
            }
            let c = shown[k] / mean[k];
            largest = largest.max(c);
            c.min(1.0)
        }));
        (colour, largest)
    }
}

/// The exposure in stops that `render`'s automatic exposure gives the view
/// from `camera` of `shading`, leaving out pixels dimmer than
/// [`EXPOSURE_FLOOR`] of the brightest vertex.
pub(super) fn default_exposure(shading: &ShadingMesh, camera: &Camera, tone: ToneMap) -> f64 {
    let brightest = shading
        .radiosity
        .iter()
        .map(|b| b.luminance())
        .fold(0.0, f64::max)
        / PI;
    let mesh = ShadedMesh::radiance_of(shading.clone());
    match render(&mesh, camera, EXPOSURE_PIXELS, EXPOSURE_PIXELS) {
        Ok(image) => auto_exposure_above(&image, tone, EXPOSURE_FLOOR * brightest),
        Err(_) => 0.0,
    }
}

/// The scene's cameras, or, when it has none, the default view
/// ([`Camera::framing`]) named `default view`.
pub(super) fn cameras_to_write(scene: &Scene) -> Vec<Camera> {
    if !scene.cameras.is_empty() {
        return scene.cameras.clone();
    }
    let mut camera = Camera::framing(scene);
    camera.name = "default view".to_string();
    vec![camera]
}

/// Near and far clip distances for `camera` over `positions`: the far plane
/// just beyond the farthest vertex, the near plane half way to the nearest
/// triangle (so that nothing in view is cut), kept between 1e-5 and 1e-1 of
/// the far distance. A near plane at 1e-4 of the scene with no far plane
/// left a lamp 1 mm under a ceiling flickering through it in a 24-bit depth
/// buffer; the depth resolution at distance `z` is about
/// `z^2 / (near * 2^24)`.
pub(super) fn clip_planes(
    camera: &Camera,
    positions: &[DVec3],
    triangles: &[[u32; 3]],
) -> (f64, f64) {
    let eye = camera.position;
    let farthest = positions
        .iter()
        .map(|p| (*p - eye).length())
        .fold(0.0, f64::max);
    let far = (farthest * 1.01).max(1e-6);
    let nearest = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            point_triangle_distance(eye, a, b, c)
        })
        .fold(f64::INFINITY, f64::min);
    let near = (0.5 * nearest).clamp(1e-5 * far, 0.1 * far);
    (near, far)
}

/// The distance from `p` to the triangle `a b c`.
fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, ac) = (b - a, c - a);
    let normal = ab.cross(ac);
    let n2 = normal.length_squared();
    if n2 > 0.0 {
        // The foot of the perpendicular, if it lies inside.
        let d = (p - a).dot(normal) / n2;
        let foot = p - normal * d;
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, v)| (v - u).cross(foot - u).dot(normal) >= 0.0);
        if inside {
            return (p - foot).length();
        }
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(u, v)| point_segment_distance(p, u, v))
        .fold(f64::INFINITY, f64::min)
}

fn point_segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn distances_to_a_triangle_inside_and_past_its_edges() {
        let (a, b, c) = (v(0., 0., 0.), v(2., 0., 0.), v(0., 2., 0.));
        assert!((point_triangle_distance(v(0.5, 0.5, 3.), a, b, c) - 3.0).abs() < 1e-12);
        // Beyond the hypotenuse: nearest to its middle (1, 1, 0).
        let d = point_triangle_distance(v(2., 2., 0.), a, b, c);
        assert!((d - 2f64.sqrt()).abs() < 1e-12);
        // Beyond a corner.
        assert!((point_triangle_distance(v(-3., -4., 0.), a, b, c) - 5.0).abs() < 1e-12);
    }

    #[test]
    fn clip_planes_hold_the_scene_and_stop_short_of_the_nearest_surface() {
        let positions = [
            v(-1., -1., -5.),
            v(1., -1., -5.),
            v(0., 1., -5.),
            v(0., 0., -40.),
        ];
        let triangles = [[0, 1, 2]];
        let camera = Camera::look_at(DVec3::ZERO, v(0., 0., -1.), DVec3::Y, 45.0);
        let (near, far) = clip_planes(&camera, &positions, &triangles);
        assert!((near - 2.5).abs() < 1e-12, "{near}");
        assert!((far - 40.4).abs() < 1e-9, "{far}");
    }

    #[test]
    fn textured_colours_scale_the_mean_texel_to_its_display_value() {
        let display = Display {
            gain: PI,
            tone: ToneMap::Clamp,
        };
        // Mean reflectance 0.5, irradiance 1: radiance 0.5 shown as 0.5, so
        // the colour is 1 and the mean texel times it shows 0.5.
        let (c, largest) = display.of_irradiance(Rgb::ONE, Rgb::splat(0.5));
        let clipped = largest > 1.0;
        assert_eq!(c, Rgb::ONE);
        assert!(!clipped);
        let (c, largest) = display.of_irradiance(Rgb::splat(3.0), Rgb::new(0.5, 0.25, 0.0));
        let clipped = largest > 1.0;
        assert_eq!(c, Rgb::new(1.0, 1.0, 0.0));
        assert!(clipped);
    }
}
