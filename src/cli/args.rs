//! The command-line interface.

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// Diffuse global illumination by the radiosity method: hemi-cube form factors,
/// substructuring with adaptive quadtree subdivision, Gauss-Seidel.
///
/// With no arguments, solves the built-in Cornell box and writes
/// out/cornell_box.png, .exr and .json.
#[derive(Parser, Debug)]
#[command(name = "radiosity", version, about, long_about)]
pub struct Cli {
    /// What to do (default: solve the built-in Cornell box into out/).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Solve a scene and write images and stats.
    Solve(Box<SolveArgs>),
    /// Write a built-in scene as a glTF file.
    ExportScene(ExportArgs),
}

/// `radiosity export-scene`.
#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Name of a built-in scene (e.g. cornell_box).
    pub name: String,
    /// Output file (.gltf or .glb).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `radiosity solve`.
#[derive(Args, Debug, Clone)]
pub struct SolveArgs {
    /// A glTF 2.0 file (.gltf or .glb), or the name of a built-in scene
    /// (cornell_box).
    pub scene: String,
    /// Folder for NAME.png, NAME.exr and NAME.json.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Hemi-cube resolution: pixels across the top face (even).
    #[arg(long = "hemicube-res", default_value_t = 128)]
    pub hemicube_res: usize,
    /// Largest patch edge in metres [default: the scene's diagonal / 12].
    #[arg(long = "patch-size")]
    pub patch_size: Option<f64>,
    /// Gauss-Seidel stops when its error bound is below this fraction of the
    /// largest radiosity.
    #[arg(long, default_value_t = 1e-5)]
    pub tolerance: f64,
    /// Most Gauss-Seidel sweeps before giving up.
    #[arg(long = "max-iterations", default_value_t = 100_000)]
    pub max_iterations: usize,
    /// Over-relaxation factor for Gauss-Seidel (1 = plain; try 1.5 when
    /// reflectances are close to 1).
    #[arg(long, default_value_t = 1.0)]
    pub relaxation: f64,
    /// Solver: gauss-seidel (gathering) or progressive (shooting, with
    /// previews).
    #[arg(long, default_value = "gauss-seidel")]
    pub solver: String,
    /// Progressive: stop when the unshot power is below this fraction of the
    /// emitted power.
    #[arg(long = "unshot-tolerance", default_value_t = 1e-4)]
    pub unshot_tolerance: f64,
    /// Progressive: stop after this many shots.
    #[arg(long = "max-shots")]
    pub max_shots: Option<usize>,
    /// Progressive: stop after this many seconds of solving.
    #[arg(long = "time-budget")]
    pub time_budget: Option<f64>,
    /// Progressive: each shot renders 4^N hemi-cubes from cells N levels below
    /// the shooting patch.
    #[arg(long = "shooter-depth", default_value_t = 1)]
    pub shooter_depth: u8,
    /// Progressive: write NAME_preview_SHOTS.png (with the ambient term) every
    /// N shots.
    #[arg(long = "preview-every")]
    pub preview_every: Option<usize>,
    /// Split elements whose radiosity differs from a neighbour's by more than
    /// this fraction of the brightest reflected radiosity.
    #[arg(long = "refine-tolerance", default_value_t = 0.02)]
    pub refine_tolerance: f64,
    /// Deepest element level below a patch.
    #[arg(long = "max-depth", default_value_t = 5)]
    pub max_depth: u8,
    /// Depth every patch is split to before the first solve.
    #[arg(long = "initial-depth", default_value_t = 1)]
    pub initial_depth: u8,
    /// Smallest element area in square metres [default: (diagonal / 1000)^2].
    #[arg(long = "min-element-area")]
    pub min_element_area: Option<f64>,
    /// Most leaf elements.
    #[arg(long = "max-elements", default_value_t = 200_000)]
    pub max_elements: usize,
    /// Subdivide every patch uniformly to this depth instead of adapting.
    #[arg(long = "uniform-depth")]
    pub uniform_depth: Option<u8>,
    /// Seed of the hemi-cube rotations (same seed, same bits).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads [default: all cores].
    #[arg(long)]
    pub threads: Option<usize>,
    /// A view: EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z,FOV_DEGREES (vertical
    /// field of view). Repeat for several views of one solution. Default: the
    /// scene's first camera, else a view that frames the scene.
    #[arg(long, allow_hyphen_values = true)]
    pub camera: Vec<String>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 512)]
    pub height: u32,
    /// Exposure of the PNG in stops [default: automatic].
    #[arg(long, allow_hyphen_values = true)]
    pub exposure: Option<f64>,
    /// Tone map of the PNG: clamp, reinhard or aces.
    #[arg(long, default_value = "aces")]
    pub tonemap: String,
    /// Also draw the element mesh over the image into this PNG.
    #[arg(long = "mesh-out")]
    pub mesh_out: Option<PathBuf>,
    /// Print no progress bars.
    #[arg(long)]
    pub quiet: bool,
}
