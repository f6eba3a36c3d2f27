"""openmmdpd.packer: molecules placed in a periodic box, deterministic by seed, refused when
the density, box, bonds or counts are impossible, 10^5 beads, and a relaxed start stable at dt 0.04."""
import io

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


def test_each_axis_spans_its_own_edge_of_the_box():
    lengths = np.array([3.0, 4.0, 5.0])
    topology, positions = packer.pack([(WATER, 500)], box=tuple(lengths), seed=4)
    box = topology.getPeriodicBoxVectors().value_in_unit(unit.nanometer)
    assert [box[k][k] for k in range(3)] == list(lengths)
    x = as_array(positions)
    assert np.all(x >= 0) and np.all(x < lengths)
    assert np.all(x.max(axis=0) > 0.9 * lengths)  # not all in the narrowest edge's cube


@pytest.mark.parametrize("density", [0.0, -1.0, 11.0, float("nan")])
def test_an_impossible_density_is_refused_by_name(density):
    with pytest.raises(ValueError, match=f"density {density} beads/nm\\^3 is not possible.*max_density = 10.0"):
        packer.pack([(WATER, 1000)], density=density)


def test_a_box_narrower_than_two_cutoffs_is_refused():
    with pytest.raises(ValueError, match="narrower than twice the cutoff 1.0 nm; use more beads or a lower density"):
        packer.pack([(WATER, 20)], density=3.0)
    with pytest.raises(ValueError, match=r"box \(1.5, 10.0, 10.0\) nm is narrower than twice the cutoff 1.0 nm: "
                                         r"each box edge must be >= 2 \* cutoff = 2 nm"):
        packer.pack([(WATER, 20)], box=(1.5, 10.0, 10.0))
    packer.pack([(WATER, 20)], box=(1.5, 10.0, 10.0), cutoff=0.75)


def test_a_box_denser_than_max_density_is_refused():
    with pytest.raises(ValueError, match=r"density 250 beads/nm\^3\) is not possible: at most max_density = 10.0"):
        packer.pack([(WATER, 2000)], box=(2.0, 2.0, 2.0))
    with pytest.raises(ValueError, match="box .* must be three finite edges > 0"):
        packer.pack([(WATER, 20)], box=(3.0, float("nan"), 3.0))


def test_a_linear_molecule_bonds_its_beads_in_order():
    diblock = packer.Molecule.linear(["A"] * 2 + ["B"] * 3)
    assert diblock.residues == [("A", ("A",))] * 2 + [("B", ("B",))] * 3
    assert diblock.bonds == [(0, 1), (1, 2), (2, 3), (3, 4)]
    named = packer.Molecule.linear(["A", "B"], residues=["AE", "BE"])
    assert named.residues == [("AE", ("A",)), ("BE", ("B",))]
    with pytest.raises(ValueError, match="Molecule.linear: 1 residue names for 2 beads"):
        packer.Molecule.linear(["A", "B"], residues=["AE"])


def test_a_bond_outside_the_molecule_is_refused():
    with pytest.raises(ValueError, match=r"molecule X: bond \(0, 2\) does not join two of its 2 beads "
                                         r"\(indices 0 to 1\)"):
        packer.Molecule.single("X", ["A", "B"], [(0, 2)])
    with pytest.raises(ValueError, match=r"molecule X: bond \(1, 1\) does not join two of its 2 beads"):
        packer.Molecule.single("X", ["A", "B"], [(1, 1)])
    with pytest.raises(ValueError, match=r"molecule X: bond \(0, 1.5\) needs two whole bead indices"):
        packer.Molecule.single("X", ["A", "B"], [(0, 1.5)])


def test_a_bond_given_twice_is_refused():
    # Twice would be two topology bonds, and a force field would put two springs on them.
    with pytest.raises(ValueError, match=r"molecule X: bond \(1, 0\) is given twice"):
        packer.Molecule.single("X", ["A", "B"], [(0, 1), (1, 0)])
    with pytest.raises(ValueError, match=r"molecule X: bond \(0, 1\) is given twice"):
        packer.Molecule.single("X", ["A", "B", "C"], [(0, 1), (1, 2), (0, 1)])


