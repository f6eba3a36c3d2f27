#!/usr/bin/env bash
# Sets up, builds, and runs the whole fast test suite (the C++ tests, GoogleTest, and the
# Python tests, pytest, both through ctest) twice: against Debian's OpenMM 7.7 in build/, and
# against OpenMM 8 in build-openmm8/.  OpenMM 8 is $OPENMM8_DIR, else ../shared/openmm-8.5
# next to the repository; without one the second run is skipped, saying so.  Long statistical
# runs are marked `slow` and are left to the benchmark tool.  Then it builds the documentation
# site (scripts/docs.sh), which must have no warning, and checks an install of build/
# (scripts/install_test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

summary=()
failed=0

# The fast suite of one build folder; adds its counts (ctest's, and pytest's from ctest's log) to the summary.
run_suite() {
  local label="$1" dir="$2" status=0
  echo "=== $label: fast suite in $dir ==="
  (cd "$dir" && ctest --output-on-failure -L fast -j "$(nproc)") | tee "$dir/fast-suite.log" || status=$?
  local ctest_count pytest_count
  ctest_count=$(grep -E "tests passed, .* tests failed out of" "$dir/fast-suite.log" || echo "no ctest summary")
  # pytest runs once per test file: add up the files' closing lines.
  pytest_count=$(grep -E "^[0-9]+ (passed|failed|deselected).* in [0-9.]+s" "$dir/Testing/Temporary/LastTest.log" |
    grep -oE "[0-9]+ (passed|failed|deselected)" |
    awk '{n[$2] += $1} END {printf "%d passed, %d failed, %d deselected (slow)", n["passed"], n["failed"], n["deselected"]}')
  summary+=("$label: ctest (every C++ test, layout, each pytest file): $ctest_count; pytest: $pytest_count")
  [ "$status" -eq 0 ] || failed=1
}

find_openmm8() {
  local d
  for d in "${OPENMM8_DIR:-}" ../shared/openmm-8.5; do
    if [ -n "$d" ] && [ -f "$d/lib/libOpenMM.so" ]; then (cd "$d" && pwd); return; fi
  done
}

bash scripts/build.sh
run_suite "OpenMM 7.7 (Debian)" build
echo "=== install test (OpenMM 7.7) ==="
if bash scripts/install_test.sh build; then
  summary+=("install test (cmake --install, find_package, Python from the prefix): passed")
else
  summary+=("install test: FAILED (scripts/install_test.sh)")
  failed=1
fi

omm8=$(find_openmm8)
if [ -n "$omm8" ]; then
  # TestDPDCUDA is built too (not run: it needs a driver), so that its CUDA build is checked.
  # The 8-thread race check ran in the first suite; once per run keeps CI short.
  OPENMMDPD_BUILD_DIR=build-openmm8 bash scripts/build.sh -DOPENMM_DIR="$omm8" -DOPENMMDPD_BUILD_CUDA_TESTS=ON \
    -DOPENMMDPD_TEST_EIGHT_THREADS=OFF
  # Which OpenMM Python imports: its package, and the libraries it was linked against.  Not
  # OPENMM_PLUGIN_DIR: the tests and the package find that OpenMM's plugins themselves.
  export PYTHONPATH="$omm8/python${PYTHONPATH:+:$PYTHONPATH}" LD_LIBRARY_PATH="$omm8/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  unset OPENMM_PLUGIN_DIR
  run_suite "OpenMM 8 ($omm8)" build-openmm8
else
  summary+=("OpenMM 8: SKIPPED: none found in \$OPENMM8_DIR or ../shared/openmm-8.5")
fi

# The documentation site, every warning an error: its pages and API reference are part of the product.
echo "=== documentation site ==="
if bash scripts/docs.sh -q; then
  summary+=("docs: built with no warning")
else
  summary+=("docs: FAILED (scripts/docs.sh)")
  failed=1
fi

echo "=== summary ==="
printf '%s\n' "${summary[@]}"
exit $failed
