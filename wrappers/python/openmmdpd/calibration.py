"""The averages den Otter and Clarke's integrator needs (Nikunen et al. 2003, eqs. 6-7, Table III).

DenOtterClarkeIntegrator takes its prefactors alpha(dt) and beta(dt) from three per-particle
averages of an equilibrium ensemble at the target temperature: <FD.v>, <FD.FD> and <FR.FR>
(FR without 1/sqrt(dt)).  calibrate_den_otter_clarke() measures them on the user's System
in a short run at a small step, where the scheme is plain DPD leap-frog to O(dt);
ideal_gas_averages() gives them in closed form for the ideal gas.

A library module, not a command: the averages belong to the user's System (its forces,
density, temperature, friction and cutoffs), so they are measured from Python, with
openmmdpd.calibrate_den_otter_clarke (exported by the package; docs/guide/integrators.md).
Its other users: catalog.py gives den Otter-Clarke ("OC") the Table III averages below on
the scenes Nikunen et al. calibrated, for the tools that compare integrators (`python3 -m
openmmdpd.compare`, `openmmdpd.bench`), and the tests check both functions against the
ideal gas and Table III.  `python3 -m openmmdpd.calibration` says so and what to run instead.
"""
import copy
import math
from collections import namedtuple

import numpy as np
import openmm
from openmm import unit

from . import DenOtterClarkeIntegrator
from .units import MOLAR_GAS_CONSTANT, strip_units

__all__ = ["Averages", "PAPER_000_TABLE_III", "calibrate_den_otter_clarke", "ideal_gas_averages"]

# Nikunen et al. 2003, Table III: <FD.v>, <FD.FD>, <FR.FR> of its models in reduced units (= OpenMM units
# for kT = 1 kJ/mol, unit masses, rc = 1 nm), by the scene that builds each model here.
PAPER_000_TABLE_III = {
    "ideal": (-7.528088, 38.254933, 15.072610),    # model A
    "soft": (-4.985245, 14.507340, 9.976453),      # model B
    "polymer": (-7.566508, 38.532832, 15.150489),
}

_POWER = unit.kilojoule_per_mole / unit.picosecond
_FORCE2 = (unit.kilojoule_per_mole / unit.nanometer)**2
_FORCE2_TIME = _FORCE2 * unit.picosecond

Averages = namedtuple("Averages", "fd_dot_v fd_dot_fd fr_dot_fr fd_dot_v_error fd_dot_fd_error fr_dot_fr_error samples")
Averages.__doc__ = """<FD.v>, <FD.FD>, <FR.FR> (Quantities in OpenMM units) and their standard errors.

samples: the number of blocks the standard errors come from (0 for closed forms)."""


def _averages(values, errors, samples):
    units = (_POWER, _FORCE2, _FORCE2_TIME)
    return Averages(*[unit.Quantity(float(x), u) for x, u in zip(values, units)],
                    *[unit.Quantity(float(e), u) for e, u in zip(errors, units)], samples)


def ideal_gas_averages(num_particles, volume, friction, cutoff, temperature, mass=1.0):
    """The three averages of an ideal DPD gas of equal masses, in closed form.

    With gamma = m * friction (gamma_ij = 2 mu friction), sigma^2 = 2 gamma kT, Maxwell
    velocities independent of the uniform positions, and c1 = int wD dV = 2 pi rc^3/15,
    c2 = int wD^2 dV = 4 pi rc^3/105 over the cutoff sphere, rho = (N - 1)/V the density of
    the other particles:

        <FD.v>  = -gamma (kT/m) rho c1                       (<u (e.v_i)> = kT/m, even with
                                                              the total momentum fixed)
        <FR.FR> = sigma^2 rho c1 = -2 m <FD.v>
        <FD.FD> = gamma^2 (kT/m) [2 rho c2 + rho' rho c1^2/3], rho' = (N - 2)/V

    (the pairs j = k give 2 kT/m each, the pairs j != k share v_i: (kT/m) (e_j.e_k)^2, 1/3 on
    average).  Arguments are Quantities or numbers in OpenMM units (volume in nm^3).
    """
    volume = strip_units(volume, unit.nanometer**3, "volume", "ideal_gas_averages")
    friction = strip_units(friction, unit.picosecond**-1, "friction", "ideal_gas_averages")
    rc = strip_units(cutoff, unit.nanometer, "cutoff", "ideal_gas_averages")
    kT = strip_units(temperature, unit.kelvin, "temperature", "ideal_gas_averages") * MOLAR_GAS_CONSTANT
    mass = strip_units(mass, unit.dalton, "mass", "ideal_gas_averages")
    gamma = mass * friction
    rho, rho2 = (num_particles - 1) / volume, (num_particles - 2) / volume
    c1, c2 = 2 * math.pi * rc**3 / 15, 4 * math.pi * rc**3 / 105
    fd_dot_v = -gamma * kT / mass * rho * c1
    fd_dot_fd = gamma**2 * kT / mass * (2 * rho * c2 + rho2 * rho * c1**2 / 3)
    return _averages((fd_dot_v, fd_dot_fd, -2 * mass * fd_dot_v), (0, 0, 0), 0)


