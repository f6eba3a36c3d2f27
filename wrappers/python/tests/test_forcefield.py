"""DPD force fields read by OpenMM's app.ForceField (openmmdpd.forcefield): the Systems they
build against the same Systems built by hand from the scenes' forces, the thermostat table
copied into an integrator, bead-residue matching and the errors; Reference platform."""
import io
import os
import re
import subprocess
import sys

import numpy as np
import openmm
import pytest
from openmm import app, unit

import openmmdpd
from openmmdpd import forcefield, packer, scenes

from dpdtest import energy_and_forces, number, soft_force

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
KT = openmmdpd.KT_TEMPERATURE

# Three bead types with distinct a_ij, frictions and cutoffs, so that a misnumbered type
# changes the energies; FENE between A beads, worm-like springs between A and B, cosine angles.
TYPES = ("S", "A", "B")
A_IJ = np.array([[25.0, 30.0, 35.0], [30.0, 40.0, 45.0], [35.0, 45.0, 50.0]])
A_CUTOFF = np.array([[1.0, 0.9, 0.8], [0.9, 1.0, 0.95], [0.8, 0.95, 1.0]])
FRICTION = np.array([[4.5, 3.0, 2.0], [3.0, 5.0, 6.0], [2.0, 6.0, 7.0]])
FRICTION_CUTOFF = np.array([[1.0, 1.1, 0.9], [1.1, 1.0, 0.85], [0.9, 0.85, 1.2]])
FENE = dict(k=7.0, rmax=3.0)
WLC = dict(lp=0.5, l_spring=4.0, kT=1.0)
COSINE = dict(k=2.0, theta0=np.pi)


def pair_entries(tag, values, cutoffs, name, skip=()):
    return "".join(f'<Pair type1="{TYPES[i]}" type2="{TYPES[j]}" {name}="{values[i, j]!r}" cutoff="{cutoffs[i, j]!r}"/>'
                   for i in range(3) for j in range(i, 3) if (TYPES[i], TYPES[j]) not in skip)


def xml(a=A_IJ, friction=FRICTION, skip_a=(), skip_friction=(), extra_residues=""):
    return f"""<ForceField>
 <AtomTypes><Type name="S" class="S" mass="1.0"/><Type name="A" class="A" mass="1.0"/>
  <Type name="B" class="B" mass="2.0"/></AtomTypes>
 <Residues>
  <Residue name="SOL"><Atom name="S" type="S"/></Residue>
  <Residue name="AB3"><Atom name="A1" type="A"/><Atom name="A2" type="A"/><Atom name="B1" type="B"/>
   <Bond atomName1="A1" atomName2="A2"/><Bond atomName1="A2" atomName2="B1"/></Residue>
  {extra_residues}
 </Residues>
 <DPDSoftRepulsionForce>{pair_entries("DPDSoftRepulsionForce", a, A_CUTOFF, "a", skip_a)}</DPDSoftRepulsionForce>
 <DPDThermostat>{pair_entries("DPDThermostat", friction, FRICTION_CUTOFF, "friction", skip_friction)}</DPDThermostat>
 <FENEBondForce><Bond class1="A" class2="A" k="{FENE['k']}" rmax="{FENE['rmax']}"/></FENEBondForce>
 <WormLikeChainBondForce><Bond class1="A" class2="B" persistenceLength="{WLC['lp']}"
   springLength="{WLC['l_spring']}" kT="{WLC['kT']}"/></WormLikeChainBondForce>
 <CosineAngleForce><Angle class1="A" class2="A" class3="B" k="{COSINE['k']}" theta0="{COSINE['theta0']!r}"/>
 </CosineAngleForce>
</ForceField>"""


def load(text):
    return app.ForceField(io.StringIO(text))


TRIMER = packer.Molecule.single("AB3", ["A1", "A2", "B1"], [(0, 1), (1, 2)])
SOLVENT = packer.Molecule.single("SOL", ["S"])


def trimers_in_solvent(seed=1):
    return packer.pack([(TRIMER, 6), (SOLVENT, 100)], density=3.0, bond_length=0.8, seed=seed)


def hand_built(topology, a=A_IJ):
    """The System of the test force field, from the scenes' forces: S = 0, A = 1, B = 2."""
    names = [atom.name[0] for atom in topology.atoms()]
    types = [TYPES.index(name) for name in names]
    system = openmm.System()
    for _ in types:
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*topology.getPeriodicBoxVectors())
    soft = scenes.soft_repulsion_force(len(types), a, types, cutoff=1.0)
    for index in range(soft.getNumTypePairs()):  # per-pair cutoffs, which the helper takes as one
        t1, t2, value, _ = soft.getTypePairParameters(index)
        soft.setTypePairParameters(index, t1, t2, value, A_CUTOFF[t1, t2])
    system.addForce(soft)
    bonds = [(a.index, b.index) for a, b in topology.bonds()]
    fene = [(i, j) for i, j in bonds if names[i] == names[j] == "A"]
    system.addForce(scenes.fene_bond_force(fene, **FENE))
    system.addForce(scenes.wlc_bond_force([b for b in bonds if b not in fene], WLC["lp"], WLC["l_spring"], WLC["kT"]))
    angle = openmm.CustomAngleForce(f"{COSINE['k']!r}*(1 - cos(theta - {COSINE['theta0']!r}))")
    for residue in topology.residues():
        atoms = [atom.index for atom in residue.atoms()]
        if len(atoms) == 3:
            angle.addAngle(*atoms)
    system.addForce(angle)
    return system


