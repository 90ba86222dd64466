//! How a receiver's row is turned from pixels into form factors.

use std::str::FromStr;

/// The form-factor method of a hemi-cube row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FormFactorMethod {
    /// The classic hemi-cube: each patch gets the delta form factors of the
    /// pixels it won in the item buffer.
    Hemicube,
    /// The hemi-cube decides visibility; the magnitude is Lambert's exact
    /// point-to-polygon form factor times the fraction of the patch's pixels that
    /// it won (`F = F_exact * won / covered`). Exact for unoccluded patches, free
    /// of the aliasing of small projections, and as good as the hemi-cube where
    /// occlusion is partial. A row whose sum would exceed 1 is scaled back to 1.
    #[default]
    Hybrid,
}

impl FromStr for FormFactorMethod {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "hemicube" => Ok(FormFactorMethod::Hemicube),
            "hybrid" => Ok(FormFactorMethod::Hybrid),
            _ => Err(format!(
                "unknown form-factor method '{s}' (hemicube or hybrid)"
            )),
        }
    }
}

/// How the hybrid method decides what a receiver sees of an emitter patch
/// that its hemi-cube saw only in part.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EmitterSampling {
    /// The hemi-cube's pixels alone, as for every other patch: penumbrae
    /// are limited to the hemi-cube's resolution. For comparison.
    Pixels,
    /// Shadow rays from the element's centre (stratified, jittered): the
    /// estimate of earlier versions, kept for comparison.
    Rays,
    /// Exact visibility at the element's centre: the occluders in the shaft
    /// are clipped out of the emitter (rays only where more than a few dozen
    /// polygons lie in the shaft).
    Centre,
    /// The exact visible form factor averaged over Gauss points of the
    /// element: its mean rather than its centre's value.
    Element,
    /// [`Self::Element`] in rows where something hides part of an emitter
    /// from some Gauss point of the element (or a point sees none of its
    /// front), and [`Self::Centre`] in rows where nothing does. Where a
    /// shadow edge crosses an element the centre alone can be off by much of
    /// the element's light (a box side lit past its neighbours came out 20%
    /// dark in direct light on `many_boxes`); where the emitters are in full
    /// view the form factor varies smoothly across the element, and the
    /// centre's value keeps the closed boxes as accurate as before (the
    /// Cornell box 0.116% mean against 0.138% at the centre and 0.154% with
    /// the points everywhere). A row takes all its emitters one way: mixed,
    /// they would not add up to the receiver's whole view (a furnace's
    /// elements came out 0.3% off). Rows where more than a few surfaces cast
    /// shadows on the first point (a shaft crowded by a tessellated mesh's
    /// facets), or that see so many emitter polygons that the small ones
    /// take one ray each, take the centre: each point would clip every
    /// shadow again for an edge no sharper than the facets' own. The
    /// default: about 1.07x the CPU time of the Cornell box and 1.1x that of
    /// the 10 000-triangle atrium, for the lowest largest per-object error
    /// of any sampling on the cluttered scenes measured.
    #[default]
    Shadowed,
}

impl FromStr for EmitterSampling {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "pixels" => Ok(EmitterSampling::Pixels),
            "rays" => Ok(EmitterSampling::Rays),
            "centre" => Ok(EmitterSampling::Centre),
            "element" => Ok(EmitterSampling::Element),
            "shadowed" => Ok(EmitterSampling::Shadowed),
            _ => Err(format!(
                "unknown emitter sampling '{s}' (pixels, rays, centre, element or shadowed)"
            )),
        }
    }
}
