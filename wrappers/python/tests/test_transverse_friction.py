"""Transverse friction (friction on the part of a pair's relative velocity perpendicular to
e = r_ij / r, with its own noise): its setters, checks and XML, where it is refused, the
exact pair update it gives against the formula written out here, and the pressure tensor's
momentum flux with forces that are not central.  Its <kT> is in test_temperature.py, its
exceptions and momentum in test_thermostat_exceptions.py, CPU = Reference in
tests/TestPlatformsAgree.cpp."""
import math

import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import scenes
from dpdtest import KT

GAMMA, CUTOFF = 4.5, 1.0


def test_defaults_and_type_pairs():
    integrator = openmmdpd.DPDVVIntegrator(KT, GAMMA, CUTOFF, 0.01)
    assert integrator.getDefaultTransverseFriction() == 0 / unit.picosecond
    assert integrator.getDefaultTransverseWeightExponent() == 2
    assert not integrator.hasTransverseFriction()
    pair = integrator.addTypePair(0, 1, 3.0, 1.0)
    integrator.setDefaultTransverseFriction(2.0 / unit.picosecond)
    integrator.setDefaultTransverseWeightExponent(1.0)
    assert integrator.getTypePairTransverseFriction(pair) == [2.0 / unit.picosecond, 1.0]  # not set: the defaults
    integrator.setTypePairTransverseFriction(pair, 5.0, 0.5)
    integrator.setDefaultTransverseFriction(0.0)
    assert integrator.getTypePairTransverseFriction(pair) == [5.0 / unit.picosecond, 0.5]
    assert integrator.hasTransverseFriction()


@pytest.mark.parametrize("value", [-1.0, math.nan, math.inf])
def test_a_bad_friction_is_refused_naming_it_and_changes_nothing(value):
    integrator = openmmdpd.ShardlowIntegrator(KT, GAMMA, CUTOFF, 0.01)
    pair = integrator.addTypePair(0, 1, 3.0, 1.0)
    with pytest.raises(openmm.OpenMMException, match="defaultTransverseFriction must be >= 0 /ps"):
        integrator.setDefaultTransverseFriction(value)
    with pytest.raises(openmm.OpenMMException, match="the transverse friction of type pair 0 must be >= 0 /ps"):
        integrator.setTypePairTransverseFriction(pair, value, 2.0)
    assert integrator.getDefaultTransverseFriction() == 0 / unit.picosecond
    assert not integrator.hasTransverseFriction()


@pytest.mark.parametrize("value", [0.0, -1.0, math.nan])
def test_a_bad_exponent_is_refused_naming_it_and_changes_nothing(value):
    integrator = openmmdpd.ShardlowIntegrator(KT, GAMMA, CUTOFF, 0.01)
    pair = integrator.addTypePair(0, 1, 3.0, 1.0)
    with pytest.raises(openmm.OpenMMException, match="defaultTransverseWeightExponent must be > 0"):
        integrator.setDefaultTransverseWeightExponent(value)
    with pytest.raises(openmm.OpenMMException, match="the transverse weight exponent of type pair 0 must be > 0"):
        integrator.setTypePairTransverseFriction(pair, 1.0, value)
    assert integrator.getTypePairTransverseFriction(pair) == [0 / unit.picosecond, 2.0]
    with pytest.raises(openmm.OpenMMException, match=r"pairIndex must be in \[0, 1\), got 1"):
        integrator.setTypePairTransverseFriction(1, 1.0, 2.0)


