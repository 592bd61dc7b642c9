# Sourced by tools/sweep.sh and tools/eval_hazards.sh: how far a batch of parallel jobs
# has got, for the line each job prints when it ends.
#   progress_start DIR TOTAL   (once, before the jobs; exports what the jobs read)
#   progress_note              (in a job, after it ended: prints " (k/n, elapsed, ~left)")
# Each finished job leaves a marker file in DIR, so the count is right whatever order
# the jobs end in. Without progress_start (or on another machine) it prints nothing.

progress_start() {
  rm -rf "$1"
  mkdir -p "$1"
  export HAZMAP_PROGRESS_DIR="$1" HAZMAP_PROGRESS_TOTAL="$2" HAZMAP_PROGRESS_START="$(date +%s)"
}

progress_duration() {  # seconds -> "45 s", "3 min 05 s", "2 h 04 min"
  local s="$1"
  if [ "$s" -lt 60 ]; then printf '%d s' "$s"
  elif [ "$s" -lt 3600 ]; then printf '%d min %02d s' $((s / 60)) $((s % 60))
  else printf '%d h %02d min' $((s / 3600)) $((s % 3600 / 60)); fi
}

progress_note() {
  local dir="${HAZMAP_PROGRESS_DIR:-}" total="${HAZMAP_PROGRESS_TOTAL:-}" start="${HAZMAP_PROGRESS_START:-}"
  [ -n "$dir" ] && [ -n "$total" ] && [ -n "$start" ] && [ -d "$dir" ] || return 0
  mktemp "$dir/done.XXXXXX" >/dev/null
  local done elapsed
  done=$(find "$dir" -name 'done.*' | wc -l)
  elapsed=$(($(date +%s) - start))
  if [ "$done" -ge "$total" ]; then
    printf ' (%d/%d, %s in all)' "$done" "$total" "$(progress_duration "$elapsed")"
  else
    printf ' (%d/%d, %s elapsed, ~%s left)' "$done" "$total" "$(progress_duration "$elapsed")" \
      "$(progress_duration $((elapsed * (total - done) / done)))"
  fi
}
