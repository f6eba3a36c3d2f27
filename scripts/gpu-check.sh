#!/usr/bin/env bash
# The device check, for a machine with an NVIDIA GPU and its driver (about 8 minutes): builds
# against an OpenMM 8 with the CUDA platform ($OPENMM8_DIR, else ../shared/openmm-8.5, as
# scripts/test.sh finds it) into build-cuda/, runs the GPU tests on CUDA (TestDPDCUDA: the
# body of TestDPDOpenCL), then prints particle-steps/s at 32 000, 256 000 and a million
# particles of model B for GW, S1, Lowe, LangevinMiddleIntegrator and OpenMM's DPDIntegrator,
# GW unsheared against sheared with the pressure tensor sampled, and GW with MDPDForce in
# place of the soft force.
#
#     bash scripts/gpu-check.sh
set -euo pipefail
cd "$(dirname "$0")/.."
openmm=""
for d in "${OPENMM8_DIR:-}" ../shared/openmm-8.5; do
  if [ -n "$d" ] && [ -f "$d/lib/libOpenMM.so" ]; then openmm=$(cd "$d" && pwd); break; fi
done
[ -n "$openmm" ] || { echo "gpu-check: no OpenMM 8 in \$OPENMM8_DIR or ../shared/openmm-8.5" >&2; exit 1; }
[ -f "$openmm/lib/plugins/libOpenMMCUDA.so" ] || { echo "gpu-check: $openmm has no CUDA platform" >&2; exit 1; }
export LD_LIBRARY_PATH="$openmm/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PYTHONPATH="$PWD/build-cuda/python:$openmm/python"

echo "=== build (OpenMM $openmm, CUDA tests on) ==="
cmake -S . -B build-cuda -DCMAKE_BUILD_TYPE=Release -DOPENMM_DIR="$openmm" -DOPENMMDPD_BUILD_CUDA_TESTS=ON > /dev/null
cmake --build build-cuda -j"$(nproc)" > build-cuda/build.log || { tail -30 build-cuda/build.log; exit 1; }

echo "=== the GPU tests on CUDA ==="
build-cuda/tests/TestDPDCUDA --gtest_brief=1

echo "=== particle-steps/s on CUDA ==="
/usr/bin/python3 -m openmmdpd.bench scale --platform CUDA --repeats 3
/usr/bin/python3 -m openmmdpd.bench shear --pressure-tensor --rate 0.1 --integrators GW --sizes 32000 1000000 \
    --threads 1 --repeats 3 --platform CUDA
/usr/bin/python3 -m openmmdpd.bench mdpd --integrators GW --sizes 32000 256000 --threads 1 --repeats 3 --platform CUDA
