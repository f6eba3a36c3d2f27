"""The way back from LAMMPS (docs/guide/lammps.md): a data file and input script that
openmmdpd.lammps.export_lammps wrote, read into an OpenMM System, one of this package's
integrators and the state, so that an export can be checked by comparing what comes back with
what went out.

What comes back is what the script says: one particle type per LAMMPS atom type (the same
number, less one, for the soft force and the thermostat), a `DPDSoftRepulsionForce` unless every
a is 0, the friction rate gamma_IJ / (2 mu_IJ) per pair of types, harmonic bonds and angles,
`special_bonds` factors as soft-force exclusions (factor 0) and thermostat exceptions (factor
not 1), `fix momentum` as a CMMotionRemover, `fix deform` as the shear rate (the velocities
taken back from its flow's frame to openmm-dpd's). Tabulated bonds
and angles do not come back: their tables approximate the Forces they came from.
"""
import math
import os
from collections import namedtuple

import numpy as np
import openmm
from openmm import unit

from .dpdplugin import DPDSoftRepulsionForce, DPDVVIntegrator, ShardlowIntegrator
from .lammps import _bond_distances, read_lammps_data, read_lammps_input
from .units import reduced_temperature

__all__ = ["read_lammps_model", "LammpsModel"]

LammpsModel = namedtuple("LammpsModel", "system integrator positions velocities box steps")
LammpsModel.__doc__ = """A model read back from LAMMPS (read_lammps_model): the System, the integrator
(DPDVVIntegrator, Groot-Warren lambda 1/2, for `fix nve` with `pair dpd`; ShardlowIntegrator S1 for
`fix shardlow`), positions (nm, unwrapped by the image flags), velocities (nm/ps, or None), the
box vectors (nm) and the number of steps the script runs."""


def _refuse(message):
    raise ValueError(f"read_lammps_model: {message}")


def _pair_table(script, kT):
    """{(I, J): (a, gamma, s, rc, gamma_perp, s_perp)} from the pair_coeff lines of pair dpd, dpd/ext or dpd/fdt."""
    style = script.pair_style[0]
    table = {}
    for pair, values in script.pair_coeffs.items():
        gamma_perp, s_perp = 0.0, 2.0
        if style == "dpd":
            a, gamma, rc = values
            s = 2.0
        elif style == "dpd/ext":
            a, gamma, gamma_perp, ws, ws_perp, rc = values
            s, s_perp = 2 * ws, 2 * ws_perp
        elif style == "dpd/fdt":
            a, sigma, rc = values
            gamma, s = sigma**2 / (2 * kT), 2.0
        else:
            _refuse(f"pair_style {style} is not one export_lammps writes (dpd, dpd/ext, dpd/fdt)")
        table[pair] = (a, gamma, s, rc, gamma_perp, s_perp)
    return table


def _integrator(script, kT, dt, masses, table):
    """The integrator the fixes and pair coefficients say, with its friction table."""
    seed = int(script.pair_style[3])
    _, gamma, _, rc, _, _ = table[(1, 1)]
    scheme = ShardlowIntegrator if any(fix[1] == "shardlow" for fix in script.fixes.values()) else DPDVVIntegrator
    integrator = scheme(reduced_temperature(kT), gamma / masses[1], rc, dt)  # type 1's; every pair is listed
    if scheme is DPDVVIntegrator:
        integrator.setLambda(0.5)
    for (i, j), (_, gamma, s, rc, gamma_perp, s_perp) in sorted(table.items()):
        reduced_mass = masses[i] * masses[j] / (masses[i] + masses[j])
        index = integrator.addTypePair(i - 1, j - 1, gamma / (2 * reduced_mass), rc)
        integrator.setTypePairWeightExponent(index, s)
        integrator.setTypePairTransverseFriction(index, gamma_perp / (2 * reduced_mass), s_perp)
    integrator.setRandomNumberSeed(seed)
    shear = script.fixes.get("shear")
    if shear is not None:
        integrator.setShearRate(float(shear[shear.index("erate") + 1]))
    return integrator