def pair_table(obj, num_types):
    """{(i, j): (a or friction, cutoff)} that a force or an integrator applies to each pair of types."""
    default = obj.getDefaultA() if isinstance(obj, openmmdpd.DPDSoftRepulsionForce) else obj.getDefaultFriction()
    table = {(i, j): (number(default), number(obj.getDefaultCutoff()))
             for i in range(num_types) for j in range(i, num_types)}
    for index in range(obj.getNumTypePairs()):
        t1, t2, value, cutoff = obj.getTypePairParameters(index)
        table[tuple(sorted((t1, t2)))] = (number(value), number(cutoff))
    return table


def differences(system, expected, positions):
    """What differs between two Systems' energies, forces, particle types and a_ij tables."""
    found = []
    (e1, f1), (e2, f2) = energy_and_forces(system, positions), energy_and_forces(expected, positions)
    if abs(e1 - e2) > 1e-12 * max(1.0, abs(e2)):
        found.append(f"energy {e1} != {e2}")
    if np.max(np.abs(f1 - f2)) > 1e-12 * max(1.0, np.max(np.abs(f2))):
        found.append("forces")
    s1, s2 = soft_force(system), soft_force(expected)
    if [s1.getParticleType(i) for i in range(system.getNumParticles())] != \
            [s2.getParticleType(i) for i in range(expected.getNumParticles())]:
        found.append("particle types")
    if pair_table(s1, 3) != pair_table(s2, 3):
        found.append("a_ij table")
    return found


def test_created_system_equals_the_hand_built_one():
    topology, positions = trimers_in_solvent()
    system = load(xml()).createSystem(topology, nonbondedMethod=app.CutoffPeriodic, removeCMMotion=False)
    assert differences(system, hand_built(topology), positions) == []
    # element-less beads: their type's mass, and no constraints even where HBonds asks for them
    assert [system.getParticleMass(i) for i in range(3)] == [1.0 * unit.dalton, 1.0 * unit.dalton, 2.0 * unit.dalton]
    assert load(xml()).createSystem(topology, constraints=app.HBonds).getNumConstraints() == 0
    assert soft_force(system).getNonbondedMethod() == openmmdpd.DPDSoftRepulsionForce.CutoffPeriodic


def test_bonds_and_angles_listed_in_reverse_find_their_entries():
    # The entries name (A, B) and (A, A, B); these trimers list their beads B1, A2, A1, so
    # their bonds and angles come in the other order.
    reversed_trimer = packer.Molecule.single("AB3", ["B1", "A2", "A1"], [(0, 1), (1, 2)])
    topology, positions = packer.pack([(reversed_trimer, 6), (SOLVENT, 100)], density=3.0, seed=4)
    system = load(xml()).createSystem(topology, removeCMMotion=False)
    assert differences(system, hand_built(topology), positions) == []
    counts = {force.getName(): force for force in system.getForces()}
    assert counts["WormLikeChain"].getNumBonds() == counts["FENE"].getNumBonds() == 6
    assert counts["CosineAngle"].getNumAngles() == 6
    assert [counts["WormLikeChain"].getBondParameters(0)[:2], counts["CosineAngle"].getAngleParameters(0)[:3]] \
        == [[0, 1], [0, 1, 2]]


def test_a_mismatched_a_ij_table_is_detected():
    topology, positions = trimers_in_solvent()
    swapped = A_IJ.copy()
    swapped[0, 1] = swapped[1, 0] = 33.0
    system = load(xml(a=swapped)).createSystem(topology, removeCMMotion=False)
    found = differences(system, hand_built(topology), positions)
    assert "a_ij table" in found and any(item.startswith("energy") for item in found)


def thermostat(topology, text):
    return forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01), load(text), topology)


def expected_friction_table():
    return {(i, j): (FRICTION[i, j], FRICTION_CUTOFF[i, j]) for i in range(3) for j in range(i, 3)}


def test_the_thermostat_table_and_types_agree_with_the_force():
    topology, _ = trimers_in_solvent()
    integrator = thermostat(topology, xml())
    assert pair_table(integrator, 3) == expected_friction_table()
    system = load(xml()).createSystem(topology)
    force = soft_force(system)
    assert [integrator.getParticleType(i) for i in range(topology.getNumAtoms())] == \
        [force.getParticleType(i) for i in range(topology.getNumAtoms())]
    changed = FRICTION.copy()
    changed[1, 2] = changed[2, 1] = 1.0
    mismatched = thermostat(topology, xml(friction=changed))
    assert pair_table(mismatched, 3) != expected_friction_table()


