//! One pass of the generator over a [`Sink`]: the shell, arcades, columns,
//! balustrades, banners and furniture, in that order.

use super::arches::add_arches;
use super::balustrade::add_balustrades;
use super::cloth::add_banners;
use super::columns::add_columns;
use super::court::add_furniture;
use super::palette::Palette;
use super::plan::Plan;
use super::shell::add_shell;
use super::sink::{Names, Sink};
use super::AtriumSize;
use crate::error::Result;

/// What every part of the generator needs: where polygons go, the plan, the
/// size, the materials and the object numbering.
pub(super) struct Generator<'a, S: Sink> {
    /// Where the polygons go.
    pub sink: &'a mut S,
    /// Dimensions.
    pub plan: Plan,
    /// Layout and tessellation density.
    pub size: AtriumSize,
    /// Material indices.
    pub palette: Palette,
    /// Object numbering per kind.
    pub names: Names,
}

/// Generates the whole atrium of `size` into `sink` (the size must be valid).
pub(super) fn generate<S: Sink>(sink: &mut S, size: AtriumSize) -> Result<()> {
    let palette = Palette::register(sink)?;
    let mut g = Generator {
        sink,
        plan: Plan { bays: size.bays },
        size,
        palette,
        names: Names::default(),
    };
    add_shell(&mut g)?;
    add_arches(&mut g)?;
    add_columns(&mut g)?;
    add_balustrades(&mut g)?;
    add_banners(&mut g)?;
    add_furniture(&mut g)
}
