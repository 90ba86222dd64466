//! Ground truth independent of the hemi-cube: Monte Carlo path tracing of the
//! diffuse scene, with standard errors.
//!
//! This module shares no code with the form-factor or solver stages; it reads
//! only the [`Scene`]. It estimates the radiosity `B = E + rho H` at points
//! ([`Reference::radiosity_at`]) and the area-weighted mean radiosity of each
//! object ([`Reference::object_means`]), each with a standard error, so that
//! the radiosity solver can be measured against it.
//!
//! # Example
//!
//! ```
//! use glam::DVec3;
//! use radiosity::math::Rgb;
//! use radiosity::reference::{sample_points, Reference, ReferenceSettings};
//! use radiosity::scene::SceneBuilder;
//!
//! // A grey floor under a small light that faces it.
//! let mut b = SceneBuilder::new("demo");
//! let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO)?;
//! let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(1.0))?;
//! let p = DVec3::new;
//! b.quad(grey, p(-1.0, -1.0, 0.0), p(1.0, -1.0, 0.0), p(1.0, 1.0, 0.0), p(-1.0, 1.0, 0.0))?;
//! b.quad(lamp, p(-0.1, -0.1, 1.0), p(-0.1, 0.1, 1.0), p(0.1, 0.1, 1.0), p(0.1, -0.1, 1.0))?;
//! let scene = b.build()?;
//!
//! let reference = Reference::new(&scene)?;
//! let settings = ReferenceSettings { paths: 1_000, ..ReferenceSettings::default() };
//! let points = sample_points(&scene, 4, 7)?;
//! for (point, estimate) in points.iter().zip(reference.radiosity_at(&points, &settings)?) {
//!     assert!(estimate.radiosity.min_band() >= 0.0);
//!     assert_eq!(estimate.paths, 1_000);
//!     let _ = (point.position, estimate.std_error);
//! }
//! let probe = reference.locate(DVec3::ZERO, DVec3::Z).expect("on the floor");
//! assert_eq!(probe.surface, 0);
//! # Ok::<(), radiosity::Error>(())
//! ```
//!
//! # Physics
//!
//! Surfaces are single-sided Lambertian polygons: only the front (the side the
//! normal points to) emits and reflects; a ray that meets a back face sees
//! radiance 0 and ends (the back blocks light). Emission is exitance E, so an
//! emitter's radiance is E/pi. Punctual lights (point, spot, directional) are
//! delta lights: at every path vertex each one adds its irradiance
//! (`I cos / d^2` with the light's falloffs, `E cos` for a sun) where a
//! shadow ray reaches it (next-event estimation, exact for a delta light).
//! Each path combines light sampling and
//! cosine-weighted direction sampling by multiple importance sampling, and
//! Russian roulette after [`ReferenceSettings::min_bounces_before_roulette`]
//! reflections; both are unbiased. The only bias is the hard cap
//! [`ReferenceSettings::max_bounces`] (see there for its size). All three bands
//! are traced together, with reflectance as per-band path weights. Details in
//! the `estimator` source.
//!
//! # Textures
//!
//! A surface with texture coordinates whose material has a base-colour or
//! emissive texture reflects and emits the texture's value at each point
//! (per texel, filtered as the texture says), at the texture coordinates the
//! solver's lattice gives that point (linear on triangles, bilinear on quads).
//! Emitters are chosen for light samples by their mean power (area times the
//! material's mean exitance) and a point uniformly by area on them; the
//! sample's weight uses the exitance at that point, so light sampling stays
//! unbiased. Object means remain area means of radiosity. Surfaces without
//! texture coordinates or textures use the material's constants, as before.
//!
//! # Scale
//!
//! Ray origins are moved off their surface along the front normal by
//! 1e-7 of the scene diameter (plus a few hundred ulps of the largest
//! coordinate), and shadow rays stop the same distance short of their target.
//! Edge tests allow 1e-10 of the diameter. All lengths therefore scale with the
//! scene, which gives the same results (to rounding) from millimetre to kilometre
//! scenes, and for small scenes far from the origin.
//!
//! # Ray casting: `obvhs`
//!
//! Two BVH crates were compared on a closed room of 10,512 triangles (a
//! gridded box with 300 small boxes inside), 200,000 random closest-hit rays on
//! one thread, with the same f64 triangle test in both (`obvhs` at scales 1e-3,
//! 1 and 1e3 and 20 km from the origin, `bvh` at 1 and at 1e-3 far from the
//! origin; both agreed with brute force on a 10,000-ray subset each time):
//!
//! | | `obvhs` 0.4 (BVH2) | `bvh` 0.11 |
//! |---|---|---|
//! | precision | f32 only | generic, used in f64 |
//! | closest-hit rays | 1.3 to 1.5 million/s | 0.8 million/s |
//! | BVH build | 2 to 6 ms | 3 to 7 ms |
//! | clean release build of the crate and its dependencies | 23 crates, 18 s CPU | 48 crates (nalgebra, simba, rand), 33 s CPU |
//! | maintenance | releases 0.1 (2024) to 0.4, on glam 0.33 to 0.34 like this crate | long-lived, but 0.12 and 0.13 need Rust 1.87 and 1.90 |
//!
//! `obvhs` is used: about 1.7 times as fast, half the build cost, and on the project's
//! glam. Its f32 boxes cost no accuracy here (see the `accel` source): they are
//! centred and padded so that the broad phase is conservative, and every hit is
//! decided in f64. Its compressed wide BVH was rejected because it skips hits
//! nearer than 1e-4 units, which failed a 1e-3 scale copy of the test scene.
//!
//! # Determinism
//!
//! Every path draws from its own counter-based random stream named by the seed
//! and stable indices (point and path, or object and sample), and work is
//! reduced in fixed chunks in a fixed order: the same seed gives the same bits
//! at any thread count.

