"""Packing bead molecules into a periodic box, in the spirit of OpenMM's Modeller.

`pack` places copies of each `Molecule` at random (seeded): a molecule's first bead uniformly
in the box, every other bead one bond length from the bead it is bonded to, in a random
direction (chains as random walks, nothing avoided; a molecule with a ring is refused,
since its ring-closing bond would be left at any length). It returns an `app.Topology` with the
box set and the positions, which `app.PDBFile.writeFile`, `ForceField.createSystem` and
`Context.setPositions` take. Soft beads may overlap; `relax` minimises the energy before a run.
"""
import math
import numbers
from collections import deque

import numpy as np
import openmm
from openmm import app, unit

from .units import strip_units

__all__ = ["Molecule", "pack", "relax", "MAX_DENSITY"]

#: The densest packing pack() makes, in beads per nm^3 (per rc^3 in reduced units): twice the
#: densest DPD fluids in common use (rho = 3 to 5, where a = 75 kT/rho is fitted).
MAX_DENSITY = 10.0


class Molecule:
    """A molecule of beads: residues, each a name and its bead (atom) names, and bonds.

    bonds: pairs of bead indices counted over the whole molecule, in residue order; each pair
    of beads at most once, in either order. Bead names are what force-field templates match,
    so they must be the templates' names. A bond that closes a ring is refused: pack grows
    each molecule bead by bead along a tree of its bonds, and could not give a bond closing
    a ring its length (it would be any length, and a FENE spring past rmax is NaN).
    """

    def __init__(self, residues, bonds=()):
        self.residues = [(str(name), tuple(str(bead) for bead in beads)) for name, beads in residues]
        self.num_beads = sum(len(beads) for _, beads in self.residues)
        self.bonds = [_bead_pair(bond, self.name) for bond in bonds]
        joined = set()
        group = list(range(self.num_beads))  # union-find of the beads the bonds so far join

        def root(bead):
            while group[bead] != bead:
                group[bead] = group[group[bead]]
                bead = group[bead]
            return bead

        for i, j in self.bonds:
            if not (0 <= i < self.num_beads and 0 <= j < self.num_beads) or i == j:
                raise ValueError(f"molecule {self.name}: bond ({i}, {j}) does not join two of its "
                                 f"{self.num_beads} beads (indices 0 to {self.num_beads - 1})")
            if (min(i, j), max(i, j)) in joined:
                raise ValueError(f"molecule {self.name}: bond ({i}, {j}) is given twice (each pair of beads "
                                 f"once, in either order); twice would make two springs")
            joined.add((min(i, j), max(i, j)))
            if root(i) == root(j):
                raise ValueError(f"molecule {self.name}: bond ({i}, {j}) closes a ring; pack places beads along "
                                 f"a tree of bonds and cannot give a ring-closing bond its length")
            group[root(i)] = root(j)

    @property
    def name(self):
        return self.residues[0][0] if self.residues else "(empty)"

    @classmethod
    def single(cls, name, beads, bonds=()):
        """One residue: Molecule.single("W", ["W"]), Molecule.single("DMPC", ["H1", "T1", ...], bonds)."""
        return cls([(name, beads)], bonds)

    @classmethod
    def chain(cls, length, bead="P", residue="P"):
        """A linear chain of `length` one-bead residues, as the per-bead templates of a force
        field (e.g. groot-warren.xml's P, PE, PM) match them."""
        return cls.linear([bead] * length, [residue] * length)

    @classmethod
    def linear(cls, beads, residues=None):
        """A linear chain of one-bead residues, bead k named beads[k] and its residue
        residues[k] (by default the bead's name): Molecule.linear(["A"] * 5 + ["B"] * 5) is the
        diblock A5B5. Templates match bead names and bonds, so ends need no names of their own."""
        residues = beads if residues is None else residues
        if len(residues) != len(beads):
            raise ValueError(f"Molecule.linear: {len(residues)} residue names for {len(beads)} beads")
        return cls([(residue, [bead]) for residue, bead in zip(residues, beads)],
                   [(i, i + 1) for i in range(len(beads) - 1)])

    @classmethod
    def from_topology(cls, topology):
        """The residues and bonds of a Topology holding one molecule (e.g. read from a PDB file)."""
        index = {atom: k for k, atom in enumerate(topology.atoms())}
        return cls([(res.name, [atom.name for atom in res.atoms()]) for res in topology.residues()],
                   [(index[a], index[b]) for a, b in topology.bonds()])

    def growth_order(self):
        """(bead, bead it grows from or -1) in breadth-first order over the bonds, each
        unbonded part starting anew."""
        neighbours = [[] for _ in range(self.num_beads)]
        for i, j in self.bonds:
            neighbours[i].append(j)
            neighbours[j].append(i)
        parent = [None] * self.num_beads
        order = []
        for root in range(self.num_beads):
            if parent[root] is not None:
                continue
            parent[root] = -1
            queue = deque([root])
            while queue:
                bead = queue.popleft()
                order.append((bead, parent[bead]))
                for other in neighbours[bead]:
                    if parent[other] is None:
                        parent[other] = bead
                        queue.append(other)
        return order


