//! Groups of a scene's sources (emissive surfaces, punctual lights, the
//! sky): how they are formed ([`LightGroups::each`], [`LightGroups::by_rule`]),
//! checked against the scene ([`LightGroups::validate`]) and mixed into a
//! scene of scaled emission ([`LightGroups::scaled_scene`]). Solving them is
//! `crate::light_groups`' part.

mod scaled;
mod spec;
mod validate;

pub use spec::{GroupPattern, GroupRule, LightGroup, LightGroups};
