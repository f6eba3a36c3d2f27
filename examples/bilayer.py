"""A lipid bilayer self-assembling from a random start: lipids h3(t4)2 (the shape of Groot and
Rabone's (2001) lipid) in water, the package's lipid-h3t4.xml, run with DPDVVIntegrator at dt 0.04.

The box edge L sets the lipids, 2 L^2 / (area per lipid): enough for one flat bilayer across
the box; water fills the rest at rho = 3.  Every --report steps it prints kT, the water around
the tail beads as a share of what a uniform mix would put there (1 at the random start, a few
per cent once the tails hide inside a bilayer) and the order S of the lipids' head-to-tail
vectors (0 when they point anywhere; a flat bilayer aligns them along its normal).  Writes the
OpenMM log (log.csv), the last frame (end.pdb) and, with --figure, the bead densities across
the bilayer (density.png) into --out.

    PYTHONPATH=build/python /usr/bin/python3 examples/bilayer.py [--quick]
"""
import argparse
import os

import numpy as np
import openmm
from openmm import app, unit
from scipy.spatial import cKDTree

import openmmdpd
from openmmdpd import forcefield, packer

LIPID = forcefield.LIPID_H3T4
WATER = packer.Molecule.single("w", ["w"])


def tail_water_contacts(x, kinds, box):
    """Water beads within rc = 1 of a tail bead, per tail bead, over what a uniform mix would give."""
    water = kinds == "w"
    tree = cKDTree(x[water] % box, boxsize=box)
    counts = tree.query_ball_point(x[kinds == "t"] % box, 1.0, return_length=True)
    return counts.mean() / (water.sum() / np.prod(box) * 4 * np.pi / 3)


def lipid_order(x, kinds, box):
    """S, the largest eigenvalue of <(3 u u - 1)/2> over the unit vectors u from h1 to each tail's
    end, and its axis (the bilayer normal once S is large)."""
    h1 = np.flatnonzero(kinds == "h")[::3]
    u = np.concatenate([x[h1 + 6] - x[h1], x[h1 + 10] - x[h1]])
    u -= box * np.round(u / box)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    values, vectors = np.linalg.eigh(1.5 * np.einsum("ni,nj->ij", u, u) / len(u) - 0.5 * np.eye(3))
    return values[-1], vectors[:, -1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--edge", type=float, default=14.0, help="box edge L (rc)")
    parser.add_argument("--area", type=float, default=1.6, help="area per lipid (rc^2) the lipid count is set by")
    parser.add_argument("--steps", type=int, default=50000)
    parser.add_argument("--report", type=int, default=5000, help="steps between printed lines")
    parser.add_argument("--quick", action="store_true", help="a smoke run: L = 8, 3000 steps (seconds)")
    parser.add_argument("--out", default="bilayer")
    parser.add_argument("--figure", action="store_true", help="also write density.png")
    parser.add_argument("--platform", default="CPU")
    args = parser.parse_args(argv)
    if args.quick:
        args.edge, args.steps, args.report = 8.0, 3000, 1000
    os.makedirs(args.out, exist_ok=True)

    ff = app.ForceField(forcefield.data_path("lipid-h3t4.xml"))
    lipids = round(2 * args.edge ** 2 / args.area)
    waters = round(3 * args.edge ** 3) - lipids * LIPID.num_beads
    topology, positions = packer.pack([(LIPID, lipids), (WATER, waters)], box=[args.edge] * 3, bond_length=0.7, seed=3)
    system = ff.createSystem(topology, nonbondedMethod=app.CutoffPeriodic, removeCMMotion=False)
    kT, dt = openmmdpd.KT_TEMPERATURE, 0.04 * unit.picosecond
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(kT, 4.5, 1.0, dt), ff, topology)
    integrator.setRandomNumberSeed(11)
    simulation = app.Simulation(topology, system, integrator, openmm.Platform.getPlatformByName(args.platform))
    simulation.context.setPositions(positions)
    kinds = np.array([atom.name[0] for atom in topology.atoms()])
    box = np.full(3, args.edge)
    start = tail_water_contacts(positions.value_in_unit(unit.nanometer), kinds, box)
    packer.relax(simulation)
    simulation.context.setVelocitiesToTemperature(kT, 5)
    simulation.reporters.append(app.StateDataReporter(os.path.join(args.out, "log.csv"), args.report, step=True,
                                                      potentialEnergy=True, temperature=True, speed=True))

    dof = 3 * system.getNumParticles() - 3  # momentum is conserved

    def measure():
        state = simulation.context.getState(getPositions=True, getEnergy=True)
        x = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
        kt = 2 * state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole) / dof
        return x, kt, tail_water_contacts(x, kinds, box), lipid_order(x, kinds, box)

    print(f"{lipids} lipids h3(t4)2 and {waters} water beads in a box of {args.edge:g}^3; "
          f"tail-water contacts at the random start {start:.2f} of a uniform mix")
    print(f"{'step':>7} {'kT':>6} {'contacts':>9} {'S':>6}")
    for step in range(args.report, args.steps + 1, args.report):
        simulation.step(args.report)
        x, kt, contacts, (order, normal) = measure()
        print(f"{step:7d} {kt:6.3f} {contacts:9.3f} {order:6.3f}", flush=True)
    axis = int(np.argmax(np.abs(normal)))
    print(f"bilayer: tail-water contacts {contacts:.3f} of a uniform mix (start {start:.2f}), "
          f"S = {order:.2f} about {'xyz'[axis]}, kT = {kt:.3f}")
    with open(os.path.join(args.out, "end.pdb"), "w") as pdb:
        app.PDBFile.writeFile(topology, x * unit.nanometer, pdb)
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        bins = np.linspace(0, args.edge, 4 * int(args.edge) + 1)
        for kind, label in (("w", "water"), ("h", "heads"), ("t", "tails")):
            counts, _ = np.histogram(x[kinds == kind, axis] % args.edge, bins)
            plt.plot(0.5 * (bins[1:] + bins[:-1]), counts / (np.diff(bins)[0] * args.edge ** 2), label=label)
        plt.xlabel(f"{'xyz'[axis]} (rc)")
        plt.ylabel("beads per rc$^3$")
        plt.legend()
        plt.savefig(os.path.join(args.out, "density.png"), dpi=100)
    return contacts, order, kt


if __name__ == "__main__":
    main()
