"""The weight exponent s of the thermostat (wD = (1 - r/rc)^s, wR = (1 - r/rc)^(s/2)): its
setters, its checks, its XML, where it is refused, and the pair forces it gives against the
formula written out here.  Its effect on <kT> is in test_temperature.py (the pair rules stay
exact at any s) and CPU = Reference with it in tests/TestPlatformsAgree.cpp."""
import math

import numpy as np
import openmm
import pytest

import openmmdpd
from openmmdpd import scenes
from dpdtest import KT


def test_default_is_the_standard_weight_and_type_pairs_follow_it():
    integrator = openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.01)
    assert integrator.getDefaultWeightExponent() == 2
    assert integrator.hasStandardWeights()
    pair = integrator.addTypePair(0, 1, 3.0, 1.0)
    assert integrator.getTypePairWeightExponent(pair) == 2
    integrator.setDefaultWeightExponent(1.0)
    assert integrator.getTypePairWeightExponent(pair) == 1.0  # not set: the default
    integrator.setTypePairWeightExponent(pair, 0.5)
    integrator.setDefaultWeightExponent(1.5)
    assert integrator.getTypePairWeightExponent(pair) == 0.5
    assert not integrator.hasStandardWeights()


@pytest.mark.parametrize("value", [0.0, -1.0, math.nan, math.inf])
def test_invalid_exponents_raise_naming_the_parameter_and_change_nothing(value):
    integrator = openmmdpd.ShardlowIntegrator(KT, 4.5, 1.0, 0.01)
    pair = integrator.addTypePair(0, 1, 3.0, 1.0)
    with pytest.raises(openmm.OpenMMException, match="defaultWeightExponent must be > 0"):
        integrator.setDefaultWeightExponent(value)
    with pytest.raises(openmm.OpenMMException, match="weight exponent of type pair 0 must be > 0"):
        integrator.setTypePairWeightExponent(pair, value)
    assert integrator.getDefaultWeightExponent() == 2 and integrator.getTypePairWeightExponent(pair) == 2


def test_a_type_pair_that_does_not_exist_is_refused():
    integrator = openmmdpd.ShardlowIntegrator(KT, 4.5, 1.0, 0.01)
    with pytest.raises(openmm.OpenMMException, match=r"pairIndex must be in \[0, 0\), got 0"):
        integrator.setTypePairWeightExponent(0, 1.0)


def test_xml_keeps_the_exponents_and_older_files_read_as_standard():
    integrator = openmmdpd.LoweAndersenIntegrator(KT, 4.5, 1.0, 0.01)
    integrator.addTypePair(0, 1, 3.0, 1.0)
    integrator.addTypePair(1, 1, 2.0, 0.9)
    integrator.setDefaultWeightExponent(1.0)
    integrator.setTypePairWeightExponent(1, 0.25)
    xml = openmm.XmlSerializer.serialize(integrator)
    copy = openmmdpd.LoweAndersenIntegrator.cast(openmm.XmlSerializer.deserialize(xml))
    assert copy.getDefaultWeightExponent() == 1.0
    assert [copy.getTypePairWeightExponent(k) for k in range(2)] == [1.0, 0.25]
    start, end = xml.index("<WeightExponents>"), xml.index("</WeightExponents>") + len("</WeightExponents>")
    older = xml[:start] + xml[end:]
    older = older.replace(' defaultWeightExponent="1"', "")
    assert " defaultWeightExponent" not in older and "WeightExponents" not in older
    plain = openmmdpd.LoweAndersenIntegrator.cast(openmm.XmlSerializer.deserialize(older))
    assert plain.hasStandardWeights()


def test_a_bad_exponent_in_xml_is_refused():
    integrator = openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.01)
    xml = openmm.XmlSerializer.serialize(integrator).replace('defaultWeightExponent="2"', 'defaultWeightExponent="-2"')
    with pytest.raises(openmm.OpenMMException, match="defaultWeightExponent"):
        openmm.XmlSerializer.deserialize(xml)


def two_particles(integrator, r):
    system = openmm.System()
    for _ in range(2):
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) for row in 5 * np.eye(3)))
    system.addForce(scenes.periodic_marker_force())
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("Reference"))
    context.setPositions([openmm.Vec3(1, 1, 1), openmm.Vec3(1 + r, 1, 1)])
    return context


def test_edpd_refuses_exponents_other_than_two():
    integrator = openmmdpd.EDPDIntegrator(KT, 4.5, 1.0, 10.0, 0.01)
    integrator.setDefaultWeightExponent(1.0)
    with pytest.raises(openmm.OpenMMException, match="EDPDIntegrator: the weight exponents must be 2"):
        two_particles(integrator, 0.5)


@pytest.mark.parametrize("s", [0.5, 1.0, 2.0])
def test_the_friction_of_a_pair_follows_its_weight(s):
    # Two unit masses approaching at u along x, no conservative force and no noise (kT = 0):
    # the pair OU after the Verlet drift decays u exactly by exp(-gamma wD dt / mu), mu = 1/2,
    # with wD = (1 - r/rc)^s at the pair's distance after the drift, r - u dt.
    r, u, dt, gamma = 0.6, 1.0, 0.01, 4.5
    integrator = openmmdpd.LoweAndersenIntegrator(0.0, gamma, 1.0, dt)
    integrator.setMethod(openmmdpd.LoweAndersenIntegrator.PairOrnsteinUhlenbeck)
    integrator.setSplitting(openmmdpd.LoweAndersenIntegrator.AfterVerlet)
    integrator.setDefaultWeightExponent(s)
    context = two_particles(integrator, r)
    context.setVelocities([openmm.Vec3(u / 2, 0, 0), openmm.Vec3(-u / 2, 0, 0)])
    integrator.step(1)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    expected = u * math.exp(-gamma * (1 - (r - u * dt)) ** s * dt / 0.5)
    assert v[0][0] - v[1][0] == pytest.approx(expected, rel=1e-12)