def _soft_force(table, types):
    if not any(a for a, *_ in table.values()):
        return None
    force = DPDSoftRepulsionForce(0.0, 1.0)
    force.setNonbondedMethod(DPDSoftRepulsionForce.CutoffPeriodic)
    for (i, j), (a, _, _, rc, _, _) in sorted(table.items()):
        force.addTypePair(i - 1, j - 1, a, rc)
    for particle, number in enumerate(types):
        force.setParticleType(particle, int(number) - 1)
    return force


def _harmonic_terms(script, data, kind):
    """A HarmonicBondForce or HarmonicAngleForce of the data's bonds or angles (k = 2K)."""
    terms = data.bonds if kind == "bond" else data.angles
    if not len(terms):
        return None
    style = dict(script.commands)[f"{kind}_style"]
    if style != ["harmonic"]:
        _refuse(f"{kind}_style {' '.join(style)}: tabulated {kind}s approximate the Forces they came from and are "
                f"not read back")
    coefficients = script.bond_coeffs if kind == "bond" else script.angle_coeffs
    force = openmm.HarmonicBondForce() if kind == "bond" else openmm.HarmonicAngleForce()
    for term in terms:
        K, rest = coefficients[int(term[0])]
        if kind == "bond":
            force.addBond(int(term[1]), int(term[2]), rest, 2 * K)
        else:
            force.addAngle(int(term[1]), int(term[2]), int(term[3]), math.radians(rest), 2 * K)
    force.setUsesPeriodicBoundaryConditions(True)
    return force


def _special_pairs(script, data, table, soft, integrator):
    """special_bonds lj f12 f13 f14: exclusions of the soft force where the factor is 0, thermostat
    exceptions where it is not 1."""
    factors = [float(f) for f in script.special_bonds[1:4]]
    if factors == [1.0, 1.0, 1.0]:
        return
    for (i, j), distance in sorted(_bond_distances(len(data.types), data.bonds[:, 1:].tolist()).items()):
        factor = factors[distance - 1]
        pair = tuple(sorted((int(data.types[i]), int(data.types[j]))))
        if soft is not None and table[pair][0] != 0:
            if 0 < factor < 1:
                _refuse(f"special_bonds factor {factor} scales the soft repulsion of particles {i} and {j}; "
                        f"DPDSoftRepulsionForce only excludes")
            if factor == 0:
                soft.addExclusion(i, j)
        if factor != 1:
            integrator.addThermostatException(i, j, factor)


def read_lammps_model(path):
    """Read path + ".data" and path + ".in", as export_lammps(..., path) wrote them, into a LammpsModel."""
    data = read_lammps_data(os.fspath(path) + ".data")
    script = read_lammps_input(os.fspath(path) + ".in")
    commands = dict(script.commands)
    kT = float(script.pair_style[1])
    table = _pair_table(script, kT)
    masses = {int(t): float(m) for t, m in data.masses.items()}
    system = openmm.System()
    for number in data.types:
        system.addParticle(masses[int(number)])
    box = [openmm.Vec3(*row) for row in data.box]
    system.setDefaultPeriodicBoxVectors(*box)
    integrator = _integrator(script, kT, float(commands["timestep"][0]), masses, table)
    for particle, number in enumerate(data.types):
        integrator.setParticleType(particle, int(number) - 1)
    soft = _soft_force(table, data.types)
    for force in (soft, _harmonic_terms(script, data, "bond"), _harmonic_terms(script, data, "angle")):
        if force is not None:
            system.addForce(force)
    _special_pairs(script, data, table, soft, integrator)
    momentum = script.fixes.get("momentum")
    if momentum is not None:
        system.addForce(openmm.CMMotionRemover(int(momentum[2])))
    positions = data.positions + data.images @ data.box
    velocities = data.velocities
    rate = integrator.getShearRate().value_in_unit(unit.picosecond**-1)
    if velocities is not None and rate:
        velocities = velocities - [rate * data.box[1, 1] / 2, 0, 0]  # from fix deform's frame to openmm-dpd's
    return LammpsModel(system, integrator, positions, velocities, box, int(commands["run"][0]))
