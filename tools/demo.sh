#!/usr/bin/env bash
# Installs dependencies, builds hazmap (Release) and maps the embedded sample sequence
# data/sample with config/default.yaml into out/demo/ (replacing the previous demo's
# output: --overwrite, so the script can be run again), then writes out/demo/view.html.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/install_deps.sh"
"$root/tools/build.sh" Release
out="$root/out/demo"
"$root/build/hazmap" run --config "$root/config/default.yaml" --sequence "$root/data/sample" \
  --out "$out" --overwrite "$@"
"$root/build/hazmap" view "$out"
echo
echo "Wrote to $out:"
echo "  summary.json, run.log"
for frame in "$out"/frames/*/; do
  echo "  frames/$(basename "$frame")/: $(cd "$frame" && ls | tr '\n' ' ')"
done
last="$(ls -d "$out"/frames/*/ | tail -n 1)"
echo
echo "Look at the last frame's hazard map: ${last}L0_hazard.png"
echo "(grey unknown, green traversable, red hazard; the white ring is the robot, its tick the heading)"
echo "or the whole run in a browser: $out/view.html"
