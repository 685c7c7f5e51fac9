#!/bin/sh
# oas-smallpt from the command line (ctest SmallptGpu.CommandLine): the benchmark at a toy size
# prints a row for every configuration, and a count Bose cannot make is refused with exit 1 and
# the nearest counts it can. No Vulkan device: exit 77 (ctest's SKIPPED), a failure under
# OAS_REQUIRE_GPU=1 as for the other GPU tests.
set -u
bin=$1
out=$("$bin" --bench --size 8 --spp 9 --rounds 1 --seeds 1 --ref-spp 16 2>&1)
rc=$?
echo "$out"
if [ "$rc" = 77 ]; then
  [ "${OAS_REQUIRE_GPU:-0}" = 1 ] && { echo "FAIL: no Vulkan device and OAS_REQUIRE_GPU=1"; exit 1; }
  echo "SKIPPED: no Vulkan device"; exit 77
fi
[ "$rc" = 0 ] || { echo "FAIL: --bench exited $rc"; exit 1; }
for row in "own hash" "oas inline " "oas inline, 2 vert." "oas inline, 3 vert." "oas prefetch " "oas prefetch, 2 vert." "oas prefetch, 3 vert."; do
  echo "$out" | grep -q "^$row" || { echo "FAIL: no row '$row'"; exit 1; }
done
bad=$("$bin" --spp 63 2>&1)
rc=$?
echo "$bad"
[ "$rc" = 1 ] || { echo "FAIL: --spp 63 exited $rc, not 1"; exit 1; }
echo "$bad" | grep -q -- "--spp 63: .*nearest valid spp: 49, 64" || { echo "FAIL: --spp 63's message does not name 49 and 64"; exit 1; }
echo "PASS"
