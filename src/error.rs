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
    #[error("geometry: {0}")]
    Geometry(String),
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
    #[error("{0}")]
    NoLight(String),
    /// A setting is out of its range.
    #[error("setting {name}: {message}")]
    Setting {
        /// The setting's name as the CLI spells it.
        name: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A configured limit (triangles, elements, memory) was reached.
    #[error("limit reached: {0}")]
    Limit(String),
    /// The solver could not converge, or met a numerically unusable system.
    #[error("solver: {0}")]
    Solver(String),
    /// An output could not be encoded.
    #[error("output {path}: {message}")]
    Output {
        /// The file being written.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}

/// The library's result type.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// An I/O error for `path`.
    pub fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            error,
        }
    }
}
