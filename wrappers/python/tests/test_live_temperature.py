"""setTemperature on a live Context: every integrator, started at kT = 1,
reaches the <kT> it has when its Context is made at kT = 2, to within 3 sigma, with sigma
small enough (<= 0.0067) to see a 1 % error.

Scene: model B (rho 4, a = 25, gamma 4.5, rc 1, unit masses), N = 500 in a 5^3 box,
dt = 0.01, the CPU platform on one thread.  Each run: 2 ps at kT = 1 from random positions,
setTemperature(2 kT) on the same integrator (no reinitialize), 2 ps to relax (the kinetic
temperature relaxes in ~0.3 ps), then kT = 2 KE / (3N - 3) sampled every 0.02 ps in 10-ps
chunks until its sigma_stat = sqrt(g var / n) (g: pymbar's statistical inefficiency) is small
enough; sigma = sqrt(sigma_live^2 + sigma_target^2).

The target: the same integrator's <kT> with a Context made at kT = 2, measured in the same
test (the constructor's path, independent of the live setter's), sampled to the same sigma.
Its distance from 2 is the integrator's own discretisation error at this dt (e.g. SC-VV's
2/(1 + g dt/2) = 1.983), which test_temperature.py checks on its own; a live change has to
be indistinguishable from a fresh start.  An ignored setTemperature stays at <kT> ~ 1.
`pytest -s` prints every number; GW, S1 and Lowe run in the fast suite, the rest with -m slow.
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
SIGMA_GOAL = 0.0043      # where each of the two runs stops sampling (combined: 0.0061, a margin for the noise of g)
SAMPLE_EVERY = 2         # steps (0.02 ps)
CHUNK_TIME, MAX_SAMPLE_TIME, MIN_SAMPLE_TIME = 10.0, 400.0, 60.0   # ps; g from >= 60 ps

Staggered = openmmdpd.StaggeredDPDIntegrator

def make_integrator(name, kT):
    """The integrator `name` at temperature kT; the staggered ones sub-cycle half the particles (K = 2)
    with the forces of their fast group (a force acting on nothing: the thermostat is what
    is tested here) and Symeonidis and Karniadakis' recommended parameters for their base."""
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
# One of each family in the fast suite (~40 s); all of them with -m slow (~4 min).  That
# every setter reaches the dynamics of every integrator is tested fast in C++
# (LiveSetters.TakeEffectAtTheNextStepAlike).
FAST = ("GW-0.5", "S1", "Lowe")


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


def sample(context, integrator, goal, max_time):
    """kT samples in chunks until sigma_stat <= goal or max_time runs out."""
    samples = []
    per_chunk = round(CHUNK_TIME / (SAMPLE_EVERY * DT))
    while len(samples) * SAMPLE_EVERY * DT < max_time:
        for _ in range(per_chunk):
            integrator.step(SAMPLE_EVERY)
            samples.append(reduced_kT(context, N))
        if (len(samples) * SAMPLE_EVERY * DT >= MIN_SAMPLE_TIME
                and mean_and_error(np.array(samples))[1] <= goal):
            break
    return np.array(samples)


def sampled_kT(context, integrator):
    """(<kT>, sigma_stat, g, ps sampled) of a run already at its temperature."""
    samples = sample(context, integrator, SIGMA_GOAL, MAX_SAMPLE_TIME)
    return mean_and_error(samples) + (len(samples) * SAMPLE_EVERY * DT,)


@pytest.mark.parametrize("name", [name if name in FAST else pytest.param(name, marks=pytest.mark.slow) for name in NAMES])
def test_live_set_temperature_reaches_the_new_temperature(name):
    begin = time.time()
    seed = 101 + NAMES.index(name)
    context, integrator = start(name, seed)
    integrator.step(round(2.0 / DT))
    integrator.setTemperature(2 * KT)
    integrator.step(round(2.0 / DT))
    mean, sigma_live, g, live_time = sampled_kT(context, integrator)
    fresh_context, fresh_integrator = start(name, seed + 50, kT=2 * KT)
    fresh_integrator.step(round(2.0 / DT))
    target, sigma_fresh, g_fresh, fresh_time = sampled_kT(fresh_context, fresh_integrator)
    sigma = math.hypot(sigma_live, sigma_fresh)
    print(f"\n{name}: live kT 1 -> 2: <kT> = {mean:.4f} +- {sigma_live:.4f} (g = {g:.1f}, {live_time:g} ps); "
          f"made at kT = 2: {target:.4f} +- {sigma_fresh:.4f} (g = {g_fresh:.1f}, {fresh_time:g} ps); "
          f"sigma = {sigma:.4f}, |diff|/sigma = {abs(mean - target) / sigma:.2f}, {time.time() - begin:.1f} s")
    assert sigma <= SIGMA_LIMIT, f"sigma = {sigma:.4f}: too little statistics to see a 1 % error"
    assert abs(mean - target) <= 3 * sigma, f"<kT> = {mean:.4f}, made at kT = 2: {target:.4f}, 3 sigma = {3 * sigma:.4f}"
