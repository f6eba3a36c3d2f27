"""openmmdpd.packer: molecules placed in a periodic box, deterministic by seed, refused when
the density is impossible, fast at 10^5 beads, and a relaxed start stable at dt 0.04."""
import io
import time

import numpy as np
import openmm
import pytest
from openmm import app, unit

import openmmdpd
from openmmdpd import forcefield, packer

WATER = packer.Molecule.single("W", ["W"])
CHAIN = packer.Molecule.chain(10)


def as_array(positions):
    return np.asarray(positions.value_in_unit(unit.nanometer))


def test_the_box_holds_the_beads_at_the_density():
    topology, positions = packer.pack([(WATER, 270), (CHAIN, 3)], density=3.0, seed=1)
    assert topology.getNumAtoms() == 300 and topology.getNumBonds() == 27
    box = topology.getPeriodicBoxVectors().value_in_unit(unit.nanometer)
    assert box[0][0] == pytest.approx(100.0 ** (1 / 3)) and box[0][1] == 0.0 and box[2][2] == box[0][0]
    assert as_array(positions).shape == (300, 3)
    # one chain for the water, one per polymer; one residue per water and per chain bead
    assert topology.getNumChains() == 4 and topology.getNumResidues() == 300


def test_bonded_beads_are_one_bond_length_apart_and_molecules_whole():
    topology, positions = packer.pack([(CHAIN, 20)], density=3.0, bond_length=0.7, seed=3)
    x = as_array(positions)
    lengths = [np.linalg.norm(x[a.index] - x[b.index]) for a, b in topology.bonds()]
    assert lengths == pytest.approx([0.7] * len(lengths))


def test_the_same_seed_gives_the_same_start():
    first = as_array(packer.pack([(WATER, 50), (CHAIN, 2)], density=3.0, seed=7)[1])
    again = as_array(packer.pack([(WATER, 50), (CHAIN, 2)], density=3.0, seed=7)[1])
    other = as_array(packer.pack([(WATER, 50), (CHAIN, 2)], density=3.0, seed=8)[1])
    assert np.array_equal(first, again) and not np.array_equal(first, other)


def test_a_box_may_be_given_and_a_topology_is_a_molecule():
    dimer = app.Topology()
    residue = dimer.addResidue("D", dimer.addChain())
    a, b = dimer.addAtom("A", None, residue), dimer.addAtom("B", None, residue)
    dimer.addBond(a, b)
    topology, _ = packer.pack([(dimer, 30)], box=(3.0, 4.0, 5.0) * unit.nanometer)
    assert topology.getPeriodicBoxVectors()[1][1] == 4.0 * unit.nanometer
    assert [atom.name for atom in topology.atoms()][:2] == ["A", "B"] and topology.getNumBonds() == 30


@pytest.mark.parametrize("density", [0.0, -1.0, 11.0, float("nan")])
def test_an_impossible_density_is_refused_by_name(density):
    with pytest.raises(ValueError, match=f"density {density} beads/nm\\^3 is not possible.*max_density = 10.0"):
        packer.pack([(WATER, 1000)], density=density)


def test_a_box_narrower_than_two_cutoffs_is_refused():
    with pytest.raises(ValueError, match="narrower than twice the cutoff"):
        packer.pack([(WATER, 20)], density=3.0)
    with pytest.raises(ValueError, match="max_density = 10.0"):
        packer.pack([(WATER, 2000)], box=(2.0, 2.0, 2.0))


def test_a_bond_outside_the_molecule_is_refused():
    with pytest.raises(ValueError, match=r"molecule X: bond \(0, 2\) does not join two of its 2 beads"):
        packer.Molecule.single("X", ["A", "B"], [(0, 2)])


def test_a_hundred_thousand_beads_in_seconds_and_pdb_writes_them():
    start = time.perf_counter()
    topology, positions = packer.pack([(WATER, 90000), (CHAIN, 1000)], density=3.0, seed=1)
    assert time.perf_counter() - start < 5.0
    assert topology.getNumAtoms() == 100000
    small_topology, small_positions = packer.pack([(WATER, 90), (CHAIN, 1)], density=3.0)
    pdb = io.StringIO()
    app.PDBFile.writeFile(small_topology, small_positions, pdb)
    assert pdb.getvalue().count("HETATM") == 100 and "CRYST1" in pdb.getvalue()


def test_a_relaxed_start_runs_stable_at_dt_0_04():
    ff = app.ForceField(forcefield.data_path("groot-warren.xml"))
    topology, positions = packer.pack([(WATER, 900), (CHAIN, 30)], density=3.0, seed=2)
    system = ff.createSystem(topology, removeCMMotion=False)
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, 0.04)
    forcefield.apply_thermostat_parameters(integrator, ff, topology)
    integrator.setInstabilityThreshold(40)
    integrator.setRandomNumberSeed(5)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("CPU"))
    context.setPositions(positions)
    before = context.getState(getEnergy=True).getPotentialEnergy()
    assert packer.relax(context) < before
    context.setVelocitiesToTemperature(openmmdpd.KT_TEMPERATURE, 3)
    integrator.step(300)
    kinetic = context.getState(getEnergy=True).getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
    assert 2 * kinetic / (3 * system.getNumParticles() - 3) == pytest.approx(1.0, abs=0.15)