def test_xml_keeps_it_and_older_files_read_as_none():
    integrator = openmmdpd.LoweAndersenIntegrator(KT, GAMMA, CUTOFF, 0.01)
    integrator.addTypePair(0, 1, 3.0, 1.0)
    integrator.addTypePair(1, 1, 2.0, 0.9)
    integrator.setDefaultTransverseFriction(1.5)
    integrator.setDefaultTransverseWeightExponent(0.75)
    integrator.setTypePairTransverseFriction(1, 6.0, 0.25)
    xml = openmm.XmlSerializer.serialize(integrator)
    copy = openmmdpd.LoweAndersenIntegrator.cast(openmm.XmlSerializer.deserialize(xml))
    assert copy.getDefaultTransverseFriction() == 1.5 / unit.picosecond
    assert copy.getDefaultTransverseWeightExponent() == 0.75
    assert [copy.getTypePairTransverseFriction(k) for k in range(2)] == [[1.5 / unit.picosecond, 0.75],
                                                                        [6.0 / unit.picosecond, 0.25]]
    start, end = xml.index("<TransverseFriction>"), xml.index("</TransverseFriction>") + len("</TransverseFriction>")
    older = xml[:start] + xml[end:]
    older = older.replace(' defaultTransverseFriction="1.5"', "").replace(' defaultTransverseWeightExponent=".75"', "")
    assert "Transverse" not in older
    assert not openmmdpd.LoweAndersenIntegrator.cast(openmm.XmlSerializer.deserialize(older)).hasTransverseFriction()
    with pytest.raises(openmm.OpenMMException, match="transverse friction of type pair 1 must be >= 0"):
        openmm.XmlSerializer.deserialize(xml.replace('friction="6"', 'friction="-6"'))


def two_particles(integrator, r, platform_name="Reference", constrained=False):
    """Two unit masses r apart along y in a 5 nm box, no conservative force."""
    system = openmm.System()
    for _ in range(2):
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) for row in 5 * np.eye(3)))
    system.addForce(scenes.periodic_marker_force())
    if constrained:
        system.addConstraint(0, 1, r)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName(platform_name))
    context.setPositions([openmm.Vec3(1, 1, 1), openmm.Vec3(1, 1 + r, 1)])
    return context


def pair_ou(kT, dt):
    integrator = openmmdpd.LoweAndersenIntegrator(kT, GAMMA, CUTOFF, dt)
    integrator.setMethod(openmmdpd.LoweAndersenIntegrator.PairOrnsteinUhlenbeck)
    return integrator


@pytest.mark.parametrize("make, message", [
    (lambda: openmmdpd.LoweAndersenIntegrator(KT, GAMMA, CUTOFF, 0.01), "PairOrnsteinUhlenbeck method"),
    (lambda: openmmdpd.EDPDIntegrator(KT, GAMMA, CUTOFF, 10.0, 0.01), "EDPDIntegrator: transverse friction"),
    (lambda: openmmdpd.StaggeredDPDIntegrator(KT, GAMMA, CUTOFF, 0.01, 1), "StaggeredDPDIntegrator: transverse friction"),
])
def test_schemes_without_it_refuse_it(make, message):
    integrator = make()
    integrator.setDefaultTransverseFriction(GAMMA)
    with pytest.raises(openmm.OpenMMException, match=message):
        two_particles(integrator, 0.5)


@pytest.mark.parametrize("make", [lambda: openmmdpd.ShardlowIntegrator(KT, GAMMA, CUTOFF, 0.01), lambda: pair_ou(KT, 0.01)])
def test_the_sweeps_refuse_it_with_constraints(make):
    integrator = make()
    integrator.setDefaultTransverseFriction(GAMMA)
    with pytest.raises(openmm.OpenMMException, match="transverse friction is not available with constraints"):
        two_particles(integrator, 0.5, constrained=True)


