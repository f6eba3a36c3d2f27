"""Helpers shared by the integrator and force-field tests."""
import numpy as np
import openmm
from openmm import unit

import openmmdpd

KT = openmmdpd.KT_TEMPERATURE


def platform(name):
    return openmm.Platform.getPlatformByName(name)


def have_opencl():
    """Whether OpenMM has an OpenCL platform and openmmdpd its OpenCL plugin."""
    names = {openmm.Platform.getPlatform(i).getName() for i in range(openmm.Platform.getNumPlatforms())}
    return "OpenCL" in names and any(p.endswith("libOpenMMDPDOpenCL.so") for p in openmmdpd.loaded_plugins)


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


# --- force fields: what a System or integrator holds, for comparison ---------------------------

def energy_and_forces(system, positions):
    """Potential energy (kJ/mol) and forces (kJ/mol/nm, an array) on the Reference platform."""
    context = openmm.Context(system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    state = context.getState(getEnergy=True, getForces=True)
    return (state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole),
            state.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer))


def soft_force(system):
    return next(f for f in system.getForces() if isinstance(f, openmmdpd.DPDSoftRepulsionForce))


def number(quantity):
    return quantity.value_in_unit(quantity.unit)


def named_pair_table(obj, types):
    """{(type name, type name): (a or friction, cutoff)} that a force or an integrator applies."""
    default = obj.getDefaultA() if isinstance(obj, openmmdpd.DPDSoftRepulsionForce) else obj.getDefaultFriction()
    table = {(i, j): (number(default), number(obj.getDefaultCutoff()))
             for i in range(len(types)) for j in range(i, len(types))}
    for index in range(obj.getNumTypePairs()):
        t1, t2, value, cutoff = obj.getTypePairParameters(index)
        table[tuple(sorted((t1, t2)))] = (number(value), number(cutoff))
    return {(types[i], types[j]): values for (i, j), values in table.items()}
