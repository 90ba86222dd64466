//! # radiosity
//!
//! Diffuse global illumination by the radiosity method (Greenberg, Cohen, Torrance
//! 1986), with hemi-cube form factors (Cohen & Greenberg 1985) and substructuring
//! with adaptive quadtree subdivision (Cohen, Greenberg, Immel, Brock 1986).
//!
//! ## Brief overview
//!
//! The pipeline runs one way, one module per stage:
//!
//! - [`scene`]: a [`scene::Scene`] of planar surfaces with diffuse materials,
//!   imported from glTF ([`gltf_io`]) or built in code ([`scene::SceneBuilder`],
//!   [`scenes`]).
#![warn(missing_docs, unreachable_pub)]

pub mod analytic;
pub mod error;
pub mod gltf_io;
pub mod input;
pub mod math;
pub mod output;
pub mod reference;
pub mod render;
#[cfg(feature = "cli")]
pub mod report;
pub mod scene;
pub mod scenes;

pub use error::{Error, Result};
pub mod formfactor;
pub mod mesh;
pub mod pipeline;
pub mod refine;
pub mod solution;
pub mod solve;

pub use pipeline::{solve, Settings};
pub use solution::Solution;
