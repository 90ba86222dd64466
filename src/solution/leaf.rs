//! A view of one leaf element with what the solve found for it.

use crate::formfactor::RowState;
use crate::math::Rgb;
use crate::mesh::{Element, ElementKey};
use std::f64::consts::PI;

/// A leaf element of a solution with what the solve found for it. Derefs to
/// the [`Element`]'s geometry (area, centroid, surface, cell).
#[derive(Clone, Copy, Debug)]
pub struct Leaf<'a> {
    /// Its key in the mesh.
    pub key: ElementKey,
    /// Its geometry.
    pub element: &'a Element,
    /// Its radiosity (exitance), per band.
    pub radiosity: Rgb,
    /// Its form-factor row and the row's state.
    pub row: &'a RowState,
}

impl std::ops::Deref for Leaf<'_> {
    type Target = Element;

    fn deref(&self) -> &Element {
        self.element
    }
}

impl Leaf<'_> {
    /// Its radiance (radiosity / pi): what a camera sees on a diffuse surface.
    #[must_use]
    pub fn radiance(&self) -> Rgb {
        self.radiosity / PI
    }

    /// The share of its area that can be seen: 1 for most leaves, less for
    /// one that another object stands on in part (its row says how much is
    /// covered), 0 for one shut in under an object.
    #[must_use]
    pub fn visible(&self) -> f64 {
        // Straight from the row: `RowState::view` would sum its entries.
        match self.row {
            RowState::ShutIn(_) => 0.0,
            RowState::Computed(row) => row.visible(),
            RowState::Pending | RowState::Skipped => 1.0,
        }
    }

    /// The radiosity of its visible part. [`Leaf::radiosity`] is the mean
    /// over its whole area, which counts a covered part as dark: a wall
    /// element half hidden behind a pier shows half its light there. Its
    /// reflected light came from its visible part alone, so that part's
    /// radiosity is `E + (B - E) / visible`. The same as `radiosity` for a
    /// leaf wholly visible or wholly hidden.
    #[must_use]
    pub fn visible_radiosity(&self) -> Rgb {
        let visible = self.visible();
        if visible <= 0.0 || visible >= 1.0 {
            return self.radiosity;
        }
        let emission = self.element.emission;
        emission + (self.radiosity - emission) * (1.0 / visible)
    }

    /// Its row's `(patch, form factor)` entries (none unless its row is
    /// held: see [`RowState`]).
    #[must_use]
    pub fn entries(&self) -> &[(u32, f32)] {
        match self.row {
            RowState::Computed(row) => row.entries(),
            _ => &[],
        }
    }

    /// The sum of its row: the part of its hemisphere that sees a front face
    /// (0 when its row is not held).
    #[must_use]
    pub fn row_sum(&self) -> f64 {
        match self.row {
            RowState::Computed(row) => row.sum(),
            _ => 0.0,
        }
    }
}
