//! The five hemi-cube faces as coordinate maps from the receiver's local frame
//! `(x, y, z)` (z along the normal) to face coordinates `(sx, sy, depth)`.

use glam::DVec3;

/// One face of the hemi-cube.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Face {
    /// Looks along the normal; `n x n` pixels, `sy` in [-1, 1].
    Top,
    /// Looks along +x; `n x n/2` pixels, `sy` (height above the horizon) in [0, 1].
    PosX,
    /// Looks along -x.
    NegX,
    /// Looks along +y.
    PosY,
    /// Looks along -y.
    NegY,
}

impl Face {
    /// All five faces, top first.
    pub(crate) const ALL: [Face; 5] = [Face::Top, Face::PosX, Face::NegX, Face::PosY, Face::NegY];

    /// Maps a local vector to `(sx, sy, depth)`. The map is a signed permutation,
    /// so it maps plane normals the same way as points.
    #[inline]
    pub(crate) fn map(self, l: DVec3) -> DVec3 {
        match self {
            Face::Top => l,
            Face::PosX => DVec3::new(l.y, l.z, l.x),
            Face::NegX => DVec3::new(l.y, l.z, -l.x),
            Face::PosY => DVec3::new(l.x, l.z, l.y),
            Face::NegY => DVec3::new(l.x, l.z, -l.y),
        }
    }

    /// True for the top face.
    #[inline]
    pub(crate) fn is_top(self) -> bool {
        self == Face::Top
    }
}
