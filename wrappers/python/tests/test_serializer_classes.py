"""With openmmdpd imported, OpenMM's own calls hand our integrators and forces back as their own
classes: XmlSerializer.deserialize and clone, System.getForce(s) (of a System read back from XML
too) and CompoundIntegrator.getIntegrator. OpenMM's own classes pass through unchanged."""
import copy
import gc
import pickle

import openmm
import pytest

import openmmdpd
from dpdtest import KT

INTEGRATORS = {
    "DPDVVIntegrator": lambda: openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.01),
    "ShardlowIntegrator": lambda: openmmdpd.ShardlowIntegrator(KT, 4.5, 1.0, 0.02),
    "LoweAndersenIntegrator": lambda: openmmdpd.LoweAndersenIntegrator(KT, 4.5, 1.0, 0.02),
    "EDPDIntegrator": lambda: openmmdpd.EDPDIntegrator(KT, 4.5, 1.0, 0.5, 0.01),
    "DenOtterClarkeIntegrator": lambda: openmmdpd.DenOtterClarkeIntegrator(KT, 4.5, 1.0, 0.02),
    "StaggeredDPDIntegrator": lambda: openmmdpd.StaggeredDPDIntegrator(KT, 4.5, 1.0, 0.02, 3),
}


def soft_force():
    force = openmmdpd.DPDSoftRepulsionForce(25.0, 1.0)
    force.setParticleType(1, 1)
    force.addTypePair(0, 1, 40.0, 0.9)
    return force


@pytest.mark.parametrize("name", list(INTEGRATORS))
def test_integrator_comes_back_from_xml_as_its_own_class(name):
    original = INTEGRATORS[name]()
    original.setRandomNumberSeed(17)
    xml = openmm.XmlSerializer.serialize(original)
    for again in (openmm.XmlSerializer.deserialize(xml), openmm.XmlSerializer.clone(original)):
        assert type(again) is type(original) and type(again).__name__ == name
        assert openmm.XmlSerializer.serialize(again) == xml
        assert again.getStepSize() == original.getStepSize()
    # A cast of what is already the class is harmless, as the docs' older examples do it.
    assert type(type(original).cast(openmm.XmlSerializer.deserialize(xml))) is type(original)


def test_class_specific_methods_work_on_what_comes_back():
    xml = openmm.XmlSerializer.serialize(INTEGRATORS["ShardlowIntegrator"]())
    assert openmm.XmlSerializer.deserialize(xml).getOrder() == 1
    xml = openmm.XmlSerializer.serialize(INTEGRATORS["StaggeredDPDIntegrator"]())
    assert openmm.XmlSerializer.deserialize(xml).getNumSubSteps() == 3


def test_what_comes_back_owns_its_object():
    """The base proxy OpenMM made is dropped: the returned object must keep the C++ object."""
    original = INTEGRATORS["DPDVVIntegrator"]()
    xml = openmm.XmlSerializer.serialize(original)
    again = openmm.XmlSerializer.deserialize(xml)
    assert again.thisown
    gc.collect()
    for _ in range(10):
        INTEGRATORS["DPDVVIntegrator"]()  # reuse freed memory, if any was freed
    assert openmm.XmlSerializer.serialize(again) == xml
    # pickle and copy (which go through XmlSerializer.deserialize) still hand over the object.
    for copied in (pickle.loads(pickle.dumps(original)), copy.deepcopy(original), copy.copy(original)):
        gc.collect()
        assert type(copied) is type(original) and openmm.XmlSerializer.serialize(copied) == xml


def test_soft_repulsion_force_comes_back_from_xml_as_its_own_class():
    original = soft_force()
    xml = openmm.XmlSerializer.serialize(original)
    for again in (openmm.XmlSerializer.deserialize(xml), openmm.XmlSerializer.clone(original)):
        assert type(again) is openmmdpd.DPDSoftRepulsionForce
        assert again.getParticleType(1) == 1 and openmm.XmlSerializer.serialize(again) == xml


def test_system_gives_the_soft_repulsion_force_as_its_own_class():
    system = openmm.System()
    for _ in range(2):
        system.addParticle(1.0)
    system.addForce(openmm.NonbondedForce())
    system.addForce(soft_force())
    for copied in (system, openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(system))):
        assert [type(f) for f in copied.getForces()] == [openmm.NonbondedForce, openmmdpd.DPDSoftRepulsionForce]
        force = copied.getForce(1)
        assert force.getParticleType(1) == 1
        force.setParticleType(0, 1)  # a reference into the System, as for OpenMM's own forces
        assert copied.getForce(1).getParticleType(0) == 1


def test_openmm_classes_pass_through_unchanged():
    for integrator in (openmm.LangevinMiddleIntegrator(300, 1, 0.002), openmm.VerletIntegrator(0.001)):
        again = openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(integrator))
        assert type(again) is type(integrator)
        assert type(openmm.XmlSerializer.clone(integrator)) is type(integrator)
    force = openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(openmm.HarmonicBondForce()))
    assert type(force) is openmm.HarmonicBondForce
    state_xml = openmm.XmlSerializer.serialize(openmm.System())
    assert type(openmm.XmlSerializer.deserialize(state_xml)) is openmm.System


def test_compound_integrator_gives_ours_as_its_own_class():
    compound = openmm.CompoundIntegrator()
    compound.addIntegrator(openmm.VerletIntegrator(0.001))
    compound.addIntegrator(INTEGRATORS["ShardlowIntegrator"]())
    assert type(compound.getIntegrator(0)) is openmm.VerletIntegrator
    assert type(compound.getIntegrator(1)) is openmmdpd.ShardlowIntegrator
    assert compound.getIntegrator(1).getOrder() == 1
