#!/usr/bin/env bash
# Installs the Debian 12 packages oas needs to build and test, only those missing, plus any
# package named on the command line (scripts/fuzz.sh adds clang and its fuzzer runtime).
# Needs root (or sudo). Safe to run again: it does nothing when everything is present.
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers vulkan-tools glslang-tools spirv-tools
  libglm-dev libglfw3-dev libopenexr-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libstb-dev libgtest-dev
  python3-scipy  # tests/sobol_scipy_test.py: the Sobol baseline against scipy.stats.qmc.Sobol
  python3-distributed  # scripts/cluster.py (Dask) and its test, tests/cluster_test.py
  xvfb xauth     # tests/view_test.cpp: oas-view under a virtual X server (xvfb-run); lavapipe presents to X11
  "$@"
)
missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi
echo "setup: installing ${missing[*]}"
sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