def test_a_ring_is_refused_naming_the_bond_that_closes_it():
    # Growing along a tree of bonds leaves a ring-closing bond at any length (6 nm in a
    # 20-bead ring), where a FENE spring is NaN.
    with pytest.raises(ValueError, match=r"molecule RING: bond \(19, 0\) closes a ring"):
        packer.Molecule.single("RING", ["R"] * 20, [(i, (i + 1) % 20) for i in range(20)])
    ring = app.Topology()
    residue = ring.addResidue("TRI", ring.addChain())
    atoms = [ring.addAtom(name, None, residue) for name in "ABC"]
    for a, b in [(0, 1), (1, 2), (2, 0)]:
        ring.addBond(atoms[a], atoms[b])
    with pytest.raises(ValueError, match=r"molecule TRI: bond \(2, 0\) closes a ring"):
        packer.pack([(ring, 3)], density=3.0)
    branched = packer.Molecule.single("Y", ["A", "B", "C", "D"], [(0, 1), (0, 2), (0, 3)])  # a tree: no ring
    assert branched.bonds == [(0, 1), (0, 2), (0, 3)]


@pytest.mark.parametrize("arguments, error, message", [
    (dict(bond_length=0.0), ValueError, "pack: bond_length must be finite and > 0 \\(nm\\), got 0.0"),
    (dict(bond_length=-0.8), ValueError, "pack: bond_length must be finite and > 0"),
    (dict(bond_length=float("nan")), ValueError, "pack: bond_length must be finite and > 0"),
    (dict(cutoff=0.0), ValueError, "pack: cutoff must be finite and > 0 \\(nm\\), got 0.0"),
    (dict(cutoff=float("nan")), ValueError, "pack: cutoff must be finite and > 0"),
    (dict(bond_length=0.8 * unit.picosecond), TypeError, "pack: bond_length must be a length"),
    (dict(cutoff=1.0 * unit.kelvin), TypeError, "pack: cutoff must be a length"),
])
def test_bond_length_and_cutoff_are_checked(arguments, error, message):
    with pytest.raises(error, match=message):
        packer.pack([(CHAIN, 30)], density=3.0, **arguments)


def test_quantities_are_taken_in_their_units():
    topology, positions = packer.pack([(CHAIN, 30)], density=3.0 / unit.nanometer**3, bond_length=7.0 * unit.angstrom,
                                      cutoff=10.0 * unit.angstrom, seed=3)
    x = as_array(positions)
    lengths = [np.linalg.norm(x[a.index] - x[b.index]) for a, b in topology.bonds()]
    assert lengths == pytest.approx([0.7] * len(lengths))
    assert topology.getPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer) == pytest.approx(100 ** (1 / 3))
    with pytest.raises(TypeError, match="pack: density must be .*, got 3.0 nm"):
        packer.pack([(CHAIN, 30)], density=3.0 * unit.nanometer)
    with pytest.raises(TypeError, match="pack: box must be three lengths"):
        packer.pack([(CHAIN, 30)], box=(3.0, 4.0, 5.0) * unit.picosecond)


@pytest.mark.parametrize("count", [2.5, -1, "3", True])
def test_a_count_that_is_not_a_whole_number_is_refused(count):
    with pytest.raises(ValueError, match=f"molecule W: needs beads and a count that is a whole number >= 0, "
                                         f"got {count!r}"):
        packer.pack([(WATER, count), (CHAIN, 30)], density=3.0)


def test_a_hundred_thousand_beads_and_pdb_writes_them():
    # How fast this is, is measured by the benchmarks, not asserted here.
    topology, positions = packer.pack([(WATER, 90000), (CHAIN, 1000)], density=3.0, seed=1)
    assert topology.getNumAtoms() == 100000 and as_array(positions).shape == (100000, 3)
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