def _bead_pair(bond, name):
    """A bond as two whole bead indices (ints, or floats such as 2.0)."""
    bond = tuple(bond)
    if len(bond) != 2 or not all(isinstance(k, numbers.Real) and not isinstance(k, bool) and float(k).is_integer()
                                 for k in bond):
        raise ValueError(f"molecule {name}: bond {bond} needs two whole bead indices")
    return int(bond[0]), int(bond[1])


def _as_molecule(molecule):
    return Molecule.from_topology(molecule) if isinstance(molecule, app.Topology) else molecule


def _box_lengths(num_beads, density, box, max_density, cutoff):
    """The box edges (nm), from a bead density or given; refuses a density outside (0, max_density]
    and a box narrower than two cutoffs (the force and the integrators need rc <= half the box)."""
    if (density is None) == (box is None):
        raise ValueError("pack: give either density or box")
    if box is None:
        density = strip_units(density, unit.nanometer**-3, "density", "pack")
        if not (np.isfinite(density) and 0 < density <= max_density):
            raise ValueError(f"pack: density {density} beads/nm^3 is not possible: it must be > 0 and at most "
                             f"max_density = {max_density} beads/nm^3")
        lengths = np.full(3, (num_beads / density) ** (1 / 3))
        if lengths.min() < 2 * cutoff:
            raise ValueError(f"pack: density {density:.3g} beads/nm^3 gives {num_beads} beads a box of "
                             f"{lengths.min():.3g} nm, narrower than twice the cutoff {cutoff} nm; "
                             f"use more beads or a lower density")
        return lengths
    if unit.is_quantity(box) and not box.unit.is_compatible(unit.nanometer):
        raise TypeError(f"pack: box must be three lengths (a Quantity in nanometer or numbers), got {box}")
    lengths = np.array(box.value_in_unit(unit.nanometer) if unit.is_quantity(box) else box, dtype=float)
    if not (lengths.shape == (3,) and np.all(np.isfinite(lengths)) and np.all(lengths > 0)):
        raise ValueError(f"pack: box {box} is not possible: it must be three finite edges > 0 (nm)")
    density = num_beads / np.prod(lengths)
    if density > max_density:
        raise ValueError(f"pack: box {tuple(lengths)} nm (density {density:.3g} beads/nm^3) is not possible: "
                         f"at most max_density = {max_density} beads/nm^3")
    if lengths.min() < 2 * cutoff:
        raise ValueError(f"pack: box {tuple(lengths)} nm is narrower than twice the cutoff {cutoff} nm: each "
                         f"box edge must be >= 2 * cutoff = {2 * cutoff:g} nm")
    return lengths


