#!/usr/bin/env bash
# Quick start command (2): set up, build, run the whole ctest suite. .ci/run runs exactly this.
# GPU tests run on lavapipe unless you chose a driver (VK_DRIVER_FILES / VK_ICD_FILENAMES), with the
# validation layer on. OAS_REQUIRE_GPU=1 (the default here) makes "no Vulkan device" a failure
# instead of a visible SKIPPED; export OAS_REQUIRE_GPU=0 to allow skipping on a machine without one.
set -euo pipefail
cd "$(dirname "$0")/.."
export OAS_REQUIRE_GPU="${OAS_REQUIRE_GPU:-1}"
scripts/setup.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
