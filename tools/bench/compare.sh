#!/usr/bin/env bash
# Map insertion, this working tree against revision REV, timed side by side on real
# point clouds (docs/benchmarks.md, "Comparing two revisions").
#
#   tools/bench/compare.sh REV [--rounds N] [--passes N] [--warmup N] [--sets sample,full]
#                              [--case SUBSTR] [--full-frames N] [--jobs N] [--keep]
#
# 1. Builds the insertion driver (tools/bench/compare/insertion_compare.cpp, from this
#    tree, for both sides) against REV's library: a temporary `git worktree` of REV, built
#    (library and driver only) in its own build folder inside it, both removed
#    afterwards; the binary is kept in the cache, keyed by REV's commit and the driver's
#    source, so a second comparison against REV builds nothing. The driver joins REV's
#    build through CMAKE_PROJECT_hazmap_INCLUDE (tools/bench/compare/driver.cmake); ccache
#    is used when installed.
# 2. Builds the same driver in this tree's build/ (target hazmap_insertion_compare;
#    configured Release first if build/ does not exist), uncommitted changes included.
# 3. Makes the clouds once, into the cache: `hazmap stereo` on data/sample (~195 k points
#    per frame) and on a full-resolution rocks sequence (`hazmap simulate --scale 1.0`,
#    then stereo with config/cadre_full_res.yaml: ~1.25 M points per frame).
# 4. Runs both drivers interleaved: each round runs REV's then this tree's (the order
#    swapped every other round), each run `warmup` untimed and `passes` timed passes per
#    case; prints per case the median over every timed pass of ns per point and layer
#    (conversion included in the *_cloud cases), then / now and now / then.
#
# Cache: $HAZMAP_COMPARE_CACHE, else ${XDG_CACHE_HOME:-~/.cache}/hazmap-compare (delete it
# to remake the clouds). Raw timings: <cache>/last_run.txt.
set -euo pipefail

usage() {
  sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
}

[[ $# -ge 1 ]] || usage
REV=$1
shift
ROUNDS=6 PASSES=2 WARMUP=2 SETS=sample,full CASE="" FULL_FRAMES=3 JOBS=2 KEEP=0
while [[ $# -gt 0 ]]; do
  case $1 in
    --rounds) ROUNDS=$2; shift 2 ;;
    --passes) PASSES=$2; shift 2 ;;
    --warmup) WARMUP=$2; shift 2 ;;
    --sets) SETS=$2; shift 2 ;;
    --case) CASE=$2; shift 2 ;;
    --full-frames) FULL_FRAMES=$2; shift 2 ;;
    --jobs) JOBS=$2; shift 2 ;;
    --keep) KEEP=1; shift ;;
    -h|--help) usage ;;
    *) echo "compare.sh: unknown option '$1'" >&2; usage ;;
  esac
done

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
DRIVER_DIR=$ROOT/tools/bench/compare
CACHE=${HAZMAP_COMPARE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/hazmap-compare}
mkdir -p "$CACHE/bin" "$CACHE/clouds"

SHA=$(git -C "$ROOT" rev-parse --verify --quiet "$REV^{commit}") ||
  { echo "compare.sh: '$REV' is not a commit" >&2; exit 2; }
DRIVER_HASH=$(cat "$DRIVER_DIR/insertion_compare.cpp" "$DRIVER_DIR/driver.cmake" \
  "$ROOT/tools/bench/bench_layers.hpp" | sha1sum | cut -c1-10)

CMAKE_ARGS=(-DCMAKE_BUILD_TYPE=Release)
if command -v ccache >/dev/null && [[ -z ${CMAKE_CXX_COMPILER_LAUNCHER:-} ]]; then
  CMAKE_ARGS+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi

# Scratch under build/ (git ignores it): REV's tree at a fixed path per commit, with its
# build folder inside it as in this tree, so that a rebuild of REV (the driver changed)
# finds its objects in ccache (the same paths, the same compile lines).
mkdir -p "$ROOT/build"
SCRATCH=$ROOT/build/compare-${SHA:0:12}
cleanup() {
  if [[ -d $SCRATCH/src ]]; then
    git -C "$ROOT" worktree remove --force "$SCRATCH/src" 2>/dev/null || true
  fi
  git -C "$ROOT" worktree prune 2>/dev/null || true
  [[ $KEEP == 1 ]] || rm -rf "$SCRATCH"
}
cleanup; rm -rf "$SCRATCH"  # what an interrupted run left
mkdir -p "$SCRATCH"
trap cleanup EXIT

build() {  # build folder, log name, targets...
  local dir=$1 log=$SCRATCH/$2.log
  shift 2
  cmake --build "$dir" -j "$JOBS" --target "$@" >"$log" 2>&1 || { tail -40 "$log" >&2; exit 1; }
}

# 1. The driver against REV's library (cached).
THEN_BIN=$CACHE/bin/insertion_compare-${SHA:0:12}-$DRIVER_HASH
if [[ ! -x $THEN_BIN ]]; then
  echo "building the driver against ${SHA:0:12} (once; cached in $CACHE/bin)" >&2
  git -C "$ROOT" worktree add --detach --quiet "$SCRATCH/src" "$SHA"
  cmake -S "$SCRATCH/src" -B "$SCRATCH/src/build" "${CMAKE_ARGS[@]}" -DHAZMAP_BUILD_TESTS=OFF \
    -DHAZMAP_BUILD_TOOLS=OFF -DHAZMAP_BUILD_PYTHON=OFF \
    -DCMAKE_PROJECT_hazmap_INCLUDE="$DRIVER_DIR/driver.cmake" >"$SCRATCH/then-configure.log" 2>&1 ||
    { tail -40 "$SCRATCH/then-configure.log" >&2; exit 1; }
  build "$SCRATCH/src/build" then-build hazmap_insertion_compare
  cp "$SCRATCH/src/build/hazmap_insertion_compare" "$THEN_BIN.tmp$$"
  mv "$THEN_BIN.tmp$$" "$THEN_BIN"
  git -C "$ROOT" worktree remove --force "$SCRATCH/src"
