#!/usr/bin/env bash
# Hazard acceptance evaluation (issue 19): renders a fixed set of synthetic scenarios once,
# maps each with every given configuration (`hazmap run`), scores the maps
# (`hazmap evaluate --near`), and prints one compact table per configuration.
#
#   tools/eval_hazards.sh config/cadre_flight.yaml config/thesis_ccm.yaml out/eval_hazards
#   tools/eval_hazards.sh --jobs 2 --frames 15 config/default.yaml out/eh
#   tools/eval_hazards.sh --scenes lowsun --matchers bm,sgbm config/cadre_flight.yaml out/ls
#
# Scenarios (seeds 901.. that no test uses; --seed-base moves them), 0.4 image scale,
# 4 cm per frame, with depth images (simulate --depth) for the seen-cell tables:
#   ramp15, ramp25   ramp of 15 / 25 deg (a 25 deg ramp exceeds max_slope 20 deg)
#   craters          fractal ground with craters
#   sine             sine wave (steepest slope 17.4 deg)
#   rocks3..rocks24  hemispherical rocks of radius (= height) 3, 6, 12, 24 cm, unburied,
#                    beside the path (15 cm clear of it, as tools/sweep.sh lays them out)
# --scenes lowsun (issue 33): ls_ramp15, ls_ramp25, ls_craters, ls_rocks6, ls_rocks12,
#   ls_rocks24: the same terrains (seeds 911..) under lunar polar light and imperfect
#   cameras (the low-sun keys below, the POLAR-matched ones of docs/simulator.md).
# --matchers bm,sgbm maps every config with each matcher (stereo.matcher=M; folders
#   <config>_<matcher>); adding a matcher is one more word in the list.
#
# Layout of OUT: seq/<scenario>/ (sequences, cached: re-rendered only when their
# simulate arguments change), <config>/<scenario>/ (the run; eval/ inside it),
# logs/<job>.log, tables.txt (what is printed at the end).
#
# Table columns, per layer and the fused and footprint maps, pooled over the frames:
#   FA%      false-alarm area / known area
#   miss_cm2 missed obstacle area [cm^2] (obstacles >= the map's h_min called traversable)
#   miss_c   the same in cells of that map (area / cell area)
#   rec%     hazard recall: obstacle pixels (>= h_min) labelled hazard / all of them
#   nrec%    the same within --near metres of the rover's true position
#   unk%     obstacle pixels labelled unknown
#   vv_all%  variance violations over every published height (|h - h_gt| > 3 sigma)
#   rms_all  height RMS over every published height [cm]
#   below_cm the deepest published cell height below the ground truth at its centre, over
#            the frames [cm] (max_below_m; negative: none below)
# "-" = undefined (no obstacle of that height in view, or a hazard-only map).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
self="$repo/tools/eval_hazards.sh"
# shellcheck source=tools/progress.sh
. "$repo/tools/progress.sh"

