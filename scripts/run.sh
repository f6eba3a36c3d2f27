#!/usr/bin/env bash
# Sets up, builds, and runs the main job: every integrator on scene `soft` over a sweep of
# time steps; charts, CSV and report go to results/compare-soft/ (options: --help).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
PYTHONPATH="$PWD/build/python" /usr/bin/python3 -m openmmdpd.compare "$@"
