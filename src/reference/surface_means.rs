//! The area-weighted mean radiosity of each object.
//!
//! The mean of B over an object is `(1/A) integral B dA`. Choosing a point
//! uniformly by area over the object's surfaces and tracing one path from it
//! gives an unbiased estimate of that mean; the points are independent, so the
//! usual standard error applies exactly (no stratification, which would make it
//! pessimistic).

use super::rng::{Domain, Rng};
use super::sampling::Cdf;
use super::stats::{ProbeEstimate, RunningStats};
use super::{Reference, ReferenceSettings, CHUNK_PATHS};
use crate::error::Result;
use rayon::prelude::*;

/// The surfaces of one object and how to pick among them by area.
#[derive(Clone, Debug)]
pub(crate) struct ObjectArea {
    /// Indices of the object's surfaces.
    surfaces: Vec<u32>,
    /// Choice among `surfaces` by area; `None` for an object with no area.
    choice: Option<Cdf>,
}

impl ObjectArea {
    /// The object made of `surfaces`, whose areas are `areas`.
    pub(crate) fn new(surfaces: Vec<u32>, areas: &[f64]) -> ObjectArea {
        let choice = Cdf::new(areas);
        ObjectArea { surfaces, choice }
    }
}

impl Reference {
    /// The mean radiosity of each object of the scene (in `Scene::objects`
    /// order), from `settings.paths` points chosen uniformly by area, one path
    /// each. Objects without surfaces get zeros and `paths: 0`.
    ///
    /// Sample `k` of object `o` draws from the random stream
    /// `(settings.seed, o, k)`; chunks are merged in order, so the result is the
    /// same bits at any thread count.
    pub fn object_means(&self, settings: &ReferenceSettings) -> Result<Vec<ProbeEstimate>> {
        settings.validate()?;
        let chunks = settings.paths.div_ceil(CHUNK_PATHS);
        let work: Vec<(usize, u64)> = (0..self.objects.len())
            .filter(|o| self.objects[*o].choice.is_some())
            .flat_map(|o| (0..chunks).map(move |c| (o, c)))
            .collect();
        let partial: Vec<RunningStats> = work
            .par_iter()
            .map(|&(o, chunk)| self.object_chunk(o, chunk, settings))
            .collect();
        let mut means = vec![ProbeEstimate::default(); self.objects.len()];
        for (parts, work_item) in partial
            .chunks(chunks as usize)
            .zip(work.chunks(chunks as usize))
        {
            let mut total = RunningStats::default();
            for p in parts {
                total.merge(p);
            }
            means[work_item[0].0] = total.estimate();
        }
        Ok(means)
    }

    /// Samples `chunk * CHUNK_PATHS ..` of object `o`.
    fn object_chunk(&self, o: usize, chunk: u64, settings: &ReferenceSettings) -> RunningStats {
        let object = &self.objects[o];
        let mut stats = RunningStats::default();
        let Some(choice) = &object.choice else {
            return stats;
        };
        let first = chunk * CHUNK_PATHS;
        let last = (first + CHUNK_PATHS).min(settings.paths);
        for k in first..last {
            let mut rng = Rng::for_stream(settings.seed, Domain::ObjectMean, o as u64, k);
            let (i, u1) = choice.pick(rng.uniform());
            let surface = object.surfaces[i];
            let position = self.geometry[surface as usize].sample(u1, rng.uniform());
            stats.push(self.trace_path(surface, position, settings, &mut rng));
        }
        stats
    }
}