usage() {
  awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$self"
  cat <<'EOF'
Usage: tools/eval_hazards.sh [options] CONFIG.yaml [CONFIG.yaml ...] OUT
Options:
  --frames N       frames per sequence (default 30; a 30-frame sequence takes about a
                   minute to render on one core)
  --scale S        image scale (default 0.4)
  --near R         radius of the near metrics in metres (default 1.5)
  --jobs N         parallel jobs (default 1: the machine is shared)
  --only LIST      comma-separated scenarios (default: all of the scene set)
  --seed-base N    seeds N, N+1, ... for the scenarios in the order above (default 901;
                   the low-sun scenes use N+10 ..)
  --scenes SET     default (the eight above) | lowsun (the six low-sun scenes)
  --matchers LIST  comma-separated stereo matchers, e.g. bm,sgbm (default: each config's own)
  --hazmap BIN     the hazmap executable (default $HAZMAP or build/hazmap)
  --tables-only    print the tables of what OUT already holds
EOF
}

# ---------------------------------------------------------------------------------------
# Scenario table: name, seed, simulate arguments.
# $2: the first seed (ramp15's; the others follow in this order).
scenario_args() {
  local b="${2:-901}"
  case "$1" in
    ramp15) echo "--scenario ramp --ramp-deg 15 --seed $b" ;;
    ramp25) echo "--scenario ramp --ramp-deg 25 --seed $((b + 1))" ;;
    craters) echo "--scenario craters --seed $((b + 2))" ;;
    sine) echo "--scenario sine --seed $((b + 3))" ;;
    rocks3 | rocks6 | rocks12 | rocks24)
      local r_cm="${1#rocks}" seed
      case "$r_cm" in 3) seed=$((b + 4)) ;; 6) seed=$((b + 5)) ;; 12) seed=$((b + 6)) ;; 24) seed=$((b + 7)) ;; esac
      # Layout of tools/sweep.sh: rocks beside the path within reach of the finest layers.
      awk -v rc="$r_cm" -v seed="$seed" 'BEGIN {
        r = rc / 100; x0 = 0.3 + r; x1 = x0 + (6 * r > 0.8 ? 6 * r : 0.8); if (x1 > 3.2) x1 = 3.2;
        y = 0.15 + r + (2 * r > 0.3 ? 2 * r : 0.3);
        n = r < 0.15 ? 4 : (r < 0.3 ? 3 : 2);
        printf "--scenario rocks --seed %d --rock-radius %.4f --rock-buried 0 --rock-count %d --rock-box %.4f,%.4f,%.4f --rock-clearance 0.15 --gt-margin 3\n", seed, r, n, x0, x1, y }'
      ;;
    ls_*)
      # Low sun: the terrain of the default scene (another seed), lunar polar light from
      # behind-left, regolith albedo, fine relief, noisy cameras with a small row offset.
      local base seed
      case "$1" in
        ls_ramp15) seed=$((b + 10)) ;; ls_ramp25) seed=$((b + 11)) ;; ls_craters) seed=$((b + 12)) ;;
        ls_rocks6) seed=$((b + 15)) ;; ls_rocks12) seed=$((b + 16)) ;; ls_rocks24) seed=$((b + 17)) ;;
        *) echo "eval_hazards: unknown scenario '$1'" >&2; return 1 ;;
      esac
      base="$(scenario_args "${1#ls_}" "$b")" || return 1
      echo "$(sed "s/--seed [0-9]*/--seed $seed/" <<<"$base") $lowsun_args"
      ;;
    *) echo "eval_hazards: unknown scenario '$1'" >&2; return 1 ;;
  esac
}
default_scenarios="ramp15 ramp25 craters sine rocks3 rocks6 rocks12 rocks24"
lowsun_scenarios="ls_ramp15 ls_ramp25 ls_craters ls_rocks6 ls_rocks12 ls_rocks24"
# The low-sun keys (docs/simulator.md, "Low-sun scenes").
lowsun_args="--lunar-polar-light --sun-elevation-deg 6 --sun-azimuth-deg 135 --terrain-resolution 0.005 --noise-octaves 9 --noise-gain 0.55 --exposure 0.6 --gain 1,1.05 --electrons-per-dn 10 --noise-sigma 2 --vignetting 0.15 --row-offset-px 0.3"

# ---------------------------------------------------------------------------------------
# Jobs (run through xargs, possibly in parallel). Each writes OUT/logs/<name>.log and
# prints one status line.
if [ "${1:-}" = "--sim-job" ]; then
  hazmap="$2" out="$3" common="$4" scenario="$5" seed_base="$6"
  dir="$out/seq/$scenario"
  args="$(scenario_args "$scenario" "$seed_base") $common"
  if [ -f "$dir/.done" ] && [ "$(cat "$dir/.done")" = "$args" ]; then
    echo "eval_hazards: sequence $scenario cached$(progress_note)"
    exit 0
  fi
  rm -rf "$dir"
  mkdir -p "$dir"
  read -r -a sim <<<"$args"
  start=$(date +%s)
  if "$hazmap" simulate --out "$dir" --ground-truth --depth --quiet "${sim[@]}" >"$out/logs/sim_$scenario.log" 2>&1; then
    echo "$args" >"$dir/.done"
    echo "eval_hazards: sequence $scenario rendered in $(($(date +%s) - start)) s$(progress_note)"
  else
    echo "eval_hazards: simulate $scenario failed, see $out/logs/sim_$scenario.log" >&2
    exit 1
  fi
  exit 0
