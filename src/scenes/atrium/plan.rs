//! The atrium's plan and section: every dimension in metres, and the frames
//! that place the two mirrored sides of the court.
//!
//! The building is `bays * BAY` long (x, west to east) and
//! `2 * (AMBULATORY + 2 * PIER_HALF) + COURT` wide (z, south to north); +y
//! is up and the floor is at y = 0. Along each long side, from the outer
//! wall in: an ambulatory [`AMBULATORY`] deep behind an arcade on columns,
//! and above it [`GALLERIES`] storeys of galleries (balconies) opening onto
//! the court over a balustrade, with columns carrying the slab above. The
//! short sides are plain end walls. The court between the two arcades is
//! open to the sky.

use glam::DVec3;

/// Distance between column axes along the court (m).
pub(super) const BAY: f64 = 4.0;
/// Half the side of a column's square plinth, pedestal and abacus, and half
/// the thickness of the arcade wall the arches cut (m).
pub(super) const PIER_HALF: f64 = 0.35;
/// Height of the ground columns' abacus tops, where the arches spring (m).
pub(super) const SPRING: f64 = 3.3;
/// Thickness of the floor slabs and the roof (m).
pub(super) const SLAB: f64 = 0.5;
/// Clear height of a gallery storey, floor to ceiling (m).
pub(super) const STOREY: f64 = 3.8;
/// Number of gallery storeys above the arcade.
pub(super) const GALLERIES: usize = 2;
/// Depth of the ground-floor ambulatory, outer wall to arcade (m).
pub(super) const AMBULATORY: f64 = 4.0;
/// Width of the open court between the arcades' faces (m).
pub(super) const COURT: f64 = 12.0;
/// Height of the balustrades and of the upper columns' pedestals (m).
pub(super) const PARAPET_HEIGHT: f64 = 1.0;
/// Thickness of the balustrades (m).
pub(super) const PARAPET_THICKNESS: f64 = 0.25;

/// The radius of the ground arches: half a bay less the abacus they spring from.
pub(super) const ARCH_RADIUS: f64 = BAY / 2.0 - PIER_HALF;

/// Heights and positions derived from the number of bays.
#[derive(Clone, Copy, Debug)]
pub(super) struct Plan {
    /// Bays along the court (columns per side and storey: `bays - 1`).
    pub bays: u32,
}

impl Plan {
    /// Length of the building along x (m).
    pub(super) fn length(&self) -> f64 {
        f64::from(self.bays) * BAY
    }

    /// Width of the building along z (m).
    pub(super) fn width(&self) -> f64 {
        2.0 * self.court_face() + COURT
    }

    /// Distance of the arcade's axis (the column axes) from the outer wall.
    pub(super) fn arcade_axis(&self) -> f64 {
        AMBULATORY + PIER_HALF
    }

    /// Distance of the court-facing plane of arcade, slabs and balustrades
    /// from the outer wall.
    pub(super) fn court_face(&self) -> f64 {
        AMBULATORY + 2.0 * PIER_HALF
    }

    /// Top of the arcade wall and ambulatory ceiling: the square around each
    /// arch is a bay wide and half a bay tall.
    pub(super) fn arcade_top(&self) -> f64 {
        SPRING + BAY / 2.0
    }

    /// Floor level of gallery `k` (0 is the lowest).
    pub(super) fn gallery_floor(&self, k: usize) -> f64 {
        self.arcade_top() + SLAB + k as f64 * (STOREY + SLAB)
    }

    /// Ceiling level of gallery `k`.
    pub(super) fn gallery_ceiling(&self, k: usize) -> f64 {
        self.gallery_floor(k) + STOREY
    }

    /// Top of the roof, the rim of the opening to the sky.
    pub(super) fn roof(&self) -> f64 {
        self.gallery_ceiling(GALLERIES - 1) + SLAB
    }

    /// The x of column axis `i`, 1 to `bays - 1`.
    pub(super) fn column_x(&self, i: u32) -> f64 {
        f64::from(i) * BAY
    }

    /// The x intervals between the pedestals of a storey (and the end walls),
    /// where the balustrade runs.
    pub(super) fn between_pedestals(&self) -> Vec<(f64, f64)> {
        (0..self.bays)
            .map(|i| {
                let start = if i == 0 {
                    0.0
                } else {
                    self.column_x(i) + PIER_HALF
                };
                let end = if i + 1 == self.bays {
                    self.length()
                } else {
                    self.column_x(i + 1) - PIER_HALF
                };
                (start, end)
            })
            .collect()
    }
}

/// One of the two long sides, each with its ambulatory, arcade and galleries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Side {
    /// Along z = 0.
    South,
    /// Along z = width, the south side mirrored.
    North,
}

impl Side {
    /// Both sides, south first.
    pub(super) const BOTH: [Side; 2] = [Side::South, Side::North];

    /// The side's name in object names.
    pub(super) fn name(self) -> &'static str {
        match self {
            Side::South => "south",
            Side::North => "north",
        }
    }
}

/// Places geometry drawn in a side's own coordinates `(x, y, d)`, where `d`
/// is the distance from that side's outer wall towards the court, into the
/// world. The north side is the south side mirrored in z, so its polygons
/// are reversed to stay counter-clockwise around their (mirrored) fronts.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    mirror_width: Option<f64>,
}

impl Frame {
    /// World coordinates as they are (d is z).
    pub(super) const WORLD: Frame = Frame { mirror_width: None };

    /// The frame of `side` of the building `plan`.
    pub(super) fn of(side: Side, plan: &Plan) -> Frame {
        match side {
            Side::South => Frame::WORLD,
            Side::North => Frame {
                mirror_width: Some(plan.width()),
            },
        }
    }

    /// The world point at side coordinates `(x, y, d)`.
    pub(super) fn point(self, x: f64, y: f64, d: f64) -> DVec3 {
        match self.mirror_width {
            None => DVec3::new(x, y, d),
            Some(w) => DVec3::new(x, y, w - d),
        }
    }

    /// World vertices of a polygon given in side coordinates (x, y, d as the
    /// vector's x, y, z), counter-clockwise around its front in both.
    pub(super) fn polygon(self, local: &[DVec3]) -> Vec<DVec3> {
        let mut world: Vec<DVec3> = local.iter().map(|p| self.point(p.x, p.y, p.z)).collect();
        if self.mirror_width.is_some() {
            world.reverse();
        }
        world
    }
}
