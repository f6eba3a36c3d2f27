"""DPDSoftRepulsionForce from Python: units, copies, and the same energy and forces as the
CustomNonbondedForce version of scene `soft` (the scenes' switch)."""
import copy
import pickle

import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import scenes

Force = openmmdpd.DPDSoftRepulsionForce


def energy_and_forces(scene, platform_name):
    context = openmm.Context(scene.system, openmm.VerletIntegrator(0.001),
                             openmm.Platform.getPlatformByName(platform_name))
    context.setPositions(scene.positions)
    state = context.getState(getEnergy=True, getForces=True)
    return (state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole),
            state.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer))


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
def test_native_scene_matches_custom_nonbonded_scene(platform_name):
    a = [[25.0, 35.0], [35.0, 15.0]]
    types = [i % 2 for i in range(1000)]
    native = scenes.soft_scene(num_particles=1000, a=a, soft_repulsion_types=types)
    custom = scenes.soft_scene(num_particles=1000, a=a, soft_repulsion_types=types, native_force=False)
    assert any(isinstance(Force.cast(f), Force) for f in native.system.getForces())
    e1, f1 = energy_and_forces(native, platform_name)
    e2, f2 = energy_and_forces(custom, "Reference")
    assert e1 > 1000
    assert e1 == pytest.approx(e2, rel=1e-5)
    assert np.abs(f1 - f2).max() < 1e-5 * max(1.0, np.abs(f2).max())


def test_units_and_getters():
    force = Force(25 * unit.kilojoule_per_mole / unit.nanometer, 10 * unit.angstrom)
    assert force.getDefaultA() == 25 * unit.kilojoule_per_mole / unit.nanometer
    assert force.getDefaultCutoff() == 1.0 * unit.nanometer
    force.addTypePair(0, 1, 40.0, 0.9 * unit.nanometer)
    t1, t2, a, rc = force.getTypePairParameters(0)
    assert (t1, t2) == (0, 1) and a.value_in_unit(unit.kilojoule_per_mole / unit.nanometer) == 40.0
    assert rc == 0.9 * unit.nanometer
    force.addExclusion(3, 4)
    assert force.getExclusionParticles(0) == [3, 4]
    with pytest.raises(TypeError):
        Force(25 * unit.kelvin, 1.0)
    with pytest.raises(openmm.OpenMMException, match="defaultCutoff"):
        Force(25, -1.0)


def test_copies_keep_class_and_parameters():
    force = Force(25, 1.0)
    force.setParticleType(2, 1)
    force.addTypePair(0, 1, 40.0, 0.9)
    force.addExclusion(0, 1)
    xml = openmm.XmlSerializer.serialize(force)
    for other in (copy.deepcopy(force), pickle.loads(pickle.dumps(force)),
                  Force.cast(openmm.XmlSerializer.deserialize(xml))):
        assert type(other) is Force
        assert openmm.XmlSerializer.serialize(other) == xml


def test_update_parameters_in_context():
    scene = scenes.soft_scene(num_particles=500)
    force = [Force.cast(f) for f in scene.system.getForces() if Force.cast(f) is not None][0]
    context = openmm.Context(scene.system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(scene.positions)
    before = context.getState(getEnergy=True).getPotentialEnergy()
    force.setDefaultA(50.0)
    force.updateParametersInContext(context)
    after = context.getState(getEnergy=True).getPotentialEnergy()
    assert after / before == pytest.approx(2.0, rel=1e-12)
