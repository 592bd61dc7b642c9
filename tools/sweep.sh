#!/usr/bin/env bash
# Obstacle-size, height-precision and pose-drift sweeps (issue 7, thesis chapter 7):
# simulate -> run -> evaluate for every case, independent cases in parallel through GNU
# parallel (locally, or spread over machines with --sshlogin), then one summary with
# tables, heat maps and report.html (`hazmap evaluate --sweep`).
#
#   tools/sweep.sh --quick                      # a few minutes on 2 cores
#   tools/sweep.sh                              # the thesis' 27 radii, 2..70 cm
#   tools/sweep.sh --sshlogin 8/:,8/user@hostA,8/user@hostB   # spread over machines
#
# Experiments (--only to pick):
#   sizes    rocks of one radius per case (hemispheres: height = radius, width 2 r) in plain
#            view beside a straight path; thesis_pwc.yaml and thesis_ccm.yaml on the same
#            sequence -> missed-obstacle fraction by layer and radius
#   craters  fractal ground with craters, both configs -> height RMS by layer
#   drift    sine terrain with 8 cm rocks, poses drifting 0..20 % of the distance
#            travelled along the wave, thesis_ccm.yaml -> missed obstacles and false alarms
#
# Remote machines (--sshlogin) need the repository built at the same absolute path and
# password-less ssh; each case's folder is returned with rsync (--return) and removed
# there (--cleanup), so no shared file system is needed.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
self="$repo/tools/sweep.sh"
# shellcheck source=tools/progress.sh
. "$repo/tools/progress.sh"

usage() {
  awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$self"
  cat <<'EOF'
Options:
  --quick             radii 3 4 8 16 34 cm, scale 0.25, 10 frames of 8 cm, drift 0 10 20 %
  --out DIR           sweep folder (default out/sweep, out/sweep-quick with --quick)
  --hazmap BIN        the hazmap executable (default $HAZMAP or build/hazmap)
  --jobs N            parallel jobs per machine (default: number of cores)
  --sshlogin LIST     GNU parallel --sshlogin list, e.g. 4/:,8/me@host (':' = this machine)
  --only LIST         comma-separated subset of sizes,craters,drift
  --radii "R ..."     obstacle radii in cm (default: the thesis' list, or the quick one)
  --drifts "D ..."    drift fractions in % (default 0 5 10 15 20, quick 0 10 20)
  --seed N            simulation seed (default 7)
  --keep-images       keep the rendered stereo images of every case
  --publish DIR       copy the summary's figures and tables.md into DIR (e.g. docs/eval)
  --summary-only      skip the cases; summarise what OUT already holds (after a partial run)
EOF
}

# ---------------------------------------------------------------------------------------
# One case (runs on whichever machine GNU parallel picks):
#   sweep.sh --job HAZMAP OUT CASE EXPERIMENT MAPS SIM_ARGS KEEP_IMAGES
if [ "${1:-}" = "--job" ]; then
  shift
  hazmap="$1" out="$2" case_id="$3" experiment="$4" maps="$5" sim_args="$6" keep="$7"
  dir="$out/runs/$case_id"
  rm -rf "$dir"
  mkdir -p "$dir"
  read -r -a sim <<<"$sim_args"
  {
    echo "case $case_id ($experiment): hazmap simulate ${sim_args}"
    "$hazmap" simulate --out "$dir/seq" --ground-truth --quiet "${sim[@]}"
    for map in ${maps//,/ }; do
      "$hazmap" run --config "$repo/config/$map.yaml" --sequence "$dir/seq" --out "$dir/$map" \
        --mosaic --quiet
      "$hazmap" evaluate --run "$dir/$map" --sequence "$dir/seq" --quiet
    done
    if [ "$keep" != 1 ]; then rm -rf "$dir/seq/left" "$dir/seq/right"; fi
  } >"$dir/job.log" 2>&1 || {
    echo "sweep: case $case_id failed, see $dir/job.log" >&2
    tail -n 5 "$dir/job.log" >&2
    exit 1
  }
  echo "sweep: case $case_id done$(progress_note)"
  exit 0
fi

# ---------------------------------------------------------------------------------------
quick=0 out="" hazmap="${HAZMAP:-$repo/build/hazmap}" jobs="" sshlogin="" only="sizes,craters,drift"
radii="" drifts="" seed=7 keep=0 publish="" summary_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --out) out="$2"; shift ;;
    --hazmap) hazmap="$2"; shift ;;
    --jobs) jobs="$2"; shift ;;
    --sshlogin) sshlogin="$2"; shift ;;
    --only) only="$2"; shift ;;
    --radii) radii="$2"; shift ;;
    --drifts) drifts="$2"; shift ;;
    --seed) seed="$2"; shift ;;
    --keep-images) keep=1 ;;
    --publish) publish="$2"; shift ;;
    --summary-only) summary_only=1 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "sweep: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done

command -v parallel >/dev/null || { echo "sweep: GNU parallel missing (tools/install_deps.sh installs it)" >&2; exit 1; }
[ -x "$hazmap" ] || { echo "sweep: no hazmap executable at $hazmap (build it, or pass --hazmap)" >&2; exit 1; }
hazmap="$(cd "$(dirname "$hazmap")" && pwd)/$(basename "$hazmap")"

