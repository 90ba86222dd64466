//! What the last shaped gather of a solve with every light on leaves for
//! the light groups, which gather with the same shaped patches.

use super::source_shape::{NearWeights, SourceShapes};

/// What the last shaped gather of a solve with every light on leaves for
/// the groups: the unevenly lit patches and their parts, what their near
/// receivers weigh of the parts (geometry, and the part views drawn), and
/// how many corrections of the patch radiosities followed the gather (see
/// the driver's gathering solver).
#[derive(Debug)]
pub(crate) struct KeptShapes {
    /// The shaped patches; each group takes their parts' values anew.
    pub shapes: SourceShapes,
    /// What near receivers weigh of the parts.
    pub near: NearWeights,
    /// Corrections made after the shaped gather.
    pub corrections: usize,
}
