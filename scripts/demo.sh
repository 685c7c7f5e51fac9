#!/usr/bin/env bash
# Quick start command (1): set up, build, then render the default scene - the 7D Cornell box
# (antialiasing, thin lens, motion blur, area light, direct lighting) with the best orthogonal
# array at 121 spp on the GPU (lavapipe unless you chose a driver). Prints where the EXR and PNG
# are. The first render compiles the path-tracing pipeline (about 20 s on lavapipe).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
build/oas-render scenes/cornell7d.json --explain
build/oas-render scenes/cornell7d.json -o out/cornell7d.exr
