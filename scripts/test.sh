#!/usr/bin/env bash
# Quick start command (2): set up, build, run the whole ctest suite, then the sanitizer build
# (scripts/sanitize.sh: ASan + UBSan over every test that does not need the Vulkan device).
# .ci/run runs exactly this, with an empty HOME.
# GPU tests run on lavapipe unless you chose a driver (VK_DRIVER_FILES / VK_ICD_FILENAMES), with the
# validation layer on. OAS_REQUIRE_GPU=1 (the default here) makes "no Vulkan device" a failure
# instead of a visible SKIPPED; export OAS_REQUIRE_GPU=0 to allow skipping on a machine without one.
# OAS_SANITIZE=0 skips the sanitizer build (a quicker local run; CI always does it).
set -euo pipefail
cd "$(dirname "$0")/.."
export OAS_REQUIRE_GPU="${OAS_REQUIRE_GPU:-1}"
scripts/setup.sh
scripts/build.sh
start=$SECONDS
ctest --test-dir build --output-on-failure -j "$(nproc)"
echo "test: main suite took $((SECONDS - start)) s"
if [[ "${OAS_SANITIZE:-1}" != 0 ]]; then
  start=$SECONDS
  scripts/sanitize.sh
  echo "test: sanitizer build and run took $((SECONDS - start)) s"
fi
