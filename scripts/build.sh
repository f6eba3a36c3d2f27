#!/usr/bin/env bash
# Sets up the machine (idempotent) and builds everything into build/.
# Extra arguments go to CMake's configure step (e.g. -DOPENMM_DIR=$CONDA_PREFIX).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build build -j"$(nproc)"