def test_a_live_change_to_a_scheme_without_it_is_refused_at_the_next_step():
    integrator = pair_ou(KT, 0.01)
    integrator.setDefaultTransverseFriction(GAMMA)
    context = two_particles(integrator, 0.5)
    integrator.step(1)
    integrator.setMethod(openmmdpd.LoweAndersenIntegrator.Lowe)
    with pytest.raises(openmm.OpenMMException, match="PairOrnsteinUhlenbeck method"):
        integrator.step(1)
    assert context.getState().getStepCount() == 1


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
@pytest.mark.parametrize("s", [0.5, 2.0])
def test_the_pair_update_decays_each_direction_at_its_own_rate(s, platform_name):
    # kT = 0 (no noise), the pair OU after the Verlet drift, relative velocity u = (ux, uy, 0)
    # with the pair along y: the drift moves j by -u dt relative to i, and the update then
    # decays u's part along the new e by exp(-gamma wD dt/mu) and its part across e by
    # exp(-gamma_perp wD_perp dt/mu), mu = 1/2, wD = (1 - r/rc)^2, wD_perp = (1 - r/rc)^s.
    r, ux, uy, dt, gamma_perp = 0.6, 0.8, -0.5, 0.01, 3.0
    integrator = pair_ou(0.0, dt)
    integrator.setDefaultTransverseFriction(gamma_perp)
    integrator.setDefaultTransverseWeightExponent(s)
    context = two_particles(integrator, r, platform_name)
    context.setVelocities([openmm.Vec3(ux / 2, uy / 2, 0), openmm.Vec3(-ux / 2, -uy / 2, 0)])
    integrator.step(1)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    u = np.array([ux, uy, 0.0])
    d = np.array([0.0, -r, 0.0]) + u * dt  # r_i - r_j after the drift
    distance = np.linalg.norm(d)
    e = d / distance
    w = 1 - distance / CUTOFF
    along = e * e.dot(u) * math.exp(-GAMMA * w ** 2 * dt / 0.5)
    across = (u - e * e.dot(u)) * math.exp(-gamma_perp * w ** s * dt / 0.5)
    np.testing.assert_allclose(v[0] - v[1], along + across, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(v[0] + v[1], 0, atol=1e-15)  # momentum


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
def test_the_pressure_tensor_holds_the_momentum_flux_of_a_transverse_force(platform_name):
    # The same kT = 0 pair OU: its impulse J (on i) over dt is the pair force, and the
    # thermostat's part of the pressure tensor is sum r_b J_a / (V dt) for its component ab
    # (a <= b): P_xy is the flux of x momentum across planes of constant y.  For central
    # forces it is symmetric; here J has a part across e, so r_y J_x differs from r_x J_y.
    r, ux, dt, gamma_perp = 0.6, 0.8, 0.01, 3.0
    integrator = pair_ou(0.0, dt)
    integrator.setDefaultTransverseFriction(gamma_perp)
    integrator.setPressureTensorEnabled(True)
    context = two_particles(integrator, r, platform_name)
    context.setVelocities([openmm.Vec3(ux / 2, 0, 0), openmm.Vec3(-ux / 2, 0, 0)])
    integrator.step(1)
    thermostat = np.array(integrator.getAveragePressureTensor(integrator.PressureThermostat)._value)
    u = np.array([ux, 0.0, 0.0])
    d = np.array([0.0, -r, 0.0]) + u * dt
    distance = np.linalg.norm(d)
    e = d / distance
    w = 1 - distance / CUTOFF
    target = e * e.dot(u) * math.exp(-GAMMA * w ** 2 * dt / 0.5) + (u - e * e.dot(u)) * math.exp(-gamma_perp * w ** 2 * dt / 0.5)
    J = 0.5 * (target - u)
    flux = np.outer(d, J) / (125.0 * dt)  # flux[b, a] = r_b J_a
    expected = [flux[0, 0], flux[1, 1], flux[2, 2], flux[1, 0], flux[2, 0], flux[2, 1]]
    np.testing.assert_allclose(thermostat, expected, rtol=1e-10, atol=1e-14)
    assert abs(flux[1, 0] - flux[0, 1]) > 0.1 * abs(flux[1, 0])  # not symmetric: the other convention would fail


@pytest.mark.parametrize("variant", ["GrootWarren", "DPDVV", "SelfConsistent"])
def test_the_velocity_verlet_family_conserves_momentum_and_not_angular_momentum(variant):
    # Two particles with transverse friction only (gamma along e = 0), kT = 0: the pair
    # force is all across e, so it is not central, and the pair's angular momentum about its
    # centre changes while its momentum does not.
    integrator = openmmdpd.DPDVVIntegrator(0.0, 0.0, CUTOFF, 0.01)
    integrator.setVariant(getattr(openmmdpd.DPDVVIntegrator, variant))
    integrator.setDefaultTransverseFriction(GAMMA)
    context = two_particles(integrator, 0.5)
    context.setVelocities([openmm.Vec3(0.4, 0, 0), openmm.Vec3(-0.4, 0, 0)])

    def momenta():
        state = context.getState(getPositions=True, getVelocities=True)
        x, v = state.getPositions(asNumpy=True)._value, state.getVelocities(asNumpy=True)._value
        return v.sum(axis=0), np.cross(x[0] - x[1], v[0] - v[1]) / 2

    p0, l0 = momenta()
    integrator.step(10)
    p1, l1 = momenta()
    np.testing.assert_allclose(p1, p0, atol=1e-15)
    assert np.linalg.norm(l1) < 0.9 * np.linalg.norm(l0)  # the friction across e slows the pair's rotation
