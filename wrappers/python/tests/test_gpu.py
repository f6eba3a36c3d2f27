"""The OpenCL platform's kernels from Python: <kT> and the sheared viscosity against the CPU platform's.

The trajectories on OpenCL follow the Reference platform's to float rounding for a few steps
(tests/TestGpuPlatform.cpp); over a long run they part ways, so what must agree is the
statistics.  Each case runs the same scene, integrator and seed on OpenCL and on the CPU
platform (whose trajectories equal the Reference platform's to 1e-10, TestPlatformsAgree)
and compares <kT>: each sigma (pymbar's statistical inefficiency) must be <= 0.003, else the
test FAILS (a 1 % difference must be visible), and the two must agree within 3 combined sigma.
Under Lees-Edwards shear (model B, N 4000, GW, rate 0.5) the velocity profile's slope is the
rate within 2 % on OpenCL, and the NEMD viscosity -<P_xy>/rate agrees with the CPU's within 3
combined sigma (each <= 0.02, to see a 5 % difference).
Slow: POCL runs OpenCL on this CPU at ~20 steps/s for N = 2000 (the sheared case: ~8 minutes).
Skipped where OpenMM has no OpenCL platform or openmmdpd no OpenCL plugin.
"""
import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import catalog, shear, staggered
from openmmdpd.analysis import standard_error
from openmmdpd.catalog import integrators
from openmmdpd.pressure import pressure_tensor
from openmmdpd.scenes import build_scene, ideal_scene, soft_scene

from dpdtest import have_opencl, make_context, reduced_kT, set_velocities

N = 2000
DT = 0.04
EQUILIBRATION_STEPS = 200
SAMPLES = 400
STEPS_PER_SAMPLE = 5
MAX_SIGMA = 0.003


pytestmark = pytest.mark.skipif(not have_opencl(), reason="no OpenCL platform or no openmmdpd OpenCL plugin")

SCENES = {"ideal": ideal_scene, "soft": soft_scene}
GPU_INTEGRATORS = ["GW", "DPD-VV", "SC-VV", "S1", "S2", "Lowe", "PairOU", "Lowe-mid", "PairOU-mid", "OC", "EDPD-OneSided",
                   "EDPD-Symmetric"]
EDPD_ALPHA = 10.0  # /ps: alpha dt = 0.4
# The symmetric scheme damps the kinetic energy's fluctuations more slowly: 4 times the samples keep sigma <= 0.003.
SAMPLE_FACTOR = {"EDPD-Symmetric": 4}


def edpd(scheme):
    """EDPDIntegrator with the catalog's friction and cutoff, alpha EDPD_ALPHA, in the given scheme."""
    def make(dt):
        integrator = openmmdpd.EDPDIntegrator(openmmdpd.KT_TEMPERATURE, catalog.FRICTION, catalog.CUTOFF, EDPD_ALPHA, dt)
        integrator.setScheme(scheme)
        return integrator
    return make


def factories(scene_name):
    """The catalog's integrators for the scene, and extended DPD in both schemes."""
    return {**integrators(scene_name), "EDPD-OneSided": edpd(openmmdpd.EDPDIntegrator.OneSided),
            "EDPD-Symmetric": edpd(openmmdpd.EDPDIntegrator.Symmetric)}
SHEAR_RATE, SHEAR_DT, SHEAR_TIME, BLOCK = 0.5, 0.01, 60.0, 0.5


def mean_kT(scene_name, integrator_name, platform_name):
    """(<kT>, sigma) over SAMPLES samples (times SAMPLE_FACTOR) after EQUILIBRATION_STEPS."""
    scene = SCENES[scene_name](num_particles=N)
    integrator = factories(scene_name)[integrator_name](DT)
    integrator.setRandomNumberSeed(2024)
    context = make_context(scene, integrator, platform_name)
    set_velocities(context, scene.system, 7)
    integrator.step(EQUILIBRATION_STEPS)
    samples = []
    for _ in range(SAMPLES * SAMPLE_FACTOR.get(integrator_name, 1)):
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


