//! Options a solve would not honour are refused, naming the option, rather
//! than ignored with exit 0: the progressive solver's stopping rules and
//! previews given to Gauss-Seidel, and the adaptive refinement's options
//! given with a uniform mesh.

use super::args::SolveSettingsArgs;
use anyhow::{bail, Result};
use radiosity::pipeline::SolverKind;

/// The options of `a` that only the progressive solver reads, by flag, and
/// whether each was given.
fn progressive_only(a: &SolveSettingsArgs) -> [(&'static str, bool); 4] {
    [
        ("--unshot-tolerance", a.unshot_tolerance.is_some()),
        ("--max-shots", a.max_shots.is_some()),
        ("--time-budget", a.time_budget.is_some()),
        ("--preview-every", a.preview_every.is_some()),
    ]
}

/// The options of `a` that only adaptive refinement reads, by flag, and
/// whether each was given (source splitting is off at 0, its default).
fn adaptive_only(a: &SolveSettingsArgs) -> [(&'static str, bool); 6] {
    [
        ("--refine-tolerance", a.refine_tolerance.is_some()),
        ("--dim-floor", a.dim_floor.is_some()),
        ("--near-floor", a.near_floor.is_some()),
        ("--max-depth", a.max_depth.is_some()),
        ("--initial-depth", a.initial_depth.is_some()),
        ("--source-tolerance", a.source_tolerance > 0.0),
    ]
}

/// Refuses the first option of `a` that a solve by `solver` (and, with
/// `--uniform-depth`, on a uniform mesh) would leave unread.
pub fn refuse_unread(a: &SolveSettingsArgs, solver: SolverKind) -> Result<()> {
    if solver != SolverKind::Progressive {
        if let Some((flag, _)) = progressive_only(a).into_iter().find(|(_, given)| *given) {
            bail!(
                "{flag} applies to the progressive solver only (--solver progressive); \
                 Gauss-Seidel, the default, would ignore it"
            );
        }
    }
    if let Some(depth) = a.uniform_depth {
        if let Some((flag, _)) = adaptive_only(a).into_iter().find(|(_, given)| *given) {
            bail!(
                "{flag} applies to adaptive refinement only; with --uniform-depth {depth} \
                 every patch is split to that depth and nothing is refined"
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::args::{Cli, Command};
    use super::super::solve_cmd::settings;
    use clap::Parser;
    use radiosity::pipeline::ProgressiveSettings;
    use radiosity::refine::RefineSettings;

    fn solve_args(extra: &[&str]) -> super::SolveSettingsArgs {
        let mut argv = vec!["radiosity", "solve", "cornell_box"];
        argv.extend(extra);
        match Cli::try_parse_from(argv).unwrap().command {
            Some(Command::Solve(a)) => a.settings,
            other => panic!("not a solve: {other:?}"),
        }
    }

    #[test]
    fn options_left_out_take_the_librarys_defaults() {
        let s = settings(&solve_args(&[])).unwrap();
        let (refine, progressive) = (RefineSettings::default(), ProgressiveSettings::default());
        assert_eq!(s.refine.tolerance, refine.tolerance);
        assert_eq!(s.refine.dim_floor, refine.dim_floor);
        assert_eq!(s.refine.near_floor, refine.near_floor);
        assert_eq!(s.refine.max_depth, refine.max_depth);
        assert_eq!(s.refine.initial_depth, refine.initial_depth);
        assert_eq!(s.progressive.tolerance, progressive.tolerance);
        let p = settings(&solve_args(&["--solver", "progressive"])).unwrap();
        assert_eq!(p.progressive.tolerance, progressive.tolerance);
    }

    #[test]
    fn progressive_options_given_to_gauss_seidel_are_refused_by_flag() {
        for (flag, value) in [
            ("--unshot-tolerance", "0.01"),
            ("--max-shots", "10"),
            ("--time-budget", "5"),
            ("--preview-every", "3"),
        ] {
            let message = settings(&solve_args(&[flag, value]))
                .unwrap_err()
                .to_string();
            assert!(message.starts_with(flag), "{flag}: {message}");
            let progressive = settings(&solve_args(&["--solver", "progressive", flag, value]));
            assert!(progressive.is_ok(), "{flag}: {progressive:?}");
        }
    }

    #[test]
    fn adaptive_options_given_with_a_uniform_mesh_are_refused_by_flag() {
        for (flag, value) in [
            ("--refine-tolerance", "0.1"),
            ("--dim-floor", "0.1"),
            ("--near-floor", "0.1"),
            ("--max-depth", "3"),
            ("--initial-depth", "0"),
            ("--source-tolerance", "0.1"),
        ] {
            let uniform = settings(&solve_args(&["--uniform-depth", "2", flag, value]));
            let message = uniform.unwrap_err().to_string();
            assert!(message.starts_with(flag), "{flag}: {message}");
            assert!(message.contains("--uniform-depth 2"), "{message}");
            let adaptive = settings(&solve_args(&[flag, value]));
            assert!(adaptive.is_ok(), "{flag}: {adaptive:?}");
        }
        // A source tolerance of 0 (its default: no splitting) asks nothing.
        assert!(settings(&solve_args(&[
            "--uniform-depth",
            "2",
            "--source-tolerance",
            "0"
        ]))
        .is_ok());
    }
}
