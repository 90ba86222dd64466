#!/usr/bin/env sh
# Rewrites papers/cli-reference.md from the binary's --help (every
# subcommand). The suite's cli_reference test holds the committed file to
# the binary and fails when it is stale; this runs that test in its
# writing mode.
set -eu
cd "$(dirname "$0")/.."
RADIOSITY_UPDATE_CLI_REFERENCE=1 cargo test --release --test suite \
    cli_reference::the_committed_cli_reference_matches_the_binarys_help -- --exact
echo "wrote papers/cli-reference.md"