def test_ignore_external_bonds_reaches_the_thermostat_matching():
    # Solvent beads bonded in pairs match SOL (which has no external bond) only when external
    # bonds are ignored, in apply_thermostat_parameters as in createSystem.
    pair = packer.Molecule([("SOL", ["S"]), ("SOL", ["S"])], [(0, 1)])
    topology, _ = packer.pack([(TRIMER, 6), (pair, 50)], density=3.0, seed=5)
    ff = load(xml())
    system = ff.createSystem(topology, ignoreExternalBonds=True)
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01), ff, topology,
                                                        ignoreExternalBonds=True, system=system)
    force = soft_force(system)
    types = [integrator.getParticleType(i) for i in range(topology.getNumAtoms())]
    assert types == [force.getParticleType(i) for i in range(topology.getNumAtoms())]
    assert types[:4] == [1, 1, 2, 1] and types[18:] == [0] * 100
    assert pair_table(integrator, 3) == expected_friction_table()
    with pytest.raises(ValueError, match=r"No template found for residue \d+ \(SOL\)"):  # which one: OpenMM's order
        forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01), ff, topology)


def test_types_are_numbered_in_the_force_fields_order_of_the_types_present():
    solvent_only = packer.pack([(SOLVENT, 30)], density=3.0)[0]
    system = load(xml()).createSystem(solvent_only)
    force = soft_force(system)
    assert force.getNumTypePairs() == 0 and number(force.getDefaultA()) == A_IJ[0, 0]
    trimers_only = packer.pack([(TRIMER, 10)], density=3.0)[0]
    system = load(xml()).createSystem(trimers_only)
    force = soft_force(system)
    assert [force.getParticleType(i) for i in range(3)] == [0, 0, 1]  # A = 0, B = 1 here
    assert number(force.getDefaultA()) == A_IJ[1, 1]


def test_groot_warren_matches_the_scenes_helpers():
    water, chain = packer.Molecule.single("W", ["W"]), packer.Molecule.chain(5)
    topology, positions = packer.pack([(chain, 3), (water, 60)], density=3.0, seed=2)
    system = app.ForceField(forcefield.data_path("groot-warren.xml")).createSystem(topology, removeCMMotion=False)
    types = [0 if atom.name == "W" else 1 for atom in topology.atoms()]
    expected = openmm.System()
    for _ in types:
        expected.addParticle(1.0)
    expected.setDefaultPeriodicBoxVectors(*topology.getPeriodicBoxVectors())
    expected.addForce(scenes.soft_repulsion_force(len(types), [[25.0, 25.0], [25.0, 25.0]], types))
    expected.addForce(scenes.harmonic_bond_force([(a.index, b.index) for a, b in topology.bonds()], k=4.0))
    (e1, f1), (e2, f2) = energy_and_forces(system, positions), energy_and_forces(expected, positions)
    assert e1 == pytest.approx(e2, rel=1e-12) and np.max(np.abs(f1 - f2)) < 1e-12 * np.max(np.abs(f2))
    force = soft_force(system)
    assert [force.getParticleType(i) for i in range(len(types))] == types
    assert pair_table(force, 2) == pair_table(soft_force(expected), 2) == \
        {(0, 0): (25.0, 1.0), (0, 1): (25.0, 1.0), (1, 1): (25.0, 1.0)}
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 2.0, 0.04),
                                                        app.ForceField(forcefield.data_path("groot-warren.xml")),
                                                        topology)
    assert pair_table(integrator, 2) == {(0, 0): (4.5, 1.0), (0, 1): (4.5, 1.0), (1, 1): (4.5, 1.0)}
    assert [system.getParticleMass(i) for i in range(len(types))] == [1.0 * unit.dalton] * len(types)


# --- Weight exponents and thermostat exceptions ----------------------------------------------

def thermostat_options(s_s="1.5", a_b="0.5", factor12="0", factor13="0.5"):
    """xml() with weight exponents on the (S, S) and (A, B) pairs and bond factors on the tag."""
    text = xml().replace("<DPDThermostat>", f'<DPDThermostat bondFactor12="{factor12}" bondFactor13="{factor13}">')
    for pair, exponent in (('type1="S" type2="S"', s_s), ('type1="A" type2="B"', a_b)):
        text = re.sub(f'(<Pair {pair} friction="[^"]*")', rf'\1 weightExponent="{exponent}"', text)
    return text


def weight_exponents(integrator, num_types):
    """{(i, j): s} that the integrator applies to each pair of types."""
    table = {(i, j): integrator.getDefaultWeightExponent() for i in range(num_types) for j in range(i, num_types)}
    for index in range(integrator.getNumTypePairs()):
        t1, t2 = integrator.getTypePairParameters(index)[:2]
        table[tuple(sorted((t1, t2)))] = integrator.getTypePairWeightExponent(index)
    return table


def thermostat_exceptions(integrator):
    return {(min(p1, p2), max(p1, p2), f) for p1, p2, f in
            (integrator.getThermostatExceptionParameters(k) for k in range(integrator.getNumThermostatExceptions()))}


