//! `papers/cli-reference.md` is the `--help` of every subcommand, as the
//! binary prints it. `--help` stays the source of truth: this test builds the
//! reference from the binary and fails when the committed file differs.
//! `scripts/cli_reference.sh` rewrites the file (it runs this test with
//! `RADIOSITY_UPDATE_CLI_REFERENCE=1`).

use super::cli_run::radiosity;
use std::path::Path;

/// The environment variable that makes the test write the reference.
const UPDATE_VAR: &str = "RADIOSITY_UPDATE_CLI_REFERENCE";

/// Where the reference lives, from the crate's root.
const REFERENCE: &str = "papers/cli-reference.md";

/// What `radiosity ARGS` prints on standard output, which must succeed.
fn help(args: &[&str]) -> String {
    let out = radiosity(args);
    assert!(out.status.success(), "radiosity {args:?} failed");
    String::from_utf8(out.stdout).expect("help is UTF-8")
}

/// The subcommands the top-level help lists (its `Commands:` section), but
/// clap's own `help`.
fn subcommands(top: &str) -> Vec<String> {
    top.lines()
        .skip_while(|l| l.trim() != "Commands:")
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect()
}

/// The whole reference: the top-level help, then each subcommand's.
fn reference() -> String {
    let top = help(&["--help"]);
    let mut text = String::from(
        "# Command-line reference\n\n\
         Generated from `radiosity --help` and `radiosity <command> --help` by\n\
         `scripts/cli_reference.sh`; a test (`cargo test --release --test suite\n\
         cli_reference`) fails when this file no longer matches the binary.\n",
    );
    let section =
        |title: &str, body: &str| format!("\n## {title}\n\n```text\n{}\n```\n", body.trim_end());
    text += &section("radiosity", &top);
    for name in subcommands(&top) {
        text += &section(&format!("radiosity {name}"), &help(&[&name, "--help"]));
    }
    text
}

#[test]
fn the_top_level_help_lists_every_subcommand_the_cli_runs() {
    // Checked against names written here, so that a parsing slip in
    // `subcommands` cannot leave commands out of the reference unseen.
    let names = subcommands(&help(&["--help"]));
    for expected in [
        "solve",
        "export-scene",
        "bake",
        "render",
        "view",
        "diff",
        "reference",
        "compare",
        "probe",
        "converge",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "{expected} missing from {names:?}"
        );
    }
}

#[test]
fn the_committed_cli_reference_matches_the_binarys_help() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(REFERENCE);
    let expected = reference();
    if std::env::var_os(UPDATE_VAR).is_some() {
        std::fs::write(&path, &expected).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == expected,
        "{REFERENCE} is stale: run scripts/cli_reference.sh and commit the result"
    );
}
