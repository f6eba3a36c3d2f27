#!/usr/bin/env bash
# Sets up the machine (idempotent) and builds everything into build/ (or $OPENMMDPD_BUILD_DIR).
# Extra arguments go to CMake's configure step (e.g. -DOPENMM_DIR=$CONDA_PREFIX).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${OPENMMDPD_BUILD_DIR:-build}"
bash scripts/setup.sh
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$build_dir" -j"$(nproc)"
