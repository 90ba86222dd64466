//! Built-in scenes, built in code with [`SceneBuilder`](crate::scene::SceneBuilder):
//! the Cornell box, penumbra scenes that come with their exact answer, and a
//! model of the Ferren sculpture from the seed paper's example, and a
//! scale scene of many boxes.

mod cornell;
pub mod ferren;
pub mod many_boxes;
pub mod penumbra;

pub use cornell::cornell_box;
pub use ferren::ferren_sculpture;
pub use many_boxes::{many_boxes, many_boxes_with};

use crate::scene::Scene;

/// The names of the built-in scenes, as [`by_name`] accepts them.
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
];

/// The built-in scene called `name`, if there is one.
#[must_use]
pub fn by_name(name: &str) -> Option<Scene> {
    match name {
        "cornell_box" => Some(cornell_box()),
        "ferren_sculpture" => Some(ferren_sculpture()),
        "many_boxes" => Some(many_boxes()),
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
        assert_eq!(NAMES.len(), 3 + penumbra::VARIANTS.len());
        assert!(by_name("no_such_scene").is_none());
    }
}
