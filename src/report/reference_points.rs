//! The ground truth a sweep is measured against, at fixed points.

use super::floor_points;
use super::hidden::sees_only_back_faces;
use super::metrics::ERROR_FLOOR_FRACTION;
use crate::error::{Error, GeometryFault, Result};
use crate::math::Rgb;
use crate::reference::{sample_points, Reference, ReferenceSettings};
use crate::scene::Scene;
use crate::scenes::penumbra::PenumbraSpec;
use glam::DVec3;
use rayon::prelude::*;
use std::time::Instant;

/// Where the reference values come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceKind {
    /// The exact oracle of a penumbra scene's floor (no error of its own beyond
    /// its quadrature's `1e-12` or so).
    Exact,
    /// The Monte Carlo path tracer, with standard errors.
    MonteCarlo {
        /// Paths per point.
        paths: u64,
        /// Seed of the points and the paths.
        seed: u64,
    },
}

/// One point of the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferencePoint {
    /// The surface it lies on (index into `Scene::surfaces`).
    pub surface: u32,
    /// The position, on the surface.
    pub position: DVec3,
    /// The surface's unit front normal.
    pub normal: DVec3,
    /// The reference radiosity (exitance) per band.
    pub radiosity: Rgb,
    /// Its standard error per band (zero for the exact oracle).
    pub std_error: Rgb,
}

/// How many Monte Carlo points and paths, and the seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MonteCarloPoints {
    /// Points drawn by [`sample_points`] over all surfaces; those that land on
    /// emitting surfaces are dropped, so slightly fewer are used.
    pub count: usize,
    /// Independent paths per point.
    pub paths: u64,
    /// Seed of the points and of the paths.
    pub seed: u64,
}

impl Default for MonteCarloPoints {
    /// 256 points, 100 000 paths each (a standard error of about 0.3 % of the
    /// value at a typical point of the Cornell box), seed 1.
    fn default() -> Self {
        MonteCarloPoints {
            count: 256,
            paths: 100_000,
            seed: 1,
        }
    }
}

/// Reference radiosities at fixed points of one scene, independent of any mesh,
/// with the floor of the relative error (see the [module docs](super)).
#[derive(Clone, Debug)]
pub struct ReferencePoints {
    /// Where the values come from.
    pub kind: ReferenceKind,
    /// The points, none on an emitting surface and none hidden inside a
    /// closed object.
    pub points: Vec<ReferencePoint>,
    /// Points left out because they lie on an emitting surface.
    pub emitting_left_out: usize,
    /// Points left out because every line of sight from them ends on the back
    /// of a surface (see [`sees_only_back_faces`]).
    pub hidden_left_out: usize,
    /// The floor `f` of the relative error `|B - R| / max(R, f)`, per band:
    /// [`ERROR_FLOOR_FRACTION`] of the mean reference radiosity of the points.
    pub error_floor: Rgb,
    /// Wall-clock seconds it took to compute (for reports).
    pub seconds: f64,
}

impl ReferencePoints {
    /// The exact radiosity at `count` points spread over the floor of a penumbra
    /// scene ([`floor_points`]). Fails if the spec's polygons are unusable.
    pub fn exact(spec: &PenumbraSpec, count: usize) -> Result<ReferencePoints> {
        Self::exact_at(spec, &floor_points(spec, count))
    }

