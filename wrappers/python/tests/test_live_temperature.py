"""setTemperature on a live Context (issue 13, point 3): every integrator, started at kT = 1,
reaches the <kT> it has when its Context is made at kT = 2, to within 3 sigma, with sigma
small enough (<= 0.0067) to see a 1 % error.

Scene: model B (rho 4, a = 25, gamma 4.5, rc 1, unit masses), N = 500 in a 5^3 box,
dt = 0.01, the CPU platform on one thread.  Each run: 2 ps at kT = 1 from random positions,
setTemperature(2 kT) on the same integrator (no reinitialize), 2 ps to relax (the kinetic
temperature relaxes in ~0.3 ps), then kT = 2 KE / (3N - 3) sampled every 0.02 ps in 10-ps
chunks until sigma is small enough.  sigma = sqrt(sigma_stat^2 + error^2), sigma_stat =
sqrt(g var / n) with g pymbar's statistical inefficiency, `error` that of the target.

The target: each integrator's own <kT> at kT = 2 and this dt, measured with a Context made
at kT = 2 (FRESH_KT2, re-measured by the slow test below).  A live change has to be
indistinguishable from that; the targets' distance from 2 is the integrators' own
discretisation error (e.g. SC-VV's 2/(1 + g dt/2) = 1.983, test_temperature.py), which
test_temperature.py checks on its own.  An ignored setTemperature stays at <kT> ~ 1.
`pytest -s` prints every number.
"""
import math
import time

import numpy as np
import openmm
import pytest
from pymbar import timeseries

import openmmdpd
from openmmdpd import scenes

from dpdtest import KT, reduced_kT, set_velocities

N, DT, FRICTION, CUTOFF = 500, 0.01, 4.5, 1.0
SIGMA_LIMIT = 0.0067     # 1 % of kT = 2 is 3 sigma
SIGMA_GOAL = 0.006       # where sampling stops (a margin for the noise of g)
SAMPLE_EVERY = 2         # steps (0.02 ps)
CHUNK_TIME, MAX_SAMPLE_TIME, MIN_SAMPLE_TIME = 10.0, 200.0, 60.0   # ps; g from >= 60 ps

Staggered = openmmdpd.StaggeredDPDIntegrator

# <kT> at kT = 2 from a Context made at kT = 2 (3 ps relaxed, then 600 ps), and its sigma.
FRESH_KT2 = {
    "GW-0.5": (2.0110, 0.0024),
    "DPD-VV": (1.9975, 0.0024),
    "SC-VV": (1.9882, 0.0023),
    "S1": (1.9997, 0.0025),
    "S2": (2.0029, 0.0025),
    "Lowe": (1.9981, 0.0013),
    "PairOU": (1.9985, 0.0023),
    "EDPD-OneSided": (2.0078, 0.0026),
    "EDPD-Symmetric": (2.0104, 0.0026),
    "Staggered-VV": (2.0089, 0.0024),
    "Staggered-Lowe": (1.9988, 0.0013),
}


def make_integrator(name, kT):
    """The integrator `name` at temperature kT; the staggered ones sub-cycle half the particles (K = 2)
    with the forces of their fast group (a force acting on nothing: the thermostat is what
    is tested here) and paper 002's recommended parameters for their base."""
    if name.startswith("EDPD"):
        integrator = openmmdpd.EDPDIntegrator(kT, FRICTION, CUTOFF, 100.0, DT)  # alpha dt = 1
        integrator.setScheme(getattr(openmmdpd.EDPDIntegrator, name.split("-")[1]))
    elif name.startswith("Staggered"):
        integrator = Staggered(kT, FRICTION, CUTOFF, DT, 2)
        integrator.setBaseScheme(Staggered.LoweAndersen if name.endswith("Lowe") else Staggered.VelocityVerlet)
        integrator.useRecommendedParameters()
        integrator.setPolymerParticles(list(range(0, N, 2)))
    elif name in ("S1", "S2"):
        integrator = openmmdpd.ShardlowIntegrator(kT, FRICTION, CUTOFF, DT)
        integrator.setOrder(int(name[1]))
    elif name in ("Lowe", "PairOU"):
        integrator = openmmdpd.LoweAndersenIntegrator(kT, FRICTION, CUTOFF, DT)
        integrator.setMethod(openmmdpd.LoweAndersenIntegrator.Lowe if name == "Lowe"
                             else openmmdpd.LoweAndersenIntegrator.PairOrnsteinUhlenbeck)
    else:
        integrator = openmmdpd.DPDVVIntegrator(kT, FRICTION, CUTOFF, DT)
        integrator.setVariant({"GW-0.5": openmmdpd.DPDVVIntegrator.GrootWarren, "DPD-VV": openmmdpd.DPDVVIntegrator.DPDVV,
                               "SC-VV": openmmdpd.DPDVVIntegrator.SelfConsistent}[name])
        integrator.setLambda(0.5)
    return integrator


