#!/usr/bin/env bash
# Builds the C++ tests with AddressSanitizer into build-asan/ and runs those that read
# checkpoints (damaged, truncated, foreign) and the EDPD pair-variable tests under it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="-fsanitize=address -fno-omit-frame-pointer" \
    -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address -DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=address "$@"
cmake --build build-asan -j"$(nproc)" --target TestDPD
cd build-asan
ASAN_OPTIONS=detect_leaks=0 ./tests/TestDPD --gtest_filter='*Checkpoint*:DamagedPairVariables.*:EDPDIntegrator.*'
