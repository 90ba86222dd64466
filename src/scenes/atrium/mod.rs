//! A large interior built in code: an atrium, the size series of the scale
//! work (10 000 to 1 000 000 triangles).
//!
//! A rectangular court open to the sky, 12 metres wide and
//! `4 * bays` long, between two long sides that each have, from the outside
//! in: an ambulatory behind an arcade of columns and semicircular arches,
//! then two storeys of galleries (balconies) with columns and balustrades
//! opening onto the court, under a flat roof. The short sides are plain end
//! walls. Banners hang in front of the top gallery's columns and on the end
//! walls; tables, benches, planters and a fountain stand on the floor. The
//! roof's opening is lit by an emitting sky quad 3 metres
//! above it, facing down, with radiance (0.9, 1.0, 1.15) (relative
//! units: W m^-2 sr^-1 if you like; only ratios matter to the images, whose
//! exposure is automatic). A sun can be added from [`SUN_DIRECTION`] as a
//! directional [`Light`](crate::scene::Light); the built-in scene has none,
//! so that its figures stay comparable with earlier runs.
//!
//! Units are metres; +y is up, x runs along the court (west to east), z
//! across it (south to north), and the floor is at y = 0.
//!
//! - **Size**: [`atrium`]`(target)` builds a scene within 10% of `target`
//!   triangles for targets of [`MIN_TRIANGLES`] to [`MAX_TRIANGLES`]. A
//!   quad surface counts as two triangles ([`triangle_count`]). Larger
//!   targets get more bays (a longer court), balusters instead of solid
//!   parapets, and above all finer curves: the density of segments along
//!   columns, arches, balusters, cloth and furniture is searched so that the
//!   count comes closest to the target ([`AtriumSize::for_target`]). Flat
//!   surfaces stay single quads; the mesher cuts them into patches.
//! - **Objects** (a few hundred at the largest size): `floor`,
//!   `end_wall_west`, `end_wall_east`; per side (`south`, `north`)
//!   `ambulatory_SIDE` (outer wall and ceiling), `gallery_SIDE_K` (outer
//!   wall, floor, ceiling of gallery K), `facade_SIDE` (the slab edges facing
//!   the court), `roof_SIDE`; `sky`; `arch_K`, `respond_K` (the half-piers
//!   at the end walls), `column_K` (each with its plinth or pedestal and
//!   abacus), `balustrade_K`, `banner_K`, `fountain`, `table_K`, `bench_K`,
//!   `planter_K`. Numbers count from 0 per kind.
//! - **Hygiene**: every surface faces into the building or out of the solid
//!   it bounds (solids have no faces against what they stand on or carry);
//!   furniture stands on the floor; parts meet edge to edge, never overlapping
//!   in one plane.
//! - **Determinism**: variations come from a fixed hash, and sines and
//!   cosines from additions and multiplications alone (no platform maths
//!   library), so a size gives the same bits on every run and platform.

mod arches;
mod balustrade;
mod camera;
mod cloth;
mod columns;
mod court;
mod furniture;
mod generator;
mod palette;
mod plan;
mod shapes;
mod shell;
mod sink;
mod size;
mod trig;

pub use size::{AtriumSize, MAX_BAYS, MAX_DENSITY, MIN_BAYS, MIN_DENSITY};

use crate::error::Result;
use crate::scene::{Scene, SceneBuilder};
use glam::DVec3;

/// Smallest target of [`atrium`].
pub const MIN_TRIANGLES: usize = 10_000;
/// Largest target of [`atrium`].
pub const MAX_TRIANGLES: usize = 1_000_000;
/// The target of [`atrium_default`] and of the built-in name `atrium`: the
/// smallest of the size series (a solve at default settings takes minutes
/// today, and every larger size much longer).
pub const DEFAULT_TRIANGLES: usize = 10_000;

/// Unit vector from the scene towards the sun, for a directional light
/// (the built-in scene has none): 60 degrees above the horizon, from
/// 30 degrees south of the court's east-west axis, so that it reaches down
/// into the court and lights the north arcade and part of the floor.
pub const SUN_DIRECTION: DVec3 =
    DVec3::new(0.433_012_701_892_219_3, 0.866_025_403_784_438_6, -0.25);

