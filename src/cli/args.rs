//! The command-line interface.

use super::bake_cmd::BakeArgs;
use super::diff_cmd::DiffArgs;
use super::render_cmd::RenderArgs;
use super::view_args::ViewArgs;
use super::view_cmd::ViewArgs as ViewCommandArgs;
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
    /// Solve a scene and write the refined mesh as glTF that any viewer shows
    /// as `render` does (COLOR_0), each light group kept apart, to view
    /// anywhere, relight with `view` or render again with `render`.
    Bake(Box<BakeArgs>),
    /// Render more views of a baked solution (from `bake`) without solving.
    Render(Box<RenderArgs>),
    /// Serve a baked solution on 127.0.0.1 with a page to walk through it and
    /// relight its light groups in a browser; prints the address.
    View(ViewCommandArgs),
    /// Compare two EXR or HDR images: difference image, MAE, RMSE, relative RMSE.
    Diff(DiffArgs),
    /// Path-traced ground truth: the mean radiosity of every object, with
    /// standard errors (independent of the hemi-cube and the solver).
    Reference(ReferenceArgs),
    /// Compare the per-surface radiosities of a solve's stats JSON with a
    /// reference JSON (from `radiosity reference`): relative error per surface
    /// and band, their mean and maximum.
    Compare(CompareArgs),
    /// Solve a scene and write the radiosity at given points as CSV.
    Probe(Box<ProbeArgs>),
    /// Run time against error: sweep subdivision depths, adaptive tolerances,
    /// hemi-cube resolutions and progressive stopping points, measure each solve against a reference at
    /// fixed points, and write CSV, Markdown and plots (SVG and PNG).
    Converge(Box<ConvergeArgs>),
}

/// `radiosity converge`.
#[derive(Args, Debug, Clone)]
pub struct ConvergeArgs {
    /// Built-in scene names or glTF files; each gets its own report.
    #[arg(required = true)]
    pub scenes: Vec<String>,
    /// Folder for SCENE.csv, SCENE.md, SCENE_error_time.svg/.png and
    /// SCENE_error_depth.svg/.png (and SCENE_objects.csv with --objects).
    #[arg(long, default_value = "out/converge")]
    pub out: PathBuf,
    /// Which sweeps to run: uniform, adaptive, hemicube, patches, progressive.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "uniform,adaptive,hemicube,progressive"
    )]
    pub methods: Vec<String>,
    /// Uniform subdivision depths (method uniform).
    #[arg(long, value_delimiter = ',', default_value = "0,1,2,3")]
    pub depths: Vec<u8>,
    /// Adaptive refinement tolerances (method adaptive).
    #[arg(long, value_delimiter = ',', default_value = "0.2,0.1,0.05,0.025")]
    pub tolerances: Vec<f64>,
    /// Hemi-cube resolutions, at the other base settings (method hemicube).
    #[arg(long, value_delimiter = ',', default_value = "32,64,128,256")]
    pub resolutions: Vec<usize>,
    /// Divisors of the base patch size for uniformly small patches with no
    /// elements below them (method patches).
    #[arg(
        long = "patch-divisions",
        value_delimiter = ',',
        default_value = "1,2,3"
    )]
    pub patch_divisions: Vec<u32>,
    /// Unshot-power fractions at which the progressive solver stops, one run
    /// each, at the base mesh settings (method progressive).
    #[arg(
        long = "unshot-fractions",
        value_delimiter = ',',
        default_value = "0.3,0.1,0.03,0.01,0.001"
    )]
    pub unshot_fractions: Vec<f64>,
    /// Reference points (on the floor for the exact oracle of a built-in
    /// penumbra scene, else spread over all surfaces for Monte Carlo).
    #[arg(long, default_value_t = 256)]
    pub points: usize,
    /// Monte Carlo paths per reference point.
    #[arg(long, default_value_t = 100_000)]
    pub paths: u64,
    /// Seed of the Monte Carlo points and paths.
    #[arg(long = "reference-seed", default_value_t = 1)]
    pub reference_seed: u64,
    /// Use the Monte Carlo reference even where an exact oracle exists.
    #[arg(long = "monte-carlo")]
    pub monte_carlo: bool,
    /// Also measure per-object mean radiosity errors against path-traced
    /// object means.
    #[arg(long)]
    pub objects: bool,
    /// Paths per object for --objects.
    #[arg(long = "object-paths", default_value_t = 1_000_000)]
    pub object_paths: u64,
    /// Solve each run this many times and keep the shortest time.
    #[arg(long, default_value_t = 1)]
    pub repeats: usize,
    /// Base solve settings, which every run starts from.
    #[command(flatten)]
    pub settings: SolveSettingsArgs,
    /// Print no progress.
    #[arg(long)]
    pub quiet: bool,
}

