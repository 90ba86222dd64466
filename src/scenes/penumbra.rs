//! Penumbra test scenes: a polygonal light, black planar occluders and a grey
//! floor, with the floor's exact radiosity.
//!
//! Every scene is a `4 m x 4 m` floor at `y = 0` facing up, a light facing down
//! at `y = 3`, and one or two occluders half-way (`y = 1.5`; the second at
//! `y = 1`). The light and the occluders have reflectance 0 and the floor
//! reflects 50 % grey. Light reflected by the floor reaches only the light, the
//! occluders and empty space, none of which reflects, so the floor's radiosity
//! is exactly its direct term
//!
//! `B(x) = rho_floor * E_light * F_visible(x)`,
//!
//! with `E_light = pi * L` the light's exitance and `F_visible` the exact
//! occluded point-to-light form factor of [`crate::analytic::OccludedLight`].
//! Each occluder is a single quad facing down: in this project the back of a
//! surface blocks light too, so one quad is an opaque sheet from both sides.
//!
//! Every light has radiance `10 / A_light` (in W m^-2 sr^-1), so each emits the
//! same power, `10 pi` W, and the floor's brightness is comparable across
//! variants.

use crate::analytic::{integrate_over_polygon, OccludedLight, QuadratureSettings};
use crate::error::{Error, GeometryFault, Result};
use crate::math::{newell_normal, polygon_area, polygon_centroid, Rgb};
use crate::scene::{Camera, Scene, SceneBuilder};
use glam::{DQuat, DVec3};

/// Height of the light plane (m).
pub(crate) const LIGHT_HEIGHT: f64 = 3.0;
/// Height of the (first) occluder (m), half-way to the light.
pub(crate) const OCCLUDER_HEIGHT: f64 = 1.5;
/// Half the side of the square floor (m).
pub(crate) const FLOOR_HALF_SIDE: f64 = 2.0;
/// Reflectance of the floor, in every band.
pub const FLOOR_REFLECTANCE: f64 = 0.5;
/// Relative tolerance of [`PenumbraSpec::exact_element_mean`], relative to the
/// unoccluded ("light on") value at the element's centroid.
pub const ELEMENT_MEAN_RELATIVE_TOLERANCE: f64 = 1e-5;

/// A penumbra scene: what [`PenumbraSpec::scene`] builds and what
/// [`PenumbraSpec::exact_radiosity`] answers for.
#[derive(Clone, Debug, PartialEq)]
pub struct PenumbraSpec {
    /// The variant's name, also the scene's name.
    pub name: &'static str,
    /// The convex light polygon, counter-clockwise seen from below (facing `-y`).
    pub light: Vec<DVec3>,
    /// The light's emitted radiance (exitance is `pi` times this).
    pub light_radiance: Rgb,
    /// Black convex occluder quads, each facing `-y`; they block from both sides.
    pub occluders: Vec<[DVec3; 4]>,
    /// The floor quad, counter-clockwise seen from above (facing `+y`).
    pub floor: [DVec3; 4],
    /// The floor's reflectance.
    pub floor_reflectance: Rgb,
}

/// A function that builds one variant.
pub(crate) type VariantBuilder = fn() -> PenumbraSpec;

/// Every variant: its name and the function that builds it.
pub const VARIANTS: [(&str, VariantBuilder); 6] = [
    ("penumbra_parallel", penumbra_parallel),
    ("penumbra_rotated", penumbra_rotated),
    ("penumbra_triangle_light", penumbra_triangle_light),
    ("penumbra_two_occluders", penumbra_two_occluders),
    ("penumbra_narrow", penumbra_narrow),
    ("penumbra_wide", penumbra_wide),
];

/// The variant called `name`, if there is one.
#[must_use]
pub fn by_name(name: &str) -> Option<PenumbraSpec> {
    VARIANTS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, build)| build())
}

/// A 1 m square light centred above the origin and a 1 m square occluder over
/// `x` in `[0, 1]`, `z` in `[-0.5, 0.5]`, edges parallel to the light's. The
/// penumbra is 1 m wide; the umbra is the square `x` in `[0.5, 1.5]`, `z` in
/// `[-0.5, 0.5]`.
#[must_use]
pub fn penumbra_parallel() -> PenumbraSpec {
    spec(
        "penumbra_parallel",
        square_facing_down(DVec3::new(0.0, LIGHT_HEIGHT, 0.0), 1.0),
        vec![main_occluder()],
    )
}

