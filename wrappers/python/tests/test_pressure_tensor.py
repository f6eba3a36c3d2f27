"""The pressure tensor of the DPD integrators (algorithms.md §10) against numpy: one step's
sample equals the kinetic part from the State's velocities (peculiar under shear) and the
pair virial of the soft repulsion computed here from the State's positions; Quantities out;
clear errors."""
import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import scenes, shear
from dpdtest import KT as KT_KELVIN

PRESSURE = unit.kilojoule_per_mole / unit.nanometer**3


def _pair_virial(positions, box, a=25.0, cutoff=1.0):
    """sum over pairs of r_ij F_ij for the soft repulsion a (1 - r/rc), nearest image of a triclinic box."""
    n = len(positions)
    i, j = np.triu_indices(n, 1)
    d = positions[i] - positions[j]
    for k in (2, 1, 0):  # reduced triclinic box: c, then b, then a
        d -= np.outer(np.round(d[:, k] / box[k][k]), box[k])
    r = np.linalg.norm(d, axis=1)
    near = r < cutoff
    d, r = d[near], r[near]
    force = a * (1 - r / cutoff)
    e = d / r[:, None]
    w = (r * force)[:, None, None] * e[:, :, None] * e[:, None, :]
    t = w.sum(axis=0)
    return np.array([t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]])


def _six(t):
    return np.array([t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]])


@pytest.mark.parametrize("make", [
    lambda: openmmdpd.DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, 0.02),
    lambda: openmmdpd.ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, 0.02),
], ids=["GW", "S1"])
@pytest.mark.parametrize("rate", [0.0, 0.5])
def test_one_step_sample_equals_numpy(make, rate):
    scene = scenes.soft_scene(num_particles=500)
    integrator = make()
    integrator.setShearRate(rate)
    integrator.setPressureTensorEnabled(True)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_KELVIN, 5)
    integrator.step(3)
    integrator.resetPressureTensor()
    integrator.step(1)
    assert integrator.getPressureTensorSampleCount() == 1
    state = context.getState(getPositions=True, getVelocities=True)
    box = state.getPeriodicBoxVectors(asNumpy=True).value_in_unit(unit.nanometer)
    r = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
    volume = box[0][0] * box[1][1] * box[2][2]
    u = shear.peculiar_velocities(r, state.getVelocities(asNumpy=True), rate, box[1][1])
    kinetic = _six(u.T @ u) / volume
    conservative = _pair_virial(r, box) / volume
    got = {part: integrator.getAveragePressureTensor(part).value_in_unit(PRESSURE)
           for part in (integrator.PressureKinetic, integrator.PressureConservative)}
    np.testing.assert_allclose(got[integrator.PressureKinetic], kinetic, rtol=0, atol=1e-12)
    np.testing.assert_allclose(got[integrator.PressureConservative], conservative, rtol=0, atol=1e-10)
    total = integrator.getAveragePressureTensor()
    assert total.unit == PRESSURE
    assert np.trace(np.diag(total.value_in_unit(PRESSURE)[:3])) / 3 > 20  # model B's pressure is ~40


def test_errors_name_the_problem():
    edpd = openmmdpd.EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 10.0, 0.02)
    with pytest.raises(openmm.OpenMMException, match="pressure tensor is not available"):
        edpd.setPressureTensorEnabled(True)
    integrator = openmmdpd.DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, 0.02)
    with pytest.raises(openmm.OpenMMException, match="not bound to a Context"):
        integrator.getAveragePressureTensor()
    scene = scenes.soft_scene(num_particles=200)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(scene.positions)
    with pytest.raises(openmm.OpenMMException, match="no step has sampled"):
        integrator.getAveragePressureTensor()
    integrator.setPressureTensorEnabled(True)
    integrator.step(1)
    with pytest.raises(openmm.OpenMMException, match="part must be"):
        integrator.getAveragePressureTensor(7)
