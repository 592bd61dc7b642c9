#!/usr/bin/env bash
# Are two hazmap binaries' outputs byte-identical? Runs both on the same inputs with every
# shipped config and compares every file they write (frames' PNGs and grids, mosaics,
# fused and footprint maps), and summary.json with its timing fields removed.
#
#   tools/compare_outputs.sh OLD_BIN NEW_BIN [--work DIR] [--keep]
#
# Cases: default, cadre_flight (with --mosaic), thesis_ccm and thesis_pwc on data/sample;
# cadre_full_res on a 2-frame full-resolution render; k10 and polar_traverse on
# ../shared/data/planetary_analog and euroc_indoor on ../shared/data/euroc_v1_01_micro
# when that folder is there (skipped, and said so, when not). Prints one line per case and
# exits non-zero when any case differs, naming the first differing files.
# A refactor that claims "outputs unchanged" quotes this script's output.
set -euo pipefail

usage() { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
[[ $# -ge 2 ]] || usage
OLD=$(realpath "$1") NEW=$(realpath "$2")
shift 2
WORK="" KEEP=0
while [[ $# -gt 0 ]]; do
  case $1 in
    --work) WORK=$2; shift 2 ;;
    --keep) KEEP=1; shift ;;
    *) usage ;;
  esac
done
for bin in "$OLD" "$NEW"; do
  [[ -x $bin ]] || { echo "compare_outputs: $bin is not an executable" >&2; exit 2; }
done
root=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$root/.." && pwd)/shared
if [[ -z $WORK ]]; then
  WORK=$(mktemp -d /tmp/hazmap_compare_outputs.XXXXXX)
  [[ $KEEP == 1 ]] || trap 'rm -rf "$WORK"' EXIT
fi
mkdir -p "$WORK"

# summary.json without what depends on the clock or on where the run happened.
strip_summary() {
  python3 - "$1" <<'EOF'
import json, re, sys
timing = re.compile(r"(_ms($|_)|ms$|^ms$|_ns_per|ns_per_point|_rate|seconds|wall|cpu)")
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not timing.search(k)}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
print(json.dumps(strip(json.load(open(sys.argv[1]))), indent=1, sort_keys=True))
EOF
}

failed=0
# compare NAME CONFIG SEQUENCE [extra run args...]
compare() {
  local name=$1 config=$2 seq=$3
  shift 3
  if [[ ! -d $seq ]]; then
    printf '%-16s skipped (no %s)\n' "$name" "$seq"
    return
  fi
  local side
  for side in old new; do
    local bin=$OLD
    [[ $side == new ]] && bin=$NEW
    (cd "$root" && "$bin" run --config "$config" --sequence "$seq" --out "$WORK/$name.$side" \
       --overwrite --quiet "$@" >"$WORK/$name.$side.log" 2>&1) || {
      echo "$name: $side binary failed, see $WORK/$name.$side.log" >&2
      failed=1
      return
    }
  done
  local a=$WORK/$name.old b=$WORK/$name.new diffs
  diffs=$(diff -rq -x run.log -x summary.json -x view.html "$a" "$b" || true)
  if ! cmp -s <(strip_summary "$a/summary.json") <(strip_summary "$b/summary.json"); then
    diffs+=$'\n'"summary.json (timings removed) differs"
  fi
  local files
  files=$(find "$a" -type f ! -name run.log ! -name view.html | wc -l)
  if [[ -z ${diffs//[$'\n']/} ]]; then
    printf '%-16s identical (%d files)\n' "$name" "$files"
  else
    printf '%-16s DIFFERS:\n%s\n' "$name" "$(echo "$diffs" | sed '/^$/d' | head -5)"
    failed=1
  fi
}

compare default        config/default.yaml        data/sample
compare cadre_flight   config/cadre_flight.yaml   data/sample --mosaic
compare thesis_ccm     config/thesis_ccm.yaml     data/sample
compare thesis_pwc     config/thesis_pwc.yaml     data/sample --mosaic
compare k10            config/k10.yaml            "$shared/data/planetary_analog/k10_ames/seq"
compare polar_traverse config/polar_traverse.yaml "$shared/data/planetary_analog/polar_traverse_1m/seq"
compare euroc_indoor   config/euroc_indoor.yaml   "$shared/data/euroc_v1_01_micro" --frames 0:3 \
  --poses "$shared/data/euroc_v1_01_micro/poses_leftcam_gt.csv" --pose-frame left_camera

# cadre_full_res needs full-resolution frames: two rendered ones (made by the old binary).
full=$WORK/full_res_seq
if [[ ! -d $full ]]; then
  "$OLD" simulate --scenario rocks --out "$full" --frames 2 --scale 1.0 --seed 36 --quiet >"$WORK/simulate.log" 2>&1 ||
    { echo "simulate failed, see $WORK/simulate.log" >&2; failed=1; }
fi
compare cadre_full_res config/cadre_full_res.yaml "$full"

if [[ $failed != 0 ]]; then
  echo "outputs differ (work folder: $WORK)"
  [[ $KEEP == 1 ]] || trap - EXIT
  exit 1
fi
echo "all outputs identical"