fi
if [ "${1:-}" = "--map-job" ]; then
  hazmap="$2" out="$3" near="$4" name="$5" config="$6" matcher="$7" scenario="$8"
  set_matcher=()
  [ "$matcher" = "-" ] || set_matcher=(--set "stereo.matcher=$matcher")
  dir="$out/$name/$scenario"
  log="$out/logs/${name}_$scenario.log"
  rm -rf "$dir"
  start=$(date +%s)
  # The reasons for unknown cells (output.unknown_reasons) only add files.
  if "$hazmap" run --config "$config" "${set_matcher[@]+"${set_matcher[@]}"}" --sequence "$out/seq/$scenario" --out "$dir" --quiet \
    --set output.unknown_reasons=true >"$log" 2>&1 &&
    "$hazmap" evaluate --run "$dir" --sequence "$out/seq/$scenario" --near "$near" --quiet >>"$log" 2>&1; then
    echo "eval_hazards: $name on $scenario done in $(($(date +%s) - start)) s$(progress_note)"
  else
    echo "eval_hazards: $name on $scenario failed, see $log" >&2
    tail -n 3 "$log" >&2
    exit 1
  fi
  exit 0
fi

# ---------------------------------------------------------------------------------------
frames=30 scale=0.4 near=1.5 jobs=1 only="" seed_base=901 hazmap="${HAZMAP:-$repo/build/hazmap}" tables_only=0
scene_set=default matchers=""
positional=()
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames="$2"; shift ;;
    --scale) scale="$2"; shift ;;
    --near) near="$2"; shift ;;
    --jobs) jobs="$2"; shift ;;
    --only) only="$2"; shift ;;
    --seed-base) seed_base="$2"; shift ;;
    --scenes) scene_set="$2"; shift ;;
    --matchers) matchers="$2"; shift ;;
    --hazmap) hazmap="$2"; shift ;;
    --tables-only) tables_only=1 ;;
    -h | --help) usage; exit 0 ;;
    -*) echo "eval_hazards: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) positional+=("$1") ;;
  esac
  shift
done
if [ "${#positional[@]}" -lt 2 ]; then
  echo "eval_hazards: expected CONFIG... OUT (see --help)" >&2
  exit 2
fi
out="${positional[-1]}"
configs=("${positional[@]:0:${#positional[@]}-1}")
case "$scene_set" in
  default) all_scenarios="$default_scenarios" ;;
  lowsun) all_scenarios="$lowsun_scenarios" ;;
  *) echo "eval_hazards: --scenes expects default or lowsun" >&2; exit 2 ;;
esac
scenarios="${only//,/ }"
: "${scenarios:=$all_scenarios}"
for s in $scenarios; do scenario_args "$s" "$seed_base" >/dev/null || exit 2; done
[ -x "$hazmap" ] || { echo "eval_hazards: no hazmap executable at $hazmap (build it, or pass --hazmap)" >&2; exit 1; }
hazmap="$(cd "$(dirname "$hazmap")" && pwd)/$(basename "$hazmap")"
mkdir -p "$out/logs"
out="$(cd "$out" && pwd)"

# Stack names: config file stems (which must differ: they name the output folders), with
# _<matcher> appended for each of --matchers.
names=() stack_configs=() stack_matchers=()
matchers="${matchers//,/ }"
for c in "${configs[@]}"; do
  [ -f "$c" ] || { echo "eval_hazards: no config file $c" >&2; exit 2; }
  n="$(basename "$c")"
  n="${n%.yaml}"
  n="${n%.yml}"
  for m in ${matchers:--}; do
    name="$n"
    [ "$m" = "-" ] || name="${n}_$m"
    for existing in "${names[@]+"${names[@]}"}"; do
      [ "$existing" != "$name" ] || { echo "eval_hazards: two configs named $n" >&2; exit 2; }
    done
    names+=("$name")
    stack_configs+=("$c")
    stack_matchers+=("$m")
  done
done

