"""Thermostat exceptions: a pair with factor f has friction gamma f and noise sigma sqrt(f)
(fluctuation-dissipation kept), 0 excludes it.  The definition checked here is that an
exception with factor f on every pair of a group of particles gives the trajectory that a
type pair with friction f times as large gives (same seed), the thermostat's part of the
pressure tensor included: a sigma scaled by f instead of sqrt(f) fails it.  Also: the setters and their checks, bonds to exceptions, XML, and an
excluded pair that receives no thermostat force at all, for every integrator on Reference
and CPU.  CPU = Reference with exceptions is in tests/TestPlatformsAgree.cpp."""
import itertools

import numpy as np
import openmm
import pytest

import openmmdpd
from openmmdpd import catalog, scenes
from dpdtest import KT, properties

FRICTION, CUTOFF, DT = 4.5, 1.0, 0.02
GROUP = range(0, 300, 3)  # type 1: a tenth of the fluid, so most of their pairs are with type 0


def every_integrator():
    """Our integrators by name: the catalog's (but Langevin and OpenMM's) and extended DPD."""
    makers = {name: make for name, make in catalog.integrators("soft").items() if name not in ("Langevin", "OpenMM-DPD")}
    makers["EDPD"] = lambda dt: openmmdpd.EDPDIntegrator(KT, FRICTION, CUTOFF, 10.0, dt)
    makers["Staggered"] = staggered
    return makers


def staggered(dt):
    """Two sub-steps for the group's particles (the System gets a fast force group for them)."""
    integrator = openmmdpd.StaggeredDPDIntegrator(KT, FRICTION, CUTOFF, dt, 2)
    integrator.setPolymerParticles(list(GROUP))
    return integrator


INTEGRATORS = every_integrator()


def final_state(integrator, platform_name, steps=20):
    """Positions, velocities and (where the integrator has one) the thermostat's part of the pressure tensor."""
    scene = scenes.build_scene("soft", num_particles=1000)
    if isinstance(integrator, openmmdpd.StaggeredDPDIntegrator):
        fast = scenes.periodic_marker_force()
        fast.setForceGroup(scenes.FAST_FORCE_GROUP)
        scene.system.addForce(fast)
    integrator.setRandomNumberSeed(5)
    has_pressure = not isinstance(integrator, (openmmdpd.DenOtterClarkeIntegrator, openmmdpd.StaggeredDPDIntegrator))
    if has_pressure:
        integrator.setPressureTensorEnabled(True)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName(platform_name),
                             properties(platform_name))
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT, 7)
    integrator.step(steps)
    state = context.getState(getPositions=True, getVelocities=True)
    pressure = integrator.getAveragePressureTensor(integrator.PressureThermostat)._value if has_pressure else []
    return state.getPositions(asNumpy=True)._value, state.getVelocities(asNumpy=True)._value, np.array(pressure)


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
@pytest.mark.parametrize("factor", [0.0, 0.3])
@pytest.mark.parametrize("name", sorted(INTEGRATORS))
def test_an_exception_is_the_friction_scaled_by_its_factor(name, factor, platform_name):
    # Group pairs carry the exception; in the other run, the same pairs are type pair (1, 1)
    # with friction f times the default.  Every other pair is alike in both runs.
    with_exceptions, with_type_pair = INTEGRATORS[name](DT), INTEGRATORS[name](DT)
    for integrator in (with_exceptions, with_type_pair):
        for i in GROUP:
            integrator.setParticleType(i, 1)
        integrator.addTypePair(0, 1, FRICTION, CUTOFF)
    with_type_pair.addTypePair(1, 1, FRICTION * factor, CUTOFF)
    with_exceptions.addTypePair(1, 1, FRICTION, CUTOFF)
    for i, j in itertools.combinations(GROUP, 2):
        with_exceptions.addThermostatException(i, j, factor)
    expected, actual = final_state(with_type_pair, platform_name), final_state(with_exceptions, platform_name)
    for what, e, a in zip(("positions", "velocities", "thermostat pressure"), expected, actual):
        assert np.max(np.abs(a - e), initial=0) <= 1e-9 * np.max(np.abs(e), initial=0), f"{name}: {what}"


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
@pytest.mark.parametrize("name", sorted(INTEGRATORS))
def test_an_excluded_pair_gets_no_thermostat_force(name, platform_name):
    # Two particles 0.5 apart, no conservative force: with f = 0 nothing changes their velocities.
    integrator = INTEGRATORS[name](DT)
    integrator.addThermostatException(1, 0, 0.0)
    if isinstance(integrator, openmmdpd.StaggeredDPDIntegrator):
        integrator.setPolymerParticles([0])
    system = openmm.System()
    for _ in range(2):
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) for row in 4 * np.eye(3)))
    marker = scenes.periodic_marker_force()
    marker.setForceGroup(scenes.FAST_FORCE_GROUP)  # the staggered integrator's fast group; the others integrate every group
    system.addForce(marker)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName(platform_name), properties(platform_name))
    context.setPositions([openmm.Vec3(1, 1, 1), openmm.Vec3(1.5, 1, 1)])
    velocities = [openmm.Vec3(0.3, -0.2, 0.1), openmm.Vec3(-0.3, 0.2, 0.4)]
    context.setVelocities(velocities)
    integrator.step(5)
    after = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    assert np.array_equal(after, np.array([list(v) for v in velocities])), name


