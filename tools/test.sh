#!/usr/bin/env bash
# Installs dependencies, builds hazmap and runs every test with ctest. Exits non-zero
# on any failure.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/install_deps.sh"
"$root/tools/build.sh" Release
cd "$root/build"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