/// The atrium with about `target_triangles` triangles (within 10%, for
/// [`MIN_TRIANGLES`] to [`MAX_TRIANGLES`]); see the [module docs](self).
/// Fails with [`Error::Setting`](crate::Error::Setting) outside that range.
pub fn atrium(target_triangles: usize) -> Result<Scene> {
    let size = AtriumSize::for_target(target_triangles)?;
    let mut scene = atrium_sized(&size)?;
    scene.name = if target_triangles == DEFAULT_TRIANGLES {
        "atrium".to_string()
    } else {
        format!("atrium_{}", short_count(target_triangles))
    };
    Ok(scene)
}

/// The built-in default: [`atrium`]`(`[`DEFAULT_TRIANGLES`]`)`, called `atrium`.
#[must_use]
pub fn atrium_default() -> Scene {
    atrium(DEFAULT_TRIANGLES).expect("the default size is in range")
}

/// Most triangles [`atrium_sized`] builds (about 2 GB of surfaces).
pub const MAX_BUILT_TRIANGLES: usize = 10 * MAX_TRIANGLES;

/// The atrium of an explicit layout and density, called `atrium`. Fails with
/// [`Error::Setting`](crate::Error::Setting) when `size` is out of range, and
/// with [`Error::Limit`](crate::Error::Limit) when it would have more than
/// [`MAX_BUILT_TRIANGLES`] (counted before anything is built).
pub fn atrium_sized(size: &AtriumSize) -> Result<Scene> {
    let triangles = size.triangles()?;
    if triangles > MAX_BUILT_TRIANGLES {
        return Err(crate::Error::limit(
            crate::error::LimitKind::Triangles,
            format!(
                "an atrium of {size:?} would have {triangles} triangles, more than \
             {MAX_BUILT_TRIANGLES}; lower the density or the bays"
            ),
        ));
    }
    let mut builder = SceneBuilder::new("atrium");
    generator::generate(&mut builder, *size)?;
    builder.camera(camera::default_camera(&plan::Plan { bays: size.bays }));
    builder.build()
}

/// Triangles in `scene`, counting a quad as two.
#[must_use]
pub fn triangle_count(scene: &Scene) -> usize {
    scene.surfaces.iter().map(|s| s.vertices.len() - 2).sum()
}

/// The target named by a built-in scene name: `atrium` is
/// [`DEFAULT_TRIANGLES`], `atrium_N` is N triangles, where N may end in `k`
/// (thousands) or `m` (millions): `atrium_200k`, `atrium_1m`,
/// `atrium_150000`. `None` for any other name (the range is checked by
/// [`atrium`]).
#[must_use]
pub fn target_of_name(name: &str) -> Option<usize> {
    if name == "atrium" {
        return Some(DEFAULT_TRIANGLES);
    }
    let count = name.strip_prefix("atrium_")?;
    let (digits, scale) = match count.as_bytes().last()? {
        b'k' => (&count[..count.len() - 1], 1_000),
        b'm' => (&count[..count.len() - 1], 1_000_000),
        _ => (count, 1),
    };
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse::<usize>().ok()?.checked_mul(scale)
}

/// The atrium a built-in name asks for ([`target_of_name`]), named as asked;
/// `None` when the name is not an atrium's or its size is out of range.
#[must_use]
pub fn by_name(name: &str) -> Option<Scene> {
    let mut scene = atrium(target_of_name(name)?).ok()?;
    scene.name = name.to_string();
    Some(scene)
}

/// `n` with a `k` or `m` suffix where it is a whole number of them.
fn short_count(n: usize) -> String {
    if n.is_multiple_of(1_000_000) {
        format!("{}m", n / 1_000_000)
    } else if n.is_multiple_of(1_000) {
        format!("{}k", n / 1_000)
    } else {
        n.to_string()
    }
}

/// A fixed hash of a few small numbers (a part's kind, bay, side).
fn hash_bits(parts: &[u64]) -> u64 {
    parts.iter().fold(0, |h, &p| {
        super::hash::splitmix64(h ^ p.wrapping_mul(0x1000_0000_01B3))
    })
}

/// 16 bits of a hash as a fraction in [0, 1].
fn hash_unit(h: u64, shift: u32) -> f64 {
    super::hash::unit(h, shift)
}
