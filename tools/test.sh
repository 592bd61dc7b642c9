#!/usr/bin/env bash
# Installs dependencies, builds hazmap and runs every test with ctest, then installs the
# CMake package into a scratch prefix and builds and runs examples/embed_core and
# examples/custom_rule against it (the map core, hazmap::core, embedded by another project,
# and a rule written outside it). Exits non-zero on any failure.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/install_deps.sh"
"$root/tools/build.sh" Release
cd "$root/build"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
cmake --install "$root/build" --prefix "$scratch/prefix" --component dev > /dev/null
for example in embed_core custom_rule; do
  cmake -S "$root/examples/$example" -B "$scratch/$example" -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_PREFIX_PATH="$scratch/prefix" > /dev/null
  cmake --build "$scratch/$example"
  "$scratch/$example/$example"
done
