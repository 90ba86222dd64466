#!/bin/sh
# Regenerates every figure and table of papers/substructuring.md: run time
# against error on the Cornell box (Monte Carlo reference points) and on the
# parallel penumbra (exact oracle), written to papers/images/ as SCENE.csv,
# SCENE.md, SCENE_error_time.{svg,png} and SCENE_error_depth.{svg,png}, and the
# commit, machine and wall time of the run to papers/images/substructuring_run.txt.
#
# Usage, from anywhere in the repository:  sh papers/substructuring.sh
set -eu
cd "$(dirname "$0")/.."
out=papers/images
mkdir -p "$out"
cargo build --release --quiet
# The commit measured, and whether the code differs from it (outputs aside).
commit=$(git rev-parse HEAD 2>/dev/null || echo unknown)
modified=$(git status --porcelain --untracked-files=no -- . ':!papers' 2>/dev/null || true)
started=$(date +%s)

# Cornell box: default settings (adaptive max depth 4, the finest uniform depth).
./target/release/radiosity converge cornell_box --out "$out" \
    --methods uniform,adaptive,patches,progressive \
    --depths 0,1,2,3,4 \
    --tolerances 0.2,0.1,0.05,0.025,0.0125,0.00625 \
    --patch-divisions 1,2,3,4 \
    --unshot-fractions 0.9,0.5,0.3,0.1,0.03,0.01,0.001 \
    --points 256 --paths 100000

# Parallel penumbra: uniform meshes to depth 5, so adaptive may go one deeper.
./target/release/radiosity converge penumbra_parallel --out "$out" \
    --methods uniform,adaptive,patches,progressive \
    --max-depth 6 \
    --depths 0,1,2,3,4,5 \
    --tolerances 0.2,0.1,0.05,0.025,0.0125,0.00625 \
    --patch-divisions 1,2,4,8 \
    --unshot-fractions 0.9,0.5,0.3,0.1,0.03,0.01,0.001 \
    --points 256

finished=$(date +%s)
{
    echo "commit: $commit"
    if [ -n "$modified" ]; then
        echo "working tree: modified (not the commit's code)"
    fi
    echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "machine: $(uname -sm), $(nproc) cores"
    grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/^model name[[:space:]]*: /cpu: /' || true
    echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)"
    echo "sweep wall seconds (both scenes, after the build): $((finished - started))"
} >"$out/substructuring_run.txt"
cat "$out/substructuring_run.txt"