/// As [`penumbra_parallel`], with the occluder turned 30 degrees about the
/// vertical through its centre, so no occluder edge is parallel to a light
/// edge.
#[must_use]
pub fn penumbra_rotated() -> PenumbraSpec {
    let centre = DVec3::new(0.5, OCCLUDER_HEIGHT, 0.0);
    let turn = DQuat::from_rotation_y(30f64.to_radians());
    let occluder = main_occluder().map(|v| centre + turn * (v - centre));
    spec(
        "penumbra_rotated",
        square_facing_down(DVec3::new(0.0, LIGHT_HEIGHT, 0.0), 1.0),
        vec![occluder],
    )
}

/// An equilateral triangular light of side 1.2 m centred above the origin, with
/// the occluder of [`penumbra_parallel`].
#[must_use]
pub(crate) fn penumbra_triangle_light() -> PenumbraSpec {
    let side = 1.2;
    let height = side * 3f64.sqrt() / 2.0;
    let y = LIGHT_HEIGHT;
    // Counter-clockwise in (x, z) is clockwise seen from above: facing down.
    let light = vec![
        DVec3::new(-side / 2.0, y, -height / 3.0),
        DVec3::new(side / 2.0, y, -height / 3.0),
        DVec3::new(0.0, y, 2.0 * height / 3.0),
    ];
    spec("penumbra_triangle_light", light, vec![main_occluder()])
}

/// The setup of [`penumbra_parallel`] plus a second 1 m square occluder at
/// `y = 1` over `x` in `[-0.5, 0.5]`, `z` in `[0, 1]`. Seen from above the two
/// overlap, so parts of the floor have the light hidden by both at once and the
/// hidden part is the union of the two shadows, not their sum.
#[must_use]
pub fn penumbra_two_occluders() -> PenumbraSpec {
    let second = rectangle_facing_down(-0.5, 0.5, 0.0, 1.0, 1.0);
    spec(
        "penumbra_two_occluders",
        square_facing_down(DVec3::new(0.0, LIGHT_HEIGHT, 0.0), 1.0),
        vec![main_occluder(), second],
    )
}

/// A small (0.25 m) square light: a narrow penumbra, 0.25 m wide.
#[must_use]
pub fn penumbra_narrow() -> PenumbraSpec {
    spec(
        "penumbra_narrow",
        square_facing_down(DVec3::new(0.0, LIGHT_HEIGHT, 0.0), 0.25),
        vec![main_occluder()],
    )
}

/// A large (2 m) square light: a penumbra 2 m wide and no umbra (the occluder
/// hides all of the light from no floor point but one).
#[must_use]
pub(crate) fn penumbra_wide() -> PenumbraSpec {
    spec(
        "penumbra_wide",
        square_facing_down(DVec3::new(0.0, LIGHT_HEIGHT, 0.0), 2.0),
        vec![main_occluder()],
    )
}

impl PenumbraSpec {
    /// The scene: objects `light`, `occluder` (and `occluder_2`), `floor`, and a
    /// camera looking down at the floor at an angle.
    pub fn scene(&self) -> Result<Scene> {
        let mut b = SceneBuilder::new(self.name);
        let light = b.material("light", Rgb::ZERO, self.light_radiance)?;
        let black = b.material("occluder", Rgb::ZERO, Rgb::ZERO)?;
        let floor = b.material("floor", self.floor_reflectance, Rgb::ZERO)?;
        b.object("light");
        b.polygon(light, &self.light)?;
        for (k, o) in self.occluders.iter().enumerate() {
            if k == 0 {
                b.object("occluder");
            } else {
                b.object(&format!("occluder_{}", k + 1));
            }
            b.polygon(black, o)?;
        }
        b.object("floor");
        b.polygon(floor, &self.floor)?;
        let target = DVec3::new(0.5, 0.0, 0.0);
        let mut camera = Camera::look_at(DVec3::new(0.5, 7.0, 4.5), target, DVec3::Y, 50.0);
        camera.name = "view".to_string();
        b.camera(camera);
        b.build()
    }

