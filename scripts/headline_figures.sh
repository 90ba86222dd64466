#!/usr/bin/env sh
# Re-measures the figures of the README's "Accuracy and speed" table: the
# built-in Cornell box at default settings and with the progressive solver,
# against the path-traced reference in scenes/. Prints the counts, the
# per-surface errors and (when farm-bench is on the PATH) the whole-process
# times, median of 5. Writes only under target/headline/.
set -eu
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=target/release/radiosity
out=target/headline
mkdir -p "$out"
echo "commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown), $(date -u +%Y-%m-%d)"
for solver in gauss-seidel progressive; do
    "$bin" solve cornell_box --solver "$solver" --out "$out/$solver" --quiet
    python3 - "$out/$solver/cornell_box.json" "$solver" <<'PY'
import json, sys
stats = json.load(open(sys.argv[1]))
c, h = stats["counts"], stats["hemicube"]
print(f"{sys.argv[2]}: {c['patches']} patches, {c['elements']} elements, "
      f"{h['hemicubes']} hemi-cubes of {h['resolution']} x {h['resolution']}")
PY
    "$bin" compare "$out/$solver/cornell_box.json" scenes/cornell_box.reference.json | tail -1
    if command -v farm-bench >/dev/null 2>&1; then
        farm-bench -n 5 -- "$bin" solve cornell_box --solver "$solver" \
            --out "$out/$solver-timed" --quiet | grep -E "cpu s|wall s|peak MiB"
    else
        echo "(no farm-bench on the PATH: time the solve with a tool of your own)"
    fi
done
