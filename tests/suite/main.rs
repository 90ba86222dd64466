//! The integration test suite, one binary with a module per theme (one link
//! step instead of many on a small machine).

mod adaptive;
mod atrium;
mod awkward_geometry;
mod bake;
mod clusters;
mod common;
mod converge;
mod determinism;
mod enclosures;
mod energy;
mod ferren;
mod hemicube;
mod hostile_cli;
mod hostile_files;
mod hostile_import;
mod hostile_outputs;
mod lights;
mod memory_limits;
mod messy_cli;
mod penumbra;
mod penumbra_failure;
mod penumbra_golden;
mod penumbra_metrics;
mod probe;
mod progressive;
mod random_scenes;
mod scale;
mod scale_scene;
mod skips;
mod stability;
mod stress_scenes;
mod substructuring;
mod textures;