    /// The light's emitted exitance, `pi` times its radiance.
    #[must_use]
    pub fn light_exitance(&self) -> Rgb {
        self.light_radiance * std::f64::consts::PI
    }

    /// The exact point-to-light oracle with this scene's occluders.
    pub fn oracle(&self) -> Result<OccludedLight> {
        OccludedLight::new(&self.light, &self.occluders)
    }

    /// The exact radiosity at a floor point:
    /// `rho_floor * E_light * F_visible(point)`.
    ///
    /// Fails if the point is not finite or not on the floor (within `1e-9` of
    /// the floor's size), or if the spec's polygons are unusable.
    pub fn exact_radiosity(&self, point: DVec3) -> Result<Rgb> {
        self.check_on_floor(point)?;
        let f = self
            .oracle()?
            .visible_form_factor(point, self.floor_normal())?;
        Ok(self.radiosity_from_form_factor(f))
    }

    /// The exact mean radiosity over a floor element (a triangle or convex quad
    /// on the floor), by adaptive quadrature of [`Self::exact_radiosity`] to
    /// [`ELEMENT_MEAN_RELATIVE_TOLERANCE`] of the element's unoccluded value.
    ///
    /// Fails if a vertex is off the floor, if the element is degenerate, or if
    /// the quadrature cannot meet its tolerance ([`Error::Limit`]).
    pub fn exact_element_mean(&self, polygon: &[DVec3]) -> Result<Rgb> {
        for v in polygon {
            self.check_on_floor(*v)?;
        }
        let oracle = self.oracle()?;
        let normal = self.floor_normal();
        let area = polygon_area(polygon);
        let light_on = oracle.unoccluded_form_factor(polygon_centroid(polygon), normal)?;
        // Never ask for less than an absolute 1e-14 per unit area: an element
        // the light cannot see at all integrates to zero at once.
        let tolerance = (ELEMENT_MEAN_RELATIVE_TOLERANCE * light_on).max(1e-14) * area;
        let settings = QuadratureSettings::with_tolerance(tolerance);
        let integral = integrate_over_polygon(
            polygon,
            |p| oracle.visible_form_factor_unchecked(p, normal),
            &settings,
        )?;
        Ok(self.radiosity_from_form_factor(integral.value / area))
    }

    /// The floor's unit normal.
    #[must_use]
    pub fn floor_normal(&self) -> DVec3 {
        newell_normal(&self.floor).normalize_or(DVec3::Y)
    }

    fn radiosity_from_form_factor(&self, f: f64) -> Rgb {
        self.floor_reflectance * self.light_exitance() * f
    }

    /// Fails unless `point` is finite and lies on the floor quad.
    fn check_on_floor(&self, point: DVec3) -> Result<()> {
        let size = (self.floor[2] - self.floor[0]).length();
        let tolerance = 1e-9 * size;
        let n = self.floor_normal();
        let off_plane = (point - self.floor[0]).dot(n).abs();
        let outside = (0..4).any(|i| {
            let a = self.floor[i];
            let b = self.floor[(i + 1) % 4];
            // Distance inside the edge, positive for interior points.
            n.cross(b - a).normalize_or_zero().dot(point - a) < -tolerance
        });
        if !point.is_finite() || off_plane > tolerance || outside {
            let fault = if point.is_finite() {
                GeometryFault::Mismatch
            } else {
                GeometryFault::NonFinite
            };
            return Err(Error::geometry(
                fault,
                format!("scene '{}': point {point} is not on the floor", self.name),
            ));
        }
        Ok(())
    }
}

/// A spec with this module's floor and light power.
fn spec(name: &'static str, light: Vec<DVec3>, occluders: Vec<[DVec3; 4]>) -> PenumbraSpec {
    let light_area = polygon_area(&light);
    let h = FLOOR_HALF_SIDE;
    PenumbraSpec {
        name,
        light_radiance: Rgb::splat(10.0 / light_area),
        light,
        occluders,
        // Counter-clockwise seen from above: facing up.
        floor: [
            DVec3::new(-h, 0.0, -h),
            DVec3::new(-h, 0.0, h),
            DVec3::new(h, 0.0, h),
            DVec3::new(h, 0.0, -h),
        ],
        floor_reflectance: Rgb::splat(FLOOR_REFLECTANCE),
    }
}

