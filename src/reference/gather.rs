//! One bounce from a given radiosity function: what a point would receive if
//! everything it sees had the radiosity the caller supplies.
//!
//! Run with the solver's own radiosity, this separates the two ways a solved
//! value at a point can be wrong. If the gather agrees with the path tracer
//! but the solver's value does not, the point's own form factors (its
//! hemi-cube, its element) are at fault; if the gather is as wrong as the
//! solver, what the point sees is.

use super::rng::{Domain, Rng};
use super::sampling::cosine_direction;
use super::stats::{ProbeEstimate, RunningStats};
use super::{Reference, ReferenceSettings, SurfacePoint, CHUNK_PATHS};
use crate::error::Result;
use crate::math::Rgb;
use rayon::prelude::*;

/// A one-bounce gather at one point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GatherEstimate {
    /// `E + rho H`, with `H` the irradiance from the supplied radiosity (and
    /// from the scene's punctual lights), with its standard error.
    pub estimate: ProbeEstimate,
    /// Rays that met a front face where the supplied function had no value;
    /// they count as dark, so a large share makes the estimate low.
    pub unanswered: u64,
}

impl Reference {
    /// `B(x) = E(x) + rho(x) (P(x) + integral seen(y)/pi cos dw)` at each point,
    /// where `P` is the irradiance from punctual lights and `seen(y)` the
    /// radiosity the caller gives to the front hit `y` of each
    /// cosine-distributed ray (`settings.paths` rays per point). Rays that
    /// escape or meet a back face carry nothing, as in the path tracer.
    ///
    /// `seen` receives the hit surface, the hit position on its plane and that
    /// surface's front normal. Ray `j` of point `i` draws from the stream
    /// `(settings.seed, i, j)` and chunks merge in order, so the same inputs
    /// give the same bits at any thread count.
    ///
    /// Fails on invalid settings and on a point whose surface does not exist
    /// or whose position is not finite.
    pub fn gather_at<F>(
        &self,
        points: &[SurfacePoint],
        settings: &ReferenceSettings,
        seen: F,
    ) -> Result<Vec<GatherEstimate>>
    where
        F: Fn(SurfacePoint) -> Option<Rgb> + Sync,
    {
        settings.validate()?;
        let starts = self.starts(points, "gather")?;
        let chunks = settings.paths.div_ceil(CHUNK_PATHS);
        let work: Vec<(usize, u64)> = (0..starts.len())
            .flat_map(|i| (0..chunks).map(move |c| (i, c)))
            .collect();
        let partial: Vec<(RunningStats, u64)> = work
            .par_iter()
            .map(|&(i, chunk)| {
                let (surface, position) = starts[i];
                let normal = self.geometry[surface as usize].normal;
                let origin = position + normal * self.tolerances.offset;
                let (emission, reflectance) = self.shades[surface as usize].at(position);
                let punctual = self.punctual_term(surface, origin, normal);
                let first = chunk * CHUNK_PATHS;
                let last = (first + CHUNK_PATHS).min(settings.paths);
                let mut stats = RunningStats::default();
                let mut unanswered = 0;
                for ray in first..last {
                    let mut rng = Rng::for_stream(settings.seed, Domain::Gather, i as u64, ray);
                    let dir = cosine_direction(normal, rng.uniform(), rng.uniform());
                    // With cosine sampling, the estimate of the integral of
                    // L cos dw is pi L = B(y).
                    let mut incoming = Rgb::ZERO;
                    if let Some(hit) = self.accel.nearest(&self.geometry, origin, dir, surface) {
                        if hit.front {
                            let g = &self.geometry[hit.surface as usize];
                            let y = SurfacePoint {
                                surface: hit.surface,
                                position: g.project(origin + dir * hit.t).1,
                                normal: g.normal,
                            };
                            match seen(y) {
                                Some(b) => incoming = b,
                                None => unanswered += 1,
                            }
                        }
                    }
                    stats.push(emission + reflectance * (punctual + incoming));
                }
                (stats, unanswered)
            })
            .collect();
        Ok(partial
            .chunks(chunks as usize)
            .map(|parts| {
                let mut total = RunningStats::default();
                let mut unanswered = 0;
                for (s, u) in parts {
                    total.merge(s);
                    unanswered += u;
                }
                GatherEstimate {
                    estimate: total.estimate(),
                    unanswered,
                }
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneBuilder;
    use glam::DVec3;

    /// A closed unit cube of reflectance `rho`, faces pointing in.
    fn cube(rho: f64) -> crate::scene::Scene {
        let mut b = SceneBuilder::new("cube");
        let m = b.material("grey", Rgb::splat(rho), Rgb::ZERO).unwrap();
        let p = DVec3::new;
        let (o, x, y, z) = (p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.), p(0., 0., 1.));
        for (corner, u, v) in [
            (o, z, x),
            (y, x, z),
            (o, x, y),
            (z, y, x),
            (o, y, z),
            (x, z, y),
        ] {
            b.quad(m, corner, corner + u, corner + u + v, corner + v)
                .unwrap();
        }
        b.build().unwrap()
    }

    #[test]
    fn inside_a_closed_cube_a_constant_radiosity_gathers_rho_times_itself() {
        let scene = cube(0.6);
        let reference = Reference::new(&scene).unwrap();
        let points = crate::reference::sample_points(&scene, 12, 3).unwrap();
        let settings = ReferenceSettings {
            paths: 600,
            ..ReferenceSettings::default()
        };
        let out = reference
            .gather_at(&points, &settings, |_| Some(Rgb::splat(2.0)))
            .unwrap();
        for g in &out {
            // Every ray meets a front face: B = rho * 2 exactly.
            assert_eq!(g.unanswered, 0);
            assert_eq!(g.estimate.paths, 600);
            assert!((g.estimate.radiosity.0[1] - 1.2).abs() < 1e-12, "{g:?}");
        }
    }

    #[test]
    fn rays_the_function_cannot_answer_are_counted_and_dark() {
        let scene = cube(0.5);
        let reference = Reference::new(&scene).unwrap();
        let points = crate::reference::sample_points(&scene, 4, 1).unwrap();
        let settings = ReferenceSettings {
            paths: 1_000,
            ..ReferenceSettings::default()
        };
        // Only surface 0 answers.
        let out = reference
            .gather_at(&points, &settings, |y| (y.surface == 0).then_some(Rgb::ONE))
            .unwrap();
        for (p, g) in points.iter().zip(&out) {
            let answered = 1_000 - g.unanswered;
            // The estimate is rho times the share of rays that met surface 0.
            let expected = 0.5 * answered as f64 / 1_000.0;
            assert!(
                (g.estimate.radiosity.0[0] - expected).abs() < 1e-12,
                "{g:?}"
            );
            if p.surface == 0 {
                assert_eq!(g.unanswered, 1_000, "a plane never sees itself");
            }
        }
        let bad = [SurfacePoint {
            surface: 99,
            ..points[0]
        }];
        assert!(reference.gather_at(&bad, &settings, |_| None).is_err());
    }
}
