"""The nonionic surfactant force field surfactant.xml: it loads with app.ForceField, builds on a
small packed system of H3T3 surfactants in water the a_ij, friction and spring tables its XML
states, equals a System built by hand, gives an integrator its thermostat, and runs stable at
dt 0.04 after packer.relax."""
import math
import xml.etree.ElementTree as ElementTree

import numpy as np
import openmm
import pytest
from openmm import app, unit

import openmmdpd
from openmmdpd import forcefield, packer, scenes

from dpdtest import energy_and_forces, named_pair_table as pair_table, number, soft_force

KT = openmmdpd.KT_TEMPERATURE
NAME = "surfactant.xml"
# H3T3 as one residue per bead: every bead template but the lone ones (added below).
SURFACTANT = packer.Molecule.linear(["H"] * 3 + ["T"] * 3)
COUNT = 20


def packed(seed=1):
    """20 H3T3, a lone H and a lone T in water: about 600 beads at rho = 3."""
    lone = [(packer.Molecule.single(name, [name]), 1) for name in ("H", "T")]
    return packer.pack([(SURFACTANT, COUNT)] + lone + [(packer.Molecule.single("W", ["W"]), 478)],
                       density=3.0, seed=seed)


def created(seed=1):
    ff = app.ForceField(forcefield.data_path(NAME))
    topology, positions = packed(seed)
    return ff, topology, positions, ff.createSystem(topology, nonbondedMethod=app.CutoffPeriodic, removeCMMotion=False)


def test_the_file_is_shipped_and_loads():
    assert app.ForceField(forcefield.data_path(NAME)) is not None


def test_the_force_the_thermostat_and_the_springs_have_the_files_tables():
    ff, topology, _, system = created()
    types = forcefield.bead_types(ff, [atom.name for atom in topology.atoms()])
    assert types == ["W", "H", "T"]
    root = ElementTree.parse(forcefield.data_path(NAME)).getroot()
    written = {(p.get("type1"), p.get("type2")): (float(p.get("a")), float(p.get("cutoff")))
               for p in root.find("DPDSoftRepulsionForce").findall("Pair")}
    force_table = pair_table(soft_force(system), types)
    assert len(force_table) == len(written) == 6
    for (t1, t2), values in force_table.items():
        assert values == written.get((t1, t2), written.get((t2, t1)))
    # The values the header states: like pairs and head-water 25, tail-water and head-tail 50
    # (chi = 7.65 by Groot and Madden's a = 25 + 3.27 chi).
    assert {pair: a for pair, (a, _) in force_table.items()} == {
        ("W", "W"): 25.0, ("W", "H"): 25.0, ("W", "T"): 50.0, ("H", "H"): 25.0, ("H", "T"): 50.0, ("T", "T"): 25.0}
    assert (force_table[("W", "T")][0] - 25.0) / 3.27 == pytest.approx(7.65, abs=0.005)
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 2.0, 0.04), ff, topology,
                                                        system=system)
    assert set(pair_table(integrator, types).values()) == {(4.5, 1.0)}
    particle_types = [soft_force(system).getParticleType(i) for i in range(system.getNumParticles())]
    assert [integrator.getParticleType(i) for i in range(system.getNumParticles())] == particle_types
    assert particle_types[:6] == [1, 1, 1, 2, 2, 2]  # H3T3: heads H = 1, tails T = 2
    assert {system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())} == {1.0}
    bonds = next(f for f in system.getForces() if isinstance(f, openmm.HarmonicBondForce))
    assert bonds.getNumBonds() == COUNT * 5  # no bond to the lone beads or the water
    parameters = {tuple(number(v) for v in bonds.getBondParameters(i)[2:]) for i in range(bonds.getNumBonds())}
    assert parameters == {(0.0, 4.0)}


def test_other_head_and_tail_lengths_match_the_same_templates():
    ff = app.ForceField(forcefield.data_path(NAME))
    for heads, tails in ((1, 1), (1, 4), (2, 5)):
        molecule = packer.Molecule.linear(["H"] * heads + ["T"] * tails)
        topology, _ = packer.pack([(molecule, 2), (packer.Molecule.single("W", ["W"]), 100)], box=[4.0] * 3)
        system = ff.createSystem(topology)
        assert [soft_force(system).getParticleType(i) for i in range(heads + tails)] == [1] * heads + [2] * tails


def test_the_system_equals_a_hand_built_one():
    _, topology, positions, system = created()
    types = ["WHT".index(atom.name) for atom in topology.atoms()]
    repulsion = [[25.0, 25.0, 50.0], [25.0, 25.0, 50.0], [50.0, 50.0, 25.0]]  # W, H, T
    expected = openmm.System()
    for _ in types:
        expected.addParticle(1.0)
    expected.setDefaultPeriodicBoxVectors(*topology.getPeriodicBoxVectors())
    expected.addForce(scenes.soft_repulsion_force(len(types), repulsion, types))
    expected.addForce(scenes.harmonic_bond_force([(a.index, b.index) for a, b in topology.bonds()], k=4.0))
    (e1, f1), (e2, f2) = energy_and_forces(system, positions), energy_and_forces(expected, positions)
    assert e1 == pytest.approx(e2, rel=1e-12) and np.max(np.abs(f1 - f2)) < 1e-12 * np.max(np.abs(f2))


def test_a_relaxed_start_runs_stable_at_dt_004():
    ff, topology, positions, system = created(seed=2)
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.04), ff, topology)
    integrator.setRandomNumberSeed(5)
    simulation = app.Simulation(topology, system, integrator, openmm.Platform.getPlatformByName("CPU"))
    simulation.context.setPositions(positions)
    packer.relax(simulation)
    simulation.context.setVelocitiesToTemperature(KT, 3)
    simulation.step(200)
    dof = 3 * system.getNumParticles() - 3
    samples = []
    for _ in range(20):
        simulation.step(10)
        state = simulation.context.getState(getEnergy=True)
        samples.append(2 * state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole) / dof)
        assert math.isfinite(state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
    # GW-type velocity Verlet at dt 0.04 runs ~2-5 % hot; ~600 beads give kT to ~1 %.
    assert 0.95 < np.mean(samples) < 1.12
