#!/usr/bin/env bash
# Installs dependencies, builds hazmap (Release) and maps the embedded sample sequence
# data/sample with config/cadre_flight.yaml (the flight stack: 1 cm Kalman, 4, 16 and 64 cm
# CCM layers, the fused and footprint maps for the planner) into out/demo/ (replacing the
# previous demo's output: --overwrite, so the script can be run again), then writes
# out/demo/view.html.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/install_deps.sh"
"$root/tools/build.sh" Release
out="$root/out/demo"
# The sample's eight frames see about 1.5 m ahead: a 2.56 m planner window (the finer
# layers' extent, instead of the flight's 5.12 m) draws what was seen at 2 px per cell.
"$root/build/hazmap" run --config "$root/config/cadre_flight.yaml" --sequence "$root/data/sample" \
  --set hazard.fused_extent=2.56 --out "$out" --overwrite "$@"
"$root/build/hazmap" view "$out"
echo
echo "Wrote to $out:"
echo "  summary.json, run.log"
first="$(ls -d "$out"/frames/*/ | head -n 1)"
last="$(ls -d "$out"/frames/*/ | tail -n 1)"
echo "  frames/$(basename "$first")/ .. frames/$(basename "$last")/, each with:"
echo "    $(cd "$last" && ls | tr '\n' ' ')"
echo
echo "Look at the last frame's fused hazard map: ${last}fused_hazard.png"
echo "and where the rover's centre may go: ${last}footprint_hazard.png"
echo "(grey unknown, green traversable, red hazard; the white ring is the robot, its tick the heading)"
echo "or the whole run in a browser: $out/view.html"
