#!/usr/bin/env bash
# Configures and builds hazmap (Release by default) into build/. Usage:
#   tools/build.sh [Release|Debug|RelWithDebInfo]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_type="${1:-Release}"
jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE="$build_type"
cmake --build "$root/build" -j "$jobs"