NAMES = ["GW-0.5", "DPD-VV", "SC-VV", "S1", "S2", "Lowe", "PairOU", "EDPD-OneSided", "EDPD-Symmetric",
         "Staggered-VV", "Staggered-Lowe"]


def start(name, seed, kT=KT):
    """A Context of model B with the integrator `name` at kT (velocities at kT = 1), and the integrator."""
    scene = scenes.soft_scene(num_particles=N, seed=seed)
    if name.startswith("Staggered"):
        fast = scenes.periodic_marker_force()
        fast.setForceGroup(scenes.FAST_FORCE_GROUP)
        scene.system.addForce(fast)
    integrator = make_integrator(name, kT)
    integrator.setRandomNumberSeed(seed)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(scene.positions)
    set_velocities(context, scene.system, seed)
    return context, integrator


def mean_and_error(samples):
    """(mean, sqrt(g var/n), g) with g pymbar's statistical inefficiency."""
    g = timeseries.statisticalInefficiency(samples)
    return samples.mean(), math.sqrt(g * samples.var() / len(samples)), g


def sample(context, integrator, error, goal, max_time):
    """kT samples in chunks until sqrt(sigma_stat^2 + error^2) <= goal or max_time runs out."""
    samples = []
    per_chunk = round(CHUNK_TIME / (SAMPLE_EVERY * DT))
    while len(samples) * SAMPLE_EVERY * DT < max_time:
        for _ in range(per_chunk):
            integrator.step(SAMPLE_EVERY)
            samples.append(reduced_kT(context, N))
        if (len(samples) * SAMPLE_EVERY * DT >= MIN_SAMPLE_TIME
                and math.hypot(mean_and_error(np.array(samples))[1], error) <= goal):
            break
    return np.array(samples)


@pytest.mark.parametrize("name", NAMES)
def test_live_set_temperature_reaches_the_new_temperature(name):
    begin = time.time()
    target, error = FRESH_KT2[name]
    context, integrator = start(name, seed=101 + NAMES.index(name))
    integrator.step(round(2.0 / DT))
    integrator.setTemperature(2 * KT)
    integrator.step(round(2.0 / DT))
    samples = sample(context, integrator, error, SIGMA_GOAL, MAX_SAMPLE_TIME)
    mean, sigma_stat, g = mean_and_error(samples)
    sigma = math.hypot(sigma_stat, error)
    print(f"\n{name}: live kT 1 -> 2, {len(samples) * SAMPLE_EVERY * DT:g} ps sampled: <kT> = {mean:.4f}, "
          f"sigma_stat = {sigma_stat:.4f} (g = {g:.1f}), target {target:.4f} +- {error:.4f} (made at kT = 2), "
          f"sigma = {sigma:.4f}, |diff|/sigma = {abs(mean - target) / sigma:.2f}, {time.time() - begin:.1f} s")
    assert sigma <= SIGMA_LIMIT, f"sigma = {sigma:.4f}: too little statistics to see a 1 % error"
    assert abs(mean - target) <= 3 * sigma, f"<kT> = {mean:.4f}, target {target:.4f} +- 3 x {sigma:.4f}"


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_fresh_targets(name):
    """FRESH_KT2 re-measured: a Context made at kT = 2, 3 ps relaxed, 600 ps sampled."""
    target, error = FRESH_KT2[name]
    context, integrator = start(name, seed=201 + NAMES.index(name), kT=2 * KT)
    integrator.step(round(3.0 / DT))
    mean, sigma_stat, g = mean_and_error(sample(context, integrator, 0.0, 0.0, 600.0))
    sigma = math.hypot(sigma_stat, error)
    print(f"\n{name} made at kT = 2: <kT> = {mean:.4f} +- {sigma_stat:.4f} (g = {g:.1f}); stored {target:.4f} +- {error:.4f}")
    assert abs(mean - target) <= 3 * sigma
