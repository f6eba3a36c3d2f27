"""A nonionic surfactant H3T3 above its CMC aggregating into micelles from a random start: the
package's surfactant.xml (a_TW = a_HT = 50, the other pairs 25, springs C = 4), run with
DPDVVIntegrator at dt 0.04.

Surfactants make up --fraction of the beads; water fills the rest at rho = 3.  Two surfactants
are in the same aggregate when tail beads of theirs come within --link (0.8 rc: closer than
tails meet by chance in the mixed start, as close as they touch in a micelle's core), and an
aggregate is the connected component of that pair list.  Every --report steps it prints kT,
the fraction of free surfactant (aggregates of one) and the micelles (aggregates of at least
--micelle surfactants): their number and mean aggregation number; at the start and the end
also the aggregation-number distribution.  Writes the OpenMM log (log.csv) and the last frame
(end.pdb) into --out.

    PYTHONPATH=build/python /usr/bin/python3 examples/micelles.py [--quick]
"""
import argparse
import collections
import os

import numpy as np
import openmm
from openmm import app, unit
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

import openmmdpd
from openmmdpd import forcefield, packer


def surfactant(heads, tails):
    """H_mT_n as one residue per bead."""
    return packer.Molecule.linear(["H"] * heads + ["T"] * tails)


def aggregation_numbers(x, tail_owner, count, edge, link):
    """The number of surfactants in each aggregate: tail_owner[k] is the surfactant of tail bead k."""
    pairs = cKDTree(x % edge, boxsize=edge).query_pairs(link, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (tail_owner[pairs[:, 0]], tail_owner[pairs[:, 1]])), shape=(count, count))
    return np.bincount(connected_components(graph, directed=False)[1])


def summary(sizes, smallest):
    """(free fraction, micelles, mean aggregation number of the micelles)."""
    micelles = sizes[sizes >= smallest]
    return np.sum(sizes == 1) / sizes.sum(), len(micelles), micelles.mean() if len(micelles) else 0.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--edge", type=float, default=16.0, help="box edge L (rc)")
    parser.add_argument("--blocks", type=int, nargs=2, default=[3, 3], metavar=("HEADS", "TAILS"))
    parser.add_argument("--fraction", type=float, default=0.08, help="surfactant beads over all beads")
    parser.add_argument("--link", type=float, default=0.8, help="tail-tail distance joining two surfactants (rc)")
    parser.add_argument("--micelle", type=int, default=5, help="the smallest aggregate counted as a micelle")
    parser.add_argument("--steps", type=int, default=40000)
    parser.add_argument("--report", type=int, default=5000, help="steps between printed lines")
    parser.add_argument("--quick", action="store_true", help="a smoke run: L = 10, 3000 steps (seconds)")
    parser.add_argument("--out", default="micelles")
    parser.add_argument("--platform", default="CPU")
    args = parser.parse_args(argv)
    if args.quick:
        args.edge, args.steps, args.report = 10.0, 3000, 1000
    os.makedirs(args.out, exist_ok=True)

    ff = app.ForceField(forcefield.data_path("surfactant.xml"))
    molecule = surfactant(*args.blocks)
    beads = round(3 * args.edge ** 3)
    count = round(args.fraction * beads / molecule.num_beads)
    water = packer.Molecule.single("W", ["W"])
    topology, positions = packer.pack([(molecule, count), (water, beads - count * molecule.num_beads)],
                                      box=[args.edge] * 3, seed=6)
    system = ff.createSystem(topology, nonbondedMethod=app.CutoffPeriodic, removeCMMotion=False)
    kT, dt = openmmdpd.KT_TEMPERATURE, 0.04 * unit.picosecond
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(kT, 4.5, 1.0, dt), ff, topology,
                                                        system=system)
    integrator.setRandomNumberSeed(17)
    simulation = app.Simulation(topology, system, integrator, openmm.Platform.getPlatformByName(args.platform))
    simulation.context.setPositions(positions)
    packer.relax(simulation)
    simulation.context.setVelocitiesToTemperature(kT, 7)
    simulation.reporters.append(app.StateDataReporter(os.path.join(args.out, "log.csv"), args.report, step=True,
                                                      potentialEnergy=True, temperature=True, speed=True))

    is_tail = np.array([atom.name == "T" for atom in topology.atoms()])
    tail_owner = np.repeat(np.arange(count), args.blocks[1])  # the packer places each surfactant's beads in a row
    dof = 3 * system.getNumParticles() - 3  # momentum is conserved

    def aggregates(x):
        return aggregation_numbers(x[is_tail], tail_owner, count, args.edge, args.link)

    def distribution(sizes):
        return ", ".join(f"{n}: {k}" for n, k in sorted(collections.Counter(sizes.tolist()).items()))

    start = aggregates(positions.value_in_unit(unit.nanometer))
    print(f"{count} surfactants H{args.blocks[0]}T{args.blocks[1]} in {beads} beads, a box of {args.edge:g}^3")
    print(f"start: free {summary(start, args.micelle)[0]:.3f}; aggregation numbers (size: count) {distribution(start)}")
    print(f"{'step':>7} {'kT':>6} {'free':>6} {'micelles':>8} {'<N>':>6}")
    for step in range(args.report, args.steps + 1, args.report):
        simulation.step(args.report)
        state = simulation.context.getState(getPositions=True, getEnergy=True)
        x = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
        kt = 2 * state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole) / dof
        sizes = aggregates(x)
        free, micelles, mean = summary(sizes, args.micelle)
        print(f"{step:7d} {kt:6.3f} {free:6.3f} {micelles:8d} {mean:6.1f}", flush=True)
    print(f"end: free {free:.3f}; aggregation numbers (size: count) {distribution(sizes)}")
    print(f"micelles: {micelles} of mean aggregation number {mean:.1f}, free surfactant {free:.3f} "
          f"(start {summary(start, args.micelle)[0]:.3f}), kT = {kt:.3f}")
    with open(os.path.join(args.out, "end.pdb"), "w") as pdb:
        app.PDBFile.writeFile(topology, x * unit.nanometer, pdb)
    return summary(start, args.micelle), (free, micelles, mean), kt


if __name__ == "__main__":
    main()