/// `radiosity compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Stats JSON written by `radiosity solve`.
    pub solution: PathBuf,
    /// Reference JSON written by `radiosity reference`.
    pub reference: PathBuf,
}

/// `radiosity reference`.
#[derive(Args, Debug)]
pub struct ReferenceArgs {
    /// A glTF file or the name of a built-in scene.
    pub scene: String,
    /// Paths per object (each from an independent uniform point on it).
    #[arg(long, default_value_t = 1_000_000)]
    pub paths: u64,
    /// Seed of the path sampling.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads [default: all cores].
    #[arg(long)]
    pub threads: Option<usize>,
    /// How the scene is loaded.
    #[command(flatten)]
    pub load: LoadArgs,
    /// Report the cells of a grid this many metres wide instead of the
    /// scene's objects (each surface in the cell of its centroid), as
    /// `solve --regions` does, so that a one-mesh model can be compared
    /// region by region.
    #[arg(long, value_name = "METRES")]
    pub regions: Option<f64>,
    /// Output JSON file [default: standard output].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// How a scene is loaded: the repairs made to what real files get wrong.
#[derive(Args, Debug, Clone)]
pub struct LoadArgs {
    /// Coplanar surfaces that overlap facing the same way (decals, layered
    /// logos, a light flush with its ceiling, duplicates): resolve (the
    /// smaller object's surface covers its footprint, which is cut out of the
    /// one below; duplicates count once) or error (refuse the scene, naming
    /// the pairs).
    #[arg(long, default_value = "resolve", value_parser = ["resolve", "error"])]
    pub overlaps: String,
    /// Largest reflectance kept from a glTF file: bands above it (a
    /// pure-white baseColorFactor) are clamped to it, with a warning; at most
    /// 0.99999.
    #[arg(long = "max-reflectance", default_value_t = radiosity::gltf_io::DEFAULT_MAX_REFLECTANCE)]
    pub max_reflectance: f64,
    /// Treat every surface as two-sided (faces wound the wrong way then
    /// still reflect light).
    #[arg(long = "double-sided")]
    pub double_sided: bool,
    /// Light the scene with a sky above it (world +Y up; nothing from below
    /// the horizon): uniform (the same radiance everywhere) or overcast (the
    /// CIE standard overcast sky, three times brighter at the zenith than
    /// at the horizon). It replaces a sky the scene has; its light passes
    /// the scene's openings, with the scene's own lights.
    #[arg(long, value_parser = ["uniform", "overcast"])]
    pub sky: Option<String>,
    /// The sky's brightness as the illuminance, in lux, of an unobstructed
    /// horizontal surface [default: 10000, an overcast day].
    #[arg(
        long = "sky-illuminance",
        value_name = "LUX",
        requires = "sky",
        conflicts_with = "sky_luminance"
    )]
    pub sky_illuminance: Option<f64>,
    /// The sky's brightness as its luminance at the zenith, in cd/m².
    #[arg(long = "sky-luminance", value_name = "CD_PER_M2", requires = "sky")]
    pub sky_luminance: Option<f64>,
    /// Add a sun: AZIMUTH,ELEVATION,LUX, degrees clockwise from north (-Z)
    /// towards east (+X), degrees above the horizon, and the illuminance of
    /// a surface facing it, in lux (a clear day's sun gives about 100 000).
    #[arg(long, value_name = "AZIMUTH,ELEVATION,LUX")]
    pub sun: Option<String>,
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
    /// (cornell_box, ferren_sculpture, many_boxes, the penumbra_* scenes, atrium,
    /// or atrium_N for an atrium of about N triangles, e.g. atrium_200k; an
    /// unknown name lists them all).
    pub scene: String,
    /// Folder for NAME.png, NAME.exr and NAME.json (and NAME.hdr, NAME_false.png
    /// when asked for).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Solve settings, shared with `probe`.
    #[command(flatten)]
    pub settings: SolveSettingsArgs,
    /// Cameras and images.
    #[command(flatten)]
    pub view: ViewArgs,
    /// Also draw the element mesh over the image into this PNG.
    #[arg(long = "mesh-out")]
    pub mesh_out: Option<PathBuf>,
    /// List in the stats JSON's `surfaces` the cells of a grid this many
    /// metres wide instead of the scene's objects (each surface in the cell
    /// of its centroid), for comparison with `reference --regions`.
    #[arg(long, value_name = "METRES")]
    pub regions: Option<f64>,
    /// Print no progress (bars on a terminal, plain lines every few seconds
    /// otherwise).
    #[arg(long)]
    pub quiet: bool,
}

