#!/usr/bin/env bash
# Sets up, builds, and runs the main job: scene `soft` with DPD-VV, printing <kT>.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
PYTHONPATH="$PWD/build/python" /usr/bin/python3 examples/run_soft.py "$@"