def test_weight_exponents_and_bond_factors_reach_the_integrator():
    topology, _ = trimers_in_solvent()
    integrator = thermostat(topology, thermostat_options())
    assert [integrator.getParticleType(i) for i in range(3)] == [1, 1, 2]  # trimers first: A1 A2 B1, S = 0
    assert weight_exponents(integrator, 3) == {(0, 0): 1.5, (0, 1): 2.0, (0, 2): 2.0, (1, 1): 2.0, (1, 2): 0.5,
                                               (2, 2): 2.0}
    assert integrator.getDefaultWeightExponent() == 1.5 and not integrator.hasStandardWeights()
    assert pair_table(integrator, 3) == expected_friction_table()
    # bonded beads excluded (bondFactor12 = 0), the ends of each trimer at half the friction
    expected = set()
    for first in range(0, 18, 3):
        expected |= {(first, first + 1, 0.0), (first + 1, first + 2, 0.0), (first, first + 2, 0.5)}
    assert thermostat_exceptions(integrator) == expected
    # 1-3 pairs only where bondFactor13 is not 1
    only_bonds = thermostat(topology, thermostat_options(factor13="1"))
    assert thermostat_exceptions(only_bonds) == {e for e in expected if e[2] == 0.0}


def test_without_the_new_attributes_the_thermostat_is_standard():
    topology, _ = trimers_in_solvent()
    for integrator in (thermostat(topology, xml()), thermostat(topology, thermostat_options("2", "2", "1", "1"))):
        assert integrator.hasStandardWeights() and integrator.getNumThermostatExceptions() == 0
    water, chain = packer.Molecule.single("W", ["W"]), packer.Molecule.chain(5)
    topology, _ = packer.pack([(chain, 3), (water, 60)], density=3.0, seed=2)
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.ShardlowIntegrator(KT, 1.0, 1.0, 0.04),
                                                        app.ForceField(forcefield.data_path("groot-warren.xml")),
                                                        topology)
    assert integrator.hasStandardWeights() and integrator.getNumThermostatExceptions() == 0


@pytest.mark.parametrize("options, message", [
    (dict(a_b="0"), r"DPDThermostat: Pair .*'weightExponent': '0'.* needs .*weightExponent > 0"),
    (dict(s_s="-1"), r"DPDThermostat: Pair .*'weightExponent': '-1'.* needs .*weightExponent > 0"),
    (dict(a_b="inf"), r"DPDThermostat: Pair .*: friction, cutoff, weightExponent, transverseFriction, "
                      r"transverseWeightExponent must be finite numbers"),
    (dict(factor12="1.5"), r"DPDThermostat: bondFactor12='1.5' must be a number in \[0, 1\]"),
    (dict(factor13="-0.5"), r"DPDThermostat: bondFactor13='-0.5' must be a number in \[0, 1\]"),
    (dict(factor13="nan"), r"DPDThermostat: bondFactor13='nan' must be a number in \[0, 1\]"),
    (dict(factor12="half"), r"DPDThermostat: bondFactor12='half' must be a number in \[0, 1\]"),
])
def test_bad_exponents_and_bond_factors_are_refused_by_name(options, message):
    with pytest.raises(ValueError, match=message):
        load(thermostat_options(**options))


def test_bond_factors_refused_or_in_conflict_leave_the_force_field_as_it_was():
    ff = load(xml())
    with pytest.raises(ValueError, match="bondFactor12='2' must be"):
        ff.loadFile(io.StringIO('<ForceField><DPDThermostat bondFactor12="2"><Pair type1="S" type2="A" '
                                'friction="1" cutoff="1"/></DPDThermostat></ForceField>'))
    generator = forcefield._generator(ff, forcefield.ThermostatGenerator)
    assert len(generator.table.entries) == 6 and generator.bond_factors() == (1.0, 1.0)
    ff = load(thermostat_options())
    with pytest.raises(ValueError, match=r"bondFactor13='0.25' differs from the 0.5 of an earlier <DPDThermostat>"):
        ff.loadFile(io.StringIO('<ForceField><DPDThermostat bondFactor13="0.25"/></ForceField>'))
    ff.loadFile(io.StringIO('<ForceField><DPDThermostat bondFactor12="0.0"/></ForceField>'))  # the same: kept
    assert forcefield._generator(ff, forcefield.ThermostatGenerator).bond_factors() == (0.0, 0.5)


def test_an_exception_on_a_bonded_pair_refuses_the_bond_factors_before_any_change():
    topology, _ = trimers_in_solvent()
    integrator = openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01)
    integrator.addThermostatException(1, 0, 0.25)
    with pytest.raises(ValueError, match="particles 0, 1 already have a thermostat exception"):
        forcefield.apply_thermostat_parameters(integrator, load(thermostat_options()), topology)
    assert integrator.getNumThermostatExceptions() == 1 and integrator.getNumTypePairs() == 0
    assert integrator.hasStandardWeights() and integrator.getParticleType(0) == 0


class FakeDPDIntegrator:
    """Stands for OpenMM's DPDIntegrator (OpenMM 8.3 and later): type pairs, but no weight
    exponents and no thermostat exceptions. Records the methods called on it."""

    def __init__(self):
        self.calls = []

    def getNumTypePairs(self):
        return 0

    def __getattr__(self, name):
        return lambda *args: self.calls.append(name)


