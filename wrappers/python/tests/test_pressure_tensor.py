"""The pressure tensor of the DPD integrators (docs/theory/pressure-tensor.md) against numpy: one step's
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
    den_otter_clarke = openmmdpd.DenOtterClarkeIntegrator(KT_KELVIN, 4.5, 1.0, 0.02)
    with pytest.raises(openmm.OpenMMException, match="pressure tensor is not available"):
        den_otter_clarke.setPressureTensorEnabled(True)
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


def test_equilibrium_mean_equals_the_virial_pressure_from_positions():
    """Model B (N 1000, S1, dt 0.02): the integrator's block averages of P against kinetic +
    pair virial computed here from the State at the end of each block.  The means agree within
    3 combined standard errors (the thermostat part averages to zero in equilibrium), the
    off-diagonal means vanish within 3 standard errors, and sigma is small enough to see 1 %."""
    from openmmdpd.analysis import standard_error
    scene = scenes.soft_scene(num_particles=1000)
    integrator = openmmdpd.ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, 0.02)
    integrator.setRandomNumberSeed(3)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_KELVIN, 5)
    integrator.step(500)
    integrator.setPressureTensorEnabled(True)
    sampled, computed = [], []
    for _ in range(200):
        integrator.resetPressureTensor()
        integrator.step(20)
        sampled.append(integrator.getAveragePressureTensor().value_in_unit(PRESSURE))
        state = context.getState(getPositions=True, getVelocities=True)
        box = state.getPeriodicBoxVectors(asNumpy=True).value_in_unit(unit.nanometer)
        r = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
        u = shear.peculiar_velocities(r, state.getVelocities(asNumpy=True), 0.0, box[1][1])
        computed.append((_six(u.T @ u) + _pair_virial(r, box)) / (box[0][0] * box[1][1] * box[2][2]))
    sampled, computed = np.array(sampled), np.array(computed)
    p_sampled, p_computed = sampled[:, :3].mean(axis=1), computed[:, :3].mean(axis=1)
    error = np.hypot(standard_error(p_sampled), standard_error(p_computed))
    assert error < 0.01 * p_computed.mean() / 3
    assert abs(p_sampled.mean() - p_computed.mean()) < 3 * error
    for k in (3, 4, 5):
        assert abs(sampled[:, k].mean()) < 3 * standard_error(sampled[:, k]), k
    print(f"P {p_sampled.mean():.4f} +- {standard_error(p_sampled):.4f} (integrator), "
          f"{p_computed.mean():.4f} +- {standard_error(p_computed):.4f} (positions); "
          f"off-diagonal {sampled[:, 3:].mean(axis=0)} +- {[standard_error(sampled[:, k]) for k in (3, 4, 5)]}")