def sheared_model_b(platform_name):
    """(eta, sigma, slope/rate, sigma) of GW on model B at SHEAR_RATE over SHEAR_TIME, from block
    means of P_xy and the velocity profile at the end of each block, after 5 time units."""
    scene = build_scene("soft", seed=2024)
    integrator = integrators("soft")["GW"](SHEAR_DT)
    integrator.setRandomNumberSeed(2024)
    integrator.setShearRate(SHEAR_RATE / unit.picosecond)
    integrator.setPressureTensorEnabled(True)
    context = make_context(scene, integrator, platform_name)
    height = scene.system.getDefaultPeriodicBoxVectors()[1][1].value_in_unit(unit.nanometer)
    set_velocities(context, scene.system, 7)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    positions = scene.positions.value_in_unit(unit.nanometer)
    v[:, 0] += shear.streaming_velocity(positions[:, 1], SHEAR_RATE, height)
    context.setVelocities(v)
    integrator.step(round(5 / SHEAR_DT))
    pxy, slopes = [], []
    for _ in range(round(SHEAR_TIME / BLOCK)):
        integrator.resetPressureTensor()
        integrator.step(round(BLOCK / SHEAR_DT))
        pxy.append(pressure_tensor(integrator)[3])
        state = context.getState(getPositions=True, getVelocities=True)
        r, u = state.getPositions(asNumpy=True), state.getVelocities(asNumpy=True)
        slopes.append(shear.profile_slope(*shear.velocity_profile(r, u, height, 10))[0] / SHEAR_RATE)
    return (-np.mean(pxy) / SHEAR_RATE, standard_error(pxy) / SHEAR_RATE, np.mean(slopes), standard_error(slopes))


@pytest.mark.slow
def test_opencl_shear_profile_and_viscosity_agree_with_cpu():
    eta, sigma, slope, slope_sigma = sheared_model_b("OpenCL")
    cpu, cpu_sigma, _, _ = sheared_model_b("CPU")
    print(f"model B, GW, rate {SHEAR_RATE}: OpenCL eta {eta:.4f} +- {sigma:.4f}, slope/rate {slope:.4f} +- "
          f"{slope_sigma:.4f}; CPU eta {cpu:.4f} +- {cpu_sigma:.4f}")
    assert slope_sigma <= 0.02 / 3 and abs(slope - 1) <= 0.02
    assert sigma <= 0.02 and cpu_sigma <= 0.02, "too short to see a 5 % difference"
    assert abs(eta - cpu) <= 3 * np.hypot(sigma, cpu_sigma)


@pytest.mark.slow
@pytest.mark.parametrize("base", ["vv", "lowe"])
def test_opencl_staggered_kT_agrees_with_cpu(base):
    """StaggeredDPDIntegrator (K = 5, dt 0.002) on 2000 particles with 10 FENE chains of 5 beads:
    the total <kT> (10 block averages) on OpenCL against the CPU's, each sigma <= 0.003."""
    scene, state = staggered.equilibrated_fene_chains(chain_length=5, num_chains=10, num_particles=2000, time_units=2.0)
    runs = {name: staggered.run_fene_chains(scene, state, 5, 0.002, 80.0, base=base, platform=name)["total_kT"]
            for name in ("OpenCL", "CPU")}
    (device, device_sigma), (cpu, cpu_sigma) = runs["OpenCL"], runs["CPU"]
    print(f"staggered {base}: OpenCL {device:.4f} +- {device_sigma:.4f}, CPU {cpu:.4f} +- {cpu_sigma:.4f}")
    assert device_sigma <= MAX_SIGMA and cpu_sigma <= MAX_SIGMA, "too short to see a 1 % difference"
    assert abs(device - cpu) <= 3 * np.hypot(device_sigma, cpu_sigma)


def test_periodic_openmm_force_under_shear_in_a_rectangular_box_is_refused_on_opencl():
    """What the device cannot do fails when the Context is made, naming the platform: OpenMM's
    device kernels for a System made with a rectangular box ignore the sliding box's tilt."""
    scene = ideal_scene(num_particles=200)
    springs = openmm.HarmonicBondForce()
    springs.addBond(0, 1, 0.5, 100.0)
    springs.setUsesPeriodicBoundaryConditions(True)
    scene.system.addForce(springs)
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, 0.01)
    integrator.setShearRate(0.5 / unit.picosecond)
    with pytest.raises(openmm.OpenMMException, match="default box is rectangular.*not supported on the OpenCL platform"):
        make_context(scene, integrator, "OpenCL")