def with_transverse_friction(text, pair='type1="A" type2="B"', friction="3", exponent="1"):
    return re.sub(f'(<Pair {pair} friction="[^"]*")', rf'\1 transverseFriction="{friction}" transverseWeightExponent="{exponent}"',
                  text)


def test_transverse_friction_reaches_the_integrator():
    topology, _ = trimers_in_solvent()
    integrator = thermostat(topology, with_transverse_friction(xml()))
    assert integrator.getDefaultTransverseFriction() == 0 / unit.picosecond  # pair (S, S): none
    perpendicular = {}
    for index in range(integrator.getNumTypePairs()):
        t1, t2 = integrator.getTypePairParameters(index)[:2]
        perpendicular[tuple(sorted((t1, t2)))] = integrator.getTypePairTransverseFriction(index)
    assert perpendicular[(1, 2)] == [3.0 / unit.picosecond, 1.0]  # (A, B)
    assert all(value == [0 / unit.picosecond, 2.0] for pair, value in perpendicular.items() if pair != (1, 2))
    assert thermostat(topology, xml()).hasTransverseFriction() is False


@pytest.mark.parametrize("friction, exponent, message", [("-1", "1", "needs .*transverseFriction >= 0"),
                                                         ("1", "0", "needs .*transverseWeightExponent > 0"),
                                                         ("nan", "1", "must be finite numbers")])
def test_bad_transverse_friction_is_refused_by_name(friction, exponent, message):
    with pytest.raises(ValueError, match=f"DPDThermostat: Pair .*{message}"):
        load(with_transverse_friction(xml(), friction=friction, exponent=exponent))


def test_openmms_dpd_integrator_gets_the_table_but_refuses_exponents_and_bond_factors(monkeypatch):
    monkeypatch.setattr(openmm, "DPDIntegrator", FakeDPDIntegrator, raising=False)
    topology, _ = trimers_in_solvent()
    plain = forcefield.apply_thermostat_parameters(FakeDPDIntegrator(), load(xml()), topology)
    assert set(plain.calls) == {"setDefaultFriction", "setDefaultCutoff", "addTypePair", "setParticleType"}
    for options, lacks in ((dict(factor12="1", factor13="1"), "has no weight exponents, which"),
                           (dict(s_s="2", a_b="2"), "has no thermostat exceptions, which"),
                           ({}, "has no weight exponents and no thermostat exceptions")):
        integrator = FakeDPDIntegrator()
        with pytest.raises(ValueError, match=f"FakeDPDIntegrator {lacks}"):
            forcefield.apply_thermostat_parameters(integrator, load(thermostat_options(**options)), topology)
        assert integrator.calls == []
    integrator = FakeDPDIntegrator()
    with pytest.raises(ValueError, match="FakeDPDIntegrator has no transverse friction, which"):
        forcefield.apply_thermostat_parameters(integrator, load(with_transverse_friction(xml())), topology)
    assert integrator.calls == []


# --- Bead residues -------------------------------------------------------------------------

LIPID = """<Residue name="H3T4"><Atom name="H1" type="A"/><Atom name="H2" type="A"/><Atom name="H3" type="A"/>
 <Atom name="T1" type="B"/><Atom name="T2" type="B"/><Atom name="T3" type="B"/><Atom name="T4" type="B"/>
 <Bond atomName1="H1" atomName2="H2"/><Bond atomName1="H2" atomName2="H3"/><Bond atomName1="H3" atomName2="T1"/>
 <Bond atomName1="T1" atomName2="T2"/><Bond atomName1="T2" atomName2="T3"/><Bond atomName1="T3" atomName2="T4"/>
</Residue>"""


def test_bead_residues_match_by_bead_names_and_bonds():
    # A one-bead residue named S matches SOL only, though every one-bead template has the same
    # (empty) element signature; the lipid's head and tail beads take their types by name,
    # listed in any order.
    beads = ["T4", "T3", "T2", "T1", "H3", "H2", "H1"]
    lipid = packer.Molecule.single("LIP", beads, [(i, i + 1) for i in range(6)])
    topology, _ = packer.pack([(lipid, 4), (SOLVENT, 40)], density=3.0)
    system = load(xml(extra_residues=LIPID)).createSystem(topology)
    force = soft_force(system)
    assert [force.getParticleType(i) for i in range(7)] == [2, 2, 2, 2, 1, 1, 1]
    assert all(force.getParticleType(i) == 0 for i in range(28, 68))


