#!/usr/bin/env bash
# Builds hazmap with AddressSanitizer + UndefinedBehaviorSanitizer (float-cast-overflow
# too) into build-sanitize/ (tests only, no benchmarks; no Python bindings either, since
# HAZMAP_SANITIZE turns HAZMAP_BUILD_PYTHON off) and runs the whole ctest suite under it,
# the seeded parser fuzz pass (ParserFuzz.*) included. Any sanitizer report
# aborts its test, so the script exits non-zero. Usage: tools/sanitize.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="$(nproc 2>/dev/null || echo 2)"
build="$root/build-sanitize"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
# -O1: a fraction of Release's test time under ASan. -g1: line tables only, which is all a
# report's stack trace reads; compiles 16-33 % faster than -g (the build is most of CI's time).
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DHAZMAP_SANITIZE=ON -DHAZMAP_BUILD_TOOLS=OFF "${launcher[@]}"
cmake --build "$build" -j "$jobs"
export ASAN_OPTIONS="abort_on_error=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$build"
# ReadmeWalkthrough runs the README's quick start end to end (renders, runs, evaluates):
# the Release suite runs it; under ASan it takes over its 5-minute limit and reaches no
# code the other command-line tests do not. Of the incremental-hazard configs (75-90 s
# each here) the variants of a stack that also runs (cadre_flight static and without the
# coarse fill, thesis_ccm's centre ring and fill) are left to the Release suite.
skip='^ReadmeWalkthrough\.|IncrementalHazards.*"(cadre_flight_static|cadre_flight_no_fill|thesis_ccm_centre_ring|thesis_ccm_fill)"$'
log="$build/ctest.log"
if ! ctest --output-on-failure -j "$jobs" --timeout 1200 -E "$skip" 2>&1 | tee "$log"; then
  # LeakSanitizer's own tracer can crash while a passed test's process exits
  # ("Tracer caught signal 11", "LeakSanitizer has encountered a fatal error";
  # in RowOffset.KnownSubPixelShift... on this machine, alone too, after the test passed).
  # Only then are the failed tests run once more with ASan and UBSan but without the leak
  # check that could not run; any other report fails again, and any other failure stands.
  # The failed tests by name (ctest's --rerun-failed goes by number, which -E shifts).
  failed="$(sed -n 's/^[[:space:]]*[0-9]* - \(.*\) ([^)]*)$/\1/p' "$log" |
    perl -pe 's/([^\w\/ "\n-])/\\$1/g' | paste -sd'|')"
  if [ -n "$failed" ] && grep -q "LeakSanitizer has encountered a fatal error" "$log"; then
    echo "sanitize: LeakSanitizer itself crashed; the failed tests once more without the leak check"
    ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0" ctest --output-on-failure --timeout 1200 -R "^($failed)\$"
  else
    exit 1
  fi
fi

