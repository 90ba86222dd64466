//! Built-in scenes, built in code with [`SceneBuilder`](crate::scene::SceneBuilder):
//! the Cornell box, penumbra scenes that come with their exact answer, and a
//! model of the Ferren sculpture from the seed paper's example, a
//! scale scene of many boxes, and an atrium of 10 000 to 1 000 000 triangles.

pub mod atrium;
mod cornell;
pub mod ferren;
mod hash;
pub mod many_boxes;
pub mod penumbra;

pub use atrium::{atrium, atrium_default};
pub use cornell::cornell_box;
pub use ferren::ferren_sculpture;
pub use many_boxes::{many_boxes, many_boxes_with};

use crate::scene::Scene;

/// The names of the built-in scenes, as [`by_name`] accepts them. The atrium
/// also comes in other sizes, named as [`SIZED_NAMES`] says.
pub const NAMES: &[&str] = &[
    "cornell_box",
    "penumbra_parallel",
    "penumbra_rotated",
    "penumbra_triangle_light",
    "penumbra_two_occluders",
    "penumbra_narrow",
    "penumbra_wide",
    "ferren_sculpture",
    "many_boxes",
    "atrium",
];

/// The built-in names that take a size, for help and error messages.
pub const SIZED_NAMES: &str =
    "atrium_N (N triangles, 10k to 1m: atrium_30k, atrium_200000, atrium_1m)";

/// The built-in scene called `name`, if there is one.
#[must_use]
pub fn by_name(name: &str) -> Option<Scene> {
    match name {
        "cornell_box" => Some(cornell_box()),
        "ferren_sculpture" => Some(ferren_sculpture()),
        "many_boxes" => Some(many_boxes()),
        _ if name.starts_with("atrium") => atrium::by_name(name),
        // The penumbra specs are fixed and valid, so building them cannot fail.
        _ => penumbra::by_name(name).and_then(|spec| spec.scene().ok()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_listed_name_builds() {
        for name in NAMES {
            assert!(by_name(name).is_some(), "{name}");
        }
        assert_eq!(NAMES.len(), 4 + penumbra::VARIANTS.len());
        assert!(by_name("no_such_scene").is_none());
    }

    #[test]
    fn sized_atrium_names_build_and_keep_their_name() {
        let scene = by_name("atrium_12k").unwrap();
        assert_eq!(scene.name, "atrium_12k");
        assert!(by_name("atrium_5k").is_none(), "below the range");
        assert!(by_name("atrium_x").is_none());
    }
}
