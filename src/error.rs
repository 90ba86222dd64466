//! The library's error type: every failure names what is wrong and where.

use std::path::PathBuf;

/// Everything that can go wrong in the library. Each variant names the file, the
/// mesh or material, and the fault, so that a user can find and fix the input.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    ///
    /// The message already holds the operating system's reason, so the reason
    /// is deliberately not also reported as the error's `source()`: a report
    /// that prints the whole chain (`anyhow`'s `{:#}`) would repeat it
    /// (`Permission denied (os error 13): Permission denied (os error 13)`).
    #[error("{path}: {error}")]
    Io {
        /// The file involved.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// A scene file is not valid glTF, or uses glTF in a way this importer rejects.
    #[error("{path}: {message}")]
    Gltf {
        /// The scene file.
        path: PathBuf,
        /// The node, mesh, material, light, texture or image at fault, where
        /// one is (the message names it too).
        object: Option<GltfObject>,
        /// What is wrong, naming the mesh, accessor or buffer.
        message: String,
    },
    /// A material has a value outside its physical range (reflectance above 1,
    /// negative or non-finite emission).
    #[error("material '{material}': {message}")]
    Material {
        /// The material's name (or index, if it has none).
        material: String,
        /// What is wrong.
        message: String,
    },
    /// Geometry that cannot be used: non-finite coordinates, a non-planar or
    /// non-convex polygon handed to the builder, a scene with no surfaces.
    #[error("geometry: {message}")]
    Geometry {
        /// What kind of fault.
        fault: GeometryFault,
        /// What is wrong, naming the surface, polygon, point or scene.
        message: String,
    },
    /// A punctual light with a value outside its range (negative or
    /// non-finite intensity, colour or range, cone angles out of order).
    #[error("light {light}: {message}")]
    Light {
        /// The light, as the file or the builder names it (and its node).
        light: String,
        /// What is wrong.
        message: String,
    },
    /// Nothing in the scene gives light, so the solution would be black.
    #[error("{message}")]
    NoLight {
        /// The scene's name.
        scene: String,
        /// The names of the scene's punctual lights, which all have intensity
        /// or colour 0 (empty when the scene has none).
        dark_lights: Vec<String>,
        /// The whole message: what would give light, naming (some of) the
        /// dark lights.
        message: String,
    },
    /// A setting is out of its range.
    #[error("setting `{name}`: {message}")]
    Setting {
        /// The setting's name as the API spells it: a field of
        /// [`Settings`](crate::Settings) or of the options or arguments of the
        /// call that refused it (`patch_size`, `refine.max_depth`).
        name: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A configured limit (triangles, elements, memory) was reached.
    #[error("limit reached: {message}")]
    Limit {
        /// Which limit.
        limit: LimitKind,
        /// What would have exceeded it, naming the file where there is one.
        message: String,
    },
    /// The solver could not converge, or met a numerically unusable system.
    #[error("solver: {message}")]
    Solver {
        /// What kind of fault.
        fault: SolverFault,
        /// What went wrong, with the figures that show it.
        message: String,
    },
    /// An output could not be encoded.
    #[error("output {path}: {message}")]
    Output {
        /// The file being written.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}

/// A glTF object that an [`Error::Gltf`] names: what kind it is, its index
/// in the file's list of its kind, and its name if it has one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GltfObject {
    /// What kind of object.
    pub kind: GltfKind,
    /// Its index in the file's list of objects of its kind.
    pub index: usize,
    /// Its name in the file, if it has a non-empty one.
    pub name: Option<String>,
}

impl GltfObject {
    /// Object `index` of `kind`, named `name` (an empty name counts as none).
    #[must_use]
    pub fn new(kind: GltfKind, index: usize, name: Option<&str>) -> Self {
        GltfObject {
            kind,
            index,
            name: name.filter(|n| !n.is_empty()).map(str::to_string),
        }
    }
}

/// The kinds of glTF object an [`Error::Gltf`] can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum GltfKind {
    /// An entry of `nodes`.
    Node,
    /// An entry of `meshes` (the fault may lie in one of its primitives or
    /// the accessors they read).
    Mesh,
    /// An entry of `materials`.
    Material,
    /// A light of `KHR_lights_punctual`.
    Light,
    /// An entry of `textures`.
    Texture,
    /// An entry of `images`.
    Image,
}

/// The limits an [`Error::Limit`] names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LimitKind {
    /// Bytes of a file or of a buffer it declares
    /// (`ImportLimits::max_file_bytes`).
    FileBytes,
    /// Triangles of a file (`ImportLimits::max_triangles`) or of a built-in
    /// scene.
    Triangles,
    /// Nesting of a file's nodes (`ImportLimits::max_node_depth`).
    NodeDepth,
    /// Patches of the mesh (`Settings::max_patches`).
    Patches,
    /// Elements of the mesh (the refinement's element budget).
    Elements,
    /// Bytes of the solve (`Settings::max_memory`).
    Memory,
    /// Cells of an adaptive quadrature that did not meet its tolerance.
    QuadratureCells,
}

