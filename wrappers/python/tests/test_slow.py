"""Long statistical runs (marker `slow`): select them with `pytest -m slow`.

CPU platform; the thread count comes from OPENMMDPD_TEST_THREADS (default 1).
"""
import os

import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import analysis, scenes

DPDVV = openmmdpd.DPDVVIntegrator
KT = openmmdpd.KT_TEMPERATURE

# Groot-Warren, lambda = 0.5 (plain velocity Verlet), model B (`soft`, a = 25, rho = 4,
# gamma = 4.5), N = 4000: <kT> against dt.
GW_SOFT_KT = {0.01: 1.006, 0.02: 1.010, 0.03: 1.018, 0.05: 1.042, 0.07: 1.094}
NUM_PARTICLES = 4000
EQUILIBRATION_TIME = 2.0   # ps (reduced time units)
SAMPLE_TIME = 40.0         # ps


@pytest.mark.slow
def test_groot_warren_soft_kinetic_temperature_sweep():
    threads = os.environ.get("OPENMMDPD_TEST_THREADS", "1")
    failures = []
    for k, (dt, expected) in enumerate(sorted(GW_SOFT_KT.items())):
        scene = scenes.build_scene("soft", num_particles=NUM_PARTICLES)
        integrator = DPDVV(KT, 4.5 / unit.picosecond, 1.0 * unit.nanometer, dt * unit.picosecond)
        integrator.setVariant(DPDVV.GrootWarren)
        integrator.setLambda(0.5)
        integrator.setRandomNumberSeed(101 + k)
        context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"),
                                 {"Threads": threads})
        context.setPositions(scene.positions)
        context.setVelocitiesToTemperature(KT, 11 + k)
        integrator.step(round(EQUILIBRATION_TIME / dt))
        samples = []
        for _ in range(round(SAMPLE_TIME / dt)):
            integrator.step(1)
            # groups=0: no force is re-evaluated for the (unused) potential energy.
            ke = context.getState(getEnergy=True, groups=0).getKineticEnergy().value_in_unit(
                unit.kilojoule_per_mole)
            samples.append(2 * ke / (3 * NUM_PARTICLES - 3))
        mean, stderr = analysis.block_average(samples, nblocks=20)
        ok = abs(mean - expected) < 3 * stderr + 0.001
        print(f"\nGW lambda=0.5 soft N={NUM_PARTICLES} dt={dt}: <kT> = {mean:.4f} +- {stderr:.4f} "
              f"(reference {expected}) {'ok' if ok else 'FAIL'}")
        if not ok:
            failures.append((dt, mean, stderr, expected))
        del context
    assert not failures, f"<kT> off the reference (dt, mean, stderr, reference): {failures}"