def _grow(molecule, count, lengths, bond_length, rng):
    """(count, beads, 3) positions: each copy grown bond by bond, all copies at once."""
    positions = np.empty((count, molecule.num_beads, 3))
    for bead, parent in molecule.growth_order():
        if parent < 0:
            positions[:, bead] = rng.uniform(0.0, 1.0, (count, 3)) * lengths
        else:
            steps = rng.normal(size=(count, 3))
            steps *= bond_length / np.linalg.norm(steps, axis=1, keepdims=True)
            positions[:, bead] = positions[:, parent] + steps
    return positions


def _add_copies(topology, molecule, count):
    """Copies of the molecule: one chain per copy, or one chain for all copies of a one-residue molecule."""
    one_residue = len(molecule.residues) == 1
    chain = topology.addChain() if one_residue else None
    for _ in range(count):
        if not one_residue:
            chain = topology.addChain()
        atoms = []
        for name, beads in molecule.residues:
            residue = topology.addResidue(name, chain)
            atoms += [topology.addAtom(bead, None, residue) for bead in beads]
        for i, j in molecule.bonds:
            topology.addBond(atoms[i], atoms[j])


def pack(molecules, density=None, box=None, bond_length=0.8, seed=0, max_density=MAX_DENSITY, cutoff=1.0):
    """Place molecules in a periodic box: returns (topology, positions), positions in nm.

    molecules: (molecule, count) pairs, a molecule being a `Molecule` or an `app.Topology`
    of one molecule, and count a whole number >= 0. Give either density (beads/nm^3, or a
    Quantity in 1/nm^3; a cubic box) or box (three edge lengths, nm or a Quantity). bond_length
    (nm or a Quantity, > 0): the distance between bonded beads as placed. The same seed gives
    the same positions. A density <= 0 or above max_density, or a box whose narrowest edge is
    under two cutoffs (cutoff: nm or a Quantity, > 0), is refused, before anything is built.
    """
    molecules = [(_as_molecule(molecule), count) for molecule, count in molecules]
    for molecule, count in molecules:
        if not (isinstance(count, numbers.Real) and not isinstance(count, bool) and float(count).is_integer()
                and count >= 0) or molecule.num_beads == 0:
            raise ValueError(f"pack: molecule {molecule.name}: needs beads and a count that is a whole number "
                             f">= 0, got {count!r}")
    molecules = [(molecule, int(count)) for molecule, count in molecules]
    bond_length = strip_units(bond_length, unit.nanometer, "bond_length", "pack")
    cutoff = strip_units(cutoff, unit.nanometer, "cutoff", "pack")
    for name, value in (("bond_length", bond_length), ("cutoff", cutoff)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"pack: {name} must be finite and > 0 (nm), got {value!r}")
    num_beads = sum(molecule.num_beads * count for molecule, count in molecules)
    if num_beads == 0:
        raise ValueError("pack: no beads to place")
    lengths = _box_lengths(num_beads, density, box, max_density, cutoff)
    rng = np.random.default_rng(seed)
    topology = app.Topology()
    topology.setPeriodicBoxVectors([openmm.Vec3(*row) for row in np.diag(lengths)] * unit.nanometer)
    parts = []
    for molecule, count in molecules:
        _add_copies(topology, molecule, count)
        parts.append(_grow(molecule, count, lengths, bond_length, rng).reshape(-1, 3))
    return topology, np.vstack(parts) * unit.nanometer


def relax(target, max_iterations=500, tolerance=10.0):
    """Minimise the energy of a packed start (a Context or an app.Simulation) so that its
    overlapping beads do not blow up the first steps; velocities are left to the caller.

    tolerance: kJ/mol/nm, as LocalEnergyMinimizer takes it. Returns the potential energy after.
    """
    context = getattr(target, "context", target)
    openmm.LocalEnergyMinimizer.minimize(context, tolerance, max_iterations)
    return context.getState(getEnergy=True).getPotentialEnergy()
