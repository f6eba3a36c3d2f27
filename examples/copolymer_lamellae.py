"""A symmetric diblock copolymer melt A5B5 microphase-separating into lamellae, after Groot and
Madden (1998): the package's groot-madden-diblock.xml (a_AB = 40, chi = 4.59: chi N = 46 for
N = 10, far above the mean-field order-disorder point chi N = 10.5), run with
ShardlowIntegrator at dt 0.04 from a random (mixed) start.

Every --report steps it prints kT and the peak of the A-B structure factor
S(q) = |sum_j s_j exp(i q.r_j)|^2 / N (s = +1 for A, -1 for B) over the box's wave vectors
q = 2 pi n / L, |n_i| <= 3: of order 1 in the mixed melt, of order N / 10 and more once
lamellae of period 2 pi / |q*| form.  Writes the OpenMM log (log.csv), the last frame
(end.pdb) and, with --figure, the A fraction across the lamellae (profile.png) into --out.

    PYTHONPATH=build/python /usr/bin/python3 examples/copolymer_lamellae.py [--quick]
"""
import argparse
import itertools
import os

import numpy as np
import openmm
from openmm import app, unit

import openmmdpd
from openmmdpd import forcefield, packer

# Wave vectors n (q = 2 pi n / L) with |n_i| <= 3, one of each pair n, -n.
WAVE_NUMBERS = np.array([n for n in itertools.product(range(-3, 4), repeat=3) if n > (0, 0, 0)])


def diblock(n, m):
    """A_nB_m as one residue per bead."""
    return packer.Molecule.linear(["A"] * n + ["B"] * m)


def structure_factor(x, signs, edge):
    """S(q) at every WAVE_NUMBERS row, and the |q| of each."""
    q = 2 * np.pi * WAVE_NUMBERS / edge
    amplitudes = np.exp(1j * x @ q.T).T @ signs
    return np.abs(amplitudes) ** 2 / len(signs), np.linalg.norm(q, axis=1)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--edge", type=float, default=12.0, help="box edge L (rc)")
    parser.add_argument("--blocks", type=int, nargs=2, default=[5, 5], metavar=("N_A", "N_B"))
    parser.add_argument("--steps", type=int, default=40000)
    parser.add_argument("--report", type=int, default=5000, help="steps between printed lines")
    parser.add_argument("--quick", action="store_true", help="a smoke run: L = 8, 4000 steps (seconds)")
    parser.add_argument("--out", default="copolymer-lamellae")
    parser.add_argument("--figure", action="store_true", help="also write profile.png")
    parser.add_argument("--platform", default="CPU")
    args = parser.parse_args(argv)
    if args.quick:
        args.edge, args.steps, args.report = 8.0, 4000, 1000
    os.makedirs(args.out, exist_ok=True)

    ff = app.ForceField(forcefield.data_path("groot-madden-diblock.xml"))
    chain = diblock(*args.blocks)
    chains = round(3 * args.edge ** 3 / chain.num_beads)
    topology, positions = packer.pack([(chain, chains)], box=[args.edge] * 3, bond_length=0.8, seed=4)
    system = ff.createSystem(topology, nonbondedMethod=app.CutoffPeriodic, removeCMMotion=False)
    kT, dt = openmmdpd.KT_TEMPERATURE, 0.04 * unit.picosecond
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.ShardlowIntegrator(kT, 4.5, 1.0, dt), ff, topology)
    integrator.setRandomNumberSeed(13)
    simulation = app.Simulation(topology, system, integrator, openmm.Platform.getPlatformByName(args.platform))
    simulation.context.setPositions(positions)
    packer.relax(simulation)
    simulation.context.setVelocitiesToTemperature(kT, 5)
    simulation.reporters.append(app.StateDataReporter(os.path.join(args.out, "log.csv"), args.report, step=True,
                                                      potentialEnergy=True, temperature=True, speed=True))

    signs = np.array([1.0 if atom.name == "A" else -1.0 for atom in topology.atoms()])
    dof = 3 * system.getNumParticles() - 3  # momentum is conserved
    s_start = structure_factor(positions.value_in_unit(unit.nanometer), signs, args.edge)[0].max()
    print(f"{chains} chains A{args.blocks[0]}B{args.blocks[1]} ({len(signs)} beads) in a box of {args.edge:g}^3; "
          f"S(q*) at the random start {s_start:.1f}")
    print(f"{'step':>7} {'kT':>6} {'S(q*)':>8} {'period':>7}")
    for step in range(args.report, args.steps + 1, args.report):
        simulation.step(args.report)
        state = simulation.context.getState(getPositions=True, getEnergy=True)
        x = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
        kt = 2 * state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole) / dof
        s, q = structure_factor(x, signs, args.edge)
        peak = np.argmax(s)
        print(f"{step:7d} {kt:6.3f} {s[peak]:8.1f} {2 * np.pi / q[peak]:7.2f}", flush=True)
    print(f"lamellae: S(q*) = {s[peak]:.1f} (start {s_start:.1f}) at n = {tuple(WAVE_NUMBERS[peak])}, "
          f"period {2 * np.pi / q[peak]:.2f} rc, kT = {kt:.3f}")
    with open(os.path.join(args.out, "end.pdb"), "w") as pdb:
        app.PDBFile.writeFile(topology, x * unit.nanometer, pdb)
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        # The A fraction against the phase q*.r over one period, from all beads.
        phase = (x @ (2 * np.pi * WAVE_NUMBERS[peak] / args.edge)) % (2 * np.pi)
        bins = np.linspace(0, 2 * np.pi, 25)
        a, _ = np.histogram(phase[signs > 0], bins)
        total, _ = np.histogram(phase, bins)
        plt.plot(0.5 * (bins[1:] + bins[:-1]) / q[peak], a / np.maximum(total, 1))
        plt.xlabel("distance across the lamellae (rc)")
        plt.ylabel("A fraction")
        plt.savefig(os.path.join(args.out, "profile.png"), dpi=100)
    return s[peak], s_start, kt


if __name__ == "__main__":
    main()