/// The 1 m occluder over `x` in `[0, 1]`, `z` in `[-0.5, 0.5]` at mid height.
fn main_occluder() -> [DVec3; 4] {
    rectangle_facing_down(0.0, 1.0, -0.5, 0.5, OCCLUDER_HEIGHT)
}

/// A square light of side `side` centred at `centre`, facing down.
fn square_facing_down(centre: DVec3, side: f64) -> Vec<DVec3> {
    let h = side / 2.0;
    rectangle_facing_down(
        centre.x - h,
        centre.x + h,
        centre.z - h,
        centre.z + h,
        centre.y,
    )
    .to_vec()
}

/// The horizontal rectangle `[x0, x1] x [z0, z1]` at height `y`, facing down
/// (counter-clockwise in the `(x, z)` plane is clockwise seen from above).
fn rectangle_facing_down(x0: f64, x1: f64, z0: f64, z1: f64, y: f64) -> [DVec3; 4] {
    [
        DVec3::new(x0, y, z0),
        DVec3::new(x1, y, z0),
        DVec3::new(x1, y, z1),
        DVec3::new(x0, y, z1),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variant_builds_with_the_promised_objects_and_facings() {
        for (name, build) in VARIANTS {
            let spec = build();
            assert_eq!(spec.name, name);
            let scene = spec.scene().unwrap();
            assert_eq!(scene.name, name);
            let object = |s: &crate::scene::Surface| scene.objects[s.object as usize].name.as_str();
            let mut names: Vec<&str> = scene.surfaces.iter().map(object).collect();
            names.dedup();
            let expected: Vec<String> = std::iter::once("light".to_string())
                .chain((0..spec.occluders.len()).map(|k| {
                    if k == 0 {
                        "occluder".to_string()
                    } else {
                        format!("occluder_{}", k + 1)
                    }
                }))
                .chain(std::iter::once("floor".to_string()))
                .collect();
            assert_eq!(names, expected, "{name}");
            for s in &scene.surfaces {
                let facing = if object(s) == "floor" {
                    DVec3::Y
                } else {
                    -DVec3::Y
                };
                assert!((s.normal - facing).length() < 1e-12, "{name} {}", object(s));
                let m = scene.material_of(s);
                let expected_rho = if object(s) == "floor" {
                    FLOOR_REFLECTANCE
                } else {
                    0.0
                };
                assert_eq!(m.reflectance, Rgb::splat(expected_rho));
                assert_eq!(m.is_emitter(), object(s) == "light");
            }
            // Every light emits the same power, 10 pi W.
            let power = spec.light_exitance()[0] * polygon_area(&spec.light);
            assert!((power - 10.0 * std::f64::consts::PI).abs() < 1e-12);
            assert_eq!(scene.cameras.len(), 1);
            assert_eq!(by_name(name), Some(spec));
        }
        assert_eq!(by_name("no_such_scene"), None);
    }

    #[test]
    fn points_off_the_floor_are_refused() {
        let spec = penumbra_parallel();
        assert!(spec.exact_radiosity(DVec3::new(0.0, 0.1, 0.0)).is_err());
        assert!(spec.exact_radiosity(DVec3::new(2.5, 0.0, 0.0)).is_err());
        assert!(spec.exact_radiosity(DVec3::splat(f64::NAN)).is_err());
        assert!(spec.exact_radiosity(DVec3::new(2.0, 0.0, -2.0)).is_ok());
    }

    #[test]
    fn umbra_is_black_and_lit_floor_is_not() {
        let spec = penumbra_parallel();
        assert_eq!(
            spec.exact_radiosity(DVec3::new(1.0, 0.0, 0.0)).unwrap(),
            Rgb::ZERO
        );
        let lit = spec.exact_radiosity(DVec3::new(-1.0, 0.0, 0.0)).unwrap();
        assert!(lit[0] > 0.1, "{lit:?}");
    }
}
