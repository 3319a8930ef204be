#!/usr/bin/env bash
# Regenerates the pictures of the ready-made worlds in docs/images/ (world_NAME.png) with
# tools/world_picture.lua and gnuplot (gnuplot-nox, pngcairo). Usage: tools/world_pictures.sh
# [BUILD_DIR] (default build/).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
gaitlab="${1:-$root/build}/gaitlab"
[ -x "$gaitlab" ] || { echo "world_pictures: no gaitlab at $gaitlab (build first)" >&2; exit 1; }
command -v gnuplot >/dev/null || { echo "world_pictures: gnuplot is not installed" >&2; exit 1; }
for world in "$root"/worlds/*.lua; do
    name=$(basename "$world" .lua)
    "$gaitlab" run "$root/tools/world_picture.lua" "$name" "$root/docs/images/world_$name.png"
done