def test_setters_getters_and_checks():
    integrator = openmmdpd.ShardlowIntegrator(KT, FRICTION, CUTOFF, DT)
    assert integrator.addThermostatException(3, 1, 0.5) == 0
    assert integrator.getNumThermostatExceptions() == 1
    assert integrator.getThermostatExceptionParameters(0) == [3, 1, 0.5]
    for args, message in [((1, 3, 0.2), "particles 1, 3 already have a thermostat exception"),
                          ((2, 2, 0.2), "two different particle indices"),
                          ((-1, 2, 0.2), "two different particle indices"),
                          ((4, 5, -0.1), r"must be in \[0, 1\]"),
                          ((4, 5, 1.5), r"must be in \[0, 1\]"),
                          ((4, 5, float("nan")), r"must be in \[0, 1\]")]:
        with pytest.raises(openmm.OpenMMException, match=message):
            integrator.addThermostatException(*args)
    assert integrator.getNumThermostatExceptions() == 1
    integrator.setThermostatExceptionParameters(0, 1, 3, 0.0)  # its own pair again: allowed
    assert integrator.getThermostatExceptionParameters(0) == [1, 3, 0.0]
    with pytest.raises(openmm.OpenMMException, match="index must be in"):
        integrator.getThermostatExceptionParameters(1)


def test_bonds_give_their_one_two_and_one_three_pairs_once():
    integrator = openmmdpd.DPDVVIntegrator(KT, FRICTION, CUTOFF, DT)
    integrator.createThermostatExceptionsFromBonds([(0, 1), (1, 2), (2, 3), (1, 0)], 0.0, 0.5)
    pairs = {tuple(sorted(integrator.getThermostatExceptionParameters(k)[:2])): integrator.getThermostatExceptionParameters(k)[2]
             for k in range(integrator.getNumThermostatExceptions())}
    assert pairs == {(0, 1): 0.0, (1, 2): 0.0, (2, 3): 0.0, (0, 2): 0.5, (1, 3): 0.5}
    with pytest.raises(openmm.OpenMMException, match="already have a thermostat exception"):
        integrator.createThermostatExceptionsFromBonds([(5, 6), (2, 3)], 0.0, 1.0)
    assert integrator.getNumThermostatExceptions() == 5  # nothing added by the refused call
    only12 = openmmdpd.DPDVVIntegrator(KT, FRICTION, CUTOFF, DT)
    only12.createThermostatExceptionsFromBonds([(0, 1), (1, 2)], 0.0, 1.0)
    assert only12.getNumThermostatExceptions() == 2
    only13 = openmmdpd.DPDVVIntegrator(KT, FRICTION, CUTOFF, DT)
    only13.createThermostatExceptionsFromBonds([(0, 1), (1, 2)], 1.0, 0.5)  # factor 1: no exception listed
    assert [only13.getThermostatExceptionParameters(k) for k in range(only13.getNumThermostatExceptions())] == [[0, 2, 0.5]]


def test_a_particle_beyond_the_system_is_refused_at_context_creation():
    scene = scenes.build_scene("soft", num_particles=500)
    integrator = openmmdpd.DPDVVIntegrator(KT, FRICTION, CUTOFF, DT)
    integrator.addThermostatException(0, 500, 0.0)
    with pytest.raises(openmm.OpenMMException, match="particles 0, 500 names a particle beyond the System's 500"):
        openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("Reference"))


def test_xml_keeps_the_exceptions():
    integrator = openmmdpd.LoweAndersenIntegrator(KT, FRICTION, CUTOFF, DT)
    integrator.addThermostatException(0, 1, 0.0)
    integrator.addThermostatException(2, 7, 0.25)
    copy = openmmdpd.LoweAndersenIntegrator.cast(openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(integrator)))
    assert [copy.getThermostatExceptionParameters(k) for k in range(2)] == [[0, 1, 0.0], [2, 7, 0.25]]
    xml = openmm.XmlSerializer.serialize(integrator).replace('factor=".25"', 'factor="2"')
    assert 'factor="2"' in xml
    with pytest.raises(openmm.OpenMMException, match=r"must be in \[0, 1\]"):
        openmm.XmlSerializer.deserialize(xml)
