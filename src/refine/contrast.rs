//! How large a difference between two neighbouring radiosities is, for the
//! refinement criterion and for ending shared rows.
//!
//! A difference is measured against the brighter of the two neighbours'
//! reflected radiosities, but never against less than a floor: a fraction
//! of the scene's brightest reflected radiosity. At the default floor of 1
//! every difference is measured against the brightest, which spends the
//! elements where the light is strongest; a lower floor also refines the
//! contact shadows of dim regions (a bench in a corridor lit only by what the
//! court reflects), which matter as much to that object's mean and to the
//! eye, at the price of many more elements. The floor keeps noise-level
//! differences in nearly black regions from spending the budget.

use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::Radiosity;

/// The scales a difference between neighbours is measured against.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Contrast {
    /// The smallest scale a difference is measured against.
    least: f64,
}

impl Contrast {
    /// The scale for `radiosity` on the leaves of `mesh`, with the local scale
    /// kept at or above `floor` times the brightest reflected radiosity of any
    /// leaf (any band). `None` when nothing reflects any light (or `floor` is
    /// not positive).
    #[must_use]
    pub(crate) fn of_scene(mesh: &Mesh, radiosity: &Radiosity, floor: f64) -> Option<Self> {
        let brightest = mesh
            .leaves()
            .iter()
            .map(|&k| reflected(mesh, radiosity, k).max_band())
            .fold(0.0, f64::max);
        let least = brightest * floor.min(1.0);
        (least > 0.0).then_some(Contrast { least })
    }

    /// The difference between leaves `a` and `b` (largest band of the total
    /// radiosities' difference) over the brighter one's reflected radiosity,
    /// or over the floor where that is dimmer.
    #[must_use]
    pub(crate) fn between(
        &self,
        mesh: &Mesh,
        radiosity: &Radiosity,
        a: ElementKey,
        b: ElementKey,
    ) -> f64 {
        let difference = (radiosity.element(a) - radiosity.element(b))
            .abs()
            .max_band();
        let local = reflected(mesh, radiosity, a)
            .max_band()
            .max(reflected(mesh, radiosity, b).max_band());
        difference / local.max(self.least)
    }
}

/// What leaf `k` reflects: its radiosity less its own emission.
fn reflected(mesh: &Mesh, radiosity: &Radiosity, k: ElementKey) -> Rgb {
    radiosity.element(k) - mesh.elements[k].emission
}