fi

# 2. The driver against this working tree, in its build/.
NOW_BUILD=$ROOT/build
if [[ ! -f $NOW_BUILD/CMakeCache.txt ]]; then
  echo "configuring $NOW_BUILD (Release)" >&2
  cmake -S "$ROOT" -B "$NOW_BUILD" "${CMAKE_ARGS[@]}" >"$SCRATCH/now-configure.log" 2>&1 ||
    { tail -40 "$SCRATCH/now-configure.log" >&2; exit 1; }
fi
grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$NOW_BUILD/CMakeCache.txt" ||
  { echo "compare.sh: $NOW_BUILD is not a Release build" >&2; exit 1; }
echo "building the driver against the working tree ($NOW_BUILD)" >&2
build "$NOW_BUILD" now-build hazmap_insertion_compare
NOW_BIN=$NOW_BUILD/hazmap_insertion_compare

# 3. Clouds (made once with this tree's CLI; the same clouds for both sides).
cli() {
  if [[ -z ${CLI_BUILT:-} ]]; then
    echo "building this tree's CLI to make the clouds" >&2
    build "$NOW_BUILD" cli-build hazmap_cli
    CLI_BUILT=1
  fi
  "$NOW_BUILD/hazmap" "$@"
}
make_clouds() {  # set name
  local name=$1 out=$CACHE/clouds/$1
  [[ -f $out/.done ]] && return 0
  local tmp
  tmp=$(mktemp -d "$CACHE/clouds/.$name.XXXXXX")
  echo "making the $name clouds in $out (once)" >&2
  case $name in
    sample)
      cli stereo --config "$ROOT/config/default.yaml" --sequence "$ROOT/data/sample" \
        --out "$tmp/stereo" --quiet >/dev/null ;;
    full)
      cli simulate --scenario rocks --seed 913 --scale 1.0 --frames "$FULL_FRAMES" \
        --out "$tmp/sequence" >/dev/null
      cli stereo --config "$ROOT/config/cadre_full_res.yaml" --sequence "$tmp/sequence" \
        --out "$tmp/stereo" --quiet >/dev/null
      rm -rf "$tmp/sequence" ;;
    *) echo "compare.sh: unknown cloud set '$name' (sample, full)" >&2; exit 2 ;;
  esac
  # Keep only the clouds.
  find "$tmp/stereo" -type f ! -name '*.ply' -delete
  touch "$tmp/.done"
  rm -rf "$out"
  mv "$tmp" "$out"
}
IFS=, read -r -a SET_LIST <<<"$SETS"
for s in "${SET_LIST[@]}"; do make_clouds "$s"; done

# 4. Interleaved runs.
RAW=$CACHE/last_run.txt
: >"$RAW"
CASE_ARGS=()
[[ -n $CASE ]] && CASE_ARGS=(--case "$CASE")
echo "timing: $ROUNDS rounds x $PASSES passes after $WARMUP warm-up passes, sets $SETS" >&2
for ((round = 1; round <= ROUNDS; round++)); do
  if ((round % 2)); then order=(then now); else order=(now then); fi
  for s in "${SET_LIST[@]}"; do
    for side in "${order[@]}"; do
      bin=$THEN_BIN
      [[ $side == now ]] && bin=$NOW_BIN
      "$bin" --clouds "$CACHE/clouds/$s" --label "$s $side" --warmup "$WARMUP" \
        --passes "$PASSES" "${CASE_ARGS[@]}" >>"$RAW"
    done
  done
  echo "  round $round/$ROUNDS done" >&2
done

echo "## Insertion, ${SHA:0:7} (then) vs working tree at $(git -C "$ROOT" rev-parse --short HEAD)$(
  git -C "$ROOT" diff --quiet HEAD -- src include || echo '+changes') (now)"
echo "median ns per point and layer (thread CPU time; wall clock in the last columns) over"
echo "$((ROUNDS * PASSES)) timed passes per side, interleaved; load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
python3 - "$RAW" <<'EOF'
import statistics, sys
from collections import defaultdict
cpu, wall, points = defaultdict(list), defaultdict(list), {}
order = []
for line in open(sys.argv[1]):
    clouds, side, case, c, w, n = line.split()
    if (clouds, case) not in order:
        order.append((clouds, case))
    cpu[clouds, case, side].append(float(c))
    wall[clouds, case, side].append(float(w))
    points[clouds] = int(float(n))
print("| clouds | case | then | now | now / then | wall: then | now | now / then |")
print("|---|---|---:|---:|---:|---:|---:|---:|")
for clouds, case in order:
    t, n = (statistics.median(cpu[clouds, case, s]) for s in ("then", "now"))
    wt, wn = (statistics.median(wall[clouds, case, s]) for s in ("then", "now"))
    flag = " **> 10 % slower**" if n > 1.10 * t else ""
    print(f"| {clouds} | {case} | {t:.2f} | {n:.2f} | {n / t:.2f}{flag} | {wt:.2f} | {wn:.2f} | {wn / wt:.2f} |")
print()
print("points per frame: " + ", ".join(f"{c} {n}" for c, n in points.items()))
EOF