/// The kinds of fault an [`Error::Geometry`] names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum GeometryFault {
    /// A coordinate, normal, point or value that is not finite.
    NonFinite,
    /// A polygon with too few vertices, zero area, a zero-length edge or a
    /// normal of no direction.
    Degenerate,
    /// A quad (or polygon) whose vertices do not lie in one plane.
    NonPlanar,
    /// A polygon that is not (strictly) convex.
    NonConvex,
    /// A value outside its range: a coordinate beyond the largest the solver
    /// represents, a length or area that must be finite and positive.
    OutOfRange,
    /// A scene with no surfaces (or no triangles, or no floor where one is
    /// needed).
    NoSurfaces,
    /// Surfaces of different materials that overlap in one plane, refused.
    Overlap,
    /// Inputs that do not belong together: counts that disagree, an index
    /// (of a material, object, surface or vertex) out of range, a reference
    /// that lists other objects, a point on no surface.
    Mismatch,
    /// Input this code does not take: more occluders than an oracle takes, a
    /// polygon of more than 4 vertices where only triangles and quads are.
    Unsupported,
}

/// The kinds of fault an [`Error::Solver`] names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum SolverFault {
    /// Reflectance times form-factor row sum above the allowed contraction:
    /// light would grow without bound, or the system is too close to
    /// singular.
    Unbounded,
    /// A value that is not a number (or not finite) in the system or in an
    /// integrand.
    NotANumber,
    /// The iteration diverged: its residual or solution stopped being finite.
    Diverged,
    /// The iteration reached its sweep limit before its tolerance.
    NotConverged,
    /// A direct system that is singular.
    Singular,
    /// A state that should not occur, such as the kept shaped gather held
    /// elsewhere.
    Internal,
}

/// The library's result type.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// The glTF object a [`Error::Gltf`] names, if any.
    #[must_use]
    pub fn gltf_object(&self) -> Option<&GltfObject> {
        match self {
            Error::Gltf { object, .. } => object.as_ref(),
            _ => None,
        }
    }

    /// A glTF error without an object of its own takes `object` (the
    /// object being read when it arose); any other error is returned as it
    /// is.
    #[must_use]
    pub(crate) fn within(self, object: impl FnOnce() -> GltfObject) -> Self {
        match self {
            Error::Gltf {
                path,
                object: None,
                message,
            } => Error::Gltf {
                path,
                object: Some(object()),
                message,
            },
            other => other,
        }
    }

    /// An [`Error::Limit`] of `limit`.
    pub(crate) fn limit(limit: LimitKind, message: String) -> Self {
        Error::Limit { limit, message }
    }

    /// An [`Error::Geometry`] of `fault`.
    pub(crate) fn geometry(fault: GeometryFault, message: String) -> Self {
        Error::Geometry { fault, message }
    }

    /// An [`Error::Solver`] of `fault`.
    pub(crate) fn solver(fault: SolverFault, message: String) -> Self {
        Error::Solver { fault, message }
    }

    /// An I/O error for `path`.
    pub fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            error,
        }
    }
}
