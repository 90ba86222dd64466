#!/usr/bin/env bash
# Regenerates the Ferren sculpture figures and numbers of
# papers/greenberg-cohen-torrance-1986.md: two solves of the built-in scene at
# default settings (direct light only, and the full solution rendered from two
# views), the images copied to papers/images/, and the white fronts'
# chromaticity from each solve's stats JSON. Needs jq.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/ferren}
cargo build --release --quiet
bin=target/release/radiosity

# The scene's own camera, then a view from the left that sees the coloured
# backs and the window. The direct-only image is exposed 2 stops brighter
# (see the paper).
own=2.3,1.7,3.0,1.1,0.5,0.6,45
left=0.25,0.95,2.3,1.3,0.55,0.75,45
size=(--width 512 --height 384)
"$bin" solve ferren_sculpture --direct-only --out "$out/direct" "${size[@]}" \
    --camera "$own" --exposure=0 --quiet
"$bin" solve ferren_sculpture --out "$out/full" "${size[@]}" \
    --camera "$own" --camera "$left" --exposure=-2 --quiet

mkdir -p papers/images
cp "$out/direct/ferren_sculpture.png" papers/images/ferren_direct.png
cp "$out/full/ferren_sculpture.png" papers/images/ferren_full.png
cp "$out/full/ferren_sculpture_view2.png" papers/images/ferren_full_left.png

# Per solve: patches, elements, seconds; the chromaticity (r, g) = (R, G) /
# (R + G + B) of the area-weighted mean radiosity of all 27 fronts and its
# distance from the neutral point (1/3, 1/3); the area-weighted mean of each
# front's own distance from it; and the mean front radiosity (bands averaged).
for mode in direct full; do
    jq -r --arg mode "$mode" '
        def chroma: (add) as $s | [.[0] / $s, .[1] / $s];
        def dist: ((.[0] - 1/3) * (.[0] - 1/3) + (.[1] - 1/3) * (.[1] - 1/3)) | sqrt;
        [.surfaces[] | select(.name | endswith("_front"))] as $f
        | ($f | map(.area) | add) as $a
        | [range(3) as $k | ($f | map(.area * .radiosity[$k]) | add) / $a] as $mean
        | ($mean | chroma) as $c
        | ($f | map(.area * (.radiosity | chroma | dist)) | add / $a) as $each
        | "\($mode): \(.counts.patches) patches, \(.counts.elements) elements, "
          + "\(.seconds.total * 100 | round / 100) s; fronts: mean radiosity "
          + "\(($mean | add / 3) * 1000 | round / 1000), chromaticity of the mean "
          + "(\($c[0] * 10000 | round / 10000), \($c[1] * 10000 | round / 10000)), "
          + "\($c | dist * 10000 | round / 10000) from neutral; "
          + "mean distance of each front \($each * 10000 | round / 10000)"
    ' "$out/$mode/ferren_sculpture.json"
done
