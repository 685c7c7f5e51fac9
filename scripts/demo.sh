#!/usr/bin/env bash
# Quick start command (1): set up, build, then generate one pixel's 121-spp, 8-dimensional point set
# with the best orthogonal array on the GPU (lavapipe), print its stratification summary and
# write the points to out/samples.csv. (The path tracer will replace this with a render.)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
mkdir -p out
build/oas-samples --sampler oa --spp 121 --dims 8 --device gpu --summary -o out/samples.csv