def test_a_residue_without_a_template_is_named():
    topology, _ = packer.pack([(packer.Molecule.single("XYZ", ["Q"]), 1), (SOLVENT, 40)], density=3.0)
    with pytest.raises(ValueError, match=r"residue 0 \(XYZ\) with beads Q"):
        load(xml()).createSystem(topology)
    with pytest.raises(ValueError, match=r"OpenMM's matching by elements would take SOL, with beads S"):
        load(xml()).getUnmatchedResidues(topology)  # not a silent match to SOL
    # A residue no template fits even by OpenMM's rule is OpenMM's to report, and to list
    # (with the matcher raising here, OpenMM's patches and template generators were never tried).
    broken = packer.Molecule.single("AB3", ["A1", "A2", "B1"], [(0, 1)])  # a bond missing
    topology, _ = packer.pack([(broken, 1), (SOLVENT, 40)], density=3.0)
    assert [residue.index for residue in load(xml()).getUnmatchedResidues(topology)] == [0]
    # OpenMM's own message, whose index and wording vary between its versions
    with pytest.raises(ValueError, match=r"No template found for residue \d+ \(AB3\)"):
        load(xml()).createSystem(topology)
    ff = load(xml())

    def generator(forcefield, residue):  # a template for the residue as it is
        forcefield.loadFile(io.StringIO('<ForceField><Residues><Residue name="AB2"><Atom name="A1" type="A"/>'
                                        '<Atom name="A2" type="A"/><Atom name="B1" type="B"/>'
                                        '<Bond atomName1="A1" atomName2="A2"/></Residue></Residues></ForceField>'))
        return True
    ff.registerTemplateGenerator(generator)
    system = ff.createSystem(topology)
    assert [soft_force(system).getParticleType(i) for i in range(4)] == [1, 1, 2, 0]


def test_templates_that_match_alike_with_other_types_are_refused():
    twin = '<Residue name="SOL2"><Atom name="S" type="A"/></Residue>'
    topology, _ = packer.pack([(SOLVENT, 40)], density=3.0)
    with pytest.raises(ValueError, match="bead templates SOL and SOL2 both match residue 0"):
        load(xml(extra_residues=twin)).createSystem(topology)
    # residueTemplates chooses, in createSystem and in apply_thermostat_parameters alike
    chosen = {residue: "SOL2" if residue.index < 10 else "SOL" for residue in topology.residues()}
    system = load(xml(extra_residues=twin)).createSystem(topology, residueTemplates=chosen)
    force = soft_force(system)
    assert [force.getParticleType(i) for i in range(12)] == [1] * 10 + [0] * 2  # A (from SOL2) after S here
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01),
                                                        load(xml(extra_residues=twin)), topology, chosen)
    assert [integrator.getParticleType(i) for i in range(12)] == [1] * 10 + [0] * 2


def test_a_template_overridden_after_matching_is_the_one_used():
    # A template of a higher override level replaces the one of its name, leaving the number of
    # templates as it was: the bead-name index must still see the new one.
    override = io.StringIO('<ForceField><Residues><Residue name="SOL" override="1"><Atom name="S" type="B"/>'
                           '</Residue></Residues></ForceField>')
    topology, _ = trimers_in_solvent()
    ff = load(xml())
    before = soft_force(ff.createSystem(topology))
    assert before.getParticleType(18) == 0  # the first solvent bead: S
    ff.loadFile(override)
    system = ff.createSystem(topology)
    after = soft_force(system)
    fresh = load(xml())
    fresh.loadFile(io.StringIO(override.getvalue()))
    expected_system = fresh.createSystem(topology)
    expected = soft_force(expected_system)
    types = [after.getParticleType(i) for i in range(topology.getNumAtoms())]
    assert types == [expected.getParticleType(i) for i in range(topology.getNumAtoms())]
    assert types[18] == 1 and system.getParticleMass(18) == 2.0 * unit.dalton  # B among A, B


def test_the_system_given_checks_the_thermostat_types():
    twin = '<Residue name="SOL2"><Atom name="S" type="A"/></Residue>'
    topology, _ = packer.pack([(SOLVENT, 40)], density=3.0)
    chosen = {residue: "SOL2" if residue.index < 10 else "SOL" for residue in topology.residues()}
    ff = load(xml(extra_residues=twin))
    system = ff.createSystem(topology, residueTemplates=chosen)
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01), ff, topology,
                                                        chosen, system=system)
    assert [integrator.getParticleType(i) for i in range(12)] == [1] * 10 + [0] * 2
    # Other residueTemplates than createSystem's: every bead A, type 0 of the one type present,
    # where the force has S = 0 and A = 1. Refused before the integrator is changed.
    others = {residue: "SOL2" for residue in topology.residues()}
    fresh = openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01)
    with pytest.raises(ValueError, match=r"particle 0 is type 0 \(A\) by matching the topology but type 1 in the "
                                         r"System's DPDSoftRepulsionForce"):
        forcefield.apply_thermostat_parameters(fresh, ff, topology, others, system=system)
    assert fresh.getNumTypePairs() == 0 and number(fresh.getDefaultFriction()) == 1.0
    # A force field changed since createSystem: SOL's bead overridden to B.
    ff = load(xml())
    system = ff.createSystem(topology)
    ff.loadFile(io.StringIO('<ForceField><Residues><Residue name="SOL" override="1"><Atom name="S" type="B"/>'
                            '</Residue></Residues></ForceField>'))
    with pytest.raises(ValueError, match=r"has a, cutoff = \(25.0, 1.0\) for type pair \(0, 0\), the force field "
                                         r"\(50.0, 1.0\) for \(B, B\)"):
        forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01), ff, topology,
                                               system=system)
    with pytest.raises(ValueError, match="system has 40 particles, the topology 41 atoms"):
        bigger, _ = packer.pack([(SOLVENT, 41)], density=3.0)
        forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01), ff, bigger,
                                               system=system)


