#!/usr/bin/env bash
# POLAR Traverse against hazmap simulate (issue 33; docs/simulator.md "Against POLAR
# Traverse"): renders the POLAR-like scene, makes a half-scale copy of the real pair,
# prints image statistics and BM / SGBM valid shares (hazmap check) for both, and writes
# the side-by-side pictures.
#
#   tools/polar_compare/polar_compare.sh OUT [SCALE]     (SCALE 0.5 by default; 1 = 2048 px)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:?usage: polar_compare.sh OUT [SCALE]}"
scale="${2:-0.5}"
hazmap="${HAZMAP:-$repo/build/hazmap}"
real="$repo/../shared/data/planetary_analog/polar_traverse_1m/seq"
mkdir -p "$out"
stats="$out/image_stats"
g++ -O2 -std=c++17 "$repo/tools/polar_compare/image_stats.cpp" -o "$stats" \
  $(pkg-config --cflags opencv4) -lopencv_core -lopencv_imgproc -lopencv_imgcodecs

# The real pair at SCALE: images by area averaging, K scaled about pixel centres.
rs="$out/real"
rm -rf "$rs" && mkdir -p "$rs/left" "$rs/right"
for side in left right; do "$stats" resize "$real/$side/000000.png" "$rs/$side/000000.png" "$scale"; done
cp "$real/poses.txt" "$rs/"
awk -v s="$scale" '
  /image_(width|height)/ { printf "%s %d\n", $1, $2 * s; next }
  /K: \[/ {
    match($0, /K: \[[^]]*\]/); k = substr($0, RSTART + 4, RLENGTH - 5); split(k, a, ", ");
    a[1] *= s; a[5] *= s; a[3] = (a[3] + 0.5) * s - 0.5; a[6] = (a[6] + 0.5) * s - 0.5;
    kk = a[1]; for (i = 2; i <= 9; ++i) kk = kk ", " a[i];
    print substr($0, 1, RSTART - 1) "K: [" kk "]" substr($0, RSTART + RLENGTH); next }
  { print }' "$real/calibration.yaml" >"$rs/calibration.yaml"

# The render: craters and pits on rough fractal ground, the lamp from behind-right at
# 10 deg (estimated from the big crater's shadow, docs/simulator.md), bright exposure,
# the right camera 18 % brighter, the real pair's +1.6 px row offset (at full scale).
sim="$out/sim"
rm -rf "$sim"
"$hazmap" simulate --rig polar --scale "$scale" --frames 1 --scenario craters --terrain-size 16 \
  --terrain-resolution 0.005 --crater-box 1.2,7,2 --crater-radius 0.04:0.9 --crater-density 10 \
  --crater-depth 0.15 --noise-amplitude 0.02 --noise-wavelength 1 --noise-octaves 8 --noise-gain 0.6 \
  --lunar-polar-light --sun-elevation-deg 10 --sun-azimuth-deg -150 --exposure 1.6 --gain 1,1.18 \
  --electrons-per-dn 10 --noise-sigma 2 --row-offset-px "$(awk -v s="$scale" 'BEGIN { print 1.6 * s }')" \
  --out "$sim" 2>&1 | grep -o "rendering .*" || true

# Disparity search over the real pair's 120-520 px (full scale), in steps of 16.
nd=$(awk -v s="$scale" 'BEGIN { print int(528 * s / 16 + 0.999) * 16 }')
valid() {
  "$hazmap" check --config "$repo/config/default.yaml" --sequence "$1" --count 1 \
    --set stereo.matcher="$2" --set stereo.num_disparities="$nd" --set stereo.z_max=12 --quiet 2>&1 |
    awk '/^000000/ { print $2 }'
}
for which in real sim; do
  for side in left right; do
    echo "$which $side (rows below 60 %): $("$stats" stats "$out/$which/$side/000000.png" 0.6)"
  done
  echo "$which valid: bm $(valid "$out/$which" bm) sgbm $(valid "$out/$which" sgbm)"
done
"$stats" montage "$out/pair.png" 256 "$rs/left/000000.png" "$sim/left/000000.png"
"$stats" hist "$out/hist.png" 0.6 "$rs/left/000000.png" "$sim/left/000000.png"
echo "polar_compare: pictures in $out/pair.png, $out/hist.png"