if [ "$quick" = 1 ]; then
  : "${out:=$repo/out/sweep-quick}"
  : "${radii:=3 4 8 16 34}"
  : "${drifts:=0 10 20}"
  common="--scale 0.25 --frames 10 --step 0.08 --samples 1"
else
  : "${out:=$repo/out/sweep}"
  : "${radii:=2 3 4 5 6 8 10 12 14 16 18 20 22 24 26 28 30 34 38 42 46 50 54 58 62 66 70}"
  : "${drifts:=0 5 10 15 20}"
  common="--scale 0.5 --frames 40 --step 0.04"
fi
mkdir -p "$out"
out="$(cd "$out" && pwd)"

cases="$out/cases.tsv"
manifest="$out/sweep.tsv"
status=0
if [ "$summary_only" = 0 ]; then
  : >"$cases"
  printf 'experiment\tmap\tscenario\tradius_m\tdrift\trun_dir\n' >"$manifest"

  add_case() {  # id experiment maps scenario radius_m drift sim_args
    printf '%s\t%s\t%s\t%s\t%s\n' "$1" "$2" "$3" "$7" "$keep" >>"$cases"
    for map in ${3//,/ }; do
      printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$2" "$map" "$4" "$5" "$6" "runs/$1/$map" >>"$manifest"
    done
  }

  if [[ ",$only," == *",sizes,"* ]]; then
    for r_cm in $radii; do
      # Rocks of radius r (height r when unburied) beside the path, kept 15 cm clear of it,
      # within reach of the finest layers while the rover drives past them.
      read -r r x0 x1 y count < <(awk -v rc="$r_cm" 'BEGIN {
        r = rc / 100; x0 = 0.3 + r; x1 = x0 + (6 * r > 0.8 ? 6 * r : 0.8); if (x1 > 3.2) x1 = 3.2;
        y = 0.15 + r + (2 * r > 0.3 ? 2 * r : 0.3);
        n = r < 0.15 ? 4 : (r < 0.3 ? 3 : 2);
        printf "%.4f %.4f %.4f %.4f %d\n", r, x0, x1, y, n }')
      add_case "size_${r_cm}cm" sizes thesis_pwc,thesis_ccm rocks "$r" - \
        "--scenario rocks --seed $seed $common --rock-radius $r --rock-buried 0 --rock-count $count --rock-box $x0,$x1,$y --rock-clearance 0.15 --gt-margin 3"
    done
  fi
  if [[ ",$only," == *",craters,"* ]]; then
    add_case craters craters thesis_pwc,thesis_ccm craters - - "--scenario craters --seed $seed $common"
  fi
  if [[ ",$only," == *",drift,"* ]]; then
    for d_pct in $drifts; do
      d=$(awk -v d="$d_pct" 'BEGIN { printf "%.4f", d / 100 }')
      add_case "drift_${d_pct}pct" drift thesis_ccm sine - "$d" \
        "--scenario sine --seed $seed $common --scatter-rocks --rock-radius 0.08 --rock-buried 0 --rock-count 4 --rock-box 0.4,1.4,0.5 --rock-clearance 0.15 --drift $d --drift-direction-deg 0"
    done
  fi

  n_cases=$(wc -l <"$cases")
  echo "sweep: $n_cases cases into $out (hazmap $hazmap)"
  par=(parallel --colsep '\t' --halt never --line-buffer)
  [ -n "$jobs" ] && par+=(--jobs "$jobs")
  if [ -n "$sshlogin" ]; then
    par+=(--sshlogin "$sshlogin" --return "$out/runs/{1}" --cleanup)
  fi
  progress_start "$out/.progress" "$n_cases"
  "${par[@]}" "$self" --job "$hazmap" "$out" {1} {2} {3} {4} {5} <"$cases" || status=$?
  [ "$status" = 0 ] || echo "sweep: $status case(s) failed; summarising the others" >&2
fi

"$hazmap" evaluate --sweep "$out" --out "$out/summary" --quiet
echo "sweep: summary in $out/summary (report.html, tables.md)"
if [ -n "$publish" ]; then
  mkdir -p "$publish"
  cp "$out/summary/"*.png "$out/summary/tables.md" "$out/summary/"*.csv "$publish/"
  # One run's own evaluation figures as an example (the 8 cm rocks, CCM, if swept).
  example="$out/runs/size_8cm/thesis_ccm/eval"
  [ -d "$example" ] || example=$(ls -d "$out"/runs/*/*/eval 2>/dev/null | head -n 1)
  if [ -n "$example" ]; then
    name=$(basename "$(dirname "$(dirname "$example")")")_$(basename "$(dirname "$example")")
    cp "$example/metrics_over_time.png" "$publish/example_${name}_metrics_over_time.png"
    for f in "$example"/errors_*.png; do cp "$f" "$publish/example_${name}_$(basename "$f")"; done
  fi
  echo "sweep: figures and tables copied to $publish"
fi
[ "$status" = 0 ]
