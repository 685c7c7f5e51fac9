#!/usr/bin/env bash
# Regenerates the README's oas-view pictures (docs/images/) with oas-view's own --screenshot, the
# code path the tests check: the window's content read back from its swapchain image. Runs under
# xvfb-run (a virtual X server) on lavapipe unless a display and driver are already there.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
mkdir -p docs/images
view() {
  if [[ -n "${DISPLAY:-}" ]]; then build/oas-view "$@"; else xvfb-run -a -s '-screen 0 1600x1000x24' build/oas-view "$@"; fi
}
# Render mode: the 7D Cornell box converged at 256 spp with Bose MJ.
view scenes/cornell7d.json --sampler bose --offset mj --spp 256 --zoom 1 --screenshot docs/images/oas-view-render.png
# Points mode: Bose CMJ, 121 points, dimensions (0, 1) of 4, its 11 x 11 strata and spectrum.
view --points --sampler bose --spp 121 --dims 4 --pair 0,1 --screenshot docs/images/oas-view-points.png