    /// The exact radiosity at the given floor positions of a penumbra scene
    /// (leaving out hidden ones, of which the built-in scenes have none).
    /// Fails, naming the point, if one is not on the floor.
    pub fn exact_at(spec: &PenumbraSpec, positions: &[DVec3]) -> Result<ReferencePoints> {
        let started = Instant::now();
        let scene = spec.scene()?;
        let floor = scene
            .surfaces
            .iter()
            .position(|s| scene.objects[s.object as usize].name == "floor")
            .ok_or_else(|| {
                Error::geometry(
                    GeometryFault::NoSurfaces,
                    format!("scene '{}' has no floor", spec.name),
                )
            })? as u32;
        let normal = spec.floor_normal();
        let visible: Vec<DVec3> = positions
            .iter()
            .copied()
            .filter(|p| !sees_only_back_faces(&scene, floor, *p, normal))
            .collect();
        let hidden = positions.len() - visible.len();
        let positions = &visible;
        // Independent evaluations, collected in order: the same at any thread count.
        let values: Vec<Rgb> = positions
            .par_iter()
            .map(|p| spec.exact_radiosity(*p))
            .collect::<Result<_>>()?;
        let points = positions
            .iter()
            .zip(values)
            .map(|(p, radiosity)| ReferencePoint {
                surface: floor,
                position: *p,
                normal,
                radiosity,
                std_error: Rgb::ZERO,
            })
            .collect();
        let mut reference = Self::finish(ReferenceKind::Exact, points, 0, hidden);
        reference.seconds = started.elapsed().as_secs_f64();
        Ok(reference)
    }

    /// Path-traced radiosity at points spread over every surface of `scene`
    /// by area ([`sample_points`]), leaving out points on emitting surfaces and
    /// hidden points ([`sees_only_back_faces`]). Fails on a scene the reference
    /// cannot trace, on invalid settings, or if no point is left.
    pub fn monte_carlo(scene: &Scene, settings: &MonteCarloPoints) -> Result<ReferencePoints> {
        let started = Instant::now();
        let reference = Reference::new(scene)?;
        let emits = |surface: u32| {
            scene
                .material_of(&scene.surfaces[surface as usize])
                .is_emitter()
        };
        let all = sample_points(scene, settings.count, settings.seed)?;
        let lit: Vec<_> = all.into_iter().filter(|p| !emits(p.surface)).collect();
        let emitting = settings.count - lit.len();
        let points: Vec<_> = lit
            .into_iter()
            .filter(|p| !sees_only_back_faces(scene, p.surface, p.position, p.normal))
            .collect();
        let hidden = settings.count - emitting - points.len();
        if points.is_empty() {
            return Err(Error::Setting {
                name: "points",
                message: format!(
                    "none of {} points lies on a visible surface that does not emit",
                    settings.count
                ),
            });
        }
        let trace = ReferenceSettings {
            paths: settings.paths,
            seed: settings.seed,
            ..ReferenceSettings::default()
        };
        let estimates = reference.radiosity_at(&points, &trace)?;
        let points = points
            .iter()
            .zip(estimates)
            .map(|(p, e)| ReferencePoint {
                surface: p.surface,
                position: p.position,
                normal: p.normal,
                radiosity: e.radiosity,
                std_error: e.std_error,
            })
            .collect();
        let kind = ReferenceKind::MonteCarlo {
            paths: settings.paths,
            seed: settings.seed,
        };
        let mut reference = Self::finish(kind, points, emitting, hidden);
        reference.seconds = started.elapsed().as_secs_f64();
        Ok(reference)
    }

    fn finish(
        kind: ReferenceKind,
        points: Vec<ReferencePoint>,
        emitting_left_out: usize,
        hidden_left_out: usize,
    ) -> ReferencePoints {
        let n = points.len().max(1) as f64;
        let mean = points.iter().fold(Rgb::ZERO, |a, p| a + p.radiosity) / n;
        ReferencePoints {
            kind,
            points,
            emitting_left_out,
            hidden_left_out,
            error_floor: mean * ERROR_FLOOR_FRACTION,
            seconds: 0.0,
        }
    }

    /// The relative standard error of the reference, `SE / max(R, f)` averaged
    /// over bands and points: the noise that every measured error carries
    /// (0 for the exact oracle).
    #[must_use]
    pub fn mean_relative_std_error(&self) -> f64 {
        let n = self.points.len().max(1) as f64;
        self.points
            .iter()
            .map(|p| {
                (0..3)
                    .map(|k| p.std_error[k] / p.radiosity[k].max(self.error_floor[k]))
                    .sum::<f64>()
                    / 3.0
            })
            .sum::<f64>()
            / n
    }
}
