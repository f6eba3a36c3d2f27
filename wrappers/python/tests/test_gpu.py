"""The OpenCL platform's kernels from Python: <kT> against the CPU platform's.

The trajectories on OpenCL follow the Reference platform's to float rounding for a few steps
(tests/TestGpuPlatform.cpp); over a long run they part ways, so what must agree is the
statistics.  Each case runs the same scene, integrator and seed on OpenCL and on the CPU
platform (whose trajectories equal the Reference platform's to 1e-10, TestPlatformsAgree)
and compares <kT>: each sigma (pymbar's statistical inefficiency) must be <= 0.003, else the
test FAILS (a 1 % difference must be visible), and the two must agree within 3 combined sigma.
Slow: POCL runs OpenCL on this CPU at ~20 steps/s for N = 2000.  Skipped where OpenMM has no
OpenCL platform or openmmdpd no OpenCL plugin.
"""
import numpy as np
import openmm
import pytest

import openmmdpd
from openmmdpd.analysis import standard_error
from openmmdpd.catalog import integrators
from openmmdpd.scenes import ideal_scene, soft_scene

from dpdtest import make_context, reduced_kT, set_velocities

N = 2000
DT = 0.04
EQUILIBRATION_STEPS = 200
SAMPLES = 400
STEPS_PER_SAMPLE = 5
MAX_SIGMA = 0.003


def have_opencl():
    names = {openmm.Platform.getPlatform(i).getName() for i in range(openmm.Platform.getNumPlatforms())}
    return "OpenCL" in names and any(p.endswith("libOpenMMDPDOpenCL.so") for p in openmmdpd.loaded_plugins)


pytestmark = pytest.mark.skipif(not have_opencl(), reason="no OpenCL platform or no openmmdpd OpenCL plugin")

SCENES = {"ideal": ideal_scene, "soft": soft_scene}
GPU_INTEGRATORS = ["GW", "DPD-VV", "S1", "S2", "Lowe", "PairOU"]


def mean_kT(scene_name, integrator_name, platform_name):
    """(<kT>, sigma) over SAMPLES samples after EQUILIBRATION_STEPS."""
    scene = SCENES[scene_name](num_particles=N)
    integrator = integrators(scene_name)[integrator_name](DT)
    integrator.setRandomNumberSeed(2024)
    context = make_context(scene, integrator, platform_name)
    set_velocities(context, scene.system, 7)
    integrator.step(EQUILIBRATION_STEPS)
    samples = []
    for _ in range(SAMPLES):
        integrator.step(STEPS_PER_SAMPLE)
        samples.append(reduced_kT(context, N))
    return float(np.mean(samples)), standard_error(samples)


@pytest.mark.slow
@pytest.mark.parametrize("scene_name", SCENES)
@pytest.mark.parametrize("integrator_name", GPU_INTEGRATORS)
def test_opencl_kT_agrees_with_cpu(scene_name, integrator_name):
    device, device_sigma = mean_kT(scene_name, integrator_name, "OpenCL")
    cpu, cpu_sigma = mean_kT(scene_name, integrator_name, "CPU")
    print(f"{scene_name} {integrator_name}: OpenCL {device:.4f} +- {device_sigma:.4f}, "
          f"CPU {cpu:.4f} +- {cpu_sigma:.4f}")
    assert device_sigma <= MAX_SIGMA and cpu_sigma <= MAX_SIGMA, "too short to see a 1 % difference"
    assert abs(device - cpu) <= 3 * np.hypot(device_sigma, cpu_sigma)


def test_unsupported_integrator_is_refused_on_opencl():
    """An integrator with no OpenCL kernel fails when the Context is made, not later."""
    scene = ideal_scene(num_particles=200)
    with pytest.raises(openmm.OpenMMException, match="EDPDIntegrator|kernel"):
        make_context(scene, openmmdpd.EDPDIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, 20.0, 0.01), "OpenCL")
