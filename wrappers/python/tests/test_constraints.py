"""<kT> of a fluid of rigid dimers counts 3N - N_constraints - 3 degrees of freedom.

An ideal gas (no conservative force) of 500 dimers (N = 1000 unit-mass particles, bond 0.5
constrained) at rho = 3, gamma = 4.5, rc = 1, kT = 1.  The thermostats act on the pairs;
the constraints (RATTLE: positions after each drift, velocities after each velocity change)
remove the bond-direction velocity, so the kinetic energy has 3N - N/2 - 3 = 2497 quadratic
terms.  kT = 2 KE / (3N - Nc - 3) is measured and must be 1 within 3 sigma, sigma =
sqrt(sigma_stat^2 + systematic^2), sigma_stat = sqrt(g var / n) with g pymbar's statistical
inefficiency; sigma must be <= 0.01/3, so a 1 % error would be seen at 3 sigma (counting
3N - 3 would read 0.83).  Targets: S1 and pair OU keep Maxwell-Boltzmann exactly at fixed
positions without constraints (test_temperature.py, 1.), and their pair updates are force-like
(projected as forces are) at small gamma dt; GW (lambda = 1/2) is 1 + q D dt/2 +- q D dt/2 with q = 1 and D =
Var/(2g) from the ideal-gas friction moments (test_temperature.py, 2.).  The rotation of a
dimer, omega^2 dt^2 ~ 16 dt^2, bounds the drift's own error: <= 0.002 at dt = 0.01 (added to
the systematic).  The Lowe method draws the pair's relative normal velocity from N(0, kT/mu_eff)
with the effective reduced mass the constraints leave it (ConstrainedPairImpulse): an exact
Gibbs step of the constrained Maxwell distribution, target 1 (a free-particle redraw followed
by a projection gave <kT> = 0.879 +- 0.002 here).  S1 and pair OU use the same effective mass.
Each case takes 20-70 s: marked slow.  `pytest -s` prints every
number.
"""
import math

import numpy as np
import openmm
import pytest
from openmm import unit
from pymbar import timeseries

import openmmdpd

from dpdtest import KT, set_velocities

NUM_DIMERS, BOND, RHO, GAMMA = 500, 0.5, 3.0, 4.5
N = 2 * NUM_DIMERS
DOF = 3 * N - NUM_DIMERS - 3
G = 4 * math.pi * GAMMA * RHO / 90                    # per-particle friction, /ps
VAR = 2 / 3 * 4 * math.pi * GAMMA ** 2 * RHO / 105    # its spread, /ps^2
D = VAR / (2 * G)
SIGMA_LIMIT = 0.01 / 3
EQUILIBRATION_TIME, SAMPLE_INTERVAL = 2.0, 0.02   # ps


def dimer_gas(seed=1):
    box = (N / RHO) ** (1 / 3)
    system = openmm.System()
    system.setDefaultPeriodicBoxVectors(openmm.Vec3(box, 0, 0), openmm.Vec3(0, box, 0), openmm.Vec3(0, 0, box))
    rng = np.random.default_rng(seed)
    axes = rng.normal(size=(NUM_DIMERS, 3))
    axes *= BOND / 2 / np.linalg.norm(axes, axis=1)[:, None]
    centres = rng.uniform(0, box, (NUM_DIMERS, 3))
    positions = np.empty((N, 3))
    positions[0::2], positions[1::2] = centres - axes, centres + axes
    for k in range(NUM_DIMERS):
        system.addParticle(1.0)
        system.addParticle(1.0)
        system.addConstraint(2 * k, 2 * k + 1, BOND)
    marker = openmm.CustomBondForce("0")   # no force, but the System is periodic
    marker.setUsesPeriodicBoundaryConditions(True)
    system.addForce(marker)
    return system, positions


def make_integrator(name, dt):
    if name == "GW":
        integrator = openmmdpd.DPDVVIntegrator(KT, GAMMA, 1.0, dt)
    elif name == "S1":
        integrator = openmmdpd.ShardlowIntegrator(KT, GAMMA, 1.0, dt)
        integrator.setOrder(1)
    else:
        integrator = openmmdpd.LoweAndersenIntegrator(KT, GAMMA, 1.0, dt)
        integrator.setMethod(openmmdpd.LoweAndersenIntegrator.Lowe if name == "Lowe"
                             else openmmdpd.LoweAndersenIntegrator.PairOrnsteinUhlenbeck)
    integrator.setConstraintTolerance(1e-8)
    return integrator


# name, dt, target, its systematic, sample time (ps: GW's kinetic energy decorrelates slowest)
CASES = [("S1", 0.005, 1.0, 0.0, 120.0), ("PairOU", 0.005, 1.0, 0.0, 120.0), ("Lowe", 0.005, 1.0, 0.0, 120.0),
         ("GW", 0.002, 1 + D * 0.002 / 2, D * 0.002 / 2, 200.0)]


@pytest.mark.slow
@pytest.mark.parametrize("name, dt, target, systematic, sample_time", CASES, ids=[c[0] for c in CASES])
def test_kinetic_temperature_counts_the_constraints(name, dt, target, systematic, sample_time):
    system, positions = dimer_gas()
    integrator = make_integrator(name, dt)
    assert integrator.getConstraintTolerance() == 1e-8
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": "2"})
    context.setPositions(positions)
    set_velocities(context, system, 7)
    context.applyVelocityConstraints(1e-8)
    integrator.step(round(EQUILIBRATION_TIME / dt))
    every = round(SAMPLE_INTERVAL / dt)
    samples = []
    for _ in range(round(sample_time / SAMPLE_INTERVAL)):
        integrator.step(every)
        ke = context.getState(getEnergy=True, groups=0).getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        samples.append(2 * ke / DOF)
    samples = np.array(samples)
    g = timeseries.statisticalInefficiency(samples)
    sigma_stat = math.sqrt(g * samples.var() / len(samples))
    systematic = math.hypot(systematic, 16 * dt * dt)
    sigma = math.hypot(sigma_stat, systematic)
    mean = samples.mean()
    print(f"\n{name} dt={dt:g} N={N} Nc={NUM_DIMERS} dof={DOF}: <kT> = {mean:.5f}, sigma_stat = {sigma_stat:.5f}, "
          f"g = {g:.1f}, target = {target:.5f} +- {systematic:.5f}, sigma = {sigma:.5f}, "
          f"|diff|/sigma = {abs(mean - target) / sigma:.2f}")
    assert sigma <= SIGMA_LIMIT, f"sigma = {sigma:.4f}: too little statistics to detect a 1 % error"
    assert abs(mean - target) <= 3 * sigma, f"<kT> = {mean:.5f}, target {target:.5f} +- 3 x {sigma:.5f}"
