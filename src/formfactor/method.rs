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
    #[default]
    Centre,
    /// The exact visible form factor averaged over Gauss points of the
    /// element: its mean rather than its centre's value.
    Element,
}

impl FromStr for EmitterSampling {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "pixels" => Ok(EmitterSampling::Pixels),
            "rays" => Ok(EmitterSampling::Rays),
            "centre" => Ok(EmitterSampling::Centre),
            "element" => Ok(EmitterSampling::Element),
            _ => Err(format!(
                "unknown emitter sampling '{s}' (pixels, rays, centre or element)"
            )),
        }
    }
}