mod emitters;
mod estimator;
mod gather;
mod points;
mod probes;
mod rng;
mod sampling;
mod settings;
mod stats;
mod surface_means;
mod textures;

pub use gather::GatherEstimate;
pub use points::{sample_points, SurfacePoint, LOCATE_TOLERANCE};
pub use settings::ReferenceSettings;
pub use stats::ProbeEstimate;

use crate::error::{Error, GeometryFault, Result};
use crate::math::Rgb;
use crate::scene::rays::{Accel, SurfaceGeometry, Tolerances};
use crate::scene::Scene;
use emitters::Emitters;
use glam::DVec3;
use surface_means::ObjectArea;
use textures::Shade;

/// Paths per unit of parallel work. Fixed, so that the reduction order (and so
/// the result) does not depend on the number of threads.
const CHUNK_PATHS: u64 = 512;

/// A scene prepared for Monte Carlo estimates: surface geometry, a BVH and the
/// emitter table. Build it once per scene.
pub struct Reference {
    geometry: Vec<SurfaceGeometry>,
    /// Per surface: reflectance and emission, constant or per point.
    shades: Vec<Shade>,
    objects: Vec<ObjectArea>,
    emitters: Option<Emitters>,
    /// Punctual lights, sampled by next-event estimation.
    lights: Vec<crate::scene::Light>,
    /// The sky, met by paths that leave the scene.
    sky: Option<crate::scene::Sky>,
    accel: Accel,
    tolerances: Tolerances,
    diameter: f64,
}

/// The reference's geometry of every surface, checked.
fn scene_geometry(scene: &Scene) -> Result<Vec<SurfaceGeometry>> {
    if scene.surfaces.is_empty() {
        return Err(Error::geometry(
            GeometryFault::NoSurfaces,
            format!("scene '{}' has no surfaces", scene.name),
        ));
    }
    scene
        .surfaces
        .iter()
        .enumerate()
        .map(|(i, s)| SurfaceGeometry::new(i, s))
        .collect()
}

impl Reference {
    /// Prepares `scene`. Fails on a scene with no surfaces, on a surface the
    /// reference cannot trace (naming it), on a material out of range, and on a
    /// surface whose material or object index does not exist.
    pub fn new(scene: &Scene) -> Result<Reference> {
        let geometry = scene_geometry(scene)?;
        for m in &scene.materials {
            m.validate()?;
        }
        scene.check_lights()?;
        let mut shades = Vec::with_capacity(geometry.len());
        let mut members = vec![Vec::new(); scene.objects.len()];
        for (i, s) in scene.surfaces.iter().enumerate() {
            let Some(m) = scene.materials.get(s.material as usize) else {
                return Err(Error::geometry(
                    GeometryFault::Mismatch,
                    format!(
                        "surface {i} refers to material {}, but the scene has {}",
                        s.material,
                        scene.materials.len()
                    ),
                ));
            };
            let Some(list) = members.get_mut(s.object as usize) else {
                return Err(Error::geometry(
                    GeometryFault::Mismatch,
                    format!(
                        "surface {i} refers to object {}, but the scene has {}",
                        s.object,
                        scene.objects.len()
                    ),
                ));
            };
            list.push(i as u32);
            shades.push(Shade::new(m, s, &geometry[i]));
        }
        let objects = members
            .into_iter()
            .map(|surfaces| {
                let areas: Vec<f64> = surfaces
                    .iter()
                    .map(|s| geometry[*s as usize].area)
                    .collect();
                ObjectArea::new(surfaces, &areas)
            })
            .collect();
        let (lo, hi) =
            geometry
                .iter()
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), g| {
                    let (a, b) = g.bounds();
                    (lo.min(a), hi.max(b))
                });
        let diameter = (hi - lo).length();
        let tolerances = Tolerances::new(diameter, lo.abs().max(hi.abs()).max_element());
        let accel = Accel::new(&geometry, lo, hi, tolerances);
        let emission: Vec<Rgb> = shades.iter().map(Shade::mean_emission).collect();
        let emitters = Emitters::new(&geometry, &emission);
        Ok(Reference {
            geometry,
            shades,
            objects,
            emitters,
            lights: scene.lights.clone(),
            sky: scene.sky,
            accel,
            tolerances,
            diameter,
        })
    }

    /// The number of surfaces.
    #[must_use]
    pub fn surface_count(&self) -> usize {
        self.geometry.len()
    }
}
