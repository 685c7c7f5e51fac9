#!/usr/bin/env bash
# Runs the study (oas-study): analytic integrands, MSE vs N, slopes, plots -> docs/study/, docs/STUDY.md.
# Pass --quick for a run of 2-6 min on 2 cores (fresh clones: 5.5 min 2026-12-01, 1.8 min 2026-12-03); without
# it the full mode (about 1 to 1.5 h per scene on 2 cores: 48-93 min measured 2026-12-02/03, about
# 4 h for the three scenes, plus the other parts): every scene point gets at least 6 renders,
# then each scene shares up to 1800 s of further renders (at most 256 per point) among the points
# whose relMSE s.e. is still above 10% of the mean (--scene-min-trials, --scene-extra-seconds,
# --scene-max-trials), and the 7D and 9D scenes add the paper's 3969/4096 spp (--scene-paper-spp).
# Other oas-study options pass through, e.g. --parts scenes to rerun one part, or
# --parts scenes --scene cornell7d to (re)measure one scene and merge it with the others (shards),
# or --parts scenes --scene interior_deep --only Random Sobol BoseCMJ to measure some of a scene's
# samplers against its kept reference (sampler shards, for a scene longer than one run), or
# --parts scenes --scene cornell7d --scene-top-up to add renders to a scene's kept measurements
# where a point is still above the target (same settings; a larger budget or cap).
# The time axis is measured apart (--parts scene-costs, part of the default run): one cost run per
# scene times every measured point in 3+ alternating rounds on this machine -> docs/study/scene_costs.csv;
# the equal-time tables use only those times (rerun it alone on another machine or a GPU).
# cornell7d's four light-corner pixels get their share of the error from many CPU renders of just
# those pixels (--scene-rare-pixels, --scene-max-rare-renders).
# With --workers W or --scheduler tcp://HOST:PORT the scene part's accuracy renders run on Dask
# workers instead (scripts/study_cluster.py, its options; the same error figures, byte for byte,
# for any number of workers). Only that part: run the others (--parts analytic pairs progressive spectra cost
# scene-costs) without --workers, on one machine.
# Plots need Debian's python3-matplotlib, installed here when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  sudo=""; [[ $(id -u) -ne 0 ]] && sudo="sudo"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq python3-matplotlib
fi
scripts/build.sh
for arg in "$@"; do
  case "$arg" in
    --workers|--workers=*|--scheduler|--scheduler=*) exec /usr/bin/python3 scripts/study_cluster.py "$@" ;;
  esac
done
build/oas-study "$@"