/// The settings of a solve, shared by `solve` and `probe`.
#[derive(Args, Debug, Clone)]
pub struct SolveSettingsArgs {
    /// How the scene is loaded.
    #[command(flatten)]
    pub load: LoadArgs,
    /// Hemi-cube resolution: pixels across the top face (even).
    #[arg(long = "hemicube-res", default_value_t = 64)]
    pub hemicube_res: usize,
    /// Visibility of light sources: exact and averaged over points of each
    /// element where a few occluders hide part of a light from some of
    /// them, at the centre where nothing does or many small ones do
    /// (shadowed, the default); exact at each element's centre (centre:
    /// about 0.93x the time, but a shadow edge across a large element can
    /// then take much of its light, or none); or averaged over the points
    /// everywhere (element).
    #[arg(long = "emitter-samples", default_value = "shadowed", value_parser = ["shadowed", "centre", "element"])]
    pub emitter_samples: String,
    /// Largest patch edge in metres [default: the scene's size / 10: its diagonal, less far outliers holding little area].
    #[arg(long = "patch-size")]
    pub patch_size: Option<f64>,
    /// Gauss-Seidel stops when its error bound is below this fraction of the
    /// largest radiosity.
    #[arg(long, default_value_t = 1e-5)]
    pub tolerance: f64,
    /// Solver: gauss-seidel (gathering) or progressive (shooting, with
    /// previews).
    #[arg(long, default_value = "gauss-seidel")]
    pub solver: String,
    /// Progressive: stop when the unshot power is below this fraction of the
    /// emitted power [default: 1e-4].
    #[arg(long = "unshot-tolerance")]
    pub unshot_tolerance: Option<f64>,
    /// Progressive: stop after this many shots.
    #[arg(long = "max-shots")]
    pub max_shots: Option<usize>,
    /// Progressive: stop after this many seconds of solving.
    #[arg(long = "time-budget")]
    pub time_budget: Option<f64>,
    /// Progressive: write NAME_preview_SHOTS.png (with the ambient term) every
    /// N shots.
    #[arg(long = "preview-every")]
    pub preview_every: Option<usize>,
    /// Split elements whose radiosity differs from a neighbour's by more than
    /// this fraction of the brightest reflected radiosity (see --dim-floor;
    /// adaptive refinement only) [default: 0.05].
    #[arg(long = "refine-tolerance")]
    pub refine_tolerance: Option<f64>,
    /// Measure neighbour differences against the brighter neighbour's
    /// reflected radiosity, but at least this fraction of the scene's
    /// brightest: 1 measures all against the brightest; 0.1 also refines the
    /// contact shadows of dim corridors, for about twice the time on an
    /// interior lit through an opening and several times more in a room lit
    /// from inside (adaptive refinement only) [default: 1].
    #[arg(long = "dim-floor")]
    pub dim_floor: Option<f64>,
    /// The same as --dim-floor, for elements that see surfaces nearer than
    /// their own size over much of their view (the floor under a bench, the
    /// inside of a corner), where the light changes across them: 0.1 refines
    /// the contact shadows of dim regions without refining every dim surface
    /// (on an interior lit through an opening, a third less error for about
    /// 1.1x the time; in a room lit from inside about 1.3x the time;
    /// adaptive refinement only) [default: 1].
    #[arg(long = "near-floor")]
    pub near_floor: Option<f64>,
    /// Deepest element level below a patch (adaptive refinement only)
    /// [default: 4].
    #[arg(long = "max-depth")]
    pub max_depth: Option<u8>,
    /// Depth every patch is split to before the first solve (adaptive
    /// refinement only) [default: 1].
    #[arg(long = "initial-depth")]
    pub initial_depth: Option<u8>,
    /// Smallest element area in square metres [default: (the scene's size / 1000)^2].
    #[arg(long = "min-element-area")]
    pub min_element_area: Option<f64>,
    /// Most leaf elements [default: as many as --max-memory holds].
    #[arg(long = "max-elements")]
    pub max_elements: Option<usize>,
    /// Most patches [default: as many as --max-memory holds].
    #[arg(long = "max-patches")]
    pub max_patches: Option<usize>,
    /// Memory the solve may hold, in GB: a scene whose estimate does not fit is
    /// refused before any form factor, and refinement stops adding elements
    /// when the rows would not fit [default: three quarters of the machine's
    /// memory].
    #[arg(long = "max-memory")]
    pub max_memory: Option<f64>,
    /// Split a source patch whose elements spread by more than this fraction of
    /// the brightest reflected radiosity (its children become patches; gauss-seidel
    /// only); 0 never splits sources. Try 0.1 where sources are close to what
    /// they light.
    #[arg(long = "source-tolerance", default_value_t = 0.0)]
    pub source_tolerance: f64,
    /// Final gathers in which each element sees an unevenly lit patch close
    /// by as its parts (its elements) rather than its mean, e.g. a bench the
    /// floor in its own shadow; 0 gathers patch means, as plain
    /// substructuring does. The progressive solver makes them once it has
    /// converged (not when --max-shots or --time-budget stops it). Try 2 in
    /// cluttered scenes [default: 1; 0 with --bounces, or with an
    /// --unshot-tolerance above 1e-4, which asks for an early answer]
    #[arg(long = "shaped-gathers", value_name = "N")]
    pub shaped_gathers: Option<usize>,
    /// Subdivide every patch uniformly to this depth instead of adapting
    /// (the adaptive refinement's options are then refused).
    #[arg(long = "uniform-depth")]
    pub uniform_depth: Option<u8>,
    /// Keep emitted light and exactly N reflections instead of the full
    /// solution (1 = direct light only; gauss-seidel solver only).
    #[arg(long, value_name = "N")]
    pub bounces: Option<u32>,
    /// Direct light only, as a ray tracer with point lights and no ambient
    /// term sees diffuse surfaces: the same as --bounces 1.
    #[arg(long = "direct-only", conflicts_with = "bounces")]
    pub direct_only: bool,
    /// Seed of the hemi-cube rotations (same seed, same bits).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads [default: all cores].
    #[arg(long)]
    pub threads: Option<usize>,
}

/// `radiosity probe`.
#[derive(Args, Debug, Clone)]
pub struct ProbeArgs {
    /// A glTF 2.0 file (.gltf or .glb), or the name of a built-in scene.
    pub scene: String,
    /// CSV of probe points, one per line: x,y,z,nx,ny,nz (the point and the
    /// front normal of the surface it lies on). A header row is optional.
    #[arg(long)]
    pub points: PathBuf,
    /// Output CSV [default: standard output].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also write the exact direct radiosity (the built-in penumbra scenes
    /// only; empty for points off their floor).
    #[arg(long)]
    pub exact: bool,
    /// Largest distance of a point from a surface's plane, as a fraction of
    /// the scene's bounding-box diagonal.
    #[arg(long = "plane-tolerance", default_value_t = 1e-4)]
    pub plane_tolerance: f64,
    /// Largest angle between a point's normal and the surface's, in degrees.
    #[arg(long = "normal-tolerance", default_value_t = 5.0)]
    pub normal_tolerance: f64,
    /// Solve settings, as for `solve`.
    #[command(flatten)]
    pub settings: SolveSettingsArgs,
    /// Print no progress (bars on a terminal, plain lines every few seconds
    /// otherwise).
    #[arg(long)]
    pub quiet: bool,
}