def _set(integrator, averages):
    integrator.setAverageFDDotV(averages.fd_dot_v)
    integrator.setAverageFDDotFD(averages.fd_dot_fd)
    integrator.setAverageFRDotFR(averages.fr_dot_fr)


def _probe(system, integrator, step_size):
    """A copy of `integrator` at the calibration step, with the ideal gas as its first guess."""
    probe = copy.copy(integrator)
    probe.setStepSize(step_size)
    masses = {system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())} - {0.0}
    a, b, c = system.getDefaultPeriodicBoxVectors()
    volume = abs(np.linalg.det(np.array([v.value_in_unit(unit.nanometer) for v in (a, b, c)])))
    _set(probe, ideal_gas_averages(system.getNumParticles(), volume, integrator.getDefaultFriction(),
                                   integrator.getDefaultCutoff(), integrator.getTemperature(),
                                   masses.pop() if len(masses) == 1 else 1.0))
    return probe


def calibrate_den_otter_clarke(system, positions, integrator, step_size=0.002 * unit.picosecond,
                               equilibration_steps=2000, num_blocks=20, block_steps=500, platform=None,
                               velocity_seed=1, apply=True):
    """Measure <FD.v>, <FD.FD>, <FR.FR> of `integrator` (a DenOtterClarkeIntegrator, whose
    temperature, friction, cutoffs and types are used) on `system` from `positions`.

    A copy of the integrator runs at `step_size` (small, so that the ensemble is the target
    one to O(step_size)): equilibration_steps, then num_blocks blocks of block_steps whose
    averages (over particles with mass and steps) give the mean and its standard error
    (blocks should be longer than the velocity correlation time, ~ 3 kT / -<FD.v>).  The
    copy starts from the ideal gas's averages (ideal_gas_averages, default friction and
    cutoff), which at a small step shift alpha and beta by O(step_size) only.  Returns
    Averages; with apply, also sets them on `integrator`.
    """
    if not isinstance(integrator, DenOtterClarkeIntegrator):
        raise TypeError(f"calibrate_den_otter_clarke: integrator must be a DenOtterClarkeIntegrator, "
                        f"got {type(integrator).__name__}")
    for name, value in (("equilibration_steps", equilibration_steps), ("block_steps", block_steps)):
        if int(value) != value or value < (0 if name == "equilibration_steps" else 1):
            raise ValueError(f"calibrate_den_otter_clarke: {name} must be an integer >= "
                             f"{0 if name == 'equilibration_steps' else 1}, got {value!r}")
    if int(num_blocks) != num_blocks or num_blocks < 2:
        raise ValueError(f"calibrate_den_otter_clarke: num_blocks must be an integer >= 2, got {num_blocks!r}")
    step_size = strip_units(step_size, unit.picosecond, "step_size", "calibrate_den_otter_clarke")
    probe = _probe(system, integrator, step_size)
    args = (system, probe) if platform is None else (system, probe, platform)
    context = openmm.Context(*args)
    context.setPositions(positions)
    _set_velocities(context, system, integrator.getTemperature(), velocity_seed)
    probe.step(int(equilibration_steps))
    blocks = []
    before = _sums(probe)
    for _ in range(int(num_blocks)):
        probe.step(int(block_steps))
        after = _sums(probe)
        blocks.append((after[:3] - before[:3]) / (after[3] - before[3]))
        before = after
    del context
    blocks = np.array(blocks)
    result = _averages(blocks.mean(axis=0), blocks.std(axis=0, ddof=1) / math.sqrt(len(blocks)), len(blocks))
    if apply:
        _set(integrator, result)
    return result


def _set_velocities(context, system, temperature, seed):
    """Maxwell-Boltzmann velocities with no net momentum (OpenMM 7.7's setVelocitiesToTemperature
    leaves some, which the pair thermostat would carry along)."""
    context.setVelocitiesToTemperature(temperature, seed)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    m = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])
    v -= (m[:, None] * v).sum(axis=0) / m.sum()
    context.setVelocities(v)


def _sums(integrator):
    fd_v, fd_fd, fr_fr, count = integrator.getMeasuredSums()
    return np.array([fd_v.value_in_unit(_POWER), fd_fd.value_in_unit(_FORCE2), fr_fr.value_in_unit(_FORCE2_TIME), count],
                    dtype=float)


if __name__ == "__main__":
    from .options import not_a_command
    not_a_command("calibration",
                  "It measures den Otter-Clarke's averages on your own System from Python: "
                  "openmmdpd.calibrate_den_otter_clarke(system, positions, integrator) (about 30 s on 2 cores for "
                  "4000 particles with the defaults; see docs/guide/integrators.md).  `python3 -m openmmdpd.compare` "
                  "runs den Otter-Clarke (\"OC\") with Nikunen et al.'s averages on the scenes they calibrated "
                  "(see its --help).")
