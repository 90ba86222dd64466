//! Radiosity at given points, in parallel and in a fixed reduction order.

use super::rng::{Domain, Rng};
use super::stats::{ProbeEstimate, RunningStats};
use super::{Reference, ReferenceSettings, SurfacePoint, CHUNK_PATHS};
use crate::error::{Error, GeometryFault, Result};
use glam::DVec3;
use rayon::prelude::*;

impl Reference {
    /// The radiosity at each point: the mean over `settings.paths` independent
    /// paths, with its standard error.
    ///
    /// Path `j` of the `i`-th point draws from the random stream
    /// `(settings.seed, i, j)`, and paths are split into fixed chunks that are
    /// merged in order, so the result is the same bits at any thread count. A
    /// point's position is first projected onto its surface's plane.
    ///
    /// Fails on invalid settings, or on a point whose surface index is out of
    /// range or whose position is not finite.
    pub fn radiosity_at(
        &self,
        points: &[SurfacePoint],
        settings: &ReferenceSettings,
    ) -> Result<Vec<ProbeEstimate>> {
        settings.validate()?;
        let starts = self.starts(points, "probe")?;
        let chunks = settings.paths.div_ceil(CHUNK_PATHS);
        let work: Vec<(usize, u64)> = (0..starts.len())
            .flat_map(|i| (0..chunks).map(move |c| (i, c)))
            .collect();
        let partial: Vec<RunningStats> = work
            .par_iter()
            .map(|&(i, chunk)| {
                let (surface, position) = starts[i];
                let first = chunk * CHUNK_PATHS;
                let last = (first + CHUNK_PATHS).min(settings.paths);
                let mut stats = RunningStats::default();
                for path in first..last {
                    let mut rng = Rng::for_stream(settings.seed, Domain::Probe, i as u64, path);
                    stats.push(self.trace_path(surface, position, settings, &mut rng));
                }
                stats
            })
            .collect();
        Ok(partial
            .chunks(chunks as usize)
            .map(|parts| {
                let mut total = RunningStats::default();
                for p in parts {
                    total.merge(p);
                }
                total.estimate()
            })
            .collect())
    }
}

impl Reference {
    /// Each point's surface and its position projected onto that surface's
    /// plane. Fails, naming the `kind` of point and its index, on a surface
    /// out of range or a position that is not finite.
    pub(super) fn starts(&self, points: &[SurfacePoint], kind: &str) -> Result<Vec<(u32, DVec3)>> {
        let mut starts = Vec::with_capacity(points.len());
        for (i, p) in points.iter().enumerate() {
            let Some(g) = self.geometry.get(p.surface as usize) else {
                return Err(Error::geometry(
                    GeometryFault::Mismatch,
                    format!(
                        "{kind} point {i} refers to surface {}, but the scene has {}",
                        p.surface,
                        self.geometry.len()
                    ),
                ));
            };
            if !p.position.is_finite() {
                return Err(Error::geometry(
                    GeometryFault::NonFinite,
                    format!("{kind} point {i} has a non-finite position {}", p.position),
                ));
            }
            starts.push((p.surface, g.project(p.position).1));
        }
        Ok(starts)
    }
}