status=0
if [ "$tables_only" = 0 ]; then
  common="--frames $frames --scale $scale"
  # 1. Sequences (cached).
  progress_start "$out/.progress/seq" "$(echo $scenarios | wc -w)"
  for s in $scenarios; do printf '%s\0' "$s"; done |
    xargs -0 -I{} -P "$jobs" "$self" --sim-job "$hazmap" "$out" "$common" {} "$seed_base" || status=1
  # 2. Maps and evaluations: every config on every scenario that has a sequence.
  n_maps=0
  for s in $scenarios; do [ -f "$out/seq/$s/.done" ] && n_maps=$((n_maps + ${#names[@]})); done
  progress_start "$out/.progress/maps" "$n_maps"
  for i in "${!names[@]}"; do
    cfg="$(cd "$(dirname "${stack_configs[$i]}")" && pwd)/$(basename "${stack_configs[$i]}")"
    for s in $scenarios; do
      if [ -f "$out/seq/$s/.done" ]; then
        printf '%s\0%s\0%s\0%s\0' "${names[$i]}" "$cfg" "${stack_matchers[$i]}" "$s"
      fi
    done
  done | xargs -0 -n 4 -P "$jobs" "$self" --map-job "$hazmap" "$out" "$near" || status=1
fi

# 3. Tables from each run's eval/summary.csv (columns found by name).
tables="$out/tables.txt"
: >"$tables"
for n in "${names[@]}"; do
  {
    echo
    echo "== $n (pooled over the frames; nrec% within ${near} m of the rover) =="
    printf '%-8s %-9s %5s %6s %8s %7s %6s %6s %6s %6s %7s %7s %8s\n' scenario map cell_cm hmin_cm \
      FA% miss_cm2 miss_c rec% nrec% unk% vv_all% rms_all below_cm
    for s in $scenarios; do
      csv="$out/$n/$s/eval/summary.csv"
      if [ ! -f "$csv" ]; then
        printf '%-8s (no evaluation: see %s)\n' "$s" "$out/logs/${n}_$s.log"
        continue
      fi
      awk -F, -v scen="$s" '
        NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        function v(k) { return (k in col) ? $(col[k]) : "nan" }
        function p(x, scale, f) { return (x == "nan" || x == "") ? "-" : sprintf(f, x * scale) }
        {
          res = v("resolution_m")
          cells = (v("missed_m2") == "nan" || res == 0) ? "-" : sprintf("%.1f", v("missed_m2") / (res * res))
          printf "%-8s %-9s %5s %6s %8s %7s %6s %6s %6s %6s %7s %7s %8s\n", scen, v("layer"),
            p(res, 100, "%g"), p(v("h_min_m"), 100, "%.1f"), p(v("false_alarm_fraction"), 100, "%.2f"),
            p(v("missed_m2"), 1e4, "%.1f"), cells, p(v("hazard_recall"), 100, "%.1f"),
            p(v("near_hazard_recall"), 100, "%.1f"), p(v("hazard_unknown"), 100, "%.1f"),
            p(v("variance_violation_all"), 100, "%.2f"), p(v("height_rms_all_m"), 100, "%.2f"),
            p(v("max_below_m"), 100, "%.1f")
        }' "$csv"
    done
  } | tee -a "$tables"
done
# 4. Seen cells (issue 34): over ground the left camera saw within --near of the rover.
for n in "${names[@]}"; do
  {
    echo
    echo "== $n: seen cells within ${near} m (pooled over the frames) =="
    echo "   F = free ground, H = obstacle >= h_min, tall = >= 2 h_min; ->T/U/H traversable/unknown/hazard;"
    echo "   gF: free ground seen within the vouching layers' lateral gate (points a vouching layer would take)"
    echo "   rF: gF whose wheel-ring samples are gF too (footprint: the whole disc of footprint + ring radius)"
    echo "   reasons: of the free cells left unknown, the share with each reason (any/sole), largest first"
    printf '%-8s %-9s %7s %6s %6s %6s %6s %6s %6s %7s %7s %6s %7s %6s  %s\n' scenario map F_m2 F-T% F-U% F-H% H-H% H-U% H-T% tall-H% gF_m2 gF-T% rF_m2 rF-T% reasons
    for s in $scenarios; do
      csv="$out/$n/$s/eval/summary.csv"
      [ -f "$csv" ] || continue
      awk -F, -v scen="$s" '
        NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        function v(k) { return (k in col) ? $(col[k]) : "nan" }
        function p(x, scale, f) { return (x == "nan" || x == "") ? "-" : sprintf(f, x * scale) }
        {
          if (!("near_seen_free_m2" in col)) { printf "%-8s (no seen cells: no depth images)\n", scen; exit }
          reasons = ""; used = ""
          for (k = 0; k < 4; ++k) {
            best = ""; bv = 0
            for (c in col) if (c ~ /^near_seen_unknown_free_/ && c !~ /_sole$/ && index(used, "|" c "|") == 0) {
              x = $(col[c]); if (x != "nan" && x + 0 > bv) { bv = x + 0; best = c }
            }
            if (best == "" || bv < 0.005) break
            used = used "|" best "|"
            name = best; sub(/^near_seen_unknown_free_/, "", name)
            reasons = reasons sprintf(" %s %.0f/%.0f", name, 100 * bv, 100 * v(best "_sole"))
          }
          printf "%-8s %-9s %7s %6s %6s %6s %6s %6s %6s %7s %7s %6s %7s %6s %s\n", scen, v("layer"),
            p(v("near_seen_free_m2"), 1, "%.3f"), p(v("near_seen_free_traversable"), 100, "%.1f"),
            p(v("near_seen_free_unknown"), 100, "%.1f"), p(v("near_seen_free_hazard"), 100, "%.2f"),
            p(v("near_seen_hazard_hazard"), 100, "%.1f"), p(v("near_seen_hazard_unknown"), 100, "%.1f"),
            p(v("near_seen_hazard_traversable"), 100, "%.2f"), p(v("near_seen_tall_hazard"), 100, "%.1f"),
            p(v("near_gated_free_m2"), 1, "%.3f"), p(v("near_gated_free_traversable"), 100, "%.1f"),
            p(v("near_ring_gated_free_m2"), 1, "%.3f"), p(v("near_ring_gated_free_traversable"), 100, "%.1f"),
            reasons
        }' "$csv"
    done
  } | tee -a "$tables"
done
# 5. One summary line per stack, as in the README's tables (OUT/summary.md): fused and
# footprint false alarms on the traversable scenes (ramp 15, craters, sine), the fused
# map's missed obstacle area over every scene, and the fused rock recall near the rover.
pre=""
[ "$scene_set" = lowsun ] && pre="ls_"
summary="$out/summary.md"
{
  echo "| stack | fused FA: ramp 15 / craters / sine | footprint FA: ramp 15 / craters / sine | fused missed (all scenes) | rock recall <= ${near} m: 6 / 12 / 24 cm |"
  echo "|---|---:|---:|---:|---:|"
  for n in "${names[@]}"; do
    field() {  # field SCENE LAYER COLUMN SCALE FORMAT
      local csv="$out/$n/$1/eval/summary.csv"
      [ -f "$csv" ] || { echo "-"; return; }
      awk -F, -v layer="$2" -v key="$3" -v scale="$4" -v fmt="$5" '
        NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        $(col["layer"]) == layer { x = $(col[key]); if (x == "nan" || x == "") print "-"; else printf fmt "\n", x * scale; found = 1 }
        END { if (!found) print "-" }' "$csv"
    }
    fa() { local a=() s; for s in ramp15 craters sine; do
        [[ " $scenarios " == *" $pre$s "* ]] && a+=("$(field "$pre$s" "$1" false_alarm_fraction 100 %.3g)"); done
      local IFS=/; echo "${a[*]} %" | sed 's|/| / |g'; }
    missed=0
    for s in $scenarios; do
      m="$(field "$s" fused missed_m2 1e4 %.1f)"
      [ "$m" = "-" ] || missed="$(awk -v a="$missed" -v b="$m" 'BEGIN { print a + b }')"
    done
    rec=()
    for r in 6 12 24; do
      [[ " $scenarios " == *" ${pre}rocks$r "* ]] && rec+=("$(field "${pre}rocks$r" fused near_hazard_recall 100 %.0f)")
    done
    recall="$(IFS=/; echo "${rec[*]} %" | sed 's|/| / |g')"
    echo "| \`$n\` | $(fa fused) | $(fa footprint) | $missed cm^2 | $recall |"
  done
} >"$summary"
cat "$summary"
echo
echo "eval_hazards: tables in $tables, summary in $summary; per-run reports in $out/<config>/<scenario>/eval/report.html"
exit "$status"