# --- Errors -------------------------------------------------------------------------------

def test_a_type_pair_missing_from_a_ij_is_named():
    topology, _ = trimers_in_solvent()
    with pytest.raises(ValueError, match=r"type pair \(S, B\)"):
        load(xml(skip_a={("S", "B")})).createSystem(topology)


def test_thermostat_and_force_must_cover_the_same_pairs():
    topology, _ = trimers_in_solvent()
    with pytest.raises(ValueError, match=r"\(A, B\) is in one type-pair table but not in DPDThermostat"):
        load(xml(skip_friction={("A", "B")})).createSystem(topology)
    with pytest.raises(ValueError, match=r"\(A, B\) is in one type-pair table but not in DPDThermostat"):
        thermostat(topology, xml(skip_friction={("A", "B")}))
    with pytest.raises(ValueError, match=r"\(S, A\) is in one type-pair table but not in DPDSoftRepulsionForce"):
        thermostat(topology, xml(skip_a={("S", "A")}))


def test_apply_thermostat_parameters_refuses_what_it_cannot_fill():
    topology, _ = trimers_in_solvent()
    with pytest.raises(TypeError, match="LangevinMiddleIntegrator has no type-pair thermostat"):
        forcefield.apply_thermostat_parameters(openmm.LangevinMiddleIntegrator(KT, 1.0, 0.01), load(xml()), topology)
    used = openmmdpd.ShardlowIntegrator(KT, 1.0, 1.0, 0.01)
    used.addTypePair(0, 1, 2.0, 1.0)
    with pytest.raises(ValueError, match="already has 1 type pairs"):
        forcefield.apply_thermostat_parameters(used, load(xml()), topology)
    no_thermostat = re.sub(r"<DPDThermostat>.*</DPDThermostat>", "", xml(), flags=re.S)
    with pytest.raises(ValueError, match="has no <DPDThermostat>"):
        forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 1.0, 0.01), load(no_thermostat),
                                               topology)


def test_entries_naming_unknown_types_or_bad_values_are_refused_by_name():
    with pytest.raises(ValueError, match="DPDSoftRepulsionForce: Pair .*'X'.* names a type or class"):
        load(xml().replace('type1="S" type2="S"', 'type1="X" type2="S"', 1))
    with pytest.raises(ValueError, match="DPDThermostat: Pair .*'S'.* needs friction >= 0 and cutoff > 0"):
        load(xml().replace('friction="4.5"', 'friction="-4.5"', 1))
    with pytest.raises(ValueError, match="FENEBondForce: Bond .*'A'.*: k, rmax must be finite numbers"):
        load(xml().replace('rmax="3.0"', 'rmax="far"'))
    with pytest.raises(ValueError, match="CosineAngleForce: Angle .* lacks theta0"):
        load(re.sub(r' theta0="[^"]*"', "", xml()))


@pytest.mark.parametrize("old, new, message", [
    ('a="25.0"', 'a="nan"', "DPDSoftRepulsionForce: Pair .*: a, cutoff must be finite numbers"),
    ('a="25.0"', 'a="inf"', "DPDSoftRepulsionForce: Pair .*: a, cutoff must be finite numbers"),
    ('a="25.0"', 'a="-1"', "DPDSoftRepulsionForce: Pair .* needs a >= 0 and cutoff > 0"),
    ('rmax="3.0"', 'rmax="0"', "FENEBondForce: Bond .* needs k >= 0 and rmax > 0"),
    ('rmax="3.0"', 'rmax="-3.0"', "FENEBondForce: Bond .* needs k >= 0 and rmax > 0"),
    ('k="7.0"', 'k="-7.0"', "FENEBondForce: Bond .* needs k >= 0 and rmax > 0"),
    ('springLength="4.0"', 'springLength="0"',
     "WormLikeChainBondForce: Bond .* needs persistenceLength > 0 and springLength > 0 and kT >= 0"),
    ('persistenceLength="0.5"', 'persistenceLength="-0.5"',
     "WormLikeChainBondForce: Bond .* needs persistenceLength > 0"),
    ('kT="1.0"', 'kT="-1.0"', "WormLikeChainBondForce: Bond .* needs .*kT >= 0"),
    ('k="2.0"', 'k="-2.0"', "CosineAngleForce: Angle .* needs k >= 0"),
])
def test_values_out_of_range_are_refused_by_name(old, new, message):
    assert old in xml()
    with pytest.raises(ValueError, match=message):
        load(xml().replace(old, new, 1))


