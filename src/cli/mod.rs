//! Command-line parsing and the subcommands.

mod args;
mod bake_cmd;
mod budget;
mod camera_arg;
mod checks;
mod compare_cmd;
mod converge_cmd;
mod cost_watch;
mod daylight_args;
mod diff_cmd;
mod group_args;
mod outputs;
mod peak_memory;
mod probe_cmd;
mod progress_bar;
mod progress_lines;
mod reference_cmd;
mod render_cmd;
mod setting_flags;
mod signals;
mod solve_cmd;
mod solver_flags;
mod stdout;
mod surface_table;
mod view_args;
mod view_cmd;
mod viewer;
mod views;

use anyhow::Result;
use clap::Parser;

pub use args::{Cli, Command};
pub use setting_flags::with_flags;

/// Parses the command line and runs the chosen subcommand.
pub fn run() -> Result<()> {
    signals::install()?;
    let cli = Cli::parse();
    // No subcommand: the default job, solving the built-in Cornell box.
    let command = match cli.command {
        Some(c) => c,
        None => Cli::parse_from(["radiosity", "solve", "cornell_box"])
            .command
            .expect("the default job parses"),
    };
    match command {
        Command::Solve(a) => solve_cmd::run(&a),
        Command::ExportScene(a) => solve_cmd::export_scene(&a),
        Command::Bake(a) => bake_cmd::run(&a),
        Command::Render(a) => render_cmd::run(&a),
        Command::View(a) => view_cmd::run(&a),
        Command::Diff(a) => diff_cmd::run(&a),
        Command::Reference(a) => reference_cmd::run(&a),
        Command::Compare(a) => compare_cmd::run(&a),
        Command::Probe(a) => probe_cmd::run(&a),
        Command::Converge(a) => converge_cmd::run(&a),
    }
}
