#!/usr/bin/env bash
# Sets up, builds, and runs the whole fast test suite: the C++ tests (GoogleTest) and the
# Python tests (pytest), both through ctest.  Long statistical runs are marked `slow` and
# are left to the benchmark tool.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
ctest --output-on-failure -L fast
