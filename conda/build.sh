#!/usr/bin/env bash
# conda-build: the README's conda steps (build against the environment's OpenMM, test, install
# the Python package into its site-packages).  Untested: see README.
set -euo pipefail
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DOPENMM_DIR="$PREFIX" \
      -DCMAKE_INSTALL_PREFIX="$PREFIX" -DPython3_EXECUTABLE="$PYTHON"
cmake --build build -j"${CPU_COUNT:-2}"
(cd build && ctest -L fast -E python-tests --output-on-failure)
cmake --install build