def test_a_refused_entry_leaves_the_force_field_as_it_was():
    # The good entry before the bad one is not kept, and no generator is left behind empty.
    ff = load(xml())
    with pytest.raises(ValueError, match="needs a >= 0"):
        ff.loadFile(io.StringIO('<ForceField><DPDSoftRepulsionForce><Pair type1="S" type2="A" a="99" cutoff="1"/>'
                                '<Pair type1="A" type2="A" a="-1" cutoff="1"/></DPDSoftRepulsionForce></ForceField>'))
    assert len(forcefield._generator(ff, forcefield.SoftRepulsionGenerator).table.entries) == 6
    empty = app.ForceField()
    empty.loadFile(io.StringIO('<ForceField><AtomTypes><Type name="S" class="S" mass="1"/></AtomTypes></ForceField>'))
    with pytest.raises(ValueError, match="needs friction >= 0"):
        empty.loadFile(io.StringIO('<ForceField><DPDThermostat><Pair type1="S" type2="S" friction="-1" cutoff="1"/>'
                                   '</DPDThermostat></ForceField>'))
    assert empty.getGenerators() == [] and forcefield.match_bead_residue not in empty._templateMatchers


def test_ewald_is_refused():
    topology, _ = trimers_in_solvent()
    with pytest.raises(ValueError, match="nonbondedMethod .* does not apply to DPD forces"):
        load(xml()).createSystem(topology, nonbondedMethod=app.PME)


def test_no_cutoff_with_a_box_is_periodic():
    topology, _ = trimers_in_solvent()
    system = load(xml()).createSystem(topology, nonbondedMethod=app.NoCutoff)
    assert soft_force(system).getNonbondedMethod() == openmmdpd.DPDSoftRepulsionForce.CutoffPeriodic
    assert system.usesPeriodicBoundaryConditions()
    assert all(force.usesPeriodicBoundaryConditions() for force in system.getForces()
               if force.getName() in ("FENE", "WormLikeChain", "CosineAngle"))


def test_non_periodic_on_request_or_without_a_box():
    topology, _ = trimers_in_solvent()
    system = load(xml()).createSystem(topology, nonbondedMethod=app.CutoffNonPeriodic)
    assert soft_force(system).getNonbondedMethod() == openmmdpd.DPDSoftRepulsionForce.CutoffNonPeriodic
    topology.setPeriodicBoxVectors(None)
    assert not load(xml()).createSystem(topology).usesPeriodicBoundaryConditions()


def test_an_empty_topology_gets_no_soft_force_and_no_types():
    topology = app.Topology()
    assert load(xml()).createSystem(topology).getNumForces() == 1  # the CMMotionRemover
    assert thermostat(topology, xml()).getNumTypePairs() == 0


def test_data_path_names_what_is_shipped():
    assert os.path.isfile(forcefield.data_path("groot-warren.xml"))
    with pytest.raises(ValueError, match="no force field 'nothing.xml'.*groot-warren.xml"):
        forcefield.data_path("nothing.xml")


# --- The guide's script ---------------------------------------------------------------------

def guide_scripts():
    """The guide's scripts that swap in Langevin by one line, made small: a 5-edge box or 500
    beads, 100 steps, a log line every 50."""
    page = os.path.join(ROOT, "docs", "guide", "force-fields.md")
    if not os.path.isfile(page):
        pytest.skip("the documentation is not in this copy of the tests")
    with open(page) as f:
        blocks = re.findall(r"^```python\n(.*?)^```", f.read(), re.S | re.M)
    small = [("num_particles=\\d+", "num_particles=500"), ("edge = [\\d.]+", "edge = 5.0"),
             ("\\.step\\(\\d+\\)", ".step(100)"), ('"log.csv", \\d+', '"log.csv", 50')]
    scripts = [code for code in blocks if "# Langevin instead: this line" in code]
    for pattern, replacement in small:
        scripts = [re.sub(pattern, replacement, code) for code in scripts]
    return scripts


def run_script(code, tmp_path):
    path = [os.path.dirname(os.path.dirname(openmmdpd.__file__))] + os.environ.get("PYTHONPATH", "").split(os.pathsep)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p))
    result = subprocess.run([sys.executable, "-c", code], cwd=str(tmp_path), env=env,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return np.loadtxt(tmp_path / "log.csv", delimiter=",", usecols=1)


def test_the_guide_has_the_copolymer_melt_and_the_polymer_in_solvent():
    scripts = guide_scripts()
    assert len(scripts) == 2
    assert "groot-madden-diblock.xml" in scripts[0] and "groot-warren.xml" in scripts[1]


@pytest.mark.parametrize("which", [0, 1], ids=["copolymer-melt", "polymer-in-solvent"])
def test_a_guide_script_runs_with_a_dpd_integrator_and_with_langevin_by_one_line(which, tmp_path):
    code = guide_scripts()[which]
    assert len(code.splitlines()) <= 30
    energies = run_script(code, tmp_path)
    assert len(energies) == 2 and np.all(np.isfinite(energies))
    lines = code.splitlines()
    dpd = [k for k, line in enumerate(lines) if line.startswith("integrator = ")]
    langevin = [line[2:] for line in lines if line.startswith("# integrator = openmm.LangevinMiddleIntegrator")]
    assert len(dpd) == 1 and len(langevin) == 1
    lines[dpd[0]] = langevin[0]
    energies = run_script("\n".join(lines), tmp_path)
    assert len(energies) == 2 and np.all(np.isfinite(energies))
