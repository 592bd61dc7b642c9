#!/usr/bin/env bash
# Installs hazmap's build and test dependencies from Debian's archive, only those that
# are missing (idempotent). Run as root, or with sudo available.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libopencv-dev libeigen3-dev libyaml-cpp-dev libspdlog-dev libfmt-dev
  libgdal-dev gdal-bin zlib1g-dev
  libgtest-dev libbenchmark-dev
  parallel chromium
  pybind11-dev python3-pybind11 python3-dev python3-numpy  # Python bindings and their tests
  python3-matplotlib                                       # examples/python only
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all dependencies present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
echo "install_deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
