#!/usr/bin/env bash
# Runs the study (oas-study): analytic integrands, MSE vs N, slopes, plots -> docs/study/, docs/STUDY.md.
# Pass --quick for a run of about 11 min on 2 cores; without it the full mode, which renders every
# scene point until its relMSE has s.e. <= 10% (8 to 64 renders, at most 120 s of renders per
# point: not yet timed since that change; expect hours on 2 cores, bound it with
# --scene-seconds-per-point / --scene-max-trials).
# Other oas-study options pass through, e.g. --parts scenes to rerun one part.
# Plots need Debian's python3-matplotlib, installed here when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  sudo=""; [[ $(id -u) -ne 0 ]] && sudo="sudo"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq python3-matplotlib
fi
scripts/build.sh
build/oas-study "$@"
