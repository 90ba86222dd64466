//! # radiosity
//!
//! Diffuse global illumination by the radiosity method (Greenberg, Cohen, Torrance
//! 1986), with hemi-cube form factors (Cohen & Greenberg 1985) and substructuring
//! with adaptive quadtree subdivision (Cohen, Greenberg, Immel, Brock 1986).
//! One solution is view independent: images from any camera come from the same
//! element and vertex radiosities.
//!
//! ## Embedding it
//!
//! Load a glTF scene, solve it, read each object's light and draw one view:
//!
//! ```
//! use radiosity::{gltf_io, render, Settings};
//! # fn main() -> radiosity::Result<()> {
//! let scene = gltf_io::load_scene("scenes/cornell_box.gltf".as_ref(), &Default::default())?;
//! let solution = radiosity::solve(&scene, &Settings::default(), &|_progress| {})?;
//! for object in solution.object_radiosity(&scene) {
//!     println!("{}: radiance {:?} per band", object.name, object.radiance().0);
//! }
//! let image = render::render(&solution.radiance_mesh(), &scene.cameras[0], 160, 120)?;
//! let tone = render::ToneMap::default();
//! let stops = render::auto_exposure(&image, tone);
//! render::write_png(&image, &std::env::temp_dir().join("cornell.png"), stops, tone)?;
//! # Ok(())
//! # }
//! ```
//!
//! Units: glTF metres and one photometric system: emitted radiance in cd/m²
//! (exitance is pi times it), point and spot light intensity in candela,
//! directional light illuminance in lux; radiosity comes out in lm/m² (see
//! [`scene::Light`]). The library never prints:
//! progress comes through the callback, figures through
//! [`Solution::stats`]. The `cli` feature (on by default) adds the
//! command-line tool and the time-versus-error reports ([`report`]); build with
//! `default-features = false` for the library alone.
//!
//! ## What a program uses
//!
//! - load: [`gltf_io::load_scene`] (options in [`gltf_io::LoadOptions`]), or
//!   a scene built in code ([`scene::SceneBuilder`], [`scenes`]);
//! - settings: [`Settings`] (Gauss-Seidel or progressive:
//!   [`pipeline::SolverKind`]);
//! - solve: [`solve()`], [`pipeline::solve_with_previews`], and
//!   [`light_groups::solve_with_light_groups`] for separately mixable lights;
//! - query: [`Solution`] (per-object means, leaves, radiosity at points,
//!   the display mesh, [`Solution::stats`]);
//! - render: [`render::render`], tone mapping and image files;
//! - bake: [`gltf_io::write_baked`];
//! - reference: [`reference::Reference`], the independent path tracer;
//! - errors: [`Error`], whose variants name the file, glTF object
//!   ([`GltfObject`]), material, light or setting at fault.
//!
//! The other modules are public for tests, benchmarks and the study of the
//! method (form factors, meshes, solvers, exact oracles); the items no
//! program needs are crate-private.
//!
//! ## Brief overview
//!
//! The pipeline runs one way, one module per stage:
//!
//! - [`scene`]: a [`scene::Scene`] of planar surfaces with diffuse materials,
//!   imported from glTF ([`gltf_io`]; files read through [`input`]) or built in
//!   code ([`scene::SceneBuilder`], the built-in [`scenes`]). Real files are
//!   repaired at load, each repair a warning in [`scene::Scene::warnings`]:
//!   overlapping coplanar surfaces resolved, reflectance clamped, compressed
//!   geometry decoded ([`gltf_io::LoadOptions`]); a scene without light is
//!   refused. Punctual lights ([`scene::Light`], `KHR_lights_punctual`) are
//!   sources outside the mesh: their direct light, with exact shadows, enters
//!   the solvers as a first reflection.
//!   [`scene::Camera::framing`] gives a default view.
//! - [`mesh`]: surfaces cut into patches, each the root of an element quadtree
//!   ([`mesh::Mesh`]): geometry and topology only.
//! - [`formfactor`]: element-to-patch rows from hemi-cubes with an item buffer,
//!   Lambert's exact formula for the magnitude of what is seen and exact
//!   visibility of emitters; kept per element in a [`formfactor::FormFactors`]
//!   store with the state of each row.
//! - [`solve`](mod@solve): the patch system assembled from the rows, solved by
//!   Gauss-Seidel ([`solve::gauss_seidel`]), and the gather to elements; the
//!   result is a [`solve::Radiosity`] per element and patch.
//! - [`refine`]: where to split elements (neighbour differences) and sources.
//! - [`pipeline`]: the one driver of both solvers: [`Settings`], checks before
//!   any form factor, meshing, refinement passes, progress and the figures of
//!   a run ([`pipeline::SolveStats`]); the progressive solver (shooting, with
//!   previews: [`pipeline::SolverKind::Progressive`]) lives there whole.
//! - [`solution`]: what a solve gives: [`Solution`], per-object means, leaf
//!   views, radiosity at points, the display mesh.
//! - [`render`]: images from any camera, tone mapping, HDR and PNG files;
//!   [`output`] writes every file whole or not at all.
//! - [`reference`](mod@reference): a path tracer independent of all the above, for ground
//!   truth; [`analytic`]: exact form factors and solutions for tests.
//! - [`math`]: colour triples and polygon helpers; [`error`]: the error type.
#![warn(missing_docs, unreachable_pub)]

pub mod analytic;
pub mod error;
pub mod gltf_io;
pub mod input;
pub mod light_groups;
pub mod math;
pub mod output;
pub mod reference;
pub mod render;
#[cfg(feature = "cli")]
pub mod report;
pub mod scene;
pub mod scenes;

pub use error::{Error, GeometryFault, GltfKind, GltfObject, LimitKind, Result, SolverFault};
pub mod formfactor;
pub mod mesh;
pub mod pipeline;
pub mod refine;
pub mod solution;
pub mod solve;

pub use pipeline::{solve, Settings, DEFAULT_MAX_MEMORY};
pub use solution::Solution;
