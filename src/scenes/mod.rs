//! Built-in scenes, built in code with [`SceneBuilder`](crate::scene::SceneBuilder).

mod cornell;

pub use cornell::cornell_box;

use crate::scene::Scene;

/// The names of the built-in scenes, as [`by_name`] accepts them.
pub const NAMES: &[&str] = &["cornell_box"];

/// The built-in scene called `name`, if there is one.
#[must_use]
pub fn by_name(name: &str) -> Option<Scene> {
    match name {
        "cornell_box" => Some(cornell_box()),
        _ => None,
    }
}
