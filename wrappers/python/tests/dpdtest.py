"""Helpers shared by the integrator tests."""
import numpy as np
import openmm
from openmm import unit

import openmmdpd

KT = openmmdpd.KT_TEMPERATURE


def platform(name):
    return openmm.Platform.getPlatformByName(name)


def properties(name):
    return {"Threads": "1"} if name == "CPU" else {}


def make_context(scene, integrator, platform_name="Reference"):
    context = openmm.Context(scene.system, integrator, platform(platform_name), properties(platform_name))
    context.setPositions(scene.positions)
    return context


def set_velocities(context, system, seed):
    """Maxwell-Boltzmann velocities at kT = 1 with the centre-of-mass velocity removed.

    (OpenMM 7.7's setVelocitiesToTemperature leaves a net momentum; DPD conserves it, and
    kT = 2 KE / (3N - 3) assumes it is zero.)
    """
    context.setVelocitiesToTemperature(KT, seed)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(
        unit.nanometer / unit.picosecond)
    m = np.array([system.getParticleMass(i).value_in_unit(unit.dalton)
                  for i in range(system.getNumParticles())])
    v -= (m[:, None] * v).sum(axis=0) / m.sum()
    context.setVelocities(v)


def momentum(context, system):
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(
        unit.nanometer / unit.picosecond)
    m = np.array([system.getParticleMass(i).value_in_unit(unit.dalton)
                  for i in range(system.getNumParticles())])
    return (m[:, None] * v).sum(axis=0)


def reduced_kT(context, num_particles):
    """kT = 2 KE / (3N - 3) in kJ/mol, i.e. reduced kT, from the State's kinetic energy.

    groups=0: the potential energy that getEnergy also computes is then of no force,
    which saves a force evaluation per sample (the kinetic energy is the integrator's).
    """
    ke = context.getState(getEnergy=True, groups=0).getKineticEnergy().value_in_unit(
        unit.kilojoule_per_mole)
    return 2.0 * ke / (3 * num_particles - 3)
