"""Checkpoints from Python: openmmdpd.load_checkpoint continues a run bit for bit and, when it
refuses a checkpoint (damaged anywhere, another integrator's, trailing bytes), leaves the
Simulation exactly as it was and says why in readable text; copies, pickles and XML keep the
constraint tolerance."""
import copy
import pickle

import numpy as np
import openmm
import pytest
from openmm import app

import openmmdpd

from dpdtest import KT, platform, properties

PLATFORMS = ["Reference", "CPU"]


def simulation(integrator, platform_name, steps=5):
    scene = openmmdpd.scenes.build_scene("soft", num_particles=300)
    integrator.setRandomNumberSeed(21)
    sim = app.Simulation(scene.topology, scene.system, integrator, platform(platform_name), properties(platform_name))
    sim.context.setPositions(scene.positions)
    sim.context.setVelocitiesToTemperature(KT, 4)
    sim.step(steps)
    return sim


def snapshot(sim):
    state = sim.context.getState(getPositions=True, getVelocities=True)
    return (state.getPositions(asNumpy=True).tobytes(), state.getVelocities(asNumpy=True).tobytes(),
            state.getTime(), state.getStepCount())


@pytest.mark.parametrize("platform_name", PLATFORMS)
def test_load_checkpoint_continues_bit_for_bit(tmp_path, platform_name):
    sim = simulation(openmmdpd.ShardlowIntegrator(KT, 4.5, 1.0, 0.02), platform_name)
    path = tmp_path / "run.chk"
    sim.saveCheckpoint(str(path))
    sim.step(3)
    after = snapshot(sim)
    for source in (str(path), path, path.read_bytes(), open(path, "rb")):
        openmmdpd.load_checkpoint(sim, source)
        assert sim.currentStep == 5
        sim.step(3)
        assert snapshot(sim) == after


@pytest.mark.parametrize("platform_name", PLATFORMS)
def test_refused_checkpoints_leave_the_simulation_as_it_was(platform_name):
    gw = simulation(openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.02), platform_name, steps=3)
    sim = simulation(openmmdpd.ShardlowIntegrator(KT, 4.5, 1.0, 0.02), platform_name, steps=7)
    own = sim.context.createCheckpoint()
    sim.step(2)
    before = snapshot(sim)
    flipped = bytearray(own)
    flipped[len(own) // 3] ^= 0x10  # in OpenMM's part: the positions
    cases = {"another integrator's": (gw.context.createCheckpoint(), "written by a DPDVVIntegrator"),
             "a flipped byte": (bytes(flipped), "checksum does not match"),
             "trailing bytes": (own + b"\0", "bytes follow its end"),
             "a truncated file": (own[:-5], "truncated")}
    for name, (data, reason) in cases.items():
        with pytest.raises(openmm.OpenMMException, match=reason):
            openmmdpd.load_checkpoint(sim, data)
        assert snapshot(sim) == before, name


def test_a_damaged_integrator_name_reads_as_text():
    sim = simulation(openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.02), "Reference")
    data = bytearray(sim.context.createCheckpoint())
    name = data.find(b"DPDVVIntegrator (")
    data[name + 2] = 0xFF
    with pytest.raises(openmm.OpenMMException) as refused:
        openmmdpd.load_checkpoint(sim, bytes(data))
    message = str(refused.value)
    assert message.isprintable() and message.isascii() and "cannot load this checkpoint" in message


def test_copies_pickles_and_xml_keep_the_constraint_tolerance():
    integrator = openmmdpd.ShardlowIntegrator(KT, 4.5, 1.0, 0.02)
    assert integrator.getConstraintTolerance() == 1e-5
    integrator.setConstraintTolerance(2e-7)
    xml = openmm.XmlSerializer.serialize(integrator)
    for copied in (copy.copy(integrator), copy.deepcopy(integrator), pickle.loads(pickle.dumps(integrator)),
                   openmmdpd.ShardlowIntegrator.cast(openmm.XmlSerializer.deserialize(xml))):
        assert copied.getConstraintTolerance() == 2e-7
    with pytest.raises(openmm.OpenMMException, match="constraintTolerance must be > 0"):
        integrator.setConstraintTolerance(0)


def test_xml_that_is_not_numbers_is_refused_naming_the_attribute():
    xml = openmm.XmlSerializer.serialize(openmmdpd.StaggeredDPDIntegrator(KT, 4.5, 1.0, 0.02, 3))
    with pytest.raises(openmm.OpenMMException, match='attribute numSubSteps is "2147483648", not an integer'):
        openmm.XmlSerializer.deserialize(xml.replace('numSubSteps="3"', 'numSubSteps="2147483648"'))
    with pytest.raises(openmm.OpenMMException, match="attribute temperature is missing"):
        openmm.XmlSerializer.deserialize(xml.replace(' temperature="', ' t="'))
    with pytest.raises(openmm.OpenMMException, match="numSubSteps \\(K\\) must be from 1 to 10000"):
        openmmdpd.StaggeredDPDIntegrator(KT, 4.5, 1.0, 0.02, 2**31 - 1)
