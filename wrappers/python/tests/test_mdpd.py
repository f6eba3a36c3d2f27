"""MDPDForce from Python: energy, forces and densities against an independent numpy
implementation of Warren's many-body DPD (all pairs, minimum image), units, copies and errors."""
import copy
import pickle

import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd

FORCE_UNIT = unit.kilojoule_per_mole / unit.nanometer


def numpy_mdpd(positions, box, types, a, cutoff, b_of_type, rd, excluded):
    """Energy and forces of many-body DPD written out over all pairs (Warren 2003)."""
    d = positions[:, None, :] - positions[None, :, :]
    d -= box * np.round(d / box)
    r = np.sqrt((d ** 2).sum(-1))
    n = len(positions)
    mask = ~np.eye(n, dtype=bool)
    for i, j in excluded:
        mask[i, j] = mask[j, i] = False
    rc = cutoff[types[:, None], types[None, :]]
    aij = a[types[:, None], types[None, :]]
    inside_c = mask & (r < rc)
    inside_d = mask & (r < rd)
    wd = np.where(inside_d, 1 - r / rd, 0.0)
    rho = (15 / (2 * np.pi * rd ** 3) * wd ** 2).sum(1)
    b = b_of_type[types]
    wc = np.where(inside_c, 1 - r / rc, 0.0)
    energy = 0.5 * (0.5 * aij * rc * wc ** 2).sum() + (np.pi * rd ** 4 / 30 * b * rho ** 2).sum()
    magnitude = aij * wc + (b * rho)[:, None] * wd + (b * rho)[None, :] * wd
    with np.errstate(invalid="ignore", divide="ignore"):
        e = np.where(mask[..., None], d / r[..., None], 0.0)
    forces = (magnitude[..., None] * e).sum(1)
    return energy, forces, rho


def liquid(n=300, seed=4):
    rng = np.random.default_rng(seed)
    box = np.array([4.0, 4.0, 4.0])
    positions = rng.uniform(0, 4.0, (n, 3))
    types = np.array([1 if i % 4 == 0 else 0 for i in range(n)])
    a = np.array([[-40.0, -28.0], [-28.0, -35.0]])
    cutoff = np.array([[1.0, 0.9], [0.9, 1.2]])
    b_of_type = np.array([25.0, 18.0])
    excluded = [(i, i + 1) for i in range(0, n - 1, 9)]
    force = openmmdpd.MDPDForce(a[0, 0], b_of_type[0], cutoff[0, 0], 0.75)
    force.addTypePair(0, 1, a[0, 1], cutoff[0, 1])
    force.addTypePair(1, 1, a[1, 1], cutoff[1, 1])
    force.setTypeB(1, b_of_type[1])
    for i, t in enumerate(types):
        force.setParticleType(i, int(t))
    for i, j in excluded:
        force.addExclusion(i, j)
    system = openmm.System()
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) for row in np.diag(box)))
    for _ in range(n):
        system.addParticle(1.0)
    system.addForce(force)
    expected = numpy_mdpd(positions, box, types, a, cutoff, b_of_type, 0.75, excluded)
    return system, positions, expected


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
def test_energy_and_forces_equal_an_independent_numpy_sum(platform_name):
    system, positions, (energy, forces, rho) = liquid()
    context = openmm.Context(system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName(platform_name))
    context.setPositions(positions)
    state = context.getState(getEnergy=True, getForces=True)
    assert rho.mean() > 1.0  # the density term is exercised
    assert state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole) == pytest.approx(energy, rel=1e-10)
    ours = state.getForces(asNumpy=True).value_in_unit(FORCE_UNIT)
    assert np.abs(ours - forces).max() < 1e-10 * np.abs(forces).max()


def test_units_getters_and_copies():
    force = openmmdpd.MDPDForce(-40 * FORCE_UNIT, 25.0, 10 * unit.angstrom, 0.75 * unit.nanometer)
    assert force.getDefaultA() == -40 * FORCE_UNIT and force.getDefaultB() == 25 * FORCE_UNIT
    assert force.getDefaultCutoff() == 1.0 * unit.nanometer and force.getDensityCutoff() == 0.75 * unit.nanometer
    force.setTypeB(2, 20 * FORCE_UNIT)
    force.addTypePair(0, 2, -30.0, 0.9 * unit.nanometer)
    assert force.getTypeB(2) == 20 * FORCE_UNIT and force.getTypeB(5) == 25 * FORCE_UNIT
    t1, t2, a, rc = force.getTypePairParameters(0)
    assert (t1, t2, a, rc) == (0, 2, -30 * FORCE_UNIT, 0.9 * unit.nanometer)
    for again in (copy.copy(force), pickle.loads(pickle.dumps(force)),
                  openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(force))):
        assert type(again) is openmmdpd.MDPDForce
        assert openmm.XmlSerializer.serialize(again) == openmm.XmlSerializer.serialize(force)


@pytest.mark.parametrize("call, name", [
    (lambda: openmmdpd.MDPDForce(-40, 25, 1.0, 1.2), "densityCutoff"),
    (lambda: openmmdpd.MDPDForce(-40, -1, 1.0, 0.75), "defaultB"),
    (lambda: openmmdpd.MDPDForce(-40, 25, 1.0, 0.75).addTypePair(0, 1, -20, 0.5), "cutoff"),
    (lambda: openmmdpd.MDPDForce(-40, 25, 1.0, 0.75).setTypeB(1, -3), "B"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(openmm.OpenMMException, match=name):
        call()
    with pytest.raises(TypeError):
        openmmdpd.MDPDForce(-40 * unit.kelvin, 25, 1.0, 0.75)
